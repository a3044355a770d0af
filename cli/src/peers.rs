//! Same-run comparisons against peer simulators (Brian2), as ratios.
//!
//! `benches/peers/brian2_bench.py` runs the very cases of [`crate::bench`] in Brian2's C++
//! standalone mode and prints its simulation-loop time. It needs a Python with Brian2 (e.g.
//! `python -m venv v && v/bin/pip install brian2 "numpy<2"`) and a C++ compiler; neurotac
//! itself never needs Python.
//!
//! A comparison is like for like: the peer runs at the same precision
//! ([`brian2_precision`]) with the same integration method ([`brian2_method`]), both sides
//! say what they ran, and [`PeerResult::matches`] refuses a ratio when they differ.

use neurotac_experiments::neuron_setup::{NeuronKind, Precision};
use neurotac_neurons::Integrator;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where the peer script lives in a checkout of neurotac.
pub fn brian2_script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../benches/peers/brian2_bench.py")
}

/// Brian2's name of `precision` (its `prefs.core.default_float_dtype`).
pub fn brian2_precision(precision: Precision) -> &'static str {
    match precision {
        Precision::F32 => "float32",
        Precision::F64 => "float64",
    }
}

/// The method the Brian2 script runs for `model` integrated as neurotac's `integrator` does,
/// named as neurotac names it (the script maps it to Brian2's: `exact`, `euler`, Heun's method
/// for `rk2` — Brian2's own `rk2` is the midpoint method —, `rk4`, `exponential_euler` for
/// LIF's `exp-euler`), or why Brian2 has none.
pub fn brian2_method(model: NeuronKind, integrator: Integrator) -> Result<&'static str, PeerError> {
    let why = match (model, integrator) {
        (NeuronKind::Izhikevich, Integrator::Izhikevich2003) => {
            "Izhikevich's 2003 scheme (two half steps of v, then u from the new v)"
        }
        (NeuronKind::Izhikevich, Integrator::ExponentialEuler) => {
            "exp-euler for Izhikevich (Brian2's exponential_euler needs equations linear in \
             their own variable; v is quadratic)"
        }
        _ => return Ok(integrator.name()),
    };
    Err(PeerError::NoCounterpart {
        what: why,
        model: model.name(),
    })
}

/// A peer measurement.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PeerResult {
    /// Peer name and version.
    pub peer: String,
    /// The precision the peer ran at, as it reports it (`float32`, `float64`); `None` from a
    /// script that does not say.
    #[serde(default)]
    pub precision: Option<String>,
    /// The integration method the peer ran, named as neurotac names it; `None` from a script
    /// that does not say.
    #[serde(default)]
    pub method: Option<String>,
    /// Simulation-loop wall time (s), compilation excluded.
    pub run_s: f64,
    /// Spikes the peer fired (a sanity check that it ran the same case).
    pub spikes: u64,
}

impl PeerResult {
    /// `Ok` when the peer ran at `precision` with `method`; otherwise the line that says what
    /// differs, printed instead of a ratio.
    pub fn matches(&self, precision: &str, method: &str) -> Result<(), String> {
        let said = |x: &Option<String>| x.clone().unwrap_or_else(|| "unstated".into());
        let (p, m) = (said(&self.precision), said(&self.method));
        if p == precision && m == method {
            Ok(())
        } else {
            Err(format!(
                "no ratio: {} ran {p} / {m}, neurotac {precision} / {method}",
                self.peer
            ))
        }
    }
}

impl AsRef<PeerResult> for PeerResult {
    fn as_ref(&self) -> &PeerResult {
        self
    }
}

/// A peer's run of the Song–Abbott STDP network (`brian2_bench.py stdp`): the measurement and
/// what the run ended with.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StdpPeerResult {
    /// The measurement (`spikes`: the output neuron's).
    #[serde(flatten)]
    pub run: PeerResult,
    /// Final weight of each input's synapse (mV).
    pub weights: Vec<f64>,
    /// The output neuron's spike times (s).
    pub spike_times_s: Vec<f64>,
}

impl AsRef<PeerResult> for StdpPeerResult {
    fn as_ref(&self) -> &PeerResult {
        &self.run
    }
}

/// A peer that could not be run.
#[derive(Debug, thiserror::Error)]
pub enum PeerError {
    /// The peer has no method that integrates as the chosen integrator does.
    #[error(
        "Brian2 has no counterpart of {what}, so no like-for-like comparison: choose \
         --integrator euler, rk2 or rk4 for {model}, or drop --brian2"
    )]
    NoCounterpart {
        /// The integrator and why.
        what: &'static str,
        /// The model.
        model: &'static str,
    },
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

/// Runs the Brian2 script with `args` under `python` and reads the JSON object it prints last
/// (a [`PeerResult`], or more, e.g. [`StdpPeerResult`]).
pub fn run_brian2<T: DeserializeOwned>(python: &Path, args: &[String]) -> Result<T, PeerError> {
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
    serde_json::from_str(last).map_err(|_| {
        let mut shown: String = last.chars().take(200).collect();
        if shown.len() < last.len() {
            shown.push('…');
        }
        PeerError::Output(shown)
    })
}
