//! Throughput benchmarks: neuron updates per second and the CUBA network.
//!
//! Both are the cases Brian2 is measured on, so the numbers compare directly (see the README's
//! performance section). Timing covers stepping only; building and allocation are reported
//! apart.

use crate::neuron_setup::{NeuronKind, NeuronSetup, Precision};
use crate::threads::{ThreadPoolError, with_threads};
use neurotac_core::{
    Connectivity, ExpSynapse, GraphError, ModelError, NetworkBuilder, NetworkConfig,
};
use neurotac_neurons::{InitialPotential, Integrator, Lif, LifParams};
use serde::Serialize;
use std::time::Instant;

/// A benchmark that could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The neuron model rejected its set-up.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The network could not be built.
    #[error(transparent)]
    Graph(#[from] GraphError),
    /// A parameter outside its domain.
    #[error("{what} = {value}: {expected}")]
    InvalidParameter {
        /// Which parameter.
        what: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
    /// The thread pool could not be created.
    #[error(transparent)]
    Threads(#[from] ThreadPoolError),
}

/// What a neuron-throughput run measured.
#[derive(Debug, Clone, Serialize)]
pub struct NeuronBenchResult {
    /// Model family.
    pub model: NeuronKind,
    /// Integrator name.
    pub integrator: &'static str,
    /// Precision.
    pub precision: Precision,
    /// Neurons.
    pub n: usize,
    /// Time step (s).
    pub dt_s: f64,
    /// Steps run.
    pub steps: u64,
    /// Threads used.
    pub threads: usize,
    /// Neuron updates: `n × steps`.
    pub updates: f64,
    /// Wall time of the stepping (s).
    pub wall_s: f64,
    /// `updates / wall_s`.
    pub updates_per_s: f64,
    /// `updates_per_s / threads`.
    pub updates_per_s_per_thread: f64,
    /// Spikes fired.
    pub spikes: u64,
}

/// Runs `n` benchmark neurons (LIF at `I = 1.04` or Izhikevich RS at `I = 10`, see
/// [`crate::neuron_setup`]) for `duration_s` at `dt_s` on `threads` threads (0 = all cores).
pub fn neuron_throughput(
    kind: NeuronKind,
    n: usize,
    duration_s: f64,
    dt_s: f64,
    precision: Precision,
    integrator: Option<Integrator>,
    threads: usize,
) -> Result<NeuronBenchResult, BenchError> {
    if !(duration_s.is_finite() && duration_s >= 0.0) {
        return Err(BenchError::InvalidParameter {
            what: "duration_s",
            value: duration_s,
            expected: "finite and ≥ 0",
        });
    }
    let setup = NeuronSetup {
        integrator: integrator.unwrap_or(kind.default_integrator()),
        ..NeuronSetup::benchmark(kind, precision)
    };
    let steps = (duration_s / dt_s).round() as u64;
    let (spikes, wall_s, used) = with_threads(threads, || {
        let r = setup.run_constant(n, kind.benchmark_current(), dt_s, steps);
        r.map(|(spikes, wall)| (spikes, wall, rayon::current_num_threads()))
    })??;
    let updates = n as f64 * steps as f64;
    let updates_per_s = updates / wall_s;
    Ok(NeuronBenchResult {
        model: kind,
        integrator: setup.integrator.name(),
        precision,
        n,
        dt_s,
        steps,
        threads: used,
        updates,
        wall_s,
        updates_per_s,
        updates_per_s_per_thread: updates_per_s / used as f64,
        spikes,
    })
}

/// The CUBA benchmark network (Vogels & Abbott 2005 as in Brian2's example and benchmarks):
/// 4000 LIF neurons, 80 % excitatory / 20 % inhibitory, 2 % random connectivity, exponential
/// current synapses.
///
/// `τ_m dv/dt = (E_l − v) + g_e + g_i`, τ_m = 20 ms, E_l = −49 mV, threshold −50 mV, reset
/// −60 mV, refractory 5 ms; `τ_e = 5 ms`, `τ_i = 10 ms`, `w_e = 1.62 mV`, `w_i = −9 mV`;
/// `v₀` uniform in [−60, −50) mV; one-step synaptic delay (a spike acts on the next step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubaConfig {
    /// Excitatory neurons (3200).
    pub n_exc: usize,
    /// Inhibitory neurons (800).
    pub n_inh: usize,
    /// Connection probability (0.02).
    pub probability: f64,
    /// Simulated duration (s, default 1).
    pub duration_s: f64,
    /// Time step (s, default 0.1 ms).
    pub dt_s: f64,
    /// Seed of connectivity and initial potentials.
    pub seed: u64,
}

impl Default for CubaConfig {
    fn default() -> Self {
        Self {
            n_exc: 3200,
            n_inh: 800,
            probability: 0.02,
            duration_s: 1.0,
            dt_s: 1e-4,
            seed: 1,
        }
    }
}

/// What a CUBA run measured.
#[derive(Debug, Clone, Serialize)]
pub struct CubaResult {
    /// Neurons.
    pub neurons: usize,
    /// Synapses.
    pub synapses: usize,
    /// Simulated time (s).
    pub duration_s: f64,
    /// Wall time to build the network, connectivity included (s).
    pub build_s: f64,
    /// Wall time of the run (s).
    pub run_s: f64,
    /// Run wall time per simulated second.
    pub wall_s: f64,
    /// Spikes fired.
    pub spikes: usize,
    /// Mean firing rate (Hz).
    pub rate_hz: f64,
}

/// Builds and runs the CUBA network.
pub fn cuba(config: CubaConfig) -> Result<CubaResult, BenchError> {
    let start = Instant::now();
    let params = LifParams {
        tau_m_s: 0.02,
        v_rest: -49.0,
        v_th: -50.0,
        v_reset: -60.0,
        t_ref_s: 5e-3,
        v_min: f64::NEG_INFINITY,
    };
    let population = |n: usize, seed: u64| {
        Lif::<f64>::new(n, params)
            .with_integrator(Integrator::Exact)
            .with_initial_potential(InitialPotential::Uniform {
                low: -60.0,
                high: -50.0,
                seed,
            })
    };
    let mut b = NetworkBuilder::new();
    let exc = b.add_population("excitatory", population(config.n_exc, config.seed))?;
    let inh = b.add_population(
        "inhibitory",
        population(config.n_inh, config.seed.wrapping_add(1)),
    )?;
    let (e_syn, i_syn) = (ExpSynapse::new(5e-3), ExpSynapse::new(10e-3));
    for (k, (pre, post, weight, syn)) in [
        (exc, exc, 1.62, e_syn),
        (exc, inh, 1.62, e_syn),
        (inh, exc, -9.0, i_syn),
        (inh, inh, -9.0, i_syn),
    ]
    .into_iter()
    .enumerate()
    {
        let seed = config.seed.wrapping_mul(31).wrapping_add(k as u64 + 2);
        b.connect(
            pre,
            post,
            Connectivity::Random {
                probability: config.probability,
                weight,
                seed,
            },
            syn,
        )?;
    }
    let (re, ri) = (b.record_spikes(exc)?, b.record_spikes(inh)?);
    let mut net = b.build(NetworkConfig { dt_s: config.dt_s })?;
    let build_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let summary = net.run(config.duration_s)?;
    let run_s = start.elapsed().as_secs_f64();
    let spikes = net.readout(re).spikes().len() + net.readout(ri).spikes().len();
    let neurons = config.n_exc + config.n_inh;
    let simulated = summary.steps as f64 * config.dt_s;
    Ok(CubaResult {
        neurons,
        synapses: net.n_synapses(),
        duration_s: simulated,
        build_s,
        run_s,
        wall_s: run_s / simulated,
        spikes,
        rate_hz: spikes as f64 / neurons as f64 / simulated,
    })
}
