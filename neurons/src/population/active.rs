//! Event-driven stepping of a block population ([`NeuronModel::step_active`]): the neurons
//! with input this step merged with those still settling ([`ActiveNeurons`]), each brought up
//! to date over the steps it was skipped and then stepped alone, and what the step did
//! ([`ActiveStep`]).

use super::blocks::{BLOCK, BlockStep};
#[cfg(doc)]
use neurotac_core::NeuronModel;
use neurotac_core::SpikeBuffer;

/// What one event-driven step did ([`ActiveNeurons::run`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ActiveStep {
    /// Neurons updated: the active ones and the unsettled ones.
    pub updates: u64,
    /// Their spikes and divergence flags.
    pub step: BlockStep,
}

/// The neurons of one event-driven step and the bookkeeping around them
/// ([`BlockModel::step_neurons`](super::BlockModel::step_neurons)).
pub struct ActiveNeurons<'a, S> {
    pub(super) blocks: &'a mut [S],
    pub(super) current_to: &'a mut [u64],
    pub(super) now: u64,
    pub(super) active: &'a [u32],
    pub(super) inputs: &'a [f64],
    /// Neurons stepped before and not settled yet (ascending): stepped at input 0 when not
    /// active. Replaced by this step's unsettled neurons.
    pub(super) restless: &'a mut Vec<u32>,
    pub(super) restless_next: &'a mut Vec<u32>,
    pub(super) spikes: &'a mut SpikeBuffer,
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
