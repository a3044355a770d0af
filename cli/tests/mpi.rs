//! The distributed commands under `mpirun -n 1|2|3`: byte-identical outputs to one
//! process, bad input and faults. Built only with the `mpi` feature
//! (`cargo test --release -p neurotac-cli --features mpi --test mpi`); skipped with a
//! reason when `mpirun` is not installed.
#![cfg(feature = "mpi")]

mod common;

use common::{mpirun, mpirun_command, neurotac, neurotac_on_ranks, neurotac_per_rank};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// `simulate --set artificial` arguments writing to `out` with its own cache.
fn simulate_args(out: &Path, trials: usize, extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = [
        "simulate",
        "--set",
        "artificial",
        "--trials",
        &trials.to_string(),
        "--seed",
        "7",
        "--threads",
        "1",
        "--json",
        "--out",
        out.to_str().unwrap(),
        "--cache",
        out.with_extension("cache").to_str().unwrap(),
    ]
    .map(String::from)
    .to_vec();
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

fn strs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

#[test]
fn simulate_on_1_2_and_3_ranks_writes_the_one_process_dataset_byte_for_byte() {
    let Some(mpirun) = mpirun() else { return };
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one");
    let (ok, _, stderr) = neurotac(&strs(&simulate_args(&one, 2, &["--pixel-events"])));
    assert!(ok, "{stderr}");
    for ranks in [1, 2, 3] {
        let out = dir.path().join(format!("ranks{ranks}"));
        let args = simulate_args(&out, 2, &["--pixel-events"]);
        let (ok, stdout, stderr) = neurotac_on_ranks(&mpirun, ranks, &strs(&args));
        assert!(ok, "{ranks} ranks: {stderr}");
        // Rank 0 alone reports.
        assert_eq!(stdout.matches("artificial set:").count(), 1, "{stdout}");
        for file in ["artificial.bin", "artificial.json"] {
            let (a, b) = (read(&one.join(file)), read(&out.join(file)));
            assert!(a == b, "{file} differs on {ranks} ranks");
        }
        // Every rank wrote its own trials' pixel events: all of them are there, identical.
        let events = |root: &Path| {
            let mut files: Vec<PathBuf> = walk(&root.join("events"));
            files.sort();
            files
                .into_iter()
                .map(|f| (f.strip_prefix(root).unwrap().to_owned(), read(&f)))
                .collect::<Vec<_>>()
        };
        let (a, b) = (events(&one), events(&out));
        assert_eq!(a.len(), 22);
        assert!(a == b, "pixel events differ on {ranks} ranks");
    }
}

/// Removes the keys that hold wall times (and the rank count and exchanges) from a JSON report.
fn without_timing(text: &str) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_str(text.trim()).unwrap_or_else(|e| {
        panic!("not JSON ({e}): {text}");
    });
    if let Some(o) = v.as_object_mut() {
        o.retain(|k, _| {
            !(k.contains("timing")
                || k.ends_with("_s")
                || ["time", "ranks", "exchanges"].contains(&k.as_str()))
        });
    }
    v
}

#[test]
fn distances_classify_search_and_cuba_on_2_and_3_ranks_equal_one_process() {
    let Some(mpirun) = mpirun() else { return };
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("d.bin");
    // Two samples: on 3 ranks one rank has no rows to compute.
    let tiny = dir.path().join("tiny.bin");
    for (path, samples) in [(&data, "44"), (&tiny, "2")] {
        let (ok, _, stderr) = neurotac(&[
            "synth",
            "--output",
            path.to_str().unwrap(),
            "--samples",
            samples,
            "--classes",
            "2",
            "--channels",
            "49",
            "--spikes-per-unit",
            "8",
            "--seed",
            "3",
        ]);
        assert!(ok, "{stderr}");
    }
    let d = data.to_str().unwrap().to_owned();
    // (command line with OUT for an output file, output extension or "" for stdout JSON)
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec![
                "distances",
                "--input",
                &d,
                "--metric",
                "van-rossum",
                "--tau",
                "0.02s",
                "--cos",
                "0.4",
                "--output",
                "OUT",
            ],
            "npy",
        ),
        (
            vec![
                "distances",
                "--input",
                &d,
                "--metric",
                "euclidean",
                "--coding",
                "temporal",
                "--dt",
                "0.05s",
                "--output",
                "OUT",
            ],
            "npz",
        ),
        (
            vec![
                "distances",
                "--input",
                tiny.to_str().unwrap(),
                "--metric",
                "van-rossum",
                "--tau",
                "0.02s",
                "--cos",
                "1",
                "--output",
                "OUT",
            ],
            "json",
        ),
        (
            vec![
                "classify",
                "--input",
                &d,
                "--coding",
                "spatiotemporal",
                "--tau",
                "0.02s",
                "--cos",
                "0.4",
                "--json",
                "--matrix",
                "OUT",
            ],
            "npy",
        ),
        (
            vec![
                "classify",
                "--input",
                tiny.to_str().unwrap(),
                "--coding",
                "intensive",
                "--k",
                "1",
                "--json",
                "--matrix",
                "OUT",
            ],
            "npy",
        ),
        (
            vec![
                "search",
                "dt",
                "--input",
                tiny.to_str().unwrap(),
                "--max-window",
                "5",
                "--k",
                "1",
                "--json",
            ],
            "",
        ),
        (
            vec![
                "search",
                "dt",
                "--input",
                &d,
                "--max-window",
                "40",
                "--json",
            ],
            "",
        ),
        (
            vec![
                "bench",
                "cuba",
                "--duration",
                "0.03s",
                "--threads",
                "1",
                "--json",
            ],
            "",
        ),
    ];
    for (i, (args, ext)) in cases.iter().enumerate() {
        let run = |ranks: usize| {
            let out = dir.path().join(format!("case{i}-{ranks}.{ext}"));
            let args: Vec<&str> = args
                .iter()
                .map(|&a| if a == "OUT" { out.to_str().unwrap() } else { a })
                .collect();
            let (ok, stdout, stderr) = match ranks {
                0 => neurotac(&args),
                k => neurotac_on_ranks(&mpirun, k, &args),
            };
            assert!(ok, "{args:?} on {ranks} ranks: {stderr}");
            let file = (!ext.is_empty()).then(|| read(&out));
            let json = stdout
                .trim_start()
                .starts_with('{')
                .then(|| without_timing(&stdout));
            (file, json, stdout)
        };
        let lines = |s: &str| s.lines().filter(|l| !l.trim().is_empty()).count();
        let (one_file, one_json, one_stdout) = run(0);
        for ranks in [2, 3] {
            let (file, json, stdout) = run(ranks);
            assert!(
                file == one_file,
                "{args:?}: output file differs on {ranks} ranks"
            );
            assert_eq!(json, one_json, "{args:?} on {ranks} ranks");
            // Rank 0 alone prints.
            assert_eq!(lines(&stdout), lines(&one_stdout), "{stdout}");
        }
    }
}

#[test]
fn distances_without_samples_or_with_more_ranks_than_samples_equal_one_process() {
    let Some(mpirun) = mpirun() else { return };
    let dir = tempfile::tempdir().unwrap();
    // No sample (a 0×0 matrix, nothing to gather) and one sample (a 1×1 matrix whose upper
    // triangle is empty: every rank computes no pair).
    let empty = dir.path().join("empty.json");
    std::fs::write(&empty, r#"{"observations": [], "labels": []}"#).unwrap();
    let one = dir.path().join("one.json");
    std::fs::write(
        &one,
        r#"{"observations": [[[0.001, 0.004], [0.002]]], "labels": [0]}"#,
    )
    .unwrap();
    let metrics: [&[&str]; 2] = [
        &["--metric", "van-rossum", "--tau", "0.02s", "--cos", "0.5"],
        &["--metric", "euclidean", "--coding", "intensive"],
    ];
    for (data, ext) in [
        (&empty, "json"),
        (&empty, "npy"),
        (&empty, "npz"),
        (&one, "npy"),
    ] {
        for (m, metric) in metrics.iter().enumerate() {
            let run = |ranks: usize| {
                let out = dir.path().join(format!("m{m}-{ranks}.{ext}"));
                let mut args = vec!["distances", "--input", data.to_str().unwrap()];
                args.extend_from_slice(metric);
                args.extend(["--output", out.to_str().unwrap(), "--force"]);
                let (ok, stdout, stderr) = match ranks {
                    0 => neurotac(&args),
                    k => neurotac_on_ranks(&mpirun, k, &args),
                };
                assert!(ok, "{args:?} on {ranks} ranks: {stderr}");
                (read(&out), stdout)
            };
            let (one_process, stdout) = run(0);
            let n = if data == &empty { 0 } else { 1 };
            assert!(stdout.starts_with(&format!("{n}×{n} ")), "{stdout}");
            for ranks in [1, 2, 3] {
                assert!(
                    run(ranks).0 == one_process,
                    "{} {metric:?} .{ext} differs on {ranks} ranks",
                    data.display()
                );
            }
        }
    }
}

#[test]
fn bad_input_on_several_ranks_is_one_line_from_rank_0() {
    let Some(mpirun) = mpirun() else { return };
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.bin");
    let out = dir.path().join("d.json");
    let (ok, _, stderr) = neurotac_on_ranks(
        &mpirun,
        2,
        &[
            "distances",
            "--input",
            missing.to_str().unwrap(),
            "--metric",
            "van-rossum",
            "--tau",
            "0.01s",
            "--cos",
            "0.5",
            "--output",
            out.to_str().unwrap(),
        ],
    );
    assert!(!ok);
    let ours = error_lines(&stderr);
    assert!(
        ours[0].starts_with("error: ") && ours[0].contains("missing.bin"),
        "{stderr}"
    );
    assert!(!stderr.contains("rank 1 of 2"), "{stderr}");
    assert!(!out.exists());
    // A command that does not distribute says so.
    let (ok, _, stderr) = neurotac_on_ranks(&mpirun, 2, &["demo"]);
    assert!(!ok);
    assert!(
        stderr.contains("`neurotac demo` runs on one process"),
        "{stderr}"
    );
}

/// The lines of our own errors in an mpirun's stderr (Open MPI adds its own notices).
fn error_lines(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| l.starts_with("error")).collect()
}

#[test]
fn ranks_started_on_other_data_or_another_seed_stop_before_writing_anything() {
    let Some(mpirun) = mpirun() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.bin"), dir.path().join("b.bin"));
    for (path, seed) in [(&a, "3"), (&b, "4")] {
        let (ok, _, stderr) = neurotac(&[
            "synth",
            "--output",
            path.to_str().unwrap(),
            "--samples",
            "4",
            "--classes",
            "2",
            "--channels",
            "9",
            "--seed",
            seed,
        ]);
        assert!(ok, "{stderr}");
    }
    // The same data at another path (a copy on each machine) is the same input.
    let copy = dir.path().join("copy").join("a.bin");
    std::fs::create_dir_all(copy.parent().unwrap()).unwrap();
    std::fs::copy(&a, &copy).unwrap();
    let out = dir.path().join("d.npy");
    let distances = |input: &Path| -> Vec<String> {
        [
            "distances",
            "--input",
            input.to_str().unwrap(),
            "--metric",
            "van-rossum",
            "--tau",
            "0.02s",
            "--cos",
            "0.5",
            "--output",
            out.to_str().unwrap(),
        ]
        .map(String::from)
        .to_vec()
    };
    // Rank 1 reads another dataset: every rank stops, one line names both files, no output.
    let (ok, _, stderr) = neurotac_per_rank(&mpirun, &[strs(&distances(&a)), strs(&distances(&b))]);
    assert!(!ok, "a mixed matrix was accepted");
    let errors = error_lines(&stderr);
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(
        errors[0]
            .starts_with("error: ranks disagree on the inputs: rank 1 read a different --input (")
            && errors[0].contains("b.bin, digest ")
            && errors[0].contains("a.bin, digest "),
        "{stderr}"
    );
    assert!(!out.exists());
    // A copy of the same data agrees, and the matrix is the one-process matrix.
    let (ok, _, stderr) =
        neurotac_per_rank(&mpirun, &[strs(&distances(&a)), strs(&distances(&copy))]);
    assert!(ok, "{stderr}");
    let matrix = read(&out);
    std::fs::remove_file(&out).unwrap();
    let (ok, _, stderr) = neurotac(&strs(&distances(&a)));
    assert!(ok, "{stderr}");
    assert!(read(&out) == matrix);

    // simulate with another seed on rank 1: no dataset written, nothing cached.
    let simulate = |out: &Path, seed: &str, threads: &str| {
        let mut args = simulate_args(out, 1, &[]);
        for (flag, value) in [("--seed", seed), ("--threads", threads)] {
            let at = args.iter().position(|a| a == flag).unwrap();
            args[at + 1] = value.to_owned();
        }
        args
    };
    let sim = dir.path().join("sim");
    let (ok, _, stderr) = neurotac_per_rank(
        &mpirun,
        &[
            strs(&simulate(&sim, "1", "1")),
            strs(&simulate(&sim, "2", "1")),
        ],
    );
    assert!(!ok, "a mixed dataset was accepted");
    assert_eq!(
        error_lines(&stderr),
        [
            "error: ranks disagree on the settings: rank 1 was started with --seed 2, rank 0 with --seed 1"
        ],
        "{stderr}"
    );
    assert!(
        !sim.exists() && !sim.with_extension("cache").exists(),
        "an output or a cache entry was written"
    );
    // The thread count may differ per rank (a machine's cores): the one-process dataset.
    let (ok, _, stderr) = neurotac_per_rank(
        &mpirun,
        &[
            strs(&simulate(&sim, "1", "1")),
            strs(&simulate(&sim, "1", "2")),
        ],
    );
    assert!(ok, "{stderr}");
    let one = dir.path().join("one");
    let (ok, _, stderr) = neurotac(&strs(&simulate(&one, "1", "2")));
    assert!(ok, "{stderr}");
    assert!(read(&one.join("artificial.bin")) == read(&sim.join("artificial.bin")));
}

#[test]
fn a_rank_killed_mid_run_leaves_no_dataset_behind() {
    let Some(mpirun) = mpirun() else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("killed");
    let marker = dir.path().to_str().unwrap().to_owned();
    let mut child = mpirun_command(&mpirun, dir.path(), 2, &strs(&simulate_args(&out, 40, &[])))
        .env("NEUROTAC_TEST_MARKER", &marker)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Find rank 1 by its environment and kill it once it runs.
    let start = Instant::now();
    let victim = loop {
        if let Some(pid) = find_rank(&marker, 1) {
            break pid;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "rank 1 never started"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    std::thread::sleep(Duration::from_millis(700));
    let killed = std::process::Command::new("kill")
        .args(["-9", &victim.to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert!(
        !status.success(),
        "mpirun reported success after a rank was killed"
    );
    assert!(!out.join("artificial.bin").exists());
    assert!(!out.join("artificial.json").exists());
}

/// The pid of the process with `NEUROTAC_TEST_MARKER=marker` and `OMPI_COMM_WORLD_RANK=rank`.
fn find_rank(marker: &str, rank: usize) -> Option<u32> {
    let want = [
        format!("NEUROTAC_TEST_MARKER={marker}"),
        format!("OMPI_COMM_WORLD_RANK={rank}"),
    ];
    std::fs::read_dir("/proc").ok()?.flatten().find_map(|e| {
        let pid: u32 = e.file_name().to_str()?.parse().ok()?;
        let env = std::fs::read(e.path().join("environ")).ok()?;
        let vars: Vec<&[u8]> = env.split(|&b| b == 0).collect();
        let comm = std::fs::read_to_string(e.path().join("comm")).ok()?;
        (comm.trim() == "neurotac" && want.iter().all(|w| vars.contains(&w.as_bytes())))
            .then_some(pid)
    })
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            files.extend(walk(&p));
        } else {
            files.push(p);
        }
    }
    files
}
