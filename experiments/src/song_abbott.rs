//! Song, Miller & Abbott (Nat. Neurosci. 2000), Fig. 1: Poisson inputs onto one LIF neuron
//! through additively plastic synapses ([`Stdp`]); the weights leave their uniform start for
//! both bounds and the output rate settles.
//!
//! The network is the current-based counterpart of Brian2's documented STDP example
//! (`examples/synapses/STDP.py`, conductance-based), so that Brian2 can run the very same
//! equations (`neurotac bench stdp --brian2`):
//!
//! ```text
//! τ_m dv/dt = (v_rest − v) + I       v ≥ v_th ⇒ v ← v_reset        (LIF, exact step, f64)
//! τ_syn dI/dt = −I                   I ← I + w_i at each spike of input i (one-step delay)
//! additive STDP, all-to-all traces, τ₊ = τ₋ = 20 ms, a₊ = 0.01·w_max, a₋ = 1.05·a₊
//! ```
//!
//! | quantity | value | from the Brian2 example |
//! |---|---|---|
//! | τ_m, v_rest, v_th, v_reset | 10 ms, −74, −54, −60 mV | the same (`taum`, `El`, `vt`, `vr`) |
//! | τ_syn | 5 ms | `taue` |
//! | w_max ([`W_MAX_MV`]) | 0.6 mV | `gmax·(E_e − v_reset)` = 0.01 · (0 − (−60)) mV: the current a conductance `gmax` drives at the reset potential |
//! | a₊, a₋ | 0.01·w_max, 0.0105·w_max | `dApre = 0.01·gmax`, `dApost = −1.05·dApre` |
//! | inputs | 1000 Poisson at 15 Hz, all-to-all | `N`, `F` |
//! | initial weights | uniform in [0, w_max) from the seed | `rand()·gmax` |
//! | duration, dt | 100 s, 0.1 ms | the same |
//!
//! ```no_run
//! use neurotac_experiments::song_abbott::{SongAbbottConfig, run};
//! let r = run(&SongAbbottConfig { duration_s: 20.0, ..SongAbbottConfig::default() })?;
//! println!("{} output spikes; {:?}", r.spike_times_s.len(), r.bounds());
//! # Ok::<(), neurotac_experiments::ExperimentError>(())
//! ```

use crate::ExperimentError;
use crate::statistics::{KolmogorovSmirnov, kolmogorov_smirnov};
use neurotac_core::seed_hash::splitmix64;
use neurotac_core::{
    Connectivity, ExpSynapse, GraphError, NetworkBuilder, NetworkConfig, OneProcess, PoissonInput,
    ProjectionId, ReadoutId, SpikeRecorder, Stdp, Synapse,
};
use neurotac_neurons::{InitialPotential, Integrator, Lif, LifParams};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

/// The upper bound of the weights, w_max = gmax·(E_e − v_reset) = 0.01 · 60 mV (mV).
pub const W_MAX_MV: f64 = 0.6;

/// Time constant of the synaptic current, τ_syn (s).
pub const TAU_SYN_S: f64 = 5e-3;

/// A weight "near a bound" lies within this fraction of `w_max` of it.
pub const NEAR_BOUND: f64 = 0.1;

/// The output neuron (mV): τ_m = 10 ms, v_rest = −74, v_th = −54, v_reset = −60, no
/// refractory period.
pub fn neuron_params() -> LifParams {
    LifParams {
        tau_m_s: 10e-3,
        v_rest: -74.0,
        v_th: -54.0,
        v_reset: -60.0,
        ..LifParams::default()
    }
}

/// The plasticity: additive, all-to-all, τ₊ = τ₋ = 20 ms, a₊ = 0.01·w_max, a₋ = 0.0105·w_max,
/// weights in [0, [`W_MAX_MV`]].
pub fn stdp_rule() -> Stdp {
    Stdp::additive(20e-3, 20e-3, 0.01 * W_MAX_MV, 0.0105 * W_MAX_MV, W_MAX_MV)
}

/// What to run (defaults: the Brian2 example's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SongAbbottConfig {
    /// Poisson inputs (default 1000).
    pub inputs: usize,
    /// Their rate (Hz, default 15).
    pub rate_hz: f64,
    /// Simulated duration (s, default 100).
    pub duration_s: f64,
    /// Time step (s, default 0.1 ms).
    pub dt_s: f64,
    /// Seed of the initial weights and of the inputs (default 1).
    pub seed: u64,
}

impl Default for SongAbbottConfig {
    fn default() -> Self {
        Self {
            inputs: 1000,
            rate_hz: 15.0,
            duration_s: 100.0,
            dt_s: 1e-4,
            seed: 1,
        }
    }
}

/// The network of a [`SongAbbottConfig`], described but not built.
pub struct SongAbbottNetwork {
    /// The builder: inputs `"inputs"`, neuron `"neuron"`, the plastic projection between them.
    pub builder: NetworkBuilder,
    /// The plastic projection (read its weights with
    /// [`Network::weights`](neurotac_core::Network::weights)).
    pub projection: ProjectionId,
    /// The output neuron's spikes.
    pub spikes: ReadoutId<SpikeRecorder>,
}

/// The initial weights, uniform in `[0, w_max)`, drawn from `seed` (ChaCha8).
pub fn initial_weights(inputs: usize, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..inputs)
        .map(|_| W_MAX_MV * rng.random::<f64>())
        .collect()
}

/// Builds the description of the network (see the [module docs](self)). The inputs are drawn
/// from a seed derived from `config.seed`, the initial weights from `config.seed` itself.
pub fn network(config: &SongAbbottConfig) -> Result<SongAbbottNetwork, GraphError> {
    let mut builder = NetworkBuilder::new();
    let inputs = builder.add_spike_input(
        "inputs",
        PoissonInput::new(config.inputs, config.rate_hz, splitmix64(config.seed)),
    )?;
    let neuron = builder.add_population(
        "neuron",
        Lif::<f64>::new(1, neuron_params())
            .with_integrator(Integrator::Exact)
            .with_initial_potential(InitialPotential::Constant(neuron_params().v_rest)),
    )?;
    let synapses = initial_weights(config.inputs, config.seed)
        .into_iter()
        .enumerate()
        .map(|(i, weight)| Synapse {
            pre: i as u32,
            post: 0,
            weight,
        })
        .collect();
    // A spike of step k reaches the neuron in step k + 1, acting on v from then on and on the
    // weights at that arrival, as a spike does in Brian2 whose pathway runs before the groups.
    let projection = builder.connect_plastic(
        inputs,
        neuron,
        Connectivity::Sparse(synapses),
        ExpSynapse::new(TAU_SYN_S).with_delay(1),
        stdp_rule(),
    )?;
    let spikes = builder.record_spikes(neuron)?;
    Ok(SongAbbottNetwork {
        builder,
        projection,
        spikes,
    })
}

/// What a run ended with.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SongAbbottRun {
    /// Weight of each input's synapse at the end (mV), by input.
    pub weights: Vec<f64>,
    /// The output neuron's spike times (s).
    pub spike_times_s: Vec<f64>,
    /// Simulated duration (s).
    pub duration_s: f64,
    /// Wall time to build the network (s).
    pub build_s: f64,
    /// Wall time of the simulation loop (s).
    pub run_s: f64,
}

/// Builds and runs the network of `config` with learning on.
pub fn run(config: &SongAbbottConfig) -> Result<SongAbbottRun, ExperimentError> {
    // The rate, dt and duration are checked by the network (build and run).
    if config.inputs == 0 {
        return Err(ExperimentError::InvalidParameter {
            what: "inputs",
            value: 0.0,
            expected: "at least 1",
        });
    }
    let start = Instant::now();
    let SongAbbottNetwork {
        builder,
        projection,
        spikes,
    } = network(config)?;
    let mut net = builder.build(NetworkConfig { dt_s: config.dt_s })?;
    let build_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let summary = net.run(config.duration_s, &OneProcess)?;
    let run_s = start.elapsed().as_secs_f64();
    let weights = net.weights(projection)?;
    let mut by_input = vec![0.0; config.inputs];
    for (&i, &w) in weights.pre.iter().zip(&weights.weight) {
        by_input[i as usize] = w;
    }
    Ok(SongAbbottRun {
        weights: by_input,
        spike_times_s: net.readout(spikes)?.spikes().iter().map(|s| s.1).collect(),
        duration_s: summary.steps as f64 * config.dt_s,
        build_s,
        run_s,
    })
}

impl SongAbbottRun {
    /// The shares of the final weights near each bound.
    pub fn bounds(&self) -> BoundFractions {
        BoundFractions::of(&self.weights)
    }

    /// The output rate in the last tenth of the run (Hz): where it settled.
    pub fn final_rate_hz(&self) -> f64 {
        final_rate_hz(&self.spike_times_s, self.duration_s)
    }
}

/// The output rate in the last tenth of `[0, duration_s)`, the window `[0.9·T, T)` (Hz): a
/// spike stamped at `T` or later (after the run) is not counted.
pub fn final_rate_hz(spike_times_s: &[f64], duration_s: f64) -> f64 {
    let from = 0.9 * duration_s;
    let window = from..duration_s;
    spike_times_s.iter().filter(|t| window.contains(t)).count() as f64 / (duration_s - from)
}

/// The output rate in consecutive bins of `bin_s` over `[0, duration_s)`: `(bin centre s,
/// rate Hz)`, the last bin cut at `duration_s`.
pub fn rate_over_time(spike_times_s: &[f64], duration_s: f64, bin_s: f64) -> Vec<(f64, f64)> {
    let bins = (duration_s / bin_s).ceil().max(1.0) as usize;
    let mut counts = vec![0usize; bins];
    for &t in spike_times_s {
        if (0.0..duration_s).contains(&t) {
            counts[((t / bin_s) as usize).min(bins - 1)] += 1;
        }
    }
    counts
        .iter()
        .enumerate()
        .map(|(k, &n)| {
            let (lo, hi) = (k as f64 * bin_s, ((k + 1) as f64 * bin_s).min(duration_s));
            ((lo + hi) / 2.0, n as f64 / (hi - lo))
        })
        .collect()
}

/// Counts of `weights` in `bins` equal bins over `[0, w_max]` (w_max in the last bin).
pub fn histogram(weights: &[f64], bins: usize) -> Vec<usize> {
    let mut counts = vec![0usize; bins.max(1)];
    let last = counts.len() - 1;
    for &w in weights {
        let k = (w / W_MAX_MV * counts.len() as f64)
            .floor()
            .clamp(0.0, last as f64);
        counts[k as usize] += 1;
    }
    counts
}

/// The shares of a set of weights near each bound (within [`NEAR_BOUND`]`·w_max`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BoundFractions {
    /// Share of the weights in `[0, 0.1·w_max]`.
    pub near_zero: f64,
    /// Share of the weights in `[0.9·w_max, w_max]`.
    pub near_max: f64,
}

impl BoundFractions {
    /// The shares of `weights` (both 0 for none).
    pub fn of(weights: &[f64]) -> Self {
        let n = weights.len().max(1) as f64;
        let share =
            |near: &dyn Fn(f64) -> bool| weights.iter().filter(|&&w| near(w)).count() as f64 / n;
        Self {
            near_zero: share(&|w| w <= NEAR_BOUND * W_MAX_MV),
            near_max: share(&|w| w >= (1.0 - NEAR_BOUND) * W_MAX_MV),
        }
    }
}

/// Two runs' final weights compared: the KS test and each side's shares near the bounds.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WeightComparison {
    /// Two-sample Kolmogorov–Smirnov test of the two sets of final weights.
    pub ks: KolmogorovSmirnov,
    /// Shares near the bounds of the first set.
    pub ours: BoundFractions,
    /// Shares near the bounds of the second set.
    pub peer: BoundFractions,
}

/// Compares two sets of final weights (see [`WeightComparison`]).
pub fn compare_weights(ours: &[f64], peer: &[f64]) -> Result<WeightComparison, ExperimentError> {
    Ok(WeightComparison {
        ks: kolmogorov_smirnov(ours, peer)?,
        ours: BoundFractions::of(ours),
        peer: BoundFractions::of(peer),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_final_rate_counts_the_window_before_the_end_only() {
        // A neuron spiking every step of dt = 0.1 ms for 1 s, and once more at t = T.
        let dt = 1e-4;
        let times: Vec<f64> = (0..=10_000).map(|k| k as f64 * dt).collect();
        let rate = final_rate_hz(&times, 1.0);
        assert!(
            (9_990.0..=10_000.0 * (1.0 + 1e-12)).contains(&rate),
            "{rate} Hz at dt = 0.1 ms"
        );
        assert_eq!(final_rate_hz(&[1.0, 1.5], 1.0), 0.0, "spikes at or after T");
        assert!((final_rate_hz(&[0.95], 1.0) - 10.0).abs() < 1e-9);
    }

    /// 60 s of the default network, long enough for the weights to split (release builds).
    fn learned() -> SongAbbottRun {
        run(&SongAbbottConfig {
            duration_s: 60.0,
            ..SongAbbottConfig::default()
        })
        .unwrap()
    }

    #[test]
    fn the_weights_leave_their_uniform_start_for_both_bounds_and_stay_inside_them() {
        let r = learned();
        assert_eq!(r.weights.len(), 1000);
        assert!(
            r.weights.iter().all(|w| (0.0..=W_MAX_MV).contains(w)),
            "a weight left [0, w_max]"
        );
        // Uniform weights put a tenth in each decile; learned ones pile up at both ends (a
        // U-shaped, bimodal histogram) and leave the middle.
        let h = histogram(&r.weights, 10);
        let middle = *h[3..7].iter().max().unwrap();
        assert!(h[0] > 2 * middle && h[9] > middle, "{h:?}");
        let b = r.bounds();
        let start = BoundFractions::of(&initial_weights(1000, 1));
        assert!(b.near_zero > 2.0 * start.near_zero, "{b:?} from {start:?}");
        assert!(b.near_max > start.near_max, "{b:?} from {start:?}");
        // The output rate falls from its start as the weights split.
        let first = rate_over_time(&r.spike_times_s, r.duration_s, 6.0)[0].1;
        assert!(
            r.final_rate_hz() < 0.7 * first,
            "{first} → {}",
            r.final_rate_hz()
        );
    }

    #[test]
    fn a_frozen_projection_keeps_its_initial_weights() {
        let config = SongAbbottConfig {
            duration_s: 5.0,
            ..SongAbbottConfig::default()
        };
        let SongAbbottNetwork {
            builder,
            projection,
            spikes,
        } = network(&config).unwrap();
        let mut net = builder.build(NetworkConfig { dt_s: config.dt_s }).unwrap();
        net.set_learning(projection, false).unwrap();
        net.run(config.duration_s, &OneProcess).unwrap();
        assert!(
            !net.readout(spikes).unwrap().spikes().is_empty(),
            "the neuron fired"
        );
        let w = net.weights(projection).unwrap();
        assert_eq!(w.pre, (0..1000).collect::<Vec<u32>>());
        assert_eq!(w.weight, initial_weights(1000, config.seed));
    }

    #[test]
    fn rates_and_histograms_count_every_spike_and_weight_once() {
        let rates = rate_over_time(&[0.1, 0.2, 1.5, 2.4], 2.5, 1.0);
        assert_eq!(rates, vec![(0.5, 2.0), (1.5, 1.0), (2.25, 2.0)]);
        assert_eq!(final_rate_hz(&[0.1, 9.5, 9.9], 10.0), 2.0);
        assert_eq!(histogram(&[0.0, 0.3, W_MAX_MV, W_MAX_MV], 2), vec![1, 3]);
        let b = BoundFractions::of(&[0.0, 0.06, 0.3, 0.54, 0.6]);
        assert_eq!((b.near_zero, b.near_max), (0.4, 0.4));
    }
}
