//! Recorded datasets (`neurotac_experiments::datasets::recorded`): tiny folders of synthetic event files
//! in every format, and every way a folder can be wrong.

use neurotac_core::{Event, EventBuffer, Timestamp, error_chain};
use neurotac_experiments::datasets::recorded::{RecordedDataset, RecordedError, load_recorded};
use neurotac_sensor::format::{Compression, DAVIS240_SIZE, Format, to_bytes, write_file};
use neurotac_sensor::taxel::{TaxelLayout, TransductionConfig};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// 200 ms of events clustered on the 3 × 3 pixels around the centre of `taxel` of the default
/// layout, one every 50 µs (dense enough for the background-activity filter to keep them).
fn clustered(taxel: usize) -> EventBuffer {
    let (cx, cy) = TaxelLayout::neurotac_default().centres()[taxel];
    let (cx, cy) = (cx.round() as i64, cy.round() as i64);
    let mut events = EventBuffer::new();
    for i in 0..4000i64 {
        events.push(Event {
            t: Timestamp(1_000 + 50 * i),
            x: (cx + i % 3 - 1) as u16,
            y: (cy + (i / 3) % 3 - 1) as u16,
            polarity: i % 2 == 0,
        });
    }
    events
}

fn write(path: &Path, events: &EventBuffer) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    write_file(path, events, DAVIS240_SIZE).unwrap();
}

fn load(dir: &Path) -> Result<RecordedDataset, RecordedError> {
    load_recorded(
        dir,
        &TaxelLayout::neurotac_default(),
        TransductionConfig::default(),
        |_, _| {},
    )
}

/// An AEDAT 4.0 file whose header states a 346 × 260 sensor.
fn write_aedat4_346(path: &Path, events: &EventBuffer) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    write_file(path, events, (346, 260)).unwrap();
}

#[test]
fn two_classes_of_mixed_formats_give_labelled_spike_trains() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    // Class names sort "cotton" < "denim" whatever order the folders are made in.
    write(&root.join("denim/b.csv"), &clustered(3));
    write(&root.join("denim/a.aedat4"), &clustered(2));
    write(&root.join("cotton/t2.txt"), &clustered(1));
    write(&root.join("cotton/t1.aedat"), &clustered(0));
    // Skipped: hidden files, non-event extensions, nested folders, loose files, hidden folders.
    std::fs::write(root.join("cotton/.hidden.csv"), "garbage").unwrap();
    std::fs::write(root.join("cotton/notes.json"), "{}").unwrap();
    std::fs::write(root.join("cotton/README"), "not events").unwrap();
    std::fs::create_dir_all(root.join("cotton/extra")).unwrap();
    std::fs::write(root.join("README.md"), "about").unwrap();
    std::fs::create_dir_all(root.join(".cache")).unwrap();

    let calls = AtomicUsize::new(0);
    let last = AtomicUsize::new(0);
    let recorded = load_recorded(
        root,
        &TaxelLayout::neurotac_default(),
        TransductionConfig::default(),
        |done, total| {
            assert_eq!(total, 4);
            calls.fetch_add(1, Ordering::Relaxed);
            last.fetch_max(done, Ordering::Relaxed);
        },
    )
    .unwrap();
    assert_eq!((calls.into_inner(), last.into_inner()), (4, 4));
    let data = &recorded.dataset;
    assert_eq!(data.class_names(), ["cotton", "denim"]);
    assert_eq!(data.labels(), [0, 0, 1, 1]);
    assert_eq!(data.n_channels(), 49);
    let names: Vec<String> = recorded
        .files
        .iter()
        .map(|f| f.path.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["t1.aedat", "t2.txt", "a.aedat4", "b.csv"]);
    let sizes: Vec<_> = recorded.files.iter().map(|f| f.sensor_size).collect();
    assert_eq!(sizes, [Some((240, 180)), None, Some((240, 180)), None]);
    for (k, (file, observation)) in recorded.files.iter().zip(data.observations()).enumerate() {
        assert_eq!(file.events, 4000, "{}", file.path.display());
        assert_eq!(file.label, data.labels()[k]);
        assert_eq!(file.span_us, 50 * 3999);
        // File k's events sit on taxel k: its spikes are there and nowhere else.
        let spikes = observation.channel(k).len();
        assert!(
            spikes > 0,
            "{}: no spikes on taxel {k}",
            file.path.display()
        );
        assert_eq!(observation.total_spikes(), spikes);
        assert_eq!(file.counts.taxel_events as usize, spikes);
    }
    // One ms past the last event (0.19995 s after the first).
    assert_eq!(data.meta()["duration_s"].as_f64(), Some(0.2));
}

#[test]
fn a_class_with_one_trial_is_allowed() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("a/only.csv"), &clustered(0));
    write(&dir.path().join("b/1.csv"), &clustered(1));
    write(&dir.path().join("b/2.csv"), &clustered(2));
    let recorded = load(dir.path()).unwrap();
    assert_eq!(recorded.dataset.labels(), [0, 1, 1]);
}

#[test]
fn a_missing_path_or_a_file_is_not_a_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope");
    let e = load(&missing).unwrap_err();
    assert!(matches!(e, RecordedError::Missing { .. }), "{e}");
    assert!(e.to_string().contains("nope"), "{e}");
    let file = dir.path().join("file.csv");
    write(&file, &clustered(0));
    let e = load(&file).unwrap_err();
    assert!(matches!(e, RecordedError::NotAFolder { .. }), "{e}");
}

#[test]
fn no_class_folders_and_a_single_class_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("loose.csv"), &clustered(0));
    let e = load(dir.path()).unwrap_err();
    assert!(matches!(e, RecordedError::NoClasses { .. }), "{e}");
    write(&dir.path().join("cotton/1.csv"), &clustered(0));
    write(&dir.path().join("cotton/2.csv"), &clustered(0));
    let e = load(dir.path()).unwrap_err();
    assert!(
        matches!(&e, RecordedError::TooFewClasses { class, .. } if class == "cotton"),
        "{e}"
    );
}

#[test]
fn empty_class_folders_are_named() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("a")).unwrap();
    std::fs::create_dir_all(dir.path().join("b")).unwrap();
    std::fs::write(dir.path().join("b/notes.json"), "{}").unwrap();
    let e = load(dir.path()).unwrap_err();
    assert!(matches!(e, RecordedError::NoEventFiles { .. }), "{e}");
    write(&dir.path().join("a/1.csv"), &clustered(0));
    let e = load(dir.path()).unwrap_err();
    assert!(
        matches!(&e, RecordedError::EmptyClass { path } if path.ends_with("b")),
        "{e}"
    );
    assert!(e.to_string().starts_with("no event files in "), "{e}");
}

#[test]
fn a_corrupt_file_is_named_with_the_format_error_chained() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("a/1.csv"), &clustered(0));
    write(&dir.path().join("b/1.csv"), &clustered(1));
    std::fs::write(dir.path().join("b/2.aedat4"), b"GIF89a not an event file").unwrap();
    let e = load(dir.path()).unwrap_err();
    assert!(
        matches!(&e, RecordedError::Read { path, .. } if path.ends_with("b/2.aedat4")),
        "{e}"
    );
    let message = error_chain(&e);
    assert!(message.contains("not an event file"), "{message}");
    // A truncated AEDAT 4.0 file fails while reading its events, not only at its header.
    let bytes = to_bytes(
        &clustered(1),
        Format::Aedat4(Compression::Lz4),
        DAVIS240_SIZE,
    )
    .unwrap();
    std::fs::write(dir.path().join("b/2.aedat4"), &bytes[..bytes.len() / 2]).unwrap();
    let e = load(dir.path()).unwrap_err();
    assert!(
        matches!(e, RecordedError::Read { .. }),
        "{}",
        error_chain(&e)
    );
}

#[test]
fn an_event_file_without_events_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("a/1.csv"), &clustered(0));
    write(&dir.path().join("b/1.aedat"), &EventBuffer::new());
    let e = load(dir.path()).unwrap_err();
    assert!(matches!(e, RecordedError::NoEvents { .. }), "{e}");
}

#[test]
fn mixed_sensor_sizes_name_both_files() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("a/1.aedat4"), &clustered(0));
    write_aedat4_346(&dir.path().join("b/1.aedat4"), &clustered(1));
    let e = load(dir.path()).unwrap_err();
    assert!(
        matches!(
            &e,
            RecordedError::MixedSensorSizes {
                first_size: (240, 180),
                other_size: (346, 260),
                ..
            }
        ),
        "{e}"
    );
    let message = e.to_string();
    assert!(
        message.contains("a/1.aedat4") && message.contains("b/1.aedat4"),
        "{message}"
    );
    assert!(
        message.contains("240×180") && message.contains("346×260"),
        "{message}"
    );
}

#[test]
fn a_sensor_other_than_the_transductions_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_aedat4_346(&dir.path().join("a/1.aedat4"), &clustered(0));
    write_aedat4_346(&dir.path().join("b/1.aedat4"), &clustered(1));
    let e = load(dir.path()).unwrap_err();
    assert!(
        matches!(
            e,
            RecordedError::SensorSizeMismatch {
                size: (346, 260),
                expected: (240, 180),
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn text_events_outside_the_sensor_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("a/1.csv"), &clustered(0));
    // A CSV from a larger camera that does not state its size: x = 300 lies beyond 240 × 180.
    let mut wide = clustered(1);
    wide.push(Event {
        t: Timestamp(1_000_000),
        x: 300,
        y: 10,
        polarity: true,
    });
    let lines: String = wide
        .iter()
        .map(|e| format!("{},{},{},{}\n", e.t.0, e.x, e.y, u8::from(e.polarity)))
        .collect();
    std::fs::create_dir_all(dir.path().join("b")).unwrap();
    std::fs::write(dir.path().join("b/1.csv"), format!("t,x,y,on\n{lines}")).unwrap();
    let e = load(dir.path()).unwrap_err();
    assert!(
        matches!(e, RecordedError::EventsOutsideSensor { dropped: 1, .. }),
        "{e}"
    );
    // With a smaller transduction sensor, events inside 240 × 180 can still be outside it.
    std::fs::remove_file(dir.path().join("b/1.csv")).unwrap();
    write(&dir.path().join("b/1.csv"), &clustered(1));
    let small = TransductionConfig {
        width: 100,
        height: 100,
        ..TransductionConfig::default()
    };
    let layout = TaxelLayout::new(vec![(50.0, 50.0)]);
    let e = load_recorded(dir.path(), &layout, small, |_, _| {}).unwrap_err();
    assert!(
        matches!(e, RecordedError::EventsOutsideSensor { dropped: 0, .. }),
        "{e}"
    );
}

#[test]
fn events_going_back_in_time_are_a_transduction_error_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir.path().join("a/1.csv"), &clustered(0));
    let mut backwards = clustered(1);
    backwards.t[100] = 0;
    write(&dir.path().join("b/1.csv"), &backwards);
    let e = load(dir.path()).unwrap_err();
    assert!(
        matches!(&e, RecordedError::Transduction { path, .. } if path.ends_with("b/1.csv")),
        "{e}"
    );
    assert!(
        error_chain(&e).contains("earlier than the previous"),
        "{}",
        error_chain(&e)
    );
}

#[test]
fn invalid_settings_are_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let config = TransductionConfig {
        recentre_gain: 2.0,
        ..TransductionConfig::default()
    };
    let e = load_recorded(
        dir.path(),
        &TaxelLayout::neurotac_default(),
        config,
        |_, _| {},
    )
    .unwrap_err();
    assert!(matches!(e, RecordedError::Config(_)), "{e}");
}
