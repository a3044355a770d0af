//! A build without the `mpi` feature started by `mpirun` with several ranks refuses to run the
//! job once per rank: one line from rank 0, a non-zero exit, nothing written.
#![cfg(not(feature = "mpi"))]

mod common;

use common::{mpirun, neurotac_on_ranks, small_simulate_args};

#[test]
fn without_the_mpi_feature_mpirun_gets_one_clear_line_and_no_output() {
    let Some(mpirun) = mpirun() else { return };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sim");
    let cache = dir.path().join("cache");
    let args = small_simulate_args(&out, &cache);
    let (ok, stdout, stderr) = neurotac_on_ranks(&mpirun, 2, &args);
    assert!(!ok, "{stdout}");
    let ours: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(ours.len(), 1, "{stderr}");
    assert!(ours[0].contains("built without MPI"), "{stderr}");
    assert!(ours[0].contains("--features mpi"), "{stderr}");
    assert!(!out.join("artificial.bin").exists());
}
