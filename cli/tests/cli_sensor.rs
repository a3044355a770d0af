//! The sensor commands of the `neurotac` binary: `devices` and `record` without a
//! camera, `convert` between formats.

mod common;

use common::neurotac;

#[test]
fn devices_lists_none_without_a_camera() {
    let (ok, stdout, _) = neurotac(&["devices"]);
    assert!(ok);
    assert!(stdout.contains("no DAVIS camera found"), "{stdout}");
}

#[test]
fn record_without_a_camera_fails_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.aedat4");
    let (ok, _, stderr) = neurotac(&["record", "--out", out.to_str().unwrap(), "--duration", "1s"]);
    assert!(!ok);
    assert!(stderr.contains("no DAVIS camera found"), "{stderr}");
    assert!(!out.exists(), "no file is created without a camera");
    let (ok, _, stderr) = neurotac(&["record", "--out", "x.aedat4", "--duration", "-1"]);
    assert!(!ok && stderr.contains("--duration"), "{stderr}");
}

#[test]
fn convert_round_trips_and_prints_events_per_second() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("in.csv");
    std::fs::write(
        &csv,
        "t,x,y,on\n0,118,38,1\n3,102,28,0\n2147483650,239,179,1\n",
    )
    .unwrap();
    let mut previous = csv.clone();
    for name in ["a.aedat4", "b.aedat3", "c.txt", "d.aedat4", "e.csv"] {
        let next = dir.path().join(name);
        let (ok, stdout, stderr) = neurotac(&[
            "convert",
            previous.to_str().unwrap(),
            next.to_str().unwrap(),
            "--compression",
            "zstd",
        ]);
        assert!(ok, "{name}: {stderr}");
        assert!(
            stdout.contains("3 events") && stdout.contains("events/s"),
            "{stdout}"
        );
        previous = next;
    }
    assert_eq!(
        std::fs::read(&csv).unwrap(),
        std::fs::read(&previous).unwrap()
    );
    let (ok, _, stderr) = neurotac(&["convert", csv.to_str().unwrap(), "out.bin"]);
    assert!(!ok && stderr.contains("extension"), "{stderr}");
    let (ok, _, stderr) = neurotac(&["convert", "Cargo.toml", "out.csv"]);
    assert!(
        !ok && stderr.contains("not an event file") && stderr.contains("byte"),
        "{stderr}"
    );
}

#[test]
fn convert_reports_backwards_time_and_skipped_events() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("in.csv");
    std::fs::write(&csv, "t,x,y,on\n10,1,2,1\n5,1,2,0\n11,300,2,1\n").unwrap();
    let out = dir.path().join("out.aedat");
    let (ok, _, stderr) = neurotac(&["convert", csv.to_str().unwrap(), out.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("skipped 1 events outside the sensor"),
        "{stderr}"
    );
    assert!(stderr.contains("1 events go back in time"), "{stderr}");
}

/// The warning lines of a command's stderr.
fn warnings(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.starts_with("warning: "))
        .collect()
}

#[test]
fn convert_filter_and_transduce_share_one_policy_and_warning() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("in.csv");
    std::fs::write(&csv, "t,x,y,on\n10,1,2,1\n5,1,2,0\n11,300,2,1\n").unwrap();
    let input = csv.to_str().unwrap();
    let expected = format!(
        "warning: {input}: skipped 1 events outside the sensor; 1 events go back in time (kept in file order; the first at byte 18: 5 µs after 10 µs)"
    );
    // convert and filter: warn and count, keep the events going back in time.
    let out = dir.path().join("out.aedat");
    let (ok, _, stderr) = neurotac(&["convert", input, out.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert_eq!(warnings(&stderr), [expected.as_str()], "convert: {stderr}");
    let filtered = dir.path().join("filtered.csv");
    let (ok, stdout, stderr) = neurotac(&["filter", input, filtered.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert_eq!(warnings(&stderr), [expected.as_str()], "filter: {stderr}");
    assert!(stdout.contains("of 2 events"), "{stdout}");
    // transduce: refuses time going back, warns about the events outside the sensor.
    let spikes = dir.path().join("s.json");
    let (ok, _, stderr) = neurotac(&["transduce", input, "--out", spikes.to_str().unwrap()]);
    assert!(
        !ok && stderr.contains("earlier than the previous"),
        "{stderr}"
    );
    let ordered = dir.path().join("ordered.csv");
    std::fs::write(&ordered, "t,x,y,on\n5,1,2,1\n10,1,2,0\n11,300,2,1\n").unwrap();
    let input = ordered.to_str().unwrap();
    let expected = format!("warning: {input}: skipped 1 events outside the sensor");
    // The outputs exist from above: replacing them takes --force (the overwrite rule).
    for args in [
        vec!["transduce", input, "--out", spikes.to_str().unwrap()],
        vec!["filter", input, filtered.to_str().unwrap(), "--force"],
        vec!["convert", input, out.to_str().unwrap(), "--force"],
    ] {
        let (ok, _, stderr) = neurotac(&args);
        assert!(ok, "{args:?}: {stderr}");
        assert_eq!(warnings(&stderr), [expected.as_str()], "{args:?}: {stderr}");
    }
}

#[test]
fn convert_the_real_recording_aedat2_to_aedat4() {
    let Some(dir) = neurotac_core::testing::shared_data("davis240") else {
        return;
    };
    let data = dir.join("pick.aedat");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("pick.aedat4");
    let (ok, stdout, stderr) =
        neurotac(&["convert", data.to_str().unwrap(), out.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("118558 events") && stdout.contains("AEDAT 4.0 (LZ4)"),
        "{stdout}"
    );
}

/// A DAVIS346 recording in AEDAT 2.0 as jAER writes it (chip class `Davis346B`; raw x = 345 − x,
/// raw y = 259 − y): `n` events sweeping the whole 346 × 260 array, corners first.
fn davis346_aedat2(path: &std::path::Path, n: u32) {
    let mut file = b"#!AER-DAT2.0\r\n# This is a raw AE data file - do not edit\r\n# AEChip: eu.seebetter.ini.chips.davis.Davis346B\r\n# End Of ASCII Header\r\n".to_vec();
    for i in 0..n {
        let (x, y) = match i {
            0 => (345, 259),
            1 => (0, 0),
            _ => ((i * 7) % 346, (i * 13) % 260),
        };
        let addr = (259 - y) << 22 | (345 - x) << 12 | (i % 2) << 11;
        file.extend_from_slice(&addr.to_be_bytes());
        file.extend_from_slice(&(10 * i as i32).to_be_bytes());
    }
    std::fs::write(path, file).unwrap();
}

#[test]
fn convert_keeps_a_davis346_recording_and_its_size_in_every_format() {
    use neurotac_sensor::format::open_reader;
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("d346.aedat");
    davis346_aedat2(&input, 5000);
    let (want, read) = neurotac_sensor::format::read_file(&input).unwrap();
    assert_eq!((want.len(), read.out_of_range), (5000, 0));
    assert!(
        want.x
            .iter()
            .zip(&want.y)
            .any(|(&x, &y)| x >= 240 || y >= 180)
    );
    for name in ["a.aedat4", "b.aedat3", "c.csv", "d.txt", "e.aedat"] {
        let out = dir.path().join(name);
        let (ok, stdout, stderr) =
            neurotac(&["convert", input.to_str().unwrap(), out.to_str().unwrap()]);
        assert!(ok, "{name}: {stderr}");
        assert!(
            stdout.contains("346 × 260 sensor") && stdout.contains("5000 events"),
            "{name}: {stdout}"
        );
        assert!(warnings(&stderr).is_empty(), "{name}: {stderr}");
        let mut reader = open_reader(&out).unwrap();
        assert_eq!(reader.sensor_size(), Some((346, 260)), "{name}");
        let mut got = neurotac_core::EventBuffer::new();
        reader.read_to_end(&mut got).unwrap();
        assert_eq!(got, want, "{name}: the events read back");
    }
}

#[test]
fn convert_refuses_a_size_the_output_cannot_state_naming_format_and_size() {
    let dir = tempfile::tempdir().unwrap();
    // A DVXplorer Lite recording (320 × 240) in AEDAT 4.0.
    let input = dir.path().join("dvx.aedat4");
    let events: neurotac_core::EventBuffer = [(0u16, 0u16), (319, 239)]
        .into_iter()
        .enumerate()
        .map(|(i, (x, y))| neurotac_core::Event {
            t: neurotac_core::Timestamp(i as i64),
            x,
            y,
            polarity: true,
        })
        .collect();
    neurotac_sensor::format::write_file(&input, &events, (320, 240)).unwrap();
    for (name, format) in [("o.aedat", "AEDAT 2.0"), ("o.aedat3", "AEDAT 3.1")] {
        let out = dir.path().join(name);
        let (ok, _, stderr) =
            neurotac(&["convert", input.to_str().unwrap(), out.to_str().unwrap()]);
        assert!(!ok, "{name}");
        assert!(
            stderr.contains(format) && stderr.contains("320 × 240") && stderr.lines().count() == 1,
            "{name}: {stderr}"
        );
        assert!(!out.exists(), "{name}: nothing is written");
    }
    // A --sensor other than the size the input states is refused too.
    let out = dir.path().join("o.csv");
    let args = ["convert", input.to_str().unwrap(), out.to_str().unwrap()];
    let (ok, _, stderr) = neurotac(&[&args[..], &["--sensor", "346x260"]].concat());
    assert!(
        !ok && stderr.contains("320 × 240") && stderr.contains("346 × 260"),
        "{stderr}"
    );
    let (ok, _, stderr) = neurotac(&[&args[..], &["--sensor", "346"]].concat());
    assert!(!ok && stderr.contains("WIDTHxHEIGHT"), "{stderr}");
    assert!(!out.exists());
    // Text can state it.
    let (ok, _, stderr) = neurotac(&args);
    assert!(ok, "{stderr}");
    assert!(
        std::fs::read_to_string(&out)
            .unwrap()
            .starts_with("# sensor 320x240\n")
    );
}

#[test]
fn convert_reads_a_text_file_that_states_no_size_as_the_sensor_given() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("faery.csv");
    std::fs::write(&csv, "t,x,y,on\n0,345,259,1\n5,3,4,0\n").unwrap();
    let out = dir.path().join("o.aedat4");
    // Without --sensor: read as 240 × 180, the skipped event reported with how to keep it.
    let (ok, _, stderr) = neurotac(&["convert", csv.to_str().unwrap(), out.to_str().unwrap()]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("skipped 1 events outside the sensor") && stderr.contains("--sensor"),
        "{stderr}"
    );
    let (ok, stdout, stderr) = neurotac(&[
        "convert",
        csv.to_str().unwrap(),
        out.to_str().unwrap(),
        "--force",
        "--sensor",
        "346x260",
    ]);
    assert!(ok && stderr.is_empty(), "{stderr}");
    assert!(stdout.contains("2 events"), "{stdout}");
    let reader = neurotac_sensor::format::open_reader(&out).unwrap();
    assert_eq!(reader.sensor_size(), Some((346, 260)));
}
