//! What a newcomer trips over: numeric flags refused at parse time in the user's
//! terms, one overwrite rule (refuse without --force), one cache, PNG beside every figure.

mod common;
use common::{neurotac, small_simulate};
use std::path::Path;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn numeric_flags_are_refused_before_any_work_with_the_flag_named() {
    for (args, flag, says) in [
        (
            &["reproduce", "--quick", "--epochs", "0"][..],
            "--epochs",
            "at least 1",
        ),
        (
            &["simulate", "check", "--trials", "0"][..],
            "--trials",
            "at least 1",
        ),
        (&["demo", "--taxels", "0"][..], "--taxels", "at least 1"),
        (&["bench", "neurons", "--n", "0"][..], "--n", "at least 1"),
        (
            &["bench", "neurons", "--duration", "-1"][..],
            "--duration",
            "greater than 0",
        ),
        (
            &["demo", "--duration", "-1"][..],
            "--duration",
            "greater than 0",
        ),
        (&["demo", "--rate-hz", "nan"][..], "--rate-hz", "finite"),
        (
            &["synth", "--output", "x.json", "--samples", "-3"][..],
            "--samples",
            "at least 1",
        ),
        (
            &[
                "classify",
                "--input",
                "x",
                "--coding",
                "spatial",
                "--test-fraction",
                "1.5",
            ][..],
            "--test-fraction",
            "between 0 and 1",
        ),
        (
            &["search", "dt", "--input", "x", "--k", "zero"][..],
            "--k",
            "not a whole number",
        ),
    ] {
        let start = std::time::Instant::now();
        let (ok, stdout, stderr) = neurotac(args);
        assert!(!ok, "{args:?} was accepted: {stdout}");
        assert!(
            stderr.contains(flag) && stderr.contains(says),
            "{args:?}: {stderr}"
        );
        assert!(
            !stderr.contains("unexpected argument"),
            "{args:?}: {stderr}"
        );
        // Refused at parse time: no simulation ran (that takes many seconds).
        assert!(start.elapsed().as_secs() < 20, "{args:?} did work first");
    }
}

/// Bare numbers are milliseconds for every time-valued flag; a value written in seconds, as
/// some flags took before, is refused with the reading in seconds to write instead.
#[test]
fn time_flags_read_bare_milliseconds_and_refuse_old_seconds_with_a_hint() {
    for (args, flag, hint) in [
        (
            &[
                "recognise",
                "--train",
                "t.json",
                "--input",
                "x",
                "--dt",
                "0.159",
            ][..],
            "--dt",
            "write 0.159s for seconds",
        ),
        (
            &[
                "recognise",
                "--train",
                "t.json",
                "--input",
                "x",
                "--tau",
                "0.076",
            ][..],
            // τ = 76 µs is computed (exactly) but warned about, with the same hint.
            "warning: τ = 0.076ms is outside",
            "write 0.076s for seconds",
        ),
        (
            &["reproduce", "--quick", "--tau-step", "0.005"][..],
            "--tau-step",
            "write 0.005s for seconds",
        ),
        (
            &[
                "classify", "--input", "x", "--coding", "temporal", "--dt", "0.05",
            ][..],
            "--dt",
            "write 0.05s for seconds",
        ),
        (
            &["synth", "--output", "x.json", "--duration", "4.5"][..],
            "--duration",
            "write 4.5s for seconds",
        ),
        (
            &["neuron", "--current", "2", "--dt", "1e-4"][..],
            "--dt",
            "write 1e-4s",
        ),
        (
            &["filter", "a.csv", "b.csv", "--ba-window", "5000"][..],
            "--ba-window",
            "5000ms is above the largest, 100ms",
        ),
    ] {
        let (ok, _, stderr) = neurotac(args);
        assert!(!ok, "{args:?}");
        let first = stderr.lines().next().unwrap_or_default();
        assert!(
            first.contains(flag) && first.contains(hint),
            "{args:?}: {stderr}"
        );
    }
    // The same window however it is written: 20, 20ms, 0.02s, 20000us, 20000µs.
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("d.json");
    let (ok, _, stderr) = neurotac(&[
        "synth",
        "--output",
        s(&data),
        "--samples",
        "12",
        "--classes",
        "3",
        "--duration",
        "200ms",
    ]);
    assert!(ok, "{stderr}");
    let outputs: Vec<String> = ["20", "20ms", "0.02s", "20000us", "20000µs"]
        .iter()
        .map(|dt| {
            let (ok, stdout, stderr) = neurotac(&[
                "classify",
                "--input",
                s(&data),
                "--coding",
                "temporal",
                "--dt",
                dt,
                "--json",
            ]);
            assert!(ok, "{dt}: {stderr}");
            let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
            v["accuracy"].to_string()
        })
        .collect();
    assert!(outputs.iter().all(|o| *o == outputs[0]), "{outputs:?}");
}

#[test]
fn writing_commands_refuse_an_existing_output_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("d.json");
    let synth = |force: bool| {
        let mut args = vec![
            "synth",
            "--output",
            s(&data),
            "--samples",
            "12",
            "--classes",
            "3",
        ];
        args.extend(force.then_some("--force"));
        neurotac(&args)
    };
    assert!(synth(false).0);
    let before = std::fs::read(&data).unwrap();
    let (ok, _, stderr) = synth(false);
    assert!(
        !ok && stderr.contains("already exists (use --force to replace it)"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read(&data).unwrap(),
        before,
        "refused, yet written"
    );
    assert!(synth(true).0);

    let matrix = dir.path().join("m.json");
    let distances = |force: bool| {
        let mut args = vec!["distances", "--input", s(&data), "--metric", "euclidean"];
        args.extend(["--coding", "spatial", "--output", s(&matrix)]);
        args.extend(force.then_some("--force"));
        neurotac(&args)
    };
    assert!(distances(false).0);
    let (ok, _, stderr) = distances(false);
    assert!(!ok && stderr.contains("m.json already exists"), "{stderr}");
    assert!(distances(true).0);
}

#[test]
fn simulate_shares_the_reproduce_cache_and_refuses_to_overwrite() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cache) = (dir.path().join("out"), dir.path().join("cache"));
    let simulate = |force: bool| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_neurotac"));
        cmd.args([
            "simulate",
            "--set",
            "artificial",
            "--trials",
            "1",
            "--threads",
            "1",
        ])
        .args(["--out", s(&out)])
        .args(force.then_some("--force"))
        .env("NEUROTAC_CACHE", &cache);
        let o = cmd.output().unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (ok, stderr) = simulate(false);
    assert!(ok, "{stderr}");
    // The default cache is the shared one ($NEUROTAC_CACHE here), not `<out>/cache`.
    assert!(!out.join("cache").exists());
    let cached: Vec<_> = std::fs::read_dir(&cache).unwrap().collect();
    assert_eq!(cached.len(), 1, "one cached dataset");
    let (ok, stderr) = simulate(false);
    assert!(
        !ok && stderr.contains("artificial.bin already exists"),
        "{stderr}"
    );
    let (ok, stderr) = simulate(true);
    assert!(ok, "{stderr}");
}

#[test]
fn help_names_the_cache_and_search_vr_has_a_matrix_cache() {
    let (ok, stdout, _) = neurotac(&["--help"]);
    assert!(ok && stdout.contains("~/.cache/neurotac") && stdout.contains("--force"));
    let (ok, stdout, _) = neurotac(&["simulate", "--help"]);
    assert!(ok && stdout.contains("~/.cache/neurotac"), "{stdout}");
    let (ok, stdout, _) = neurotac(&["search", "vr", "--help"]);
    assert!(ok && stdout.contains("--matrix-cache") && !stdout.contains("--cache <"));
}

#[test]
fn demo_states_how_many_afferent_spikes_each_taxel_spike_makes() {
    let (ok, stdout, stderr) = neurotac(&["demo", "--json"]);
    assert!(ok, "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let (taxel, afferent) = (
        v["total_taxel_spikes"].as_f64().unwrap(),
        v["total_afferent_spikes"].as_f64().unwrap(),
    );
    assert_eq!(
        v["afferent_spikes_per_taxel_spike"].as_f64(),
        Some(afferent / taxel)
    );
    // The README's numbers for the default demo (seed 1).
    assert_eq!((taxel, afferent), (998.0, 1290.0));
}

#[test]
fn transduce_raster_is_written_as_svg_and_png() {
    use neurotac_core::{Event, EventBuffer, Timestamp};
    use neurotac_sensor::taxel::TaxelLayout;
    let dir = tempfile::tempdir().unwrap();
    // Every pin twitches every 30 ms: four neighbouring pixels 150 µs apart (the BA filter
    // keeps an event whose neighbour fired shortly before).
    let mut events = Vec::new();
    for burst in 0..40i64 {
        for (p, &(cx, cy)) in TaxelLayout::neurotac_default().centres().iter().enumerate() {
            for (k, (dx, dy)) in [(0, 0), (1, 0), (0, 1), (-1, 0)].into_iter().enumerate() {
                events.push(Event {
                    t: Timestamp(burst * 30_000 + p as i64 * 40 + k as i64 * 150),
                    x: (cx.round() as i32 + dx) as u16,
                    y: (cy.round() as i32 + dy) as u16,
                    polarity: k % 2 == 0,
                });
            }
        }
    }
    events.sort_by_key(|e| e.t);
    let events: EventBuffer = events.into_iter().collect();
    let input = dir.path().join("e.csv");
    neurotac_sensor::format::write_file(&input, &events, (240, 180)).unwrap();
    let (out, raster) = (dir.path().join("s.json"), dir.path().join("r.svg"));
    let args = [
        "transduce",
        s(&input),
        "--layout",
        "default",
        "--out",
        s(&out),
        "--raster",
        s(&raster),
    ];
    let (ok, _, stderr) = neurotac(&args);
    assert!(ok, "{stderr}");
    assert!(
        std::fs::read_to_string(&raster)
            .unwrap()
            .starts_with("<svg")
    );
    let png = std::fs::read(dir.path().join("r.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let (ok, _, stderr) = neurotac(&args);
    assert!(!ok && stderr.contains("already exists"), "{stderr}");
}

#[test]
fn an_empty_cache_variable_counts_as_unset() {
    let dir = tempfile::tempdir().unwrap();
    let (work, xdg) = (dir.path().join("work"), dir.path().join("xdg"));
    std::fs::create_dir_all(&work).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_neurotac"))
        .args(["simulate", "--set", "artificial", "--trials", "1"])
        .args(["--threads", "1", "--out", "out"])
        .current_dir(&work)
        .env("NEUROTAC_CACHE", "")
        .env("XDG_CACHE_HOME", &xdg)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The cache went to $XDG_CACHE_HOME/neurotac, not into the working folder.
    let cached: Vec<_> = std::fs::read_dir(xdg.join("neurotac")).unwrap().collect();
    assert_eq!(cached.len(), 1, "one cached dataset");
    let work_files: Vec<_> = std::fs::read_dir(&work)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        work_files,
        ["out"],
        "nothing but the output in the working folder"
    );
}

#[test]
fn simulate_check_refuses_to_overwrite_either_of_its_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("check.json"), "{\"kept\": true}").unwrap();
    let (ok, _, stderr) = neurotac(&["simulate", "check", "--out", out.to_str().unwrap()]);
    assert!(
        !ok && stderr.contains("check.json already exists"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("check.json")).unwrap(),
        "{\"kept\": true}"
    );
    assert!(!out.join("check.md").exists());
}

#[test]
fn an_unusable_cache_is_said_before_simulating_and_the_run_goes_on_without_it() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cache) = (dir.path().join("out"), dir.path().join("cache"));
    // The cache "folder" is a file.
    std::fs::write(&cache, "not a folder").unwrap();
    let (ok, _, stderr) = small_simulate(&out, &cache, &["--threads", "1"]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("the cache folder") && stderr.contains("simulating without caching"),
        "{stderr}"
    );
    assert!(out.join("artificial.bin").is_file());
    assert_eq!(std::fs::read_to_string(&cache).unwrap(), "not a folder");
}

#[test]
fn a_tau_below_a_millisecond_is_computed_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("d.json");
    let out = dir.path().join("m.json");
    let (ok, _, stderr) = neurotac(&[
        "synth",
        "--output",
        data.to_str().unwrap(),
        "--samples",
        "4",
        "--classes",
        "2",
        "--channels",
        "3",
    ]);
    assert!(ok, "{stderr}");
    // The fixtures' τ = 1 µs: the library computes it exactly.
    let (ok, _, stderr) = neurotac(&[
        "distances",
        "--input",
        data.to_str().unwrap(),
        "--metric",
        "van-rossum",
        "--tau",
        "1us",
        "--cos",
        "0.5",
        "--output",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("warning: τ = 1us is outside 1ms … 10s"),
        "{stderr}"
    );
    let matrix: serde_json::Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(matrix["matrix"].as_array().unwrap().len(), 4);
}
