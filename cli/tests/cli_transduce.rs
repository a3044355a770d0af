//! The transduction commands of the `neurotac` binary: `transduce`, `filter`, `layout`.

mod common;

use common::neurotac;
use neurotac_core::{Event, EventBuffer, SpikeDataset, Timestamp};
use neurotac_sensor::filter::{BackgroundActivityFilter, MapStart};
use neurotac_sensor::format::{DAVIS240_SIZE, read_file, write_file};
use neurotac_sensor::stage::EventFilter;
use neurotac_sensor::taxel::TaxelLayout;

/// Every pin of the default layout twitches every 30 ms for 1.2 s: a small cross of pixel events
/// around it, 200 µs apart (so the BA filter keeps all but the first of each cross).
fn pin_activity() -> EventBuffer {
    let mut events = Vec::new();
    for burst in 0..40i64 {
        for (p, &(cx, cy)) in TaxelLayout::neurotac_default().centres().iter().enumerate() {
            for (k, (dx, dy)) in [(0, 0), (1, 0), (0, 1), (-1, 0), (0, -1)]
                .into_iter()
                .enumerate()
            {
                let t = 1_000_000 + burst * 30_000 + p as i64 * 50 + k as i64 * 200;
                let (x, y) = (
                    (cx.round() as i32 + dx) as u16,
                    (cy.round() as i32 + dy) as u16,
                );
                events.push(Event {
                    t: Timestamp(t),
                    x,
                    y,
                    polarity: k % 2 == 0,
                });
            }
        }
    }
    events.sort_by_key(|e| e.t);
    events.into_iter().collect()
}

#[test]
fn transduce_writes_49_taxel_trains_and_a_raster() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("touch.csv");
    write_file(&input, &pin_activity(), DAVIS240_SIZE).unwrap();
    let (out, raster) = (
        dir.path().join("spikes.json"),
        dir.path().join("raster.svg"),
    );
    let (ok, stdout, stderr) = neurotac(&[
        "transduce",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--raster",
        raster.to_str().unwrap(),
        "--label",
        "twitch",
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("taxel spikes") && stdout.contains("M events/s"),
        "{stdout}"
    );
    let data = SpikeDataset::load(&out).unwrap();
    assert_eq!((data.len(), data.n_channels()), (1, 49));
    assert_eq!(
        (data.labels(), data.class_names()),
        (&[0][..], &["twitch".to_string()][..])
    );
    // 40 bursts, 30 ms apart, each in its own 20 ms window (or split over two): ≥ 40 spikes each.
    let counts = data.observations()[0].counts();
    assert!(counts.iter().all(|&n| (40..=80).contains(&n)), "{counts:?}");
    assert!(
        std::fs::read_to_string(&raster)
            .unwrap()
            .starts_with("<svg")
    );
}

#[test]
fn layout_finds_the_pins_and_transduce_accepts_it() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("calibration.aedat4");
    write_file(&input, &pin_activity(), DAVIS240_SIZE).unwrap();
    let layout = dir.path().join("layout.json");
    let (ok, _, stderr) = neurotac(&[
        "layout",
        input.to_str().unwrap(),
        "--out",
        layout.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("found 49 of 49 taxels"), "{stderr}");
    let found = TaxelLayout::from_json_file(&layout).unwrap();
    for (a, b) in found
        .centres()
        .iter()
        .zip(TaxelLayout::neurotac_default().centres())
    {
        assert!(
            (a.0 - b.0).abs() <= 1.0 && (a.1 - b.1).abs() <= 1.0,
            "{a:?} vs {b:?}"
        );
    }
    let out = dir.path().join("s.ntspk");
    for spec in [layout.to_str().unwrap(), "auto"] {
        let (ok, _, stderr) = neurotac(&[
            "transduce",
            input.to_str().unwrap(),
            "--layout",
            spec,
            "--out",
            out.to_str().unwrap(),
            "--force", // the second spec replaces the first one's output (the overwrite rule)
        ]);
        assert!(ok, "{spec}: {stderr}");
        assert_eq!(SpikeDataset::load(&out).unwrap().n_channels(), 49);
    }
}

/// The first 600 ms of a simulated slide (rest, onset, sliding) over a 2.5 mm grid, with the
/// pins' true image positions.
fn simulated_slide() -> (EventBuffer, Vec<(f64, f64)>) {
    use neurotac_sensor::sim::{Camera, SimParams, Simulator, Texture};
    let mut params = SimParams::default();
    params.kinematics.distance_mm = 8.0;
    let mut sim = Simulator::new(params, &Camera::new(&params, 5)).unwrap();
    let texture = sim.prepare(Texture::grid(2.5).unwrap());
    let trial = sim.simulate(&texture, 9);
    let events = trial
        .events
        .iter()
        .take_while(|e| e.t.0 < 600_000)
        .collect();
    (events, sim.pins_px().to_vec())
}

#[test]
fn layout_finds_the_pins_of_a_sliding_slide() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("slide.aedat4");
    let (events, truth) = simulated_slide();
    write_file(&input, &events, DAVIS240_SIZE).unwrap();
    let layout = dir.path().join("layout.json");
    let (ok, _, stderr) = neurotac(&[
        "layout",
        input.to_str().unwrap(),
        "--out",
        layout.to_str().unwrap(),
    ]);
    assert!(ok && !stderr.contains("warning"), "{stderr}");
    let found = TaxelLayout::from_json_file(&layout).unwrap();
    for (a, b) in found.centres().iter().zip(&truth) {
        assert!((a.0 - b.0).hypot(a.1 - b.1) <= 3.0, "{a:?} vs {b:?}");
    }
    let out = dir.path().join("s.json");
    let (ok, _, stderr) = neurotac(&[
        "transduce",
        input.to_str().unwrap(),
        "--layout",
        "auto",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
}

#[test]
fn an_unreliable_automatic_layout_is_refused_unless_accepted() {
    // Pins on a 7 × 7 square grid, 16 px apart (the spec's alternative to the rings), each
    // flickering as a 5 × 5 px spot: pins, but not the NeuroTac's.
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("grid.csv");
    let mut events = Vec::new();
    for round in 0..20i64 {
        for (i, j) in (0..7).flat_map(|j| (0..7).map(move |i| (i, j))) {
            for (dx, dy) in (-2..=2).flat_map(|dy| (-2..=2).map(move |dx| (dx, dy))) {
                events.push(Event {
                    t: Timestamp(round * 10_000),
                    x: (72 + 16 * i + dx) as u16,
                    y: (42 + 16 * j + dy) as u16,
                    polarity: round % 2 == 0,
                });
            }
        }
    }
    let events: EventBuffer = events.into_iter().collect();
    write_file(&input, &events, DAVIS240_SIZE).unwrap();
    let out = dir.path().join("s.json");
    let transduce = |extra: &[&str]| {
        let mut args = vec![
            "transduce",
            input.to_str().unwrap(),
            "--layout",
            "auto",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        neurotac(&args)
    };
    let (ok, _, stderr) = transduce(&[]);
    let error: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
    assert!(!ok && error.len() == 1, "{stderr}");
    for part in [
        "is unreliable (confidence",
        "--layout default",
        "--accept-uncertain-layout",
    ] {
        assert!(error[0].contains(part), "{stderr}");
    }
    assert!(!out.exists());
    let (ok, _, stderr) = transduce(&["--accept-uncertain-layout"]);
    assert!(
        ok && stderr.contains("warning: the layout found in"),
        "{stderr}"
    );
    assert_eq!(SpikeDataset::load(&out).unwrap().n_channels(), 49);
    // `layout` prints it, with the warning.
    let (ok, stdout, stderr) = neurotac(&["layout", input.to_str().unwrap()]);
    assert!(ok && stdout.starts_with("[["), "{stdout}");
    assert!(
        stderr.contains("warning: the layout found in") && stderr.contains("--layout default"),
        "{stderr}"
    );
}

#[test]
fn filter_writes_exactly_the_events_the_ba_filter_keeps() {
    let dir = tempfile::tempdir().unwrap();
    let (input, output) = (dir.path().join("in.aedat"), dir.path().join("out.csv"));
    let events = pin_activity();
    write_file(&input, &events, DAVIS240_SIZE).unwrap();
    let (ok, stdout, stderr) = neurotac(&[
        "filter",
        input.to_str().unwrap(),
        output.to_str().unwrap(),
        "--ba-window",
        "5ms",
    ]);
    assert!(ok, "{stderr}");
    assert!(stdout.starts_with("kept "), "{stdout}");
    let mut ba = BackgroundActivityFilter::new(240, 180, 5000, MapStart::Zero).unwrap();
    let expected: EventBuffer = events.iter().filter(|&e| ba.retain(e).unwrap()).collect();
    assert_eq!(read_file(&output).unwrap().0, expected);
    assert!(expected.len() < events.len());
}

#[test]
fn bad_inputs_fail_with_one_clear_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.json");
    let (ok, _, stderr) = neurotac(&[
        "transduce",
        "no/such/file.aedat4",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        !ok && stderr.starts_with("error: ") && stderr.contains("no/such/file.aedat4"),
        "{stderr}"
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    let input = dir.path().join("in.csv");
    write_file(&input, &pin_activity(), DAVIS240_SIZE).unwrap();
    let layout = dir.path().join("three.json");
    std::fs::write(&layout, "[[10, 10], [40, 10], [70, 10]]").unwrap();
    let (ok, _, stderr) = neurotac(&[
        "transduce",
        input.to_str().unwrap(),
        "--layout",
        layout.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        !ok && stderr.contains("layout has 3 taxels, 49 required"),
        "{stderr}"
    );
    let (ok, _, stderr) = neurotac(&[
        "filter",
        input.to_str().unwrap(),
        dir.path().join("o.xyz").to_str().unwrap(),
    ]);
    assert!(!ok && stderr.starts_with("error: "), "{stderr}");
    assert!(!out.exists(), "nothing is written when the input is bad");
}
