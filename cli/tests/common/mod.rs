//! Runs the `neurotac` binary of this build.
#![allow(dead_code)] // each test file uses what it needs

use std::path::Path;
use std::process::Command;

/// `(success, stdout, stderr)` of `neurotac ARGS`.
pub fn neurotac(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_neurotac"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A small artificial `reproduce` (3 slides per texture, 12 epochs) into `out`, caching
/// datasets in `cache`, with `extra` arguments.
pub fn small_reproduce(out: &Path, cache: &Path, extra: &[&str]) -> (bool, String, String) {
    let (out, cache) = (out.to_str().unwrap(), cache.to_str().unwrap());
    let mut args = vec![
        "reproduce",
        "--set",
        "artificial",
        "--trials",
        "3",
        "--epochs",
        "12",
        "--tau-step",
        "30ms",
        "--out",
        out,
        "--cache",
        cache,
    ];
    args.extend_from_slice(extra);
    neurotac(&args)
}

/// The arguments of a one-slide artificial `simulate` into `out`, caching datasets in
/// `cache`.
pub fn small_simulate_args<'a>(out: &'a Path, cache: &'a Path) -> Vec<&'a str> {
    let (out, cache) = (out.to_str().unwrap(), cache.to_str().unwrap());
    vec![
        "simulate",
        "--set",
        "artificial",
        "--trials",
        "1",
        "--out",
        out,
        "--cache",
        cache,
    ]
}

/// A one-slide artificial `simulate` into `out` ([`small_simulate_args`]), with `extra`
/// arguments.
pub fn small_simulate(out: &Path, cache: &Path, extra: &[&str]) -> (bool, String, String) {
    let mut args = small_simulate_args(out, cache);
    args.extend_from_slice(extra);
    neurotac(&args)
}

/// `mpirun` when it is on the PATH (Open MPI), else `None` with the reason printed.
pub fn mpirun() -> Option<std::path::PathBuf> {
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join("mpirun"))
            .find(|p| p.is_file())
    });
    if found.is_none() {
        eprintln!(
            "skipped: mpirun is not installed (Debian: apt-get install openmpi-bin libopenmpi-dev)"
        );
    }
    found
}

/// `mpirun` allowed to run as root (as in CI), keeping its session files in `session`.
///
/// Each launch gets its own session folder: Open MPI 4 launches started at the same moment
/// race to create the shared `/tmp/ompi.HOST.UID` folder and one of them fails with
/// "mkdir … File exists", so tests running in parallel must not share it.
fn open_mpi(mpirun: &Path, session: &Path) -> Command {
    let mut c = Command::new(mpirun);
    c.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("TMPDIR", session)
        .arg("--oversubscribe");
    c
}

/// The `mpirun -n RANKS --oversubscribe neurotac ARGS` command, its Open MPI session files in
/// `session` (a folder that outlives the launch).
pub fn mpirun_command(mpirun: &Path, session: &Path, ranks: usize, args: &[&str]) -> Command {
    let mut c = open_mpi(mpirun, session);
    c.args(["-n", &ranks.to_string()])
        .arg(env!("CARGO_BIN_EXE_neurotac"))
        .args(args);
    c
}

/// `(success, stdout, stderr)` of `mpirun -n RANKS neurotac ARGS`.
pub fn neurotac_on_ranks(mpirun: &Path, ranks: usize, args: &[&str]) -> (bool, String, String) {
    let session = tempfile::tempdir().unwrap();
    let out = mpirun_command(mpirun, session.path(), ranks, args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `(success, stdout, stderr)` of an MPMD launch, one rank per entry of `per_rank`:
/// `mpirun -n 1 neurotac ARGS0 : -n 1 neurotac ARGS1 : …` (each rank its own command line).
pub fn neurotac_per_rank(mpirun: &Path, per_rank: &[Vec<&str>]) -> (bool, String, String) {
    let session = tempfile::tempdir().unwrap();
    let mut c = open_mpi(mpirun, session.path());
    for (rank, args) in per_rank.iter().enumerate() {
        if rank > 0 {
            c.arg(":");
        }
        c.args(["-n", "1"])
            .arg(env!("CARGO_BIN_EXE_neurotac"))
            .args(args);
    }
    let out = c.output().unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
