//! What LIF and Izhikevich populations share: initial conditions, the block layout that makes
//! parallel stepping deterministic, turning per-block spike masks into a [`SpikeBuffer`], and
//! the population itself, [`BlockPopulation`], generic over the per-model part ([`BlockModel`]:
//! parameters, block state, per-step constants, the fused step of one block).
//!
//! State is structure-of-arrays, cut into blocks of [`BLOCK`] neurons (each block holds its own
//! arrays). A step runs one fused update + threshold + reset loop per block, writing a 0/1 spike
//! mask; blocks run on rayon's pool when the population is large ([`PARALLEL_MIN`]) and the pool
//! has more than one thread, else in order on the caller's thread. The arithmetic of a neuron
//! never depends on the block split, so results are bit-identical at any thread count.

use crate::integrate::Integrator;
use crate::real::Real;
use neurotac_core::{ModelError, NeuronModel, SpikeBuffer, SynapticDrive};
use num_traits::Float;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::fmt;
use std::ops::Range;

/// Neurons per block.
pub const BLOCK: usize = 4096;

/// Smallest population stepped in parallel.
pub const PARALLEL_MIN: usize = 1 << 15;

/// Initial membrane potential of each neuron.
#[derive(Debug, Clone, PartialEq)]
pub enum InitialPotential {
    /// The same value for every neuron.
    Constant(f64),
    /// Independent uniform draws in `[low, high)` from a ChaCha8 generator seeded with `seed`.
    Uniform {
        /// Lower bound (inclusive).
        low: f64,
        /// Upper bound (exclusive).
        high: f64,
        /// Seed.
        seed: u64,
    },
    /// One value per neuron.
    Values(Vec<f64>),
}

impl InitialPotential {
    /// The values of neurons `block` of a population of `n`, validated as for all `n` (finite;
    /// a list must have `n` entries); computed for the block only, each neuron's value as in
    /// the whole population (a uniform draw seeks to the block's place in the seeded stream).
    pub(crate) fn values(
        &self,
        model: &'static str,
        n: usize,
        block: Range<usize>,
    ) -> Result<Vec<f64>, ModelError> {
        let bad = |field, value, expected| ModelError::InvalidParameter {
            model,
            field,
            value,
            expected,
        };
        if block.start > block.end || block.end > n {
            return Err(bad(
                "neuron block (end)",
                block.end as f64,
                "a block of the population's neurons",
            ));
        }
        let v = match self {
            InitialPotential::Constant(v) => vec![*v; block.len()],
            InitialPotential::Uniform { low, high, seed } => {
                if !(low.is_finite() && high.is_finite() && low <= high) {
                    return Err(bad("initial potential range", *low, "finite low ≤ high"));
                }
                let mut rng = ChaCha8Rng::seed_from_u64(*seed);
                // Each draw is one 64-bit output, two 32-bit words of the stream.
                rng.set_word_pos(2 * block.start as u128);
                block
                    .clone()
                    .map(|_| low + (high - low) * rng.random::<f64>())
                    .collect()
            }
            InitialPotential::Values(v) => {
                if v.len() != n {
                    return Err(bad(
                        "initial potentials (count)",
                        v.len() as f64,
                        "one value per neuron",
                    ));
                }
                // Every value is checked, not only the block's: each rank refuses the same list.
                if let Some(&x) = v.iter().find(|x| !x.is_finite()) {
                    return Err(bad("initial potential", x, "finite"));
                }
                v[block].to_vec()
            }
        };
        match v.iter().find(|x| !x.is_finite()) {
            Some(&x) => Err(bad("initial potential", x, "finite")),
            None => Ok(v),
        }
    }
}

/// The input of one step: one value for all neurons, or one per neuron.
#[derive(Debug, Clone, Copy)]
pub enum Drive<'a> {
    /// The same input for every neuron.
    Constant(f64),
    /// `input[i]` for neuron `i`.
    PerNeuron(&'a [f64]),
}

impl<'a> Drive<'a> {
    /// The part of this drive that feeds block `b`.
    #[inline]
    pub(crate) fn block(self, b: usize, len: usize) -> Drive<'a> {
        match self {
            Drive::Constant(c) => Drive::Constant(c),
            Drive::PerNeuron(x) => Drive::PerNeuron(&x[b * BLOCK..b * BLOCK + len]),
        }
    }

    /// Input for neuron `i` (block-local inside [`BlockModel::step_block`]).
    #[inline]
    pub fn at(self, i: usize) -> f64 {
        match self {
            Drive::Constant(c) => c,
            Drive::PerNeuron(x) => x[i],
        }
    }
}

/// Steps between two divergence checks in [`Population::run_constant`] (and in the network's
/// run loop): a check costs one call, never a pass over the neurons.
pub const DIVERGENCE_CHECK_STEPS: u64 = 256;

/// What block-stepped populations (LIF, Izhikevich) share beyond [`NeuronModel`]: stepping
/// under a [`Drive`], and the checked and benchmark entry points built on it.
pub trait Population: NeuronModel {
    /// Advances every neuron one step under `drive` and returns the number of spikes, without
    /// recording indices. The population must be prepared.
    fn advance(&mut self, drive: Drive<'_>) -> u64;

    /// The time step the population is prepared for, if it is.
    fn prepared_dt(&self) -> Option<f64>;

    /// Checks one input value for neuron `neuron`: NaN/±∞ and values beyond the population's
    /// precision (e.g. `1e39` for `f32`) are typed errors.
    fn check_input(&self, neuron: usize, value: f64) -> Result<(), ModelError>;

    /// Prepares (if needed) and runs `steps` steps of `dt_s` with the same input `current` for
    /// every neuron, without recording spike indices; returns the number of spikes. This is the
    /// benchmark path; it steps exactly as a network does, and like a network checks for
    /// divergence every [`DIVERGENCE_CHECK_STEPS`] steps and at the end.
    fn run_constant(&mut self, current: f64, dt_s: f64, steps: u64) -> Result<u64, ModelError> {
        self.check_input(0, current)?;
        if self.prepared_dt() != Some(dt_s) {
            self.prepare(dt_s)?;
        }
        let mut spikes = 0;
        for k in 1..=steps {
            spikes += self.advance(Drive::Constant(current));
            if k % DIVERGENCE_CHECK_STEPS == 0 {
                self.check_divergence()?;
            }
        }
        self.check_divergence()?;
        Ok(spikes)
    }

    /// One network-style step with per-neuron input, rejecting input of the wrong length or
    /// with NaN/±∞ values (or values beyond the precision) with a typed error (the state is then
    /// untouched).
    fn step_checked(
        &mut self,
        current: &[f64],
        spikes: &mut SpikeBuffer,
    ) -> Result<(), ModelError> {
        let model = self.model_name();
        for (i, &x) in current.iter().enumerate() {
            self.check_input(i, x)?;
        }
        if current.len() != self.len() {
            return Err(ModelError::InvalidParameter {
                model,
                field: "input length",
                value: current.len() as f64,
                expected: "one value per neuron",
            });
        }
        spikes.clear();
        self.step(current, spikes);
        Ok(())
    }
}

/// What one block's step returns: its spikes, and how many of them (or of its state updates)
/// the model's divergence criterion flagged.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BlockStep {
    /// Spikes in the block.
    pub spikes: u64,
    /// Nonzero when the model's divergence criterion flagged an update of the block (see each
    /// model's docs): the flagged spikes, plus one for any non-finite update.
    pub diverged: u64,
}

impl BlockStep {
    /// One neuron's step ([`BlockModel::step_neuron`]) without a divergence flag: its spike.
    #[inline(always)]
    pub fn one_neuron(spiked: bool) -> BlockStep {
        BlockStep {
            spikes: u64::from(spiked),
            diverged: 0,
        }
    }

    #[inline]
    fn add(self, other: BlockStep) -> BlockStep {
        BlockStep {
            spikes: self.spikes + other.spikes,
            diverged: self.diverged + other.diverged,
        }
    }
}

/// The per-model part of a block-stepped population: parameters, the state of one block,
/// per-step constants and the fused step of one block. Everything else — the builder, block
/// allocation, `prepare`/`reset`/`step`, spike collection and divergence bookkeeping — is
/// [`BlockPopulation`]'s, written once.
///
/// Implemented by [`LifModel`](crate::lif::LifModel) and
/// [`IzhikevichModel`](crate::izhikevich::IzhikevichModel); the populations are
/// [`Lif`](crate::Lif)` = BlockPopulation<LifModel<F>>` and likewise for Izhikevich.
pub trait BlockModel: Send + Sync + 'static {
    /// Precision of the state.
    type Real: Real;
    /// The parameter record (validated by [`validate`](Self::validate) at `prepare`).
    type Params: Copy + PartialEq + fmt::Debug + Send + Sync;
    /// The state of one block of up to [`BLOCK`] neurons (structure of arrays).
    type State: Clone + fmt::Debug + Send;
    /// Per-step constants computed once by `prepare` in the population's precision.
    type Constants: Copy + Default + fmt::Debug + Send + Sync;

    /// Model name used in messages (e.g. `"lif"`).
    const NAME: &'static str;
    /// Names of the state variables (see [`NeuronModel::variables`]).
    const VARIABLES: &'static [&'static str];
    /// The supported integrators, for the "unsupported integrator" error.
    const SUPPORTED: &'static str;
    /// The integrator a new population starts with.
    const DEFAULT_INTEGRATOR: Integrator;
    /// What the model's divergence criterion detects (for the error message).
    const DIVERGENCE: &'static str;

    /// `true` when the model implements `integrator`.
    fn supports(integrator: Integrator) -> bool;

    /// The initial potential of a new population with `params`.
    fn default_initial(params: &Self::Params) -> InitialPotential;

    /// Validates the parameters (finite, representable in [`Real`](Self::Real), consistent).
    fn validate(params: &Self::Params) -> Result<(), ModelError>;

    /// The per-step constants for `params` at `dt_s` (already validated).
    fn constants(params: &Self::Params, dt_s: f64) -> Self::Constants;

    /// A block starting at the initial potentials `v0` (one per neuron of the block).
    fn new_block(
        params: &Self::Params,
        k: &Self::Constants,
        v0: &[f64],
        interpolate: bool,
    ) -> Self::State;

    /// Advances one block by one step under its part of the drive: the fused update,
    /// threshold and reset loop of the model with `integrator`, then (when `interpolate`) the
    /// rest of the step after each interpolated spike.
    fn step_block(
        k: &Self::Constants,
        integrator: Integrator,
        interpolate: bool,
        state: &mut Self::State,
        drive: Drive<'_>,
    ) -> BlockStep;

    /// `true` when [`step_block_synaptic`](Self::step_block_synaptic) has a fused loop for
    /// these settings. Default `false`: the population drains the currents into its input
    /// buffer and calls [`step_block`](Self::step_block).
    fn fuses_synapses(k: &Self::Constants, integrator: Integrator, interpolate: bool) -> bool {
        let _ = (k, integrator, interpolate);
        false
    }

    /// Advances one block by one step under the synaptic currents `drive` (its part of the
    /// population's; [`NeuronModel::step_synaptic`]), summing and decaying them inside the
    /// update loop. Called only when [`fuses_synapses`](Self::fuses_synapses) holds; it must
    /// give what draining the currents and calling [`step_block`](Self::step_block) gives,
    /// which is what the default does (through a buffer on the stack).
    fn step_block_synaptic(
        k: &Self::Constants,
        integrator: Integrator,
        interpolate: bool,
        state: &mut Self::State,
        drive: SynapticDrive<'_>,
    ) -> BlockStep {
        let mut input = [0.0; BLOCK];
        let input = &mut input[..drive.len()];
        drive.drain_into(input);
        Self::step_block(k, integrator, interpolate, state, Drive::PerNeuron(input))
    }

    /// The block's spike mask of the last step (1 where a neuron spiked).
    fn spike_mask(state: &Self::State) -> &[u8];

    /// The block's in-step spike fractions of the last step (empty unless interpolating).
    fn spike_fractions(state: &Self::State) -> &[Self::Real];

    /// Variable `var` (an index into [`VARIABLES`](Self::VARIABLES)) of neuron `j` of the block.
    fn variable(state: &Self::State, var: usize, j: usize) -> f64;

    /// Event-driven stepping ([`NeuronModel::event_driven`]): `true` when, with these settings, a
    /// neuron whose input is 0 and that is [`settled`](Self::settled) can be left alone and
    /// advanced later ([`advance_idle`](Self::advance_idle)), and stepped alone
    /// ([`step_neuron`](Self::step_neuron)) with the arithmetic of
    /// [`step_block`](Self::step_block). Default `false`: clock-driven only.
    fn skips_idle(
        params: &Self::Params,
        k: &Self::Constants,
        integrator: Integrator,
        interpolate: bool,
    ) -> bool {
        let _ = (params, k, integrator, interpolate);
        false
    }

    /// `true` when neuron `j` of the block, left without input from now on, is followed by
    /// [`advance_idle`](Self::advance_idle) (exactly, or within the model's stated tolerance).
    /// A neuron that is not settled is stepped clock-driven at input 0 until it is. Default
    /// `true` (a closed form exists from any state).
    fn settled(k: &Self::Constants, state: &Self::State, j: usize) -> bool {
        let _ = (k, state, j);
        true
    }

    /// Advances settled neuron `j` of the block over `steps` steps of zero input. Called only
    /// when [`skips_idle`](Self::skips_idle) holds; the default leaves the state alone (a
    /// neuron held at its resting point).
    fn advance_idle(k: &Self::Constants, state: &mut Self::State, j: usize, steps: u64) {
        let _ = (k, state, j, steps);
    }

    /// One step of neuron `j` of the block under `input`, with the arithmetic of
    /// [`step_block`](Self::step_block): its spike (0 or 1) and whether the divergence criterion
    /// flagged it. Called only when [`skips_idle`](Self::skips_idle) holds; the default never
    /// spikes.
    fn step_neuron(
        k: &Self::Constants,
        integrator: Integrator,
        state: &mut Self::State,
        j: usize,
        input: f64,
    ) -> BlockStep {
        let _ = (k, integrator, state, j, input);
        BlockStep::default()
    }

    /// One event-driven step of the neurons `active` and of the unsettled ones
    /// ([`NeuronModel::step_active`]): each is first brought up to step `now`
    /// ([`advance_idle`](Self::advance_idle)), then stepped ([`step_neuron`](Self::step_neuron)).
    /// A model may override it to hoist its integrator choice out of the loop.
    fn step_neurons(
        k: &Self::Constants,
        integrator: Integrator,
        active: ActiveNeurons<'_, Self::State>,
    ) -> ActiveStep {
        active.run(
            |s, j, idle| Self::advance_idle(k, s, j, idle),
            |s, j, input| Self::step_neuron(k, integrator, s, j, input),
            |s, j| Self::settled(k, s, j),
        )
    }
}

/// What one event-driven step did ([`ActiveNeurons::run`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ActiveStep {
    /// Neurons updated: the active ones and the unsettled ones.
    pub updates: u64,
    /// Their spikes and divergence flags.
    pub step: BlockStep,
}

/// The neurons of one event-driven step and the bookkeeping around them
/// ([`BlockModel::step_neurons`]).
pub struct ActiveNeurons<'a, S> {
    blocks: &'a mut [S],
    current_to: &'a mut [u64],
    now: u64,
    active: &'a [u32],
    inputs: &'a [f64],
    /// Neurons stepped before and not settled yet (ascending): stepped at input 0 when not
    /// active. Replaced by this step's unsettled neurons.
    restless: &'a mut Vec<u32>,
    restless_next: &'a mut Vec<u32>,
    spikes: &'a mut SpikeBuffer,
}

impl<S> ActiveNeurons<'_, S> {
    /// For each active or restless neuron, in ascending order: `idle(block, j, steps)` over
    /// the steps it was skipped, then `step(block, j, input)` (input 0 for a restless neuron
    /// without input), pushing its spike; the neurons that are not `settled(block, j)`
    /// afterwards are stepped again next step.
    #[inline(always)]
    pub fn run(
        self,
        mut idle: impl FnMut(&mut S, usize, u64),
        mut step: impl FnMut(&mut S, usize, f64) -> BlockStep,
        mut settled: impl FnMut(&S, usize) -> bool,
    ) -> ActiveStep {
        let Self {
            blocks,
            current_to,
            now,
            active,
            inputs,
            restless,
            restless_next,
            spikes,
        } = self;
        restless_next.clear();
        let mut out = ActiveStep::default();
        each_active_or_restless(
            active,
            inputs,
            restless,
            #[inline(always)]
            |i: u32, input: f64| {
                let i_ = i as usize;
                let (block, j) = (&mut blocks[i_ / BLOCK], i_ % BLOCK);
                let to = &mut current_to[i_];
                if *to < now {
                    advance_skipped(&mut idle, block, j, now - *to);
                }
                let s = step(block, j, input);
                if s.spikes > 0 {
                    spikes.push(i);
                }
                if !settled(block, j) {
                    restless_next.push(i);
                }
                *to = now + 1;
                out.updates += 1;
                out.step = out.step.add(s);
            },
        );
        std::mem::swap(restless, restless_next);
        out
    }
}

/// `idle(block, j, steps)`, out of the event-driven loop: a neuron comes back after skipped
/// steps once per input burst, while the loop runs every step, and inlined the closed form's
/// registers cost the loop its own.
#[cold]
#[inline(never)]
fn advance_skipped<S>(
    idle: &mut impl FnMut(&mut S, usize, u64),
    block: &mut S,
    j: usize,
    steps: u64,
) {
    idle(block, j, steps);
}

/// Calls `visit(i, input)` for the neurons `active` (ascending, with `inputs`) merged with the
/// neurons `restless` (ascending, input 0 unless also active), each once, in ascending order.
/// Every neuron settled (always so for LIF): the active ones only, in a loop of their own.
#[inline(always)]
fn each_active_or_restless(
    active: &[u32],
    inputs: &[f64],
    restless: &[u32],
    mut visit: impl FnMut(u32, f64),
) {
    if restless.is_empty() {
        for (&i, &input) in active.iter().zip(inputs) {
            visit(i, input);
        }
        return;
    }
    let (mut a, mut r) = (0, 0);
    loop {
        let (i, input) = match (active.get(a), restless.get(r)) {
            (Some(&x), Some(&y)) if y < x => {
                r += 1;
                (y, 0.0)
            }
            (Some(&x), next) => {
                r += usize::from(next == Some(&x));
                a += 1;
                (x, inputs[a - 1])
            }
            (None, Some(&y)) => {
                r += 1;
                (y, 0.0)
            }
            (None, None) => break,
        };
        visit(i, input);
    }
}

/// A population of `n` neurons of model `M`, in blocks of [`BLOCK`]: the builder, the block
/// allocation and the `prepare`/`reset`/`step` scaffolding shared by every model.
///
/// Use it through the model aliases, [`Lif`](crate::Lif) and [`Izhikevich`](crate::Izhikevich).
pub struct BlockPopulation<M: BlockModel> {
    n: usize,
    /// The whole population this one is a block of ([`NeuronModel::restrict`]), and the index
    /// there of this one's first neuron (`n` and 0 when it is whole): initial values are those
    /// of the whole population's neurons `first..first + n`.
    whole: usize,
    first: usize,
    params: M::Params,
    integrator: Integrator,
    interpolate: bool,
    initial: InitialPotential,
    blocks: Vec<M::State>,
    k: M::Constants,
    dt_s: f64,
    /// Steps advanced since `prepare`/`reset`.
    steps: u64,
    /// The first step (0-based) in which the divergence criterion fired, if any.
    diverged_at: Option<u64>,
    /// Event-driven stepping: the step up to which each neuron's state is current (empty when
    /// the model cannot skip idle neurons with these settings).
    current_to: Vec<u64>,
    /// Event-driven stepping: the neurons not settled after their last step (ascending), and
    /// the buffer for the next step's.
    restless: Vec<u32>,
    restless_next: Vec<u32>,
}

impl<M: BlockModel> Clone for BlockPopulation<M> {
    fn clone(&self) -> Self {
        Self {
            n: self.n,
            whole: self.whole,
            first: self.first,
            params: self.params,
            integrator: self.integrator,
            interpolate: self.interpolate,
            initial: self.initial.clone(),
            blocks: self.blocks.clone(),
            k: self.k,
            dt_s: self.dt_s,
            steps: self.steps,
            diverged_at: self.diverged_at,
            current_to: self.current_to.clone(),
            restless: self.restless.clone(),
            restless_next: Vec::new(),
        }
    }
}

impl<M: BlockModel> fmt::Debug for BlockPopulation<M> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct(M::NAME)
            .field("n", &self.n)
            .field("params", &self.params)
            .field("integrator", &self.integrator)
            .field("interpolate", &self.interpolate)
            .field("initial", &self.initial)
            .field("dt_s", &self.dt_s)
            .field("steps", &self.steps)
            .finish_non_exhaustive()
    }
}

impl<M: BlockModel> BlockPopulation<M> {
    /// `n` neurons with `params`, the model's default integrator and initial potential, grid
    /// spike times.
    pub fn new(n: usize, params: M::Params) -> Self {
        Self {
            n,
            whole: n,
            first: 0,
            params,
            integrator: M::DEFAULT_INTEGRATOR,
            interpolate: false,
            initial: M::default_initial(&params),
            blocks: Vec::new(),
            k: M::Constants::default(),
            dt_s: 0.0,
            steps: 0,
            diverged_at: None,
            current_to: Vec::new(),
            restless: Vec::new(),
            restless_next: Vec::new(),
        }
    }

    /// Chooses the integrator (checked by `prepare`).
    pub fn with_integrator(mut self, integrator: Integrator) -> Self {
        self.integrator = integrator;
        self
    }

    /// Interpolates spike times inside the step (see the model's docs).
    pub fn with_interpolation(mut self, interpolate: bool) -> Self {
        self.interpolate = interpolate;
        self
    }

    /// Sets the initial membrane potentials (see the model's docs for the other variables).
    pub fn with_initial_potential(mut self, initial: InitialPotential) -> Self {
        self.initial = initial;
        self
    }

    /// The parameters.
    pub fn params(&self) -> &M::Params {
        &self.params
    }

    /// The integrator.
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }

    /// Variable `var` of neuron `i` (after `prepare`).
    pub(crate) fn variable(&self, var: usize, i: usize) -> f64 {
        M::variable(&self.blocks[i / BLOCK], var, i % BLOCK)
    }

    fn advance_blocks(&mut self, drive: Drive<'_>) -> u64 {
        let (n, k, integrator, interpolate) = (self.n, self.k, self.integrator, self.interpolate);
        let step = for_blocks(&mut self.blocks, n, |b, s| {
            let len = M::spike_mask(s).len();
            M::step_block(&k, integrator, interpolate, s, drive.block(b, len))
        });
        self.count_step(step)
    }

    /// Ends a step that `step` summarises: notes its first divergence and counts it; returns
    /// its spike count.
    fn count_step(&mut self, step: BlockStep) -> u64 {
        if step.diverged > 0 && self.diverged_at.is_none() {
            self.diverged_at = Some(self.steps);
        }
        self.steps += 1;
        step.spikes
    }

    /// Pushes the last step's spikes (`count` of them) from the blocks' masks, in ascending
    /// order.
    fn collect_spikes(&self, count: u64, spikes: &mut SpikeBuffer) {
        if count == 0 {
            return;
        }
        for (b, s) in self.blocks.iter().enumerate() {
            let phi = self.interpolate.then_some(M::spike_fractions(s));
            collect_block_spikes(b, M::spike_mask(s), phi, spikes);
        }
    }
}

impl<M: BlockModel> Population for BlockPopulation<M> {
    fn advance(&mut self, drive: Drive<'_>) -> u64 {
        self.advance_blocks(drive)
    }

    fn prepared_dt(&self) -> Option<f64> {
        (self.dt_s > 0.0 && self.blocks.len() == n_blocks(self.n)).then_some(self.dt_s)
    }

    fn check_input(&self, neuron: usize, value: f64) -> Result<(), ModelError> {
        if !value.is_finite() {
            return Err(ModelError::NonFiniteInput {
                model: M::NAME,
                neuron,
                value,
            });
        }
        if !M::Real::of(value).is_finite() {
            return Err(ModelError::InputOutOfRange {
                model: M::NAME,
                neuron,
                value,
                precision: M::Real::NAME,
                max: M::Real::max_value().f64(),
            });
        }
        Ok(())
    }
}

impl<M: BlockModel> NeuronModel for BlockPopulation<M> {
    fn model_name(&self) -> &'static str {
        M::NAME
    }

    fn len(&self) -> usize {
        self.n
    }

    fn variables(&self) -> &'static [&'static str] {
        M::VARIABLES
    }

    fn prepare(&mut self, dt_s: f64) -> Result<(), ModelError> {
        check_param(M::NAME, "dt_s", dt_s, true)?;
        check_representable::<M::Real>(M::NAME, "dt_s", dt_s)?;
        M::validate(&self.params)?;
        if !M::supports(self.integrator) {
            return Err(ModelError::UnsupportedIntegrator {
                model: M::NAME,
                integrator: self.integrator.name(),
                supported: M::SUPPORTED,
            });
        }
        self.k = M::constants(&self.params, dt_s);
        let block = self.first..self.first + self.n;
        let v0 = self.initial.values(M::NAME, self.whole, block)?;
        self.blocks = (0..n_blocks(self.n))
            .map(|b| {
                let v0 = &v0[b * BLOCK..b * BLOCK + block_len(self.n, b)];
                M::new_block(&self.params, &self.k, v0, self.interpolate)
            })
            .collect();
        self.dt_s = dt_s;
        self.steps = 0;
        self.diverged_at = None;
        self.current_to.clear();
        self.restless.clear();
        if M::skips_idle(&self.params, &self.k, self.integrator, self.interpolate) {
            self.current_to.resize(self.n, 0);
            let k = &self.k;
            let blocks = &self.blocks;
            self.restless.extend(
                (0..self.n as u32)
                    .filter(|&i| !M::settled(k, &blocks[i as usize / BLOCK], i as usize % BLOCK)),
            );
        }
        Ok(())
    }

    fn reset(&mut self) {
        // `prepare` succeeded before, so this cannot fail.
        let _ = self.prepare(self.dt_s);
    }

    fn step(&mut self, current: &[f64], spikes: &mut SpikeBuffer) {
        let step = self.advance_blocks(Drive::PerNeuron(current));
        self.collect_spikes(step, spikes);
    }

    /// Models with a fused loop ([`BlockModel::fuses_synapses`]) drain the currents inside it,
    /// block by block (in parallel for large populations, as [`step`](NeuronModel::step)).
    fn step_synaptic(
        &mut self,
        drive: SynapticDrive<'_>,
        input: &mut [f64],
        spikes: &mut SpikeBuffer,
    ) {
        let (k, integrator, interpolate) = (self.k, self.integrator, self.interpolate);
        if !M::fuses_synapses(&k, integrator, interpolate) || drive.len() != self.n {
            drive.drain_into(input);
            self.step(input, spikes);
            return;
        }
        let parallel = self.n >= PARALLEL_MIN && rayon::current_num_threads() > 1;
        let step = step_blocks_synaptic(&mut self.blocks, drive, parallel, &|s, d| {
            M::step_block_synaptic(&k, integrator, interpolate, s, d)
        });
        let step = self.count_step(step);
        self.collect_spikes(step, spikes);
    }

    fn read_variable(&self, var: usize, neurons: &[u32], out: &mut Vec<f64>) {
        out.extend(neurons.iter().map(|&i| self.variable(var, i as usize)));
    }

    fn event_driven(&self) -> bool {
        self.current_to.len() == self.n && self.n > 0
    }

    fn step_active(&mut self, active: &[u32], inputs: &[f64], spikes: &mut SpikeBuffer) -> u64 {
        let neurons = ActiveNeurons {
            blocks: &mut self.blocks,
            current_to: &mut self.current_to,
            now: self.steps,
            active,
            inputs,
            restless: &mut self.restless,
            restless_next: &mut self.restless_next,
            spikes,
        };
        let done = M::step_neurons(&self.k, self.integrator, neurons);
        self.count_step(done.step);
        done.updates
    }

    fn settle(&mut self) {
        let (k, now) = (self.k, self.steps);
        for (i, to) in self.current_to.iter_mut().enumerate() {
            if *to < now {
                M::advance_idle(&k, &mut self.blocks[i / BLOCK], i % BLOCK, now - *to);
                *to = now;
            }
        }
    }

    /// The neurons `range` as a population of their own, with the parameters, integrator,
    /// interpolation and initial potentials they have here (a seeded uniform draw gives each
    /// neuron the value it gets in the whole population), unprepared.
    fn restrict(&self, range: Range<usize>) -> Option<Box<dyn NeuronModel>> {
        if range.start > range.end || range.end > self.n {
            return None;
        }
        let mut part = Self::new(range.len(), self.params)
            .with_integrator(self.integrator)
            .with_interpolation(self.interpolate)
            .with_initial_potential(self.initial.clone());
        part.whole = self.whole;
        part.first = self.first + range.start;
        Some(Box::new(part))
    }

    fn check_divergence(&self) -> Result<(), ModelError> {
        match self.diverged_at {
            None => Ok(()),
            Some(step) => Err(ModelError::Diverged {
                model: M::NAME,
                step,
                t_s: step as f64 * self.dt_s,
                dt_s: self.dt_s,
                integrator: self.integrator.name(),
                what: M::DIVERGENCE,
            }),
        }
    }
}

/// Number of blocks for `n` neurons and the length of block `b`.
pub(crate) fn block_len(n: usize, b: usize) -> usize {
    (n - b * BLOCK).min(BLOCK)
}

pub(crate) fn n_blocks(n: usize) -> usize {
    n.div_ceil(BLOCK)
}

/// Runs `f` on every block (in parallel when worthwhile) and sums what it returns.
pub(crate) fn for_blocks<B: Send>(
    blocks: &mut [B],
    n: usize,
    f: impl Fn(usize, &mut B) -> BlockStep + Sync,
) -> BlockStep {
    if n >= PARALLEL_MIN && rayon::current_num_threads() > 1 {
        blocks
            .par_iter_mut()
            .enumerate()
            .map(|(b, blk)| f(b, blk))
            .reduce(BlockStep::default, BlockStep::add)
    } else {
        blocks
            .iter_mut()
            .enumerate()
            .map(|(b, blk)| f(b, blk))
            .fold(BlockStep::default(), BlockStep::add)
    }
}

/// Runs `f` on every block with its part of `drive` (halving the blocks over rayon's pool
/// when `parallel`) and sums what it returns.
fn step_blocks_synaptic<B: Send>(
    blocks: &mut [B],
    drive: SynapticDrive<'_>,
    parallel: bool,
    f: &(impl Fn(&mut B, SynapticDrive<'_>) -> BlockStep + Sync),
) -> BlockStep {
    match blocks {
        [] => BlockStep::default(),
        [block] => f(block, drive),
        _ => {
            let mid = blocks.len() / 2;
            let (left, right) = blocks.split_at_mut(mid);
            let (d_left, d_right) = drive.split_at(mid * BLOCK);
            let (a, b) = if parallel {
                rayon::join(
                    || step_blocks_synaptic(left, d_left, parallel, f),
                    || step_blocks_synaptic(right, d_right, parallel, f),
                )
            } else {
                (
                    step_blocks_synaptic(left, d_left, parallel, f),
                    step_blocks_synaptic(right, d_right, parallel, f),
                )
            };
            a.add(b)
        }
    }
}

/// Bit of a block's spike-mask byte that the fused step sets for a neuron whose update the
/// model's divergence criterion flagged; [`take_diverged`] clears it before the mask is read.
pub(crate) const DIVERGED_BIT: u8 = 2;

/// `true` when some neuron of a block's mask carries [`DIVERGED_BIT`] (one pass over the bytes).
#[inline]
pub(crate) fn has_flags(mask: &[u8]) -> bool {
    mask.iter().fold(0, |acc, &m| acc | m) & DIVERGED_BIT != 0
}

/// The number of neurons flagged with [`DIVERGED_BIT`] in a block's mask, clearing the bit so
/// the mask is 0/1 again: one pass over the mask bytes per block (a second pass, clearing,
/// only when something was flagged).
#[inline]
pub(crate) fn take_diverged(mask: &mut [u8]) -> u64 {
    if !has_flags(mask) {
        return 0;
    }
    let mut flagged = 0;
    for m in mask {
        flagged += u64::from(*m >> 1);
        *m &= 1;
    }
    flagged
}

/// Calls `f(i)` for every `i` with `mask[i] != 0`, skipping eight silent neurons at a time.
#[inline]
pub fn for_each_spike(mask: &[u8], mut f: impl FnMut(usize)) {
    let mut words = mask.chunks_exact(8);
    let mut base = 0;
    for word in words.by_ref() {
        if u64::from_ne_bytes(word.try_into().expect("8 bytes")) != 0 {
            (0..8).filter(|&j| word[j] != 0).for_each(|j| f(base + j));
        }
        base += 8;
    }
    let rest = words.remainder();
    (0..rest.len())
        .filter(|&j| rest[j] != 0)
        .for_each(|j| f(base + j));
}

/// Pushes the spikes recorded in `mask` (block `b`) into `out`, with `phi` fractions when given.
#[inline]
pub(crate) fn collect_block_spikes<F: Real>(
    b: usize,
    mask: &[u8],
    phi: Option<&[F]>,
    out: &mut SpikeBuffer,
) {
    let base = b * BLOCK;
    for_each_spike(mask, |i| match phi {
        Some(p) => out.push_at((base + i) as u32, unit_fraction(p[i].f64())),
        None => out.push((base + i) as u32),
    });
}

/// An in-step spike fraction limited to `[0, 1]`; NaN (a 0/0 crossing) means the end of the step.
#[inline]
pub fn unit_fraction(phi: f64) -> f64 {
    if phi.is_nan() {
        1.0
    } else {
        phi.clamp(0.0, 1.0)
    }
}

/// Refuses a finite `x` that overflows `F` (only `f32` can: `|x| > 3.4·10³⁸`).
pub fn check_representable<F: Real>(
    model: &'static str,
    field: &'static str,
    x: f64,
) -> Result<(), ModelError> {
    if x.is_finite() && !F::of(x).is_finite() {
        return Err(ModelError::InvalidParameter {
            model,
            field,
            value: x,
            expected: "within the f32 range (|x| ≤ 3.4028235e38)",
        });
    }
    Ok(())
}

/// Validates that `x` is finite and, optionally, positive.
pub fn check_param(
    model: &'static str,
    field: &'static str,
    x: f64,
    positive: bool,
) -> Result<(), ModelError> {
    if !x.is_finite() || (positive && x <= 0.0) {
        return Err(ModelError::InvalidParameter {
            model,
            field,
            value: x,
            expected: if positive { "finite and > 0" } else { "finite" },
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Izhikevich, IzhikevichParams, Lif, LifParams};

    /// Steps `whole` and its blocks `cuts` (each restricted from `whole` before `prepare`)
    /// under the same random inputs in `[0, drive)`; the blocks' spikes (shifted to global indices) and states must
    /// be the whole population's.
    fn blocks_step_as_the_whole(whole: &dyn NeuronModel, cuts: &[usize], drive: f64) {
        let n = whole.len();
        let mut full = whole.restrict(0..n).expect("LIF and Izhikevich restrict");
        let mut parts: Vec<_> = cuts
            .windows(2)
            .map(|w| {
                (
                    w[0],
                    whole
                        .restrict(w[0]..w[1])
                        .expect("a block of the population"),
                )
            })
            .collect();
        full.prepare(1e-4).unwrap();
        parts.iter_mut().for_each(|(_, p)| p.prepare(1e-4).unwrap());
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let (mut spikes, mut part_spikes) = (SpikeBuffer::new(), SpikeBuffer::new());
        let states = |full: &dyn NeuronModel, parts: &[(usize, Box<dyn NeuronModel>)]| {
            let mut a = Vec::new();
            full.read_variable(0, &(0..n as u32).collect::<Vec<_>>(), &mut a);
            let mut b = Vec::new();
            for (_, p) in parts {
                p.read_variable(0, &(0..p.len() as u32).collect::<Vec<_>>(), &mut b);
            }
            let first = a.iter().zip(&b).position(|(x, y)| x != y);
            assert!(
                a.len() == b.len() && first.is_none(),
                "states differ at {first:?}"
            );
        };
        states(full.as_ref(), &parts);
        let mut total = 0;
        for _ in 0..1000 {
            let input: Vec<f64> = (0..n).map(|_| drive * rng.random::<f64>()).collect();
            spikes.clear();
            full.step(&input, &mut spikes);
            let mut gathered = Vec::new();
            for (first, p) in &mut parts {
                part_spikes.clear();
                p.step(&input[*first..*first + p.len()], &mut part_spikes);
                gathered.extend(part_spikes.indices().iter().map(|&i| i + *first as u32));
            }
            assert_eq!(spikes.indices(), gathered.as_slice());
            total += gathered.len();
        }
        assert!(total >= n, "{total} spikes: the test must exercise spiking");
        states(full.as_ref(), &parts);
    }

    #[test]
    fn restricted_populations_step_as_their_block_of_the_whole() {
        let params = LifParams {
            v_th: 10.0,
            t_ref_s: 2e-3,
            ..LifParams::default()
        };
        let lif = Lif::<f64>::new(9000, params).with_initial_potential(InitialPotential::Uniform {
            low: 0.0,
            high: 10.0,
            seed: 3,
        });
        // Blocks that cut through the 4096-neuron state blocks, an empty one, a restriction of
        // a restriction.
        blocks_step_as_the_whole(&lif, &[0, 1, 4000, 4000, 6001, 9000], 30.0);
        let tail = lif.restrict(3000..9000).unwrap();
        let mut direct = lif.restrict(5000..9000).unwrap();
        let mut nested = tail.restrict(2000..6000).unwrap();
        direct.prepare(1e-4).unwrap();
        nested.prepare(1e-4).unwrap();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        direct.read_variable(0, &[0, 1, 3999], &mut a);
        nested.read_variable(0, &[0, 1, 3999], &mut b);
        assert_eq!(a, b);
        let v0: Vec<f64> = (0..50).map(|i| -70.0 + 0.3 * i as f64).collect();
        let rs = Izhikevich::<f32>::new(50, IzhikevichParams::rs())
            .with_initial_potential(InitialPotential::Values(v0));
        blocks_step_as_the_whole(&rs, &[0, 17, 18, 50], 100.0);
        assert!(lif.restrict(10..9001).is_none());
    }
}
