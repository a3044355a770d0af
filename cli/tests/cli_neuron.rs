//! `neurotac neuron` and `bench neurons` under hostile numbers (a blow-up, values beyond the
//! precision, a partial last step, a step bound) and a closed stdout.

mod common;

use common::neurotac;
use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};

fn spike_times(json: &str) -> Vec<f64> {
    let v: serde_json::Value = serde_json::from_str(json).expect("one JSON object");
    v["spike_times_s"]
        .as_array()
        .expect("spike_times_s")
        .iter()
        .map(|t| t.as_f64().unwrap())
        .collect()
}

#[test]
fn izhikevich_blow_up_is_an_error_naming_the_step() {
    for args in [
        &[
            "neuron",
            "--model",
            "izhikevich",
            "--current=-1e5",
            "--json",
        ][..],
        &[
            "neuron",
            "--model",
            "izhikevich",
            "--current=-1e4",
            "--integrator",
            "euler",
        ],
        &[
            "neuron",
            "--model",
            "izhikevich",
            "--current=-1e4",
            "--integrator",
            "rk4",
        ],
        &[
            "neuron",
            "--model",
            "izhikevich",
            "--current",
            "0",
            "--dt",
            "10ms",
        ],
    ] {
        let (ok, stdout, stderr) = neurotac(args);
        assert!(!ok, "{args:?}: {stdout}");
        assert!(
            stderr.contains("diverged in step")
                && stderr.contains("smaller dt or another integrator"),
            "{args:?}: {stderr}"
        );
        assert!(!stdout.contains("0.0"), "no spike times printed: {stdout}");
    }
    // With --json a diverged run prints nothing rather than half an object.
    let (ok, stdout, stderr) = neurotac(&[
        "neuron",
        "--model",
        "izhikevich",
        "--current=-1e4",
        "--integrator",
        "euler",
        "--json",
    ]);
    assert!(!ok && stderr.contains("diverged in step"), "{stderr}");
    assert_eq!(stdout, "", "no half-written JSON");
    // A healthy run is unchanged: RS at I = 10 fires 23 times in 1 s.
    let (ok, stdout, stderr) = neurotac(&[
        "neuron",
        "--model",
        "izhikevich",
        "--current",
        "10",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(spike_times(&stdout).len(), 23);
}

#[test]
fn values_beyond_the_precision_are_refused() {
    let (ok, _, stderr) = neurotac(&["neuron", "--precision", "f32", "--current", "1e39"]);
    assert!(
        !ok && stderr.contains("--current 1e39 overflows f32"),
        "{stderr}"
    );
    // Times never reach f32's limit: their flags refuse anything past a sane range first.
    for args in [
        &[
            "neuron",
            "--precision",
            "f32",
            "--current",
            "1",
            "--dt",
            "1e39",
        ][..],
        &[
            "bench",
            "neurons",
            "--precision",
            "f32",
            "--n",
            "10",
            "--dt",
            "1e39",
        ],
        &[
            "bench",
            "neurons",
            "--precision",
            "f32",
            "--n",
            "10",
            "--duration=1e39",
        ],
    ] {
        let (ok, _, stderr) = neurotac(args);
        assert!(!ok && stderr.contains("above the largest"), "{stderr}");
    }
    // f64 holds them; `inf` stays refused.
    let (ok, _, stderr) = neurotac(&["neuron", "--current", "inf"]);
    assert!(
        !ok && stderr.contains("must be a finite number"),
        "{stderr}"
    );
}

#[test]
fn no_spike_after_the_duration() {
    // Was `[2.0]` at `--dt 2 --duration 1`: the only step ran past the duration asked for.
    let (ok, stdout, stderr) = neurotac(&[
        "neuron",
        "--current",
        "2",
        "--dt",
        "100ms",
        "--duration",
        "50ms",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(spike_times(&stdout), Vec::<f64>::new());
    assert!(stderr.contains("0 whole steps"), "{stderr}");
    let (ok, stdout, _) = neurotac(&[
        "neuron",
        "--current",
        "2",
        "--dt",
        "3ms",
        "--duration",
        "0.1s",
        "--json",
    ]);
    assert!(ok);
    let times = spike_times(&stdout);
    assert!(
        !times.is_empty() && times.iter().all(|&t| t <= 0.1),
        "{times:?}"
    );
}

#[test]
fn step_count_is_bounded_and_the_bound_can_be_raised() {
    for args in [
        &[
            "neuron",
            "--current",
            "1e6",
            "--dt",
            "1us",
            "--duration",
            "86400s",
        ][..],
        &[
            "neuron",
            "--current",
            "2",
            "--dt",
            "1us",
            "--duration",
            "1000s",
        ],
    ] {
        let (ok, stdout, stderr) = neurotac(args);
        assert!(!ok && stdout.is_empty(), "{args:?}");
        assert!(
            stderr.contains("--max-steps") && stderr.contains("steps"),
            "{stderr}"
        );
    }
    let small = [
        "neuron",
        "--current",
        "2",
        "--duration",
        "10ms",
        "--dt",
        "1µs",
    ];
    let (ok, _, stderr) = neurotac(&[&small[..], &["--max-steps", "5000"]].concat());
    assert!(!ok && stderr.contains("limit of 5000"), "{stderr}");
    let (ok, stdout, stderr) = neurotac(&[&small[..], &["--max-steps", "10000"]].concat());
    assert!(ok, "{stderr}");
    assert!(!stdout.is_empty());
}

#[test]
fn spike_times_are_streamed_in_the_same_format() {
    let (ok, stdout, _) = neurotac(&["neuron", "--current", "1.5", "--duration", "50ms", "--json"]);
    assert!(ok);
    assert!(
        stdout.starts_with("{\"spike_times_s\":[0.011") && stdout.ends_with("]}\n"),
        "{stdout}"
    );
    assert_eq!(spike_times(&stdout).len(), 4); // every 110 steps: 11, 22, 33, 44 ms
    let (ok, text, _) = neurotac(&["neuron", "--current", "1.5", "--duration", "0.05s"]);
    assert!(ok);
    // In the unit the flags read bare, and saying so.
    assert_eq!(text, "11 ms\n22 ms\n33 ms\n44 ms\n");
}

#[test]
fn a_closed_stdout_ends_the_command_quietly() {
    // `neurotac neuron --current 2 --duration 100s | head -1` panicked (exit 101).
    for args in [
        &["neuron", "--current", "2", "--duration", "100s"][..],
        &["neuron", "--current", "2", "--duration", "100s", "--json"],
        &["--help"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_neurotac"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        assert!(!first.is_empty()); // the reader is dropped here: the pipe closes
        let mut stderr = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut stderr)
            .unwrap();
        let status = child.wait().unwrap();
        assert!(stderr.is_empty(), "{args:?}: {stderr}");
        #[cfg(unix)]
        {
            use std::os::unix::process::ExitStatusExt;
            assert!(
                status.success() || status.signal() == Some(libc_sigpipe()),
                "{args:?}: {status:?}"
            );
        }
        #[cfg(not(unix))]
        assert!(status.code() != Some(101), "{args:?}: {status:?}");
    }
}

/// SIGPIPE's number on every Unix neurotac builds for.
#[cfg(unix)]
fn libc_sigpipe() -> i32 {
    13
}

#[test]
fn bench_activity_compares_clock_and_event_driven_with_identical_spikes() {
    for model in ["lif", "izhikevich"] {
        let (ok, stdout, stderr) = neurotac(&[
            "bench",
            "neurons",
            "--model",
            model,
            "--activity",
            "0.05",
            "--n",
            "2000",
            "--duration",
            "200ms",
            "--json",
        ]);
        assert!(ok, "{stderr}");
        let r: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
        assert_eq!(r["model"], model);
        assert_eq!(r["identical_spikes"], true, "{r}");
        assert_eq!(r["clock_driven"]["updates"], 2000 * 2000);
        let event = r["event_driven"]["updates"].as_u64().unwrap();
        assert!(event > 0 && event * 10 < 2000 * 2000, "{r}");
        assert!(r["speedup"].as_f64().unwrap() > 0.0);
        // The automatic run picks a mode and gives the same spikes.
        assert_eq!(r["automatic"]["spikes"], r["clock_driven"]["spikes"], "{r}");
        let mode = r["automatic_stepping"]["mode"].as_str().unwrap();
        assert!(["clock", "event"].contains(&mode), "{r}");
        assert!(r["measured_activity"].as_f64().unwrap() > 0.0, "{r}");
    }
    // The pipeline's integrators are its own.
    let (ok, _, stderr) = neurotac(&[
        "bench",
        "neurons",
        "--activity",
        "0.1",
        "--integrator",
        "euler",
    ]);
    assert!(!ok && stderr.contains("drop --integrator"), "{stderr}");
}

/// `bench neurons` says how close it came to this core's own ceilings, with the work per
/// update it divides by: LIF's exact step is `v·e^(−h)` plus a per-step constant (2 flops)
/// over `v` read and written plus the mask byte (9 bytes in f32, 17 in f64).
#[test]
fn bench_neurons_reports_its_share_of_this_cores_fma_peak_and_bandwidth() {
    for (precision, bytes) in [("f32", 9), ("f64", 17)] {
        let (ok, stdout, stderr) = neurotac(&[
            "bench",
            "neurons",
            "--n",
            "5000",
            "--duration",
            "10ms",
            "--threads",
            "1",
            "--precision",
            precision,
            "--json",
        ]);
        assert!(ok, "{stderr}");
        let r: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
        let c = &r["ceiling"];
        assert_eq!(
            (
                c["flops_per_update"].as_u64(),
                c["bytes_per_update"].as_u64()
            ),
            (Some(2), Some(bytes)),
            "{c}"
        );
        // The bandwidth was measured over what one step of the 5000 neurons moves.
        assert_eq!(
            c["working_set_bytes"].as_u64(),
            Some(5000 * bytes / 2),
            "{c}"
        );
        let per_thread = r["updates_per_s_per_thread"].as_f64().unwrap();
        let peak = c["peak_flops_per_s"].as_f64().unwrap();
        let share = c["of_peak_flops"].as_f64().unwrap();
        assert!(
            peak > 0.0 && (share - per_thread * 2.0 / peak).abs() <= 1e-12 * share,
            "{c}"
        );
        assert!(c["of_bandwidth"].as_f64().unwrap() > 0.0, "{c}");
    }
    let (ok, stdout, _) = neurotac(&["bench", "neurons", "--n", "5000", "--duration", "10ms"]);
    assert!(
        ok && stdout.contains("FMA peak") && stdout.contains("bandwidth over"),
        "{stdout}"
    );
}

/// One absurd number must not run for years, fill the memory or print NaN: the bench refuses
/// it at once, naming the flag and the limit.
#[test]
fn bench_refuses_no_step_and_work_over_its_budget_at_once() {
    for (args, says) in [
        (
            &["bench", "cuba", "--duration", "10ms", "--dt", "100ms"][..],
            "shorter than one step of --dt",
        ),
        (
            &["bench", "neurons", "--dt", "1us", "--duration", "86400s"],
            "8.6e10 steps, more than the limit",
        ),
        (
            &["bench", "cuba", "--dt", "1us", "--duration", "86400s"],
            "8.6e10 steps, more than the limit",
        ),
        (
            &["bench", "neurons", "--n", "1000000000000"],
            "--n 1e12: neurons",
        ),
        (
            &["bench", "cuba", "--neurons", "100000000000"],
            "--neurons 1e11: neurons",
        ),
        (
            &["bench", "neurons", "--activity", "0.5", "--rate", "1e300"],
            "--rate 1e300: expected input spikes",
        ),
    ] {
        let (ok, _, stderr) = neurotac(args);
        assert!(!ok && stderr.contains(says), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(
            !stderr.contains("NaN") && !stderr.contains("inf"),
            "{stderr}"
        );
    }
}

/// A spike on the last step of `--duration 300ms` at `--dt 100ms` is at 0.3 s, not at the
/// 0.30000000000000004 of `3 × 0.1` (past the duration); an absurd step is named as given.
#[test]
fn spike_times_and_absurd_steps_print_as_a_person_writes_them() {
    let (ok, stdout, stderr) = neurotac(&[
        "neuron",
        "--current",
        "2",
        "--duration",
        "300ms",
        "--dt",
        "100ms",
        "--json",
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(spike_times(&stdout), [0.1, 0.2, 0.3]);
    let (ok, _, stderr) = neurotac(&["neuron", "--current", "2", "--dt", "1e-300"]);
    assert!(!ok && stderr.contains("'1e-300' for '--dt"), "{stderr}");
    assert!(stderr.len() < 300, "{stderr}");
}

#[test]
fn bench_crossover_stores_the_crossover_that_automatic_stepping_then_uses() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().to_str().unwrap();
    let small = ["--n", "500", "--duration", "50ms", "--repeats", "1"];
    let bench = |extra: &[&str]| {
        let mut args = vec!["bench", "neurons", "--cache", cache, "--json"];
        args.extend_from_slice(&small);
        args.extend_from_slice(extra);
        neurotac(&args)
    };
    let (ok, stdout, stderr) = bench(&["--crossover"]);
    assert!(ok, "{stderr}");
    let r: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    let crossover = r["crossover"].as_f64().unwrap();
    assert!(crossover > 0.0 && crossover <= 1.0, "{r}");
    let file = dir.path().join("stepping-crossovers.json");
    let stored: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(stored["crossovers"]["lif"].as_f64(), Some(crossover));
    // The activity bench's automatic run decides with the stored crossover.
    let (ok, stdout, stderr) = bench(&["--activity", "0.01"]);
    assert!(ok, "{stderr}");
    let r: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(
        r["automatic_stepping"]["crossover"].as_f64(),
        Some(crossover)
    );
    assert_eq!(r["identical_spikes"], true, "{r}");
    // A corrupt file is refused in one line naming it.
    std::fs::write(&file, "{\"crossovers\": {\"lif\": ").unwrap();
    let (ok, _, stderr) = bench(&["--activity", "0.01"]);
    assert!(!ok);
    assert!(
        stderr.contains(&file.display().to_string()) && stderr.trim().lines().count() == 1,
        "{stderr}"
    );
}
