//! Throughput benchmarks: neuron updates per second, the afferent pipeline at a given activity
//! (clock-driven against event-driven, [`afferent_activity`]) and the CUBA network.
//!
//! Both are the cases Brian2 is measured on, so the numbers compare directly (see the README's
//! performance section). Timing covers stepping only; building and allocation are reported
//! apart.

use crate::budget::{self, BudgetError};
use neurotac_core::ranks::all_gather_f64;
use neurotac_core::{
    Connectivity, Crossovers, ExpSynapse, GraphError, ModelError, MultiSpikeTrain, Network,
    NetworkBuilder, NetworkConfig, PopulationId, PopulationStepping, Ranks, RanksError, ReadoutId,
    SpikeArrayInput, SpikeRecorder, Stepping,
};
use neurotac_experiments::afferents::{AfferentConfig, afferent_population};
use neurotac_experiments::neuron_setup::{NeuronKind, NeuronSetup, Precision};
use neurotac_experiments::threads::{ThreadPoolError, with_threads};
use neurotac_neurons::{InitialPotential, Integrator, Lif, LifParams, Real};
use rand::{RngExt, SeedableRng};
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
    #[error("{what} = {}: {expected}", neurotac_core::Compact(*value))]
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
    /// A collective operation between ranks failed.
    #[error(transparent)]
    Ranks(#[from] RanksError),
    /// More work or memory than a stated limit, or no step at all.
    #[error(transparent)]
    Budget(#[from] BudgetError),
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
/// [`neurotac_experiments::neuron_setup`]) for `duration_s` at `dt_s` on `threads` threads (0 = all cores).
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
    let steps = budget::steps(duration_s, dt_s)?;
    budget::population("--n", n, steps)?;
    let setup = NeuronSetup {
        integrator: integrator.unwrap_or(kind.default_integrator()),
        ..NeuronSetup::benchmark(kind, precision)
    };
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

/// `n` taxel trains of which the fraction `active` (evenly spaced, at least one when
/// `active > 0`) fire as Poisson processes at `rate_hz` over `duration_s`, seeded; the others
/// are silent.
pub fn activity_taxels(
    n: usize,
    active: f64,
    rate_hz: f64,
    duration_s: f64,
    seed: u64,
) -> MultiSpikeTrain {
    let n_active =
        ((active.clamp(0.0, 1.0) * n as f64).round() as usize).max(usize::from(active > 0.0));
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let channels: Vec<Vec<f64>> = (0..n)
        .map(|c| {
            let mut train = Vec::new();
            // Channel c is active when it is the first of its share of n / n_active channels.
            if n_active > 0 && (c * n_active) % n < n_active && rate_hz > 0.0 {
                let mut t = -(1.0 - rng.random::<f64>()).ln() / rate_hz;
                while t < duration_s {
                    train.push(t);
                    t += -(1.0 - rng.random::<f64>()).ln() / rate_hz;
                }
            }
            train
        })
        .collect();
    MultiSpikeTrain::from_channels(channels).expect("sorted finite Poisson times")
}

/// Runs of each mode in [`afferent_activity`]; the fastest counts.
pub const ACTIVITY_REPEATS: usize = 5;

/// One stepping mode of [`afferent_activity`] (its fastest of [`ACTIVITY_REPEATS`] runs).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ActivityRun {
    /// Wall time of the run (s; building excluded).
    pub wall_s: f64,
    /// Neuron updates done ([`neurotac_core::Network::neuron_updates`]).
    pub updates: u64,
    /// Effective throughput: `n × steps / wall_s` (the clock-driven work done per second).
    pub effective_updates_per_s: f64,
    /// Afferent spikes.
    pub spikes: usize,
}

/// What [`afferent_activity`] measured.
#[derive(Debug, Clone, Serialize)]
pub struct ActivityBenchResult {
    /// The afferent model: "lif" (exact) or "izhikevich" (RS, Izhikevich's 2003 scheme).
    pub model: &'static str,
    /// Taxels (= afferents).
    pub n: usize,
    /// Fraction of taxels firing.
    pub active_fraction: f64,
    /// Their Poisson rate (Hz).
    pub rate_hz: f64,
    /// Time step (s).
    pub dt_s: f64,
    /// Steps run.
    pub steps: u64,
    /// Every neuron updated every step.
    pub clock_driven: ActivityRun,
    /// Only neurons with synaptic input updated.
    pub event_driven: ActivityRun,
    /// Each mode chosen from the measured activity ([`Stepping::Auto`]).
    pub automatic: ActivityRun,
    /// `clock_driven.wall_s / event_driven.wall_s`.
    pub speedup: f64,
    /// `automatic.wall_s` over the faster fixed mode's wall time.
    pub automatic_ratio: f64,
    /// The afferents' stepping at the end of the automatic run: its mode, crossover, mean
    /// activity and switches.
    pub automatic_stepping: PopulationStepping,
    /// The afferents' mean activity (fraction with synaptic current per step) counted in the
    /// event-driven run, every step.
    pub measured_activity: f64,
    /// All three runs gave the same spikes (same neurons, same times).
    pub identical_spikes: bool,
}

/// The afferent pipeline's network: `taxels` → the afferents of `config` (exponential
/// synapses, τ 5 ms and the model's weight; its default integrator, f64: [`AfferentConfig::of`])
/// → spike recorder, stepped as `stepping`, at step `dt_s`, built for `ranks`
/// ([`NetworkBuilder::build_partitioned`]: the taxels replicated, the afferents split into
/// blocks; `&OneProcess` for one process); run it with [`Network::run`] on that group. Every
/// rank's recorder ends with every afferent's spikes.
pub fn afferent_network(
    taxels: &MultiSpikeTrain,
    config: AfferentConfig,
    dt_s: f64,
    stepping: Stepping,
    ranks: &dyn Ranks,
) -> Result<(Network, ReadoutId<SpikeRecorder>), GraphError> {
    let mut b = NetworkBuilder::new();
    b.stepping(stepping);
    let input = b.add_spike_input("taxels", SpikeArrayInput::new(taxels.clone()))?;
    let afferents = afferent_population(&mut b, input, taxels.n_channels(), config)?;
    let spikes = b.record_spikes(afferents)?;
    Ok((
        b.build_partitioned(NetworkConfig { dt_s }, ranks.rank(), ranks.size())?,
        spikes,
    ))
}

/// The settings of the afferent pipeline bench ([`afferent_activity`], [`afferent_crossover`]).
#[derive(Debug, Clone)]
pub struct ActivityBench {
    /// The afferents.
    pub config: AfferentConfig,
    /// Taxels (= afferents).
    pub n: usize,
    /// Poisson rate of the firing taxels (Hz).
    pub rate_hz: f64,
    /// Simulated duration of each run (s).
    pub duration_s: f64,
    /// Time step (s).
    pub dt_s: f64,
    /// Seed of the taxel trains.
    pub seed: u64,
    /// Runs of each mode, interleaved; the fastest is kept.
    pub repeats: usize,
    /// The crossovers of the automatic runs ([`Stepping::Auto`]).
    pub crossovers: Crossovers,
}

/// The afferent pipeline of `bench` (`n` taxels → exponential synapses → `n` afferents, f64)
/// with the fraction `active` of the taxels firing, run clock-driven, event-driven and
/// automatically ([`NetworkBuilder::stepping`]) on one thread, each the fastest of
/// `bench.repeats` interleaved runs; the spikes are compared.
pub fn afferent_activity(
    bench: &ActivityBench,
    active: f64,
) -> Result<ActivityBenchResult, BenchError> {
    let ActivityBench {
        config,
        n,
        rate_hz,
        duration_s,
        dt_s,
        seed,
        repeats,
        ref crossovers,
    } = *bench;
    for (what, value, ok) in [
        ("activity", active, (0.0..=1.0).contains(&active)),
        ("rate_hz", rate_hz, rate_hz.is_finite() && rate_hz >= 0.0),
        (
            "duration_s",
            duration_s,
            duration_s.is_finite() && duration_s >= 0.0,
        ),
    ] {
        if !ok {
            return Err(BenchError::InvalidParameter {
                what,
                value,
                expected: "activity in [0, 1], rate and duration finite and ≥ 0",
            });
        }
    }
    budget::population("--n", n, budget::steps(duration_s, dt_s)?)?;
    let spikes = n as f64 * active * rate_hz * duration_s;
    let what = "expected input spikes (--n × --activity × --rate × --duration)";
    budget::at_most("--rate", rate_hz, what, spikes, budget::MAX_SPIKES)?;
    let taxels = activity_taxels(n, active, rate_hz, duration_s, seed);
    type Run = (ActivityRun, Vec<(u32, f64)>, PopulationStepping);
    let run = |stepping: Stepping| -> Result<Run, BenchError> {
        let (mut net, spikes) =
            afferent_network(&taxels, config, dt_s, stepping, &neurotac_core::OneProcess)?;
        let (result, wall_s) = with_threads(1, || {
            let start = Instant::now();
            let result = net.run(duration_s, &neurotac_core::OneProcess);
            (result, start.elapsed().as_secs_f64())
        })?;
        result?;
        let steps = net.steps_done();
        let out = net.readout(spikes)?.spikes().to_vec();
        let report = net.stepping_report().swap_remove(0);
        Ok((
            ActivityRun {
                wall_s,
                updates: net.neuron_updates(),
                effective_updates_per_s: n as f64 * steps as f64 / wall_s,
                spikes: out.len(),
            },
            out,
            report,
        ))
    };
    // The shortest of the interleaved runs of each mode: a shared machine's noise only ever
    // adds time.
    let fastest = |a: Run, b: Run| if b.0.wall_s < a.0.wall_s { b } else { a };
    let modes = [
        Stepping::Clock,
        Stepping::Event,
        Stepping::Auto(crossovers.clone()),
    ];
    let mut best: Vec<Run> = Vec::new();
    for r in 0..repeats.max(1) {
        for (m, stepping) in modes.iter().enumerate() {
            let this = run(stepping.clone())?;
            if r == 0 {
                best.push(this);
            } else {
                let old = std::mem::replace(&mut best[m], this.clone());
                best[m] = fastest(old, this);
            }
        }
    }
    let [clock, event, auto]: [Run; 3] = best.try_into().expect("three modes");
    let faster = clock.0.wall_s.min(event.0.wall_s);
    Ok(ActivityBenchResult {
        model: config.model.name(),
        n,
        active_fraction: active,
        rate_hz,
        dt_s,
        steps: (duration_s / dt_s).round() as u64,
        speedup: clock.0.wall_s / event.0.wall_s,
        automatic_ratio: auto.0.wall_s / faster,
        identical_spikes: clock.1 == event.1 && clock.1 == auto.1,
        measured_activity: event.2.activity.unwrap_or(0.0),
        automatic_stepping: auto.2,
        clock_driven: clock.0,
        event_driven: event.0,
        automatic: auto.0,
    })
}

/// The taxel activities [`afferent_crossover`] sweeps (fraction of taxels firing), ascending.
pub const CROSSOVER_SWEEP: [f64; 10] = [0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0];

/// What [`afferent_crossover`] measured: one [`afferent_activity`] per swept activity, and the
/// crossover.
#[derive(Debug, Clone, Serialize)]
pub struct CrossoverBenchResult {
    /// The afferent model's name as populations report it (the crossover file's key).
    pub model: &'static str,
    /// The sweep, up to the first activity clearly past the crossover.
    pub points: Vec<ActivityBenchResult>,
    /// The measured activity at which both modes cost the same (interpolated on log-log
    /// axes between the two points around it); 1 when event-driven stepping is never slower,
    /// the lowest measured activity when it is always slower.
    pub crossover: f64,
}

/// Sweeps [`CROSSOVER_SWEEP`] with [`afferent_activity`] (stopping once event-driven stepping
/// is 1.5× slower than clock-driven) and finds the measured activity at which the two modes
/// cost the same.
pub fn afferent_crossover(bench: &ActivityBench) -> Result<CrossoverBenchResult, BenchError> {
    let mut points: Vec<ActivityBenchResult> = Vec::new();
    for active in CROSSOVER_SWEEP {
        let p = afferent_activity(bench, active)?;
        let past = p.speedup < 1.0 / 1.5;
        points.push(p);
        if past {
            break;
        }
    }
    let model = points[0].automatic_stepping.model;
    let crossover = crossover_of(
        &points
            .iter()
            .map(|p| (p.measured_activity, p.speedup))
            .collect::<Vec<_>>(),
    );
    Ok(CrossoverBenchResult {
        model,
        points,
        crossover,
    })
}

/// The activity at which `speedup` (clock wall / event wall) crosses 1, from `(activity,
/// speedup)` points in sweep order: interpolated linearly in `ln activity` against
/// `ln speedup` between the last point above 1 and the first at or below it.
pub fn crossover_of(points: &[(f64, f64)]) -> f64 {
    let usable: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|&(a, s)| a > 0.0 && s > 0.0 && a.is_finite() && s.is_finite())
        .collect();
    let Some(i) = usable.iter().position(|&(_, s)| s <= 1.0) else {
        return 1.0;
    };
    if i == 0 {
        return usable[0].0.min(1.0);
    }
    let ((a0, s0), (a1, s1)) = (usable[i - 1], usable[i]);
    let (l0, l1) = (s0.ln(), s1.ln());
    let t = if l0 == l1 { 0.0 } else { l0 / (l0 - l1) };
    (a0.ln() + t * (a1.ln() - a0.ln()))
        .exp()
        .clamp(f64::MIN_POSITIVE, 1.0)
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
    /// Synapses (of the whole network, summed over the ranks).
    pub synapses: usize,
    /// Simulated time (s).
    pub duration_s: f64,
    /// Wall time to build the network, connectivity included (s; this rank's).
    pub build_s: f64,
    /// Wall time of the run (s; this rank's, exchanges included).
    pub run_s: f64,
    /// Run wall time per simulated second.
    pub wall_s: f64,
    /// Spikes fired.
    pub spikes: usize,
    /// Mean firing rate (Hz).
    pub rate_hz: f64,
    /// Ranks the network was partitioned over (1 in one process).
    pub ranks: usize,
    /// Wall time of this rank's spike exchanges during the run (s; part of `run_s`, 0 in one
    /// process; see [`Network::exchange_s`]).
    pub exchange_s: f64,
    /// Spike exchanges done (one per epoch; the CUBA epoch is its one-step delay).
    pub exchanges: u64,
}

/// Every spike of a CUBA run as `(neuron, time_s)`, in recording order (the same on every rank,
/// and the same as in one process).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CubaSpikes {
    /// Spikes of the excitatory population.
    pub excitatory: Vec<(u32, f64)>,
    /// Spikes of the inhibitory population.
    pub inhibitory: Vec<(u32, f64)>,
}

/// The CUBA network of `config` with neurons in precision `F` (`neurotac bench cuba`'s is
/// f64), described but not built: the builder, its excitatory and inhibitory populations and
/// their spike recorders.
pub type CubaBuilder = (
    NetworkBuilder,
    [PopulationId; 2],
    [ReadoutId<SpikeRecorder>; 2],
);

/// [`CubaBuilder`] for `config` in precision `F`.
pub fn cuba_builder<F: Real>(config: &CubaConfig) -> Result<CubaBuilder, GraphError> {
    let params = LifParams::cuba();
    let population = |n: usize, seed: u64| {
        Lif::<F>::new(n, params)
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
    let recorders = [b.record_spikes(exc)?, b.record_spikes(inh)?];
    Ok((b, [exc, inh], recorders))
}

/// Builds and runs the CUBA network partitioned over `ranks` (`&OneProcess` for one process;
/// each rank builds and steps its block of each population, see
/// [`NetworkBuilder::build_partitioned`]). Every rank of the group must call it; each returns
/// the same spikes and synapse count, and its own timings.
pub fn cuba(config: CubaConfig, ranks: &dyn Ranks) -> Result<CubaResult, BenchError> {
    run_cuba(config, ranks).map(|(result, _, _)| result)
}

impl CubaSpikes {
    /// FNV-1a 64 of every spike (excitatory, then inhibitory; neuron index and the time's
    /// bits, little-endian): equal checksums mean identical spikes, to compare runs on
    /// different rank counts.
    pub fn checksum(&self) -> u64 {
        let mut h = neurotac_core::seed_hash::Fnv1a::new();
        for &(i, t) in self.excitatory.iter().chain(&self.inhibitory) {
            h.write(&i.to_le_bytes());
            h.write(&t.to_bits().to_le_bytes());
        }
        h.finish()
    }
}

/// [`cuba`], with every spike of the run.
pub fn cuba_spikes(
    config: CubaConfig,
    ranks: &dyn Ranks,
) -> Result<(CubaResult, CubaSpikes), BenchError> {
    let (result, net, [re, ri]) = run_cuba(config, ranks)?;
    let spikes = CubaSpikes {
        excitatory: net.readout(re)?.spikes().to_vec(),
        inhibitory: net.readout(ri)?.spikes().to_vec(),
    };
    Ok((result, spikes))
}

fn run_cuba(
    config: CubaConfig,
    ranks: &dyn Ranks,
) -> Result<(CubaResult, Network, [ReadoutId<SpikeRecorder>; 2]), BenchError> {
    let neurons = config.n_exc + config.n_inh;
    budget::population(
        "--neurons",
        neurons,
        budget::steps(config.duration_s, config.dt_s)?,
    )?;
    let synapses = (neurons as f64).powi(2) * config.probability;
    let what = "expected synapses (--neurons² × --probability)";
    budget::at_most(
        "--neurons",
        neurons as f64,
        what,
        synapses,
        budget::MAX_SYNAPSES,
    )?;
    let start = Instant::now();
    let (b, _, [re, ri]) = cuba_builder::<f64>(&config)?;
    let config_net = NetworkConfig { dt_s: config.dt_s };
    let mut net = b.build_partitioned(config_net, ranks.rank(), ranks.size())?;
    let build_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let summary = net.run(config.duration_s, ranks)?;
    let run_s = start.elapsed().as_secs_f64();
    let spikes = net.readout(re)?.spikes().len() + net.readout(ri)?.spikes().len();
    let simulated = summary.steps as f64 * config.dt_s;
    // Each rank holds the synapses onto its own neurons.
    let synapses = all_gather_f64(ranks, &[net.n_synapses() as f64])?
        .iter()
        .sum::<f64>() as usize;
    let result = CubaResult {
        neurons,
        synapses,
        duration_s: simulated,
        build_s,
        run_s,
        wall_s: run_s / simulated,
        spikes,
        rate_hz: spikes as f64 / neurons as f64 / simulated,
        ranks: ranks.size(),
        exchange_s: net.exchange_s(),
        exchanges: net.exchanges(),
    };
    Ok((result, net, [re, ri]))
}
