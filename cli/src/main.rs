//! `neurotac`: the command-line tool of neurotac. Each command lives in its own module of
//! [`cli`]; errors become one line on stderr and a non-zero exit code.
//!
//! When stdout (or stderr) is closed early — `neurotac neuron … | head -1` — every command exits
//! quietly, as `cat` or `head` would: SIGPIPE keeps its default action (the Rust runtime ignores
//! it, which turns the next write into an `EPIPE` error and `println!` into a panic).

mod commands;

use clap::{CommandFactory, FromArgMatches};
use neurotac_cluster::{Cluster, ClusterError};
use neurotac_core::Ranks;
use std::process::ExitCode;

/// Restores the default action of SIGPIPE (terminate quietly) before anything is written.
fn exit_quietly_on_closed_pipes() {
    #[cfg(unix)]
    // SAFETY: called first thing in `main`, before any other thread exists; SIG_DFL is a valid
    // disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    exit_quietly_on_closed_pipes();
    let matches = commands::Cli::command().get_matches();
    let args = commands::Cli::from_arg_matches(&matches)
        .map_err(|e| e.format(&mut commands::Cli::command()))
        .unwrap_or_else(|e| e.exit());
    let cluster = match Cluster::from_environment() {
        Ok(cluster) => cluster,
        Err(e) => {
            // Every rank of the launch finds the same; rank 0 says it once.
            if neurotac_cluster::launcher_ranks().is_none_or(|(rank, _)| rank == 0) {
                eprintln!("error: {e}");
            }
            return ExitCode::FAILURE;
        }
    };
    // Before any work, the ranks check that they run one computation (the same command and
    // options on the same data). Every rank finds the same difference: rank 0 says it, and
    // every rank stops, ending MPI cleanly.
    if cluster.size() > 1 {
        match cluster.agree_on(&commands::run_digest(&matches)) {
            Ok(()) => {}
            Err(e @ ClusterError::Disagree(_)) => {
                if cluster.is_root() {
                    eprintln!("error: {e}");
                }
                return ExitCode::FAILURE;
            }
            Err(e) => fail_on_ranks(&cluster, &e.into()),
        }
    }
    match commands::run(args, &cluster) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if cluster.size() == 1 => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
        Err(e) => fail_on_ranks(&cluster, &e),
    }
}

/// A failure on one of several ranks. Rank 0 prints the error and ends the whole group (the
/// others may be waiting for it in a collective). Bad input fails every rank alike, so another
/// rank first gives rank 0 a moment to do that, and prints its own error only if the group
/// still runs (it failed alone), then ends the group.
fn fail_on_ranks(cluster: &Cluster, e: &anyhow::Error) -> ! {
    if cluster.is_root() {
        eprintln!("error: {e:#}");
    } else {
        std::thread::sleep(std::time::Duration::from_secs(2));
        eprintln!(
            "error (rank {} of {}): {e:#}",
            cluster.rank(),
            cluster.size()
        );
    }
    cluster.abort(1)
}
