//! Same-run comparisons against peer simulators (Brian2), as ratios.
//!
//! `benches/peers/brian2_bench.py` runs the very cases of [`crate::bench`] in Brian2's C++
//! standalone mode and prints its simulation-loop time. It needs a Python with Brian2 (e.g.
//! `python -m venv v && v/bin/pip install brian2 "numpy<2"`) and a C++ compiler; neurotac
//! itself never needs Python.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where the peer script lives in a checkout of neurotac.
pub fn brian2_script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../benches/peers/brian2_bench.py")
}

/// A peer measurement.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PeerResult {
    /// Peer name and version.
    pub peer: String,
    /// Simulation-loop wall time (s), compilation excluded.
    pub run_s: f64,
    /// Spikes the peer fired (a sanity check that it ran the same case).
    pub spikes: u64,
}

/// A peer that could not be run.
#[derive(Debug, thiserror::Error)]
pub enum PeerError {
    /// The script is not where a checkout keeps it.
    #[error("peer script {0} not found (run from a checkout of neurotac)")]
    MissingScript(PathBuf),
    /// The interpreter could not be started.
    #[error("cannot run {python}")]
    Spawn {
        /// The interpreter.
        python: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The script failed.
    #[error("{python} {script} failed ({status}): {stderr}")]
    Failed {
        /// The interpreter.
        python: PathBuf,
        /// The script.
        script: PathBuf,
        /// Exit status.
        status: String,
        /// Last line of its standard error.
        stderr: String,
    },
    /// The script printed something else than the expected JSON.
    #[error("unexpected output from the Brian2 script: {0}")]
    Output(String),
}

/// Runs the Brian2 script with `args` under `python`.
pub fn run_brian2(python: &Path, args: &[String]) -> Result<PeerResult, PeerError> {
    let script = brian2_script();
    if !script.is_file() {
        return Err(PeerError::MissingScript(script));
    }
    let out = Command::new(python)
        .arg(&script)
        .args(args)
        .output()
        .map_err(|source| PeerError::Spawn {
            python: python.to_owned(),
            source,
        })?;
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        return Err(PeerError::Failed {
            python: python.to_owned(),
            script,
            status: out.status.to_string(),
            stderr: stderr.lines().last().unwrap_or("").to_owned(),
        });
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    let last = stdout.lines().last().unwrap_or("");
    serde_json::from_str(last).map_err(|_| PeerError::Output(last.to_owned()))
}
