//! `neurotac`: the command-line tool of neurotac. Each command lives in its own module of
//! [`cli`]; errors become one line on stderr and a non-zero exit code.
//!
//! When stdout (or stderr) is closed early — `neurotac neuron … | head -1` — every command exits
//! quietly, as `cat` or `head` would: SIGPIPE keeps its default action (the Rust runtime ignores
//! it, which turns the next write into an `EPIPE` error and `println!` into a panic).

mod cli;

use clap::Parser;
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
    let args = cli::Cli::parse();
    match cli::run(args, &neurotac_core::OneProcess) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
