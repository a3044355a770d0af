//! [`BlockPopulation`]: a population of one [`BlockModel`], written once for every model — the
//! builder, block allocation, `prepare`/`reset`/`step`, the fused synaptic step, event-driven
//! stepping, spike collection, divergence bookkeeping and restriction to a block of neurons.

use super::active::ActiveNeurons;
use super::blocks::{
    BLOCK, BlockStep, PARALLEL_MIN, block_len, collect_block_spikes, for_blocks, n_blocks,
    step_blocks_synaptic,
};
use super::checks::{check_param, check_representable};
use super::inputs::{Drive, InitialPotential};
use super::model::BlockModel;
use super::stepping::Population;
use crate::integrate::Integrator;
use crate::real::Real;
use neurotac_core::{
    ModelDescription, ModelError, ModelState, NeuronModel, SpikeBuffer, SynapticDrive,
};
use num_traits::Float;
use std::fmt;
use std::ops::Range;

/// A population of `n` neurons of model `M`, in blocks of [`BLOCK`]: the builder, the block
/// allocation and the `prepare`/`reset`/`step` scaffolding shared by every model.
///
/// Use it through the model aliases, [`Lif`](crate::Lif) and [`Izhikevich`](crate::Izhikevich).
pub struct BlockPopulation<M: BlockModel> {
    pub(super) n: usize,
    /// The whole population this one is a block of ([`NeuronModel::restrict`]), and the index
    /// there of this one's first neuron (`n` and 0 when it is whole): initial values are those
    /// of the whole population's neurons `first..first + n`.
    pub(super) whole: usize,
    pub(super) first: usize,
    pub(super) params: M::Params,
    pub(super) integrator: Integrator,
    pub(super) interpolate: bool,
    pub(super) initial: InitialPotential,
    pub(super) blocks: Vec<M::State>,
    pub(super) k: M::Constants,
    dt_s: f64,
    /// Steps advanced since `prepare`/`reset`.
    pub(super) steps: u64,
    /// The first step (0-based) in which the divergence criterion fired, if any.
    pub(super) diverged_at: Option<u64>,
    /// Event-driven stepping: the step up to which each neuron's state is current (empty when
    /// the model cannot skip idle neurons with these settings).
    pub(super) current_to: Vec<u64>,
    /// Event-driven stepping: the neurons not settled after their last step (ascending), and
    /// the buffer for the next step's.
    pub(super) restless: Vec<u32>,
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

    /// Event-driven stepping: the neurons not settled now become the restless ones.
    fn collect_restless(&mut self) {
        let (k, integrator, blocks) = (&self.k, self.integrator, &self.blocks);
        self.restless.clear();
        self.restless.extend((0..self.n as u32).filter(|&i| {
            !M::settled(
                k,
                integrator,
                &blocks[i as usize / BLOCK],
                i as usize % BLOCK,
            )
        }));
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
            self.collect_restless();
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

    /// Every neuron is current as of now (the clock-driven steps advanced them all), and the
    /// neurons still settling are collected again.
    fn resume_event_driven(&mut self) {
        if self.current_to.len() != self.n {
            return;
        }
        self.current_to.fill(self.steps);
        self.collect_restless();
    }

    fn default_crossover(&self) -> f64 {
        M::DEFAULT_CROSSOVER
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

    /// Its name, size and settings (see [`BlockPopulation::from_description`]); a population
    /// restricted to a block of a larger one is described as a population of its own, its
    /// initial potentials listed. `None` when the model has no parameter JSON
    /// ([`BlockModel::params_to_json`]) or a setting is not finite.
    fn describe(&self) -> Option<ModelDescription> {
        self.description()
    }

    /// Every number the next step depends on, as it is — neurons that event-driven stepping
    /// left behind stay behind — in the population's precision widened to `f64`:
    /// - counters `steps` (steps done since `prepare`) and `diverged_at` (the first step the
    ///   divergence criterion flagged + 1, or 0);
    /// - arrays: the model's [`STATE_ARRAYS`](BlockModel::STATE_ARRAYS) over all neurons
    ///   (empty when the settings do not use one), and `dt_s`, the step it was saved at;
    /// - index lists `current_to` (event-driven stepping: the step each neuron is current to;
    ///   empty for a clock-driven population) and `restless` (the neurons still settling,
    ///   ascending).
    ///
    /// `None` before `prepare`, or when the model lists no state arrays.
    fn save_state(&self) -> Option<ModelState> {
        self.saved_state()
    }

    /// Checks every part of `state` (names, lengths, counters within the steps done, values
    /// representable in the precision and ones a step can leave) before writing any.
    fn restore_state(&mut self, state: &ModelState) -> Result<(), ModelError> {
        self.restore(state)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Izhikevich, IzhikevichParams, Lif, LifParams};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

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
