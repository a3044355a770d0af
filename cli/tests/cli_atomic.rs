//! Data loss and fake results: outputs are never half-written, an output that is the
//! input is refused, report folders are swapped in and stale partial folders removed, and a
//! corrupt dataset is refused (or, for a cache, simulated again).

mod common;

use common::{neurotac, small_reproduce, small_simulate};
use neurotac_core::testing::folder_names;
use neurotac_core::{Event, EventBuffer, Timestamp};
use neurotac_sensor::format::{DAVIS240_SIZE, read_file, write_file};
use std::path::Path;

/// A small recording: 2000 events on a diagonal, 100 µs apart.
fn recording() -> EventBuffer {
    (0..2000i64)
        .map(|i| Event {
            t: Timestamp(1000 + 100 * i),
            x: (i % 240) as u16,
            y: (i % 180) as u16,
            polarity: i % 3 == 0,
        })
        .collect()
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The id of a process that has exited.
fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

#[test]
fn a_reader_error_mid_stream_leaves_no_output_and_keeps_an_old_one() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole.aedat");
    write_file(&whole, &recording(), DAVIS240_SIZE).unwrap();
    let bytes = std::fs::read(&whole).unwrap();
    // Cut inside the last record: every event before it decodes, then the reader fails.
    let cut = dir.path().join("t.aedat");
    std::fs::write(&cut, &bytes[..bytes.len() - 3]).unwrap();
    std::fs::remove_file(&whole).unwrap();
    for ext in ["aedat4", "aedat", "aedat3", "txt", "csv"] {
        let out = dir.path().join(format!("o.{ext}"));
        let (ok, _, stderr) = neurotac(&["convert", s(&cut), s(&out)]);
        assert!(!ok, "convert to .{ext} must fail");
        assert!(stderr.contains("truncated"), "{stderr}");
        let (ok, _, stderr) = neurotac(&["filter", s(&cut), s(&out)]);
        assert!(!ok, "filter to .{ext} must fail: {stderr}");
        assert_eq!(folder_names(dir.path()), ["t.aedat"], ".{ext}");
    }
    // An existing output keeps its old content.
    let out = dir.path().join("o.csv");
    std::fs::write(&out, "old").unwrap();
    assert!(!neurotac(&["convert", s(&cut), s(&out)]).0);
    assert!(!neurotac(&["filter", s(&cut), s(&out)]).0);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
    assert_eq!(folder_names(dir.path()), ["o.csv", "t.aedat"]);
}

#[test]
fn the_shared_recording_cut_at_byte_474357_leaves_no_aedat4() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/davis240/pick.aedat");
    if !data.exists() {
        eprintln!(
            "skipping: {} is absent (the recording is not part of the repository)",
            data.display()
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cut = dir.path().join("t.aedat");
    std::fs::write(&cut, &std::fs::read(&data).unwrap()[..474_357]).unwrap();
    let out = dir.path().join("o.aedat4");
    let (ok, _, stderr) = neurotac(&["convert", s(&cut), s(&out)]);
    assert!(!ok);
    assert!(stderr.contains("truncated at byte 474352"), "{stderr}");
    assert!(!out.exists());
    assert_eq!(folder_names(dir.path()), ["t.aedat"]);
}

#[test]
fn a_writer_error_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("big.csv");
    // The second time is beyond what a 32-bit AEDAT 2.0 timestamp holds.
    std::fs::write(&input, "t,x,y,on\n5,1,2,1\n1099511627776,3,4,0\n").unwrap();
    let out = dir.path().join("o.aedat");
    let (ok, _, stderr) = neurotac(&["convert", s(&input), s(&out)]);
    assert!(!ok);
    assert!(stderr.contains("32-bit AEDAT 2.0 timestamp"), "{stderr}");
    assert_eq!(folder_names(dir.path()), ["big.csv"]);
}

#[test]
fn transduce_with_a_raster_into_a_missing_folder_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("r.csv");
    write_file(&input, &recording(), DAVIS240_SIZE).unwrap();
    let (json, raster) = (dir.path().join("o.json"), dir.path().join("missing/r.svg"));
    let (ok, _, stderr) = neurotac(&[
        "transduce",
        s(&input),
        "--out",
        s(&json),
        "--raster",
        s(&raster),
    ]);
    assert!(!ok);
    assert!(stderr.contains("missing/r.svg"), "{stderr}");
    assert_eq!(folder_names(dir.path()), ["r.csv"]);
    // With both folders there, both outputs appear.
    let raster = dir.path().join("r.svg");
    let (ok, _, stderr) = neurotac(&[
        "transduce",
        s(&input),
        "--out",
        s(&json),
        "--raster",
        s(&raster),
    ]);
    assert!(ok, "{stderr}");
    // The raster comes as SVG and PNG.
    assert_eq!(
        folder_names(dir.path()),
        ["o.json", "r.csv", "r.png", "r.svg"]
    );
}

#[test]
fn an_output_that_is_the_input_is_refused_and_the_input_kept() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("s.aedat");
    write_file(&input, &recording(), DAVIS240_SIZE).unwrap();
    let before = std::fs::read(&input).unwrap();
    let link = dir.path().join("link.aedat");
    std::fs::hard_link(&input, &link).unwrap();
    let dotted = dir.path().join(".").join("s.aedat");
    for (command, output) in [
        ("convert", &input),
        ("convert", &dotted),
        ("convert", &link),
        ("filter", &input),
        ("filter", &link),
    ] {
        let (ok, stdout, stderr) = neurotac(&[command, s(&input), s(output)]);
        assert!(!ok, "{command} {}: {stdout}", output.display());
        assert!(
            stderr.contains("is the input") && stderr.contains("refusing"),
            "{stderr}"
        );
        assert_eq!(std::fs::read(&input).unwrap(), before);
    }
    let (ok, _, stderr) = neurotac(&["transduce", s(&input), "--out", s(&link)]);
    assert!(!ok && stderr.contains("is the input"), "{stderr}");
    assert_eq!(std::fs::read(&input).unwrap(), before);
    // A spike dataset and its distance matrix.
    let data = dir.path().join("d.bin");
    assert!(
        neurotac(&[
            "synth",
            "--output",
            s(&data),
            "--samples",
            "8",
            "--classes",
            "2"
        ])
        .0
    );
    let before = std::fs::read(&data).unwrap();
    let (ok, _, stderr) = neurotac(&[
        "distances",
        "--input",
        s(&data),
        "--metric",
        "euclidean",
        "--coding",
        "spatial",
        "--output",
        s(&data),
    ]);
    assert!(!ok && stderr.contains("is the input"), "{stderr}");
    assert_eq!(std::fs::read(&data).unwrap(), before);
    // Another output next to the input is fine.
    let other = dir.path().join("o.csv");
    assert!(neurotac(&["convert", s(&input), s(&other)]).0);
    assert_eq!(read_file(&other).unwrap().0, recording());
}

#[test]
fn classify_refuses_a_one_bit_flipped_dataset_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("d.bin");
    assert!(
        neurotac(&[
            "synth",
            "--output",
            s(&data),
            "--samples",
            "22",
            "--classes",
            "2"
        ])
        .0
    );
    let classify = |path: &Path| neurotac(&["classify", "--input", s(path), "--coding", "spatial"]);
    assert!(classify(&data).0);
    let mut bytes = std::fs::read(&data).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x04;
    let flipped = dir.path().join("flipped.bin");
    std::fs::write(&flipped, &bytes).unwrap();
    let (ok, stdout, stderr) = classify(&flipped);
    assert!(!ok, "{stdout}");
    assert!(
        stderr.contains("flipped.bin") && stderr.contains("checksum mismatch"),
        "{stderr}"
    );
}

#[test]
fn a_corrupt_cache_is_simulated_again_with_a_one_line_warning() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cache) = (dir.path().join("sim"), dir.path().join("cache"));
    // The second run replaces the first one's output (--force).
    let simulate = || small_simulate(&out, &cache, &["--force"]);
    let (ok, _, stderr) = simulate();
    assert!(ok, "{stderr}");
    let first = std::fs::read(out.join("artificial.bin")).unwrap();
    let cached = folder_names(&cache);
    assert_eq!(cached.len(), 1, "{cached:?}");
    let cached = cache.join(&cached[0]);
    let mut bytes = std::fs::read(&cached).unwrap();
    let near_end = bytes.len() - 100;
    bytes[near_end] ^= 0x01;
    std::fs::write(&cached, &bytes).unwrap();
    let (ok, stdout, stderr) = simulate();
    assert!(ok, "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("warning")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(
        warnings[0].contains("checksum mismatch") && warnings[0].contains("simulating it again"),
        "{stderr}"
    );
    assert!(!stdout.contains("loaded from the cache"), "{stdout}");
    // The same dataset again, and a good cache.
    assert_eq!(std::fs::read(out.join("artificial.bin")).unwrap(), first);
    assert_eq!(std::fs::read(&cached).unwrap(), first);
    let (ok, stdout, stderr) = simulate();
    assert!(ok && !stderr.contains("warning"), "{stderr}");
    assert!(stdout.contains("loaded from the cache"), "{stdout}");
}

#[test]
fn reproduce_removes_partial_folders_of_dead_runs() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cache) = (dir.path().join("report"), dir.path().join("cache"));
    let pid = dead_pid();
    let partial = dir.path().join(format!(".report.partial-{pid}"));
    std::fs::create_dir(&partial).unwrap();
    std::fs::write(partial.join("report.md"), "interrupted").unwrap();
    let (ok, _, stderr) = small_reproduce(&out, &cache, &[]);
    assert!(ok, "{stderr}");
    assert_eq!(folder_names(dir.path()), ["cache", "report"]);
    assert!(out.join("report.md").exists());
}

/// The files under `dir`, hidden ones included, as paths relative to it (sorted).
fn tree(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).into_iter().flatten().flatten() {
            let path = entry.path();
            match path.is_dir() {
                true => folders.push(path),
                false => found.push(s(path.strip_prefix(dir).unwrap()).to_owned()),
            }
        }
    }
    found.sort();
    found
}

#[test]
fn reproduce_refuses_an_out_that_is_holds_or_lies_inside_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let ds = dir.path().join("ds");
    for class in ["cotton", "felt"] {
        std::fs::create_dir_all(ds.join(class)).unwrap();
        write_file(&ds.join(class).join("0.csv"), &recording(), DAVIS240_SIZE).unwrap();
    }
    let params = dir.path().join("params.json");
    std::fs::write(&params, "{}").unwrap();
    let before = tree(dir.path());
    let cache = dir.path().join("cache");
    for (out, input) in [
        (ds.clone(), &ds),
        (dir.path().to_path_buf(), &ds),
        (ds.join("cotton").join("report"), &ds),
        (params.clone(), &params),
    ] {
        let (ok, _, stderr) = neurotac(&[
            "reproduce",
            "--dataset",
            s(&ds),
            "--params",
            s(&params),
            "--cache",
            s(&cache),
            "--out",
            s(&out),
            "--force",
        ]);
        assert!(!ok);
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains(&format!("the output {}", out.display()))
                && stderr.contains(&format!("the input {}", input.display())),
            "{stderr}"
        );
        assert_eq!(tree(dir.path()), before, "nothing written or deleted");
    }
}

#[test]
fn simulate_refuses_an_events_folder_holding_its_parameter_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(out.join("events")).unwrap();
    let params = out.join("events").join("params.json");
    let (ok, stdout, _) = neurotac(&["simulate", "params"]);
    assert!(ok);
    std::fs::write(&params, stdout).unwrap();
    let (ok, _, stderr) = small_simulate(
        &out,
        &dir.path().join("cache"),
        &["--params", s(&params), "--pixel-events", "--force"],
    );
    assert!(!ok);
    assert!(
        stderr.contains("holds the input") && stderr.contains("params.json"),
        "{stderr}"
    );
    assert!(params.is_file());
    assert_eq!(tree(&out), ["events/params.json"]);
}

#[test]
fn transduce_with_a_blocked_png_leaves_the_json_and_svg_as_they_were() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("r.csv");
    write_file(&input, &recording(), DAVIS240_SIZE).unwrap();
    let (json, svg, png) = (
        dir.path().join("s.json"),
        dir.path().join("s.svg"),
        dir.path().join("s.png"),
    );
    std::fs::write(&json, "old").unwrap();
    std::fs::write(&svg, "old").unwrap();
    std::fs::create_dir(&png).unwrap();
    std::fs::write(png.join("keep.txt"), "mine").unwrap();
    let transduce = || {
        neurotac(&[
            "transduce",
            s(&input),
            "--out",
            s(&json),
            "--raster",
            s(&svg),
            "--force",
        ])
    };
    let (ok, _, stderr) = transduce();
    assert!(!ok);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("s.png"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&json).unwrap(), "old");
    assert_eq!(std::fs::read_to_string(&svg).unwrap(), "old");
    assert_eq!(
        tree(dir.path()),
        ["r.csv", "s.json", "s.png/keep.txt", "s.svg"]
    );
    // Unblocked, all three are replaced together.
    std::fs::remove_dir_all(&png).unwrap();
    let (ok, _, stderr) = transduce();
    assert!(ok, "{stderr}");
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    assert_eq!(tree(dir.path()), ["r.csv", "s.json", "s.png", "s.svg"]);
}

#[test]
fn a_killed_simulate_leaves_no_events_folder_and_a_rerun_writes_it() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cache) = (dir.path().join("out"), dir.path().join("cache"));
    let args = |trials: &str| {
        [
            "simulate",
            "--set",
            "artificial",
            "--trials",
            trials,
            "--seed",
            "3",
            "--out",
            s(&out),
            "--cache",
            s(&cache),
            "--pixel-events",
            "--threads",
            "1",
        ]
        .map(str::to_owned)
    };
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_neurotac"))
        .args(args("5"))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Kill it as soon as its first pixel-event file is written (55 trials are to come).
    let mut waited = 0;
    while tree(&out).is_empty() {
        assert!(child.try_wait().unwrap().is_none(), "simulate ended early");
        assert!(waited < 6000, "no pixel-event file appeared");
        std::thread::sleep(std::time::Duration::from_millis(50));
        waited += 1;
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!out.join("events").exists(), "{:?}", tree(&out));
    let partial = format!(".events.partial-{}", child.id());
    assert_eq!(folder_names(&out), [partial.as_str()]);
    // The rerun is not told that events exists, and leaves only complete outputs.
    let (ok, _, stderr) = neurotac(&args("1").each_ref().map(String::as_str));
    assert!(ok, "{stderr}");
    assert_eq!(folder_names(&out), ["artificial.bin", "events"]);
    assert_eq!(tree(&out.join("events")).len(), 11, "one slide per texture");
}
