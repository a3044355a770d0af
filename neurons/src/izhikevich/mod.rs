//! # Izhikevich neuron (Izhikevich 2003, IEEE Trans. Neural Networks 14:1569)
//!
//! ```text
//! dv/dt = 0.04·v² + 5·v + 140 − u + I      (v in mV, t in ms)
//! du/dt = a·(b·v − u)
//! v ≥ v_peak (30 mV)  ⇒  spike, v ← c, u ← u + d
//! ```
//!
//! The equations are in Izhikevich's units (mV, ms, `I` in mV/ms); the network's `dt` in
//! seconds is converted once, `h = 1000·dt`. `I` is the step's input, held constant over the step.
//!
//! | symbol | field | unit | RS default |
//! |---|---|---|---|
//! | a | [`IzhikevichParams::a`] | 1/ms | 0.02 |
//! | b | [`IzhikevichParams::b`] | 1 | 0.2 |
//! | c | [`IzhikevichParams::c`] | mV | −65 |
//! | d | [`IzhikevichParams::d`] | mV/ms | 8 |
//! | v_peak | [`IzhikevichParams::v_peak`] | mV | 30 |
//! | v_min | [`IzhikevichParams::v_min`] | mV | −∞ (only the finite range is enforced) |
//!
//! Named presets (Izhikevich 2003, Fig. 2): [`rs`](IzhikevichParams::rs),
//! [`ib`](IzhikevichParams::ib), [`ch`](IzhikevichParams::ch), [`fs`](IzhikevichParams::fs),
//! [`lts`](IzhikevichParams::lts), [`tc`](IzhikevichParams::tc), [`rz`](IzhikevichParams::rz).
//! Initial state: `v = −65 mV` unless set, `u = b·v`.
//!
//! ## Integrators
//! - `izhikevich2003`: `v` advanced in two half steps of `h/2` (0.5 ms each at the paper's
//!   1 ms), then `u ← u + h·a·(b·v − u)` with the new `v` — the paper's own scheme;
//! - `euler`, `rk2`, `rk4`: the shared steps of [`crate::integrate`] on `(v, u)`;
//! - `exp-euler`: `v` by Euler, `u` exactly for `v` held at its start value,
//!   `u ← b·v + (u − b·v)·e^(−a·h)`;
//! - `exact` does not exist for this non-linear model (a build-time error).
//!
//! ## Spike times and extremes
//! A spike is stamped at the end of its step. With interpolation it is placed at the linear
//! crossing of `v_peak` between the step's start and (unclamped) end values, the neuron is reset
//! there (`v ← c`, `u ← u(φ) + d`) and integrated over the rest of the step, so spike times
//! converge at second order instead of first. After every step `v` is clamped to `[v_min, v_peak]` — a step that overshoots (large
//! `dt` under Euler, huge currents) spikes with `v` clamped at the peak — and `u` to the finite
//! range, so the state is never NaN or infinite. Explicit steps are stable only while
//! `h·|0.08·v + 5| < 2` (per ms): very large negative currents (−10⁶ drives `v` towards
//! −5 000 mV, where that rate is ≈ 400/ms) need microsecond steps, or the state oscillates —
//! finite, but with spurious spikes. `neurotac tradeoff neurons` shows where each scheme breaks.
//!
//! ## Event-driven stepping
//! Without input the model has no closed form, but it has a resting point: `u* = b·v*` with
//! `v*` the lower root of `0.04·v² + (5 − b)·v + 140 = 0` ([`resting_point`]; −70 mV for RS,
//! b = 0.2), a stable node or focus when `b − √D − a < 0`. In an event-driven network
//! ([`NeuronModel::event_driven`]) a neuron is stepped at every step in which it has input and
//! afterwards, at input 0, until a step at input 0 leaves `v` and `u` unchanged bit for bit: it
//! has reached the fixed point of the discrete step (within rounding of `(v*, u*)`), where the
//! clock-driven run stays too. Then it is held there, untouched, until its next input, so its
//! spikes and state are those of the clock-driven run exactly. After a spike the return to
//! that fixed point takes ≈ ln(d / δ) / |λ_slow| with δ the rounding-level distance at which
//! a step stops moving the state (≈ 10⁻¹² mV in f64, ≈ 10⁻³ mV in f32 at 0.1 ms; ≈ 1 s for RS
//! in f64), so work follows activity with that tail. A positive
//! [`rest_tolerance`](IzhikevichParams::rest_tolerance) (default 0: exact) trades exactness
//! for a shorter tail: a neuron is also held once `v` and `u` are both within it of
//! `(v*, u*)` (≈ 330 ms for RS at 10⁻³ mV); the held state then differs from the clock-driven
//! one by about the tolerance, and a spike can move when a threshold crossing is decided by
//! less than that. Event-driven stepping needs grid spike times (no interpolation) and a
//! stable resting point that the step resolves (`h·|λ_fast| < 1`); otherwise the
//! population stays clock-driven. Start a population at rest with
//! [`IzhikevichParams::resting_potential`] as its initial potential, or the first steps are
//! spent settling from −65 mV.
//!
//! ## Divergence
//! Spurious spikes of an unstable step are detected, not reported as firing. With `u` frozen
//! at `u_lo` (the smaller of its values at the step's start and end), the `v` equation reads
//! `dv/dt = g(v) = 0.04·(v − m)² + q` with `m = −62.5 mV` and `q = I − u_lo − 16.25`. A spike
//! from `v_old ≤ c` (at or below the reset) is flagged when the dynamics cannot carry `v` to
//! `v_peak` within the step:
//! - `q ≤ 0` and `v_old` below the unstable fixed point `v₊ = m + √(−q/0.04)` (i.e. `v_old < m`
//!   or `g(v_old) < 0`): `v` can never pass `v₊`;
//! - or `v_peak − v_old > 2h·max(g(v_old), g(v_peak))`: `g` is convex, so its larger end value
//!   bounds `dv/dt` on the way up, and even at that rate the rise takes more than two steps.
//!
//! A non-finite update of `v` or `u` is flagged too. The fused loop stays as lean as the step
//! itself: it updates the state in place, 256 neurons at a time, keeping their start state on
//! the stack (in L1, not in a second pair of state buffers that would cost memory traffic), and
//! the check runs after each 256 for the neurons that spiked only (rare in a healthy run): their
//! update is redone from the start state, a non-finite one is flagged, and so is a spike from
//! `v_old ≤ c` that fails the criterion above. [`NeuronModel::check_divergence`] reports the first flagged step as
//! [`ModelError::Diverged`] (`neurotac neuron --model izhikevich --current=-1e5` at 0.1 ms, or
//! `--current 0 --dt 1e-2`, are such runs).

use crate::family::{AfferentPreset, Benchmark, ModelFamily, UpdateCost};
use crate::integrate::Integrator;
use crate::population::{
    BlockModel, BlockPopulation, BlockStep, Drive, InitialPotential, for_each_spike, unit_fraction,
};
use crate::real::Real;
use neurotac_core::ModelError;
#[cfg(doc)]
use neurotac_core::NeuronModel;
use serde_json::Value;
#[cfg(target_arch = "x86_64")]
use std::any::Any;
use std::marker::PhantomData;

#[cfg(target_arch = "x86_64")]
mod avx512;
mod params;
mod state;
#[cfg(all(test, target_arch = "x86_64"))]
mod tests;

use params::MODEL;
pub use params::{IzhikevichParams, REST_TOLERANCE_MV, resting_point};
pub use state::{IzhikevichConstants, IzhikevichState};
use state::{advance_state, clamp_and_reset};

const SUPPORTED: &str = "izhikevich2003, euler, exp-euler, rk2, rk4";

/// How close to the resting point (mV, in `v` and `u`) a neuron must be before
/// [`BlockModel::settled`] tries whether a step at input 0 leaves it unchanged: the fixed
/// point of the discrete step lies within rounding of the resting point (≈ 10⁻³ mV in f32 at
/// 0.1 ms, far less in f64), so this only saves the trial step while a neuron is far away.
const NEAR_REST_MV: f64 = 1.0;

/// Vertex of the `v` nullcline, `m = −5/(2·0.04)` (mV).
const V_NULLCLINE_MIN: f64 = -62.5;
/// `140 − 0.04·m²`: `g(m) = q = I − u + this` (mV/ms).
const G_AT_MIN_OFFSET: f64 = -16.25;

/// Advances one block by one step: fused update, clamp, threshold and reset, writing the
/// spike mask; returns the number of spikes and of flagged updates (module docs, Divergence).
/// `update(v, u, I)` is the integrator.
#[inline(always)]
fn step_block<F: Real, const INTERPOLATE: bool>(
    s: &mut IzhikevichState<F>,
    drive: Drive<'_>,
    k: &IzhikevichConstants<F>,
    update: &impl Fn(F, F, F) -> (F, F),
) -> BlockStep {
    match drive {
        Drive::Constant(c) => {
            let i = F::of(c);
            step_block_with::<F, INTERPOLATE>(s, k, update, |_| i)
        }
        Drive::PerNeuron(x) => {
            let x = &x[..s.v.len()];
            step_block_with::<F, INTERPOLATE>(s, k, update, |j| F::of(x[j]))
        }
    }
}

/// Neurons per chunk of the fused loop: the loop keeps the start state of one chunk on the
/// stack (2 × 256 values, in L1) for the divergence check of its spikes, so that it can update
/// the state in place.
const CHUNK: usize = 256;

#[inline(always)]
fn step_block_with<F: Real, const INTERPOLATE: bool>(
    s: &mut IzhikevichState<F>,
    k: &IzhikevichConstants<F>,
    update: &impl Fn(F, F, F) -> (F, F),
    input: impl Fn(usize) -> F,
) -> BlockStep {
    let n = s.v.len();
    let IzhikevichState {
        v,
        u,
        phi,
        u_at_spike,
        spiked,
    } = s;
    // The start state of the chunk being stepped: a scratch buffer on the stack, in L1.
    let mut start_state = ([F::zero(); CHUNK], [F::zero(); CHUNK]);
    let mut out = BlockStep::default();
    let mut start = 0;
    while start < n {
        let r = start..n.min(start + CHUNK);
        let (phi, u_at_spike) = if INTERPOLATE {
            (&mut phi[r.clone()], &mut u_at_spike[r.clone()])
        } else {
            (&mut phi[..0], &mut u_at_spike[..0])
        };
        let input = |j: usize| input(start + j);
        let step = step_chunk::<F, INTERPOLATE>(
            &mut v[r.clone()],
            &mut u[r.clone()],
            &mut spiked[r.clone()],
            phi,
            u_at_spike,
            &mut start_state,
            k,
            update,
            input,
        );
        out = out.add(step);
        start = r.end;
    }
    out
}

/// The fused update, clamp, threshold and reset of one chunk of at most [`CHUNK`] neurons, in
/// place (`phi` and `u_at_spike` empty unless `INTERPOLATE`); then the divergence check
/// (module docs) of its spikes, redone from the start state the loop kept in the caller's
/// scratch buffer on the stack (rare: keeping the fused loop free of it keeps its speed). Out
/// of line, so that the compiler knows the slices apart (no overlap checks) and the loop has
/// the registers to itself.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn step_chunk<F: Real, const INTERPOLATE: bool>(
    v: &mut [F],
    u: &mut [F],
    spiked: &mut [u8],
    phi: &mut [F],
    u_at_spike: &mut [F],
    (v_start, u_start): &mut ([F; CHUNK], [F; CHUNK]),
    k: &IzhikevichConstants<F>,
    update: &impl Fn(F, F, F) -> (F, F),
    input: impl Fn(usize) -> F,
) -> BlockStep {
    let len = v.len().min(CHUNK);
    let (v, u, spiked) = (&mut v[..len], &mut u[..len], &mut spiked[..len]);
    let (phi, u_at_spike) = if INTERPOLATE {
        (&mut phi[..len], &mut u_at_spike[..len])
    } else {
        (&mut phi[..0], &mut u_at_spike[..0])
    };
    // Constants as locals: selects between values, not between addresses (which LLVM would
    // turn into gathers).
    let IzhikevichConstants {
        c,
        d,
        v_peak,
        v_floor,
        ..
    } = *k;
    let mut count = 0u32;
    for j in 0..len {
        let (v_old, u_old) = (v[j], u[j]);
        let i = input(j);
        let (v_raw, u_raw) = update(v_old, u_old, i);
        let (v_next, u_next, u_new, spike) = clamp_and_reset(v_raw, u_raw, c, d, v_peak, v_floor);
        // Only a spike's start state is read (`diverged_spikes`): a masked store where the
        // target has one.
        if spike {
            v_start[j] = v_old;
            u_start[j] = u_old;
        }
        if INTERPOLATE {
            let f = (v_peak - v_old) / (v_raw - v_old);
            phi[j] = if spike { f } else { F::one() };
            u_at_spike[j] = u_old + f * (u_new - u_old);
        }
        v[j] = v_next;
        u[j] = u_next;
        spiked[j] = spike as u8;
        count += spike as u32;
    }
    let diverged = if count > 0 {
        diverged_spikes(k, spiked, &v_start[..len], &u_start[..len], update, input)
    } else {
        0
    };
    BlockStep {
        spikes: count as u64,
        diverged,
    }
}

/// One Euler step of the f64 block `s` by the AVX-512 loop (`avx512`), chunk by chunk with
/// the divergence check of the portable loop: the same states, spikes and checks.
///
/// # Safety
/// The CPU must have what [`crate::avx512::available`] checks.
#[cfg(target_arch = "x86_64")]
unsafe fn step_block_euler_avx512(
    s: &mut IzhikevichState<f64>,
    k: &IzhikevichConstants<f64>,
    drive: Drive<'_>,
) -> BlockStep {
    let n = s.v.len();
    let constants = avx512::EulerConstants {
        a: k.a,
        b: k.b,
        c: k.c,
        d: k.d,
        h: k.h,
        v_peak: k.v_peak,
        v_floor: k.v_floor,
    };
    let update = |v, u, i| advance_state(Integrator::Euler, k, (v, u), i, k.h, k.u_decay);
    let (mut v_start, mut u_start) = ([0.0; CHUNK], [0.0; CHUNK]);
    let mut out = BlockStep::default();
    for start in (0..n).step_by(CHUNK) {
        let r = start..n.min(start + CHUNK);
        let input = match drive {
            Drive::Constant(c) => Drive::Constant(c),
            Drive::PerNeuron(x) => Drive::PerNeuron(&x[r.clone()]),
        };
        let len = r.len();
        let (v, u, spiked) = (&mut s.v[r.clone()], &mut s.u[r.clone()], &mut s.spiked[r]);
        let start_state = (&mut v_start[..len], &mut u_start[..len]);
        // SAFETY: the caller checked the CPU.
        let spikes = unsafe { avx512::euler_chunk(v, u, spiked, start_state, &constants, input) };
        let diverged = match spikes {
            0 => 0,
            _ => {
                let (v_start, u_start) = (&v_start[..len], &u_start[..len]);
                diverged_spikes(k, spiked, v_start, u_start, &update, |j| input.at(j))
            }
        };
        out = out.add(BlockStep { spikes, diverged });
    }
    out
}

/// The spikes of a chunk's step that diverged (module docs, Divergence): each is redone from
/// its start state `v_start`, `u_start`. A non-finite update ends in a spike (NaN and +∞
/// become the peak), except `v → −∞`, which lands on the floor; the next step from there
/// overflows to a spike and is caught then. Out of line, so the fused loop keeps its
/// registers.
#[inline(never)]
fn diverged_spikes<F: Real>(
    k: &IzhikevichConstants<F>,
    spiked: &[u8],
    v_start: &[F],
    u_start: &[F],
    update: &impl Fn(F, F, F) -> (F, F),
    input: impl Fn(usize) -> F,
) -> u64 {
    let mut diverged = 0u64;
    for_each_spike(spiked, |j| {
        diverged += u64::from(spike_diverged(k, v_start[j], u_start[j], input(j), update));
    });
    diverged
}

/// `true` when the spike of the step from `(v_old, u_old)` under input `i` diverged (module
/// docs, Divergence): a non-finite update, or a spike from at or below the reset that `g(v)`
/// cannot carry to the peak.
fn spike_diverged<F: Real>(
    k: &IzhikevichConstants<F>,
    v_old: F,
    u_old: F,
    i: F,
    update: &impl Fn(F, F, F) -> (F, F),
) -> bool {
    let (m, g_offset, quad) = (F::of(V_NULLCLINE_MIN), F::of(G_AT_MIN_OFFSET), F::of(0.04));
    let (v_raw, u_raw) = update(v_old, u_old, i);
    if !(v_raw.is_finite() && u_raw.is_finite()) {
        return true;
    }
    if v_old > k.c {
        return false;
    }
    let u_lo = if u_raw < u_old { u_raw } else { u_old };
    let q = i - u_lo + g_offset;
    let dv = v_old - m;
    let g_old = quad * dv * dv + q;
    let g_peak = k.peak_rate + q;
    let g_max = if g_old > g_peak { g_old } else { g_peak };
    let zero = F::zero();
    let trapped = (q <= zero) & ((v_old < m) | (g_old < zero));
    let too_far = k.v_peak - v_old > (k.h + k.h) * g_max;
    trapped | too_far
}

/// The Izhikevich model's part of a [`BlockPopulation`] in precision `F`: parameters, block
/// state, constants and the fused step (see the module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct IzhikevichModel<F>(PhantomData<F>);

/// A population of Izhikevich neurons in precision `F` (`f32` or `f64`); built with
/// [`new`](BlockPopulation::new) (Izhikevich's 2003 scheme, grid spike times, `v = −65 mV`,
/// `u = b·v`) and the `with_*` methods of [`BlockPopulation`].
///
/// ```
/// use neurotac_neurons::{Izhikevich, IzhikevichParams, Population};
/// let mut rs = Izhikevich::<f64>::new(1, IzhikevichParams::rs());
/// let spikes = rs.run_constant(10.0, 1e-4, 10_000)?; // 1 s of I = 10 at 0.1 ms
/// assert_eq!(spikes, 23); // tonic firing at 23 Hz, as a 1 µs RK4 run also gives
/// # Ok::<(), neurotac_core::ModelError>(())
/// ```
pub type Izhikevich<F> = BlockPopulation<IzhikevichModel<F>>;

impl<F: Real> Izhikevich<F> {
    /// `(v, u)` of neuron `i` (after `prepare`).
    pub fn state_of(&self, i: usize) -> (f64, f64) {
        (self.variable(0, i), self.variable(1, i))
    }
}

/// Izhikevich at every precision, with its presets, benchmark and afferent ([`ModelFamily`]);
/// `Model<F>` is [`IzhikevichModel<F>`].
#[derive(Debug, Clone, Copy, Default)]
pub struct IzhikevichFamily;

impl ModelFamily for IzhikevichFamily {
    type Params = IzhikevichParams;
    type Model<F: Real> = IzhikevichModel<F>;

    const LABEL: &'static str = "Izhikevich";
    const INTEGRATORS: &'static [Integrator] = &[
        Integrator::Izhikevich2003,
        Integrator::Euler,
        Integrator::ExponentialEuler,
        Integrator::Rk2,
        Integrator::Rk4,
    ];
    const PRESETS: &'static [(&'static str, IzhikevichParams)] = &IzhikevichParams::PRESETS;

    /// Brian2's Izhikevich benchmark: regular spiking ([`IzhikevichParams::rs`]) under
    /// `I = 10` mV/ms from `v = −65 mV` (tonic firing at 23 Hz).
    fn benchmark() -> Benchmark<IzhikevichParams> {
        Benchmark {
            params: IzhikevichParams::rs(),
            current: 10.0,
            initial: InitialPotential::Constant(-65.0),
        }
    }

    /// Regular spiking ([`IzhikevichParams::rs`]), Izhikevich's 2003 scheme, starting at its
    /// resting point (−70 mV; an afferent without input is at rest), weight 20 (mV/ms): one RS
    /// spike per lone taxel event from rest, and again for an event 20 ms later (a smaller
    /// weight, 15, is silenced by adaptation on the second).
    fn afferent() -> AfferentPreset<IzhikevichParams> {
        let rs = IzhikevichParams::rs();
        let rest = rs
            .resting_potential()
            .expect("RS has a stable resting point");
        AfferentPreset {
            params: rs,
            initial: InitialPotential::Constant(rest),
            weight: 20.0,
            description: "Izhikevich RS afferents",
            bench_description: "Izhikevich RS afferents (izhikevich2003, f64, from rest, held at the step's fixed point)",
        }
    }

    /// The derivative as written, `dv = 0.04·v·v + 5·v + 140 − u + I` (3 mul + 4 add/sub = 7)
    /// and `du = a·(b·v − u)` (2 mul + 1 sub = 3), is 10 flops; `axpy(x, s, y) = x + s·y` is 2
    /// per variable; every neuron also computes its reset value `u + d` (1), selected only if
    /// it spikes. Products of per-step constants alone (`h/2`, `h·a`) are not counted.
    /// - euler: `f` (10) + an axpy on `(v, u)` (4) + reset (1) = **15**;
    /// - exp-euler: `v + h·dv` (7 + 2), `u∞ = b·v` (1), `u∞ + (u − u∞)·e^(−a·h)` (3), reset (1):
    ///   **14**;
    /// - izhikevich2003: two half steps of `v`, `v + h/2·dv` (9 each), then
    ///   `u + (h·a)·(b·v − u)` (4), reset (1): **23**;
    /// - rk2: `f` twice (20), an axpy (4), `x + h/2·(k₁ + k₂)` on both (6), reset (1): **31**;
    /// - rk4: `f` four times (40), three axpys (12), `x + h/6·(k₁ + 2·(k₂ + k₃) + k₄)` on both
    ///   (12), reset (1): **65**.
    ///
    /// Clamps, threshold and the divergence check (after the loop, for spikes only) are not
    /// counted. Two state variables: 17 bytes per update in `f32`, 33 in `f64`.
    fn update_cost<F: Real>(integrator: Integrator) -> Option<UpdateCost> {
        let flops = match integrator {
            Integrator::Euler => 15,
            Integrator::ExponentialEuler => 14,
            Integrator::Izhikevich2003 => 23,
            Integrator::Rk2 => 31,
            Integrator::Rk4 => 65,
            Integrator::Exact => return None,
        };
        Some(UpdateCost::of::<F>(flops, 2))
    }

    fn preset(name: &str) -> Option<IzhikevichParams> {
        IzhikevichParams::named(name)
    }
}

impl<F: Real> IzhikevichModel<F> {
    /// Kept out of line: one function per integrator, whose fused loop gets the registers to
    /// itself (inlined into one function with the other integrators' loops, its constants
    /// spilled to the stack and it ran at ≈ 0.7× the speed).
    #[inline(never)]
    fn step_with(
        k: &IzhikevichConstants<F>,
        integrator: Integrator,
        interpolate: bool,
        s: &mut IzhikevichState<F>,
        d: Drive<'_>,
        update: impl Fn(F, F, F) -> (F, F),
    ) -> BlockStep {
        if interpolate {
            let step = step_block::<F, true>(s, d, k, &update);
            if step.spikes > 0 {
                finish_interpolated_spikes(s, d, k, integrator);
            }
            step
        } else {
            step_block::<F, false>(s, d, k, &update)
        }
    }
}

/// The resting-point part of the constants at step `h` (ms).
fn rest_constants<F: Real>(p: &IzhikevichParams, h: f64) -> IzhikevichConstants<F> {
    let rest = resting_point(p.a, p.b)
        .filter(|&(v, _, fastest)| h * fastest < 1.0 && v > p.v_min && v < p.v_peak);
    let (v, u) = rest.map_or((0.0, 0.0), |(v, u, _)| (v, u));
    IzhikevichConstants {
        v_rest: F::of(v),
        u_rest: F::of(u),
        rest_tolerance: F::of(p.rest_tolerance),
        holds_at_rest: rest.is_some(),
        ..IzhikevichConstants::default()
    }
}

impl<F: Real> BlockModel for IzhikevichModel<F> {
    type Real = F;
    type Params = IzhikevichParams;
    type State = IzhikevichState<F>;
    type Constants = IzhikevichConstants<F>;

    const NAME: &'static str = MODEL;
    const VARIABLES: &'static [&'static str] = &["v", "u"];
    const SUPPORTED: &'static str = SUPPORTED;
    const DEFAULT_INTEGRATOR: Integrator = Integrator::Izhikevich2003;
    const DIVERGENCE: &'static str = "the membrane jumped from at or below the reset to the peak in one step, faster than dv/dt allows for that input, or left the finite range";
    const DEFAULT_CROSSOVER: f64 = 0.10; // 0.103: `bench neurons --crossover --n 10000` on the 2-core VM

    /// `v` and `u` (finite, the default check).
    const STATE_ARRAYS: &'static [&'static str] = &["v", "u"];

    fn supports(integrator: Integrator) -> bool {
        integrator != Integrator::Exact
    }

    fn state_array(s: &IzhikevichState<F>, a: usize) -> &[F] {
        [&s.v, &s.u][a]
    }

    fn state_array_mut(s: &mut IzhikevichState<F>, a: usize) -> &mut [F] {
        if a == 0 { &mut s.v } else { &mut s.u }
    }

    fn params_to_json(params: &IzhikevichParams) -> Option<Value> {
        params.to_json()
    }

    fn params_from_json(value: &Value) -> Result<IzhikevichParams, String> {
        IzhikevichParams::from_json(value)
    }

    fn default_initial(_params: &IzhikevichParams) -> InitialPotential {
        InitialPotential::Constant(-65.0)
    }

    fn validate(params: &IzhikevichParams) -> Result<(), ModelError> {
        params.validate::<F>()
    }

    fn constants(p: &IzhikevichParams, dt_s: f64) -> IzhikevichConstants<F> {
        let h = dt_s * 1e3;
        IzhikevichConstants {
            a: F::of(p.a),
            b: F::of(p.b),
            c: F::of(p.c),
            d: F::of(p.d),
            v_peak: F::of(p.v_peak),
            v_floor: F::of(p.v_min).max(F::min_value()),
            h: F::of(h),
            u_decay: F::of((-p.a * h).exp()),
            peak_rate: F::of(0.04 * (p.v_peak - V_NULLCLINE_MIN).powi(2)),
            ..rest_constants(p, h)
        }
    }

    fn new_block(
        p: &IzhikevichParams,
        _k: &IzhikevichConstants<F>,
        v: &[f64],
        interpolate: bool,
    ) -> IzhikevichState<F> {
        IzhikevichState {
            v: v.iter().map(|&x| F::of(x)).collect(),
            u: v.iter().map(|&x| F::of(p.b * x)).collect(),
            phi: if interpolate {
                vec![F::one(); v.len()]
            } else {
                Vec::new()
            },
            u_at_spike: if interpolate {
                vec![F::zero(); v.len()]
            } else {
                Vec::new()
            },
            spiked: vec![0; v.len()],
        }
    }

    fn step_block(
        k: &IzhikevichConstants<F>,
        integrator: Integrator,
        interpolate: bool,
        s: &mut IzhikevichState<F>,
        d: Drive<'_>,
    ) -> BlockStep {
        #[cfg(target_arch = "x86_64")]
        if integrator == Integrator::Euler && !interpolate && crate::avx512::available() {
            let (s, k): (&mut dyn Any, &dyn Any) = (s, k);
            if let (Some(s), Some(k)) = (s.downcast_mut(), k.downcast_ref()) {
                // SAFETY: `available()` checked the CPU.
                return unsafe { step_block_euler_avx512(s, k, d) };
            }
        }
        let (k, h, u_decay) = (*k, k.h, k.u_decay);
        // One closure per integrator, so each gets its own vectorised loop.
        macro_rules! with {
            ($integrator:expr) => {
                Self::step_with(
                    &k,
                    integrator,
                    interpolate,
                    s,
                    d,
                    #[inline(always)]
                    move |v, u, i| advance_state($integrator, &k, (v, u), i, h, u_decay),
                )
            };
        }
        match integrator {
            Integrator::Izhikevich2003 => with!(Integrator::Izhikevich2003),
            Integrator::Euler => with!(Integrator::Euler),
            Integrator::ExponentialEuler => with!(Integrator::ExponentialEuler),
            Integrator::Rk2 => with!(Integrator::Rk2),
            Integrator::Rk4 => with!(Integrator::Rk4),
            Integrator::Exact => unreachable!("rejected by prepare"),
        }
    }

    fn spike_mask(s: &IzhikevichState<F>) -> &[u8] {
        &s.spiked
    }

    /// Izhikevich skips idle neurons when the resting point exists and is stable, the step
    /// resolves its fastest decay, the tolerance is positive and spikes are on the grid (module
    /// docs, Event-driven stepping).
    fn skips_idle(
        _params: &IzhikevichParams,
        k: &IzhikevichConstants<F>,
        _integrator: Integrator,
        interpolate: bool,
    ) -> bool {
        k.holds_at_rest && !interpolate
    }

    /// A step at input 0 leaves `(v, u)` unchanged bit for bit (a fixed point of the discrete
    /// step, so holding it is exact), or, with a positive tolerance, `v` and `u` are both
    /// within it of the resting point (module docs, Event-driven stepping).
    fn settled(
        k: &IzhikevichConstants<F>,
        integrator: Integrator,
        s: &IzhikevichState<F>,
        j: usize,
    ) -> bool {
        let (v, u) = (s.v[j], s.u[j]);
        let (dv, du) = ((v - k.v_rest).abs(), (u - k.u_rest).abs());
        if k.rest_tolerance > F::zero() && dv <= k.rest_tolerance && du <= k.rest_tolerance {
            return true;
        }
        // Far from rest a neuron is not at a fixed point: skip the trial step.
        let near = F::of(NEAR_REST_MV);
        if !(dv <= near && du <= near) {
            return false;
        }
        let (v_raw, u_raw) = advance_state(integrator, k, (v, u), F::zero(), k.h, k.u_decay);
        let (v_next, u_next, _, spike) =
            clamp_and_reset(v_raw, u_raw, k.c, k.d, k.v_peak, k.v_floor);
        !spike && v_next == v && u_next == u
    }

    /// The fused loop's update, clamps, threshold, reset and divergence check for one neuron.
    fn step_neuron(
        k: &IzhikevichConstants<F>,
        integrator: Integrator,
        s: &mut IzhikevichState<F>,
        j: usize,
        input: f64,
    ) -> BlockStep {
        let (v_old, u_old, i) = (s.v[j], s.u[j], F::of(input));
        let update = |v, u, i| advance_state(integrator, k, (v, u), i, k.h, k.u_decay);
        let (v_raw, u_raw) = update(v_old, u_old, i);
        let (v, u, _, spike) = clamp_and_reset(v_raw, u_raw, k.c, k.d, k.v_peak, k.v_floor);
        s.v[j] = v;
        s.u[j] = u;
        BlockStep {
            spikes: u64::from(spike),
            diverged: u64::from(spike && spike_diverged(k, v_old, u_old, i, &update)),
        }
    }

    fn spike_fractions(s: &IzhikevichState<F>) -> &[F] {
        &s.phi
    }

    fn variable(s: &IzhikevichState<F>, var: usize, j: usize) -> f64 {
        if var == 0 { s.v[j].f64() } else { s.u[j].f64() }
    }
}

/// After an interpolated spike at fraction φ: reset at the crossing (`v ← c`, `u ← u(φ) + d`)
/// and integrate over the rest of the step, `(1 − φ)·h`, with the population's integrator.
fn finish_interpolated_spikes<F: Real>(
    s: &mut IzhikevichState<F>,
    drive: Drive<'_>,
    k: &IzhikevichConstants<F>,
    integrator: Integrator,
) {
    let IzhikevichState {
        v,
        u,
        phi,
        u_at_spike,
        spiked,
        ..
    } = s;
    for_each_spike(spiked, |j| {
        let f = F::of(unit_fraction(phi[j].f64()));
        phi[j] = f;
        let h = k.h * (F::one() - f);
        let u0 = u_at_spike[j] + k.d;
        let i = F::of(drive.at(j));
        let (v_next, u_next) = advance_state(integrator, k, (k.c, u0), i, h, (-k.a * h).exp());
        // The remainder is shorter than a step: a second spike in it is not modelled.
        let v_next = if v_next < k.v_peak {
            v_next
        } else {
            k.v_peak - F::of(1e-3)
        };
        v[j] = if v_next > k.v_floor {
            v_next
        } else {
            k.v_floor
        };
        u[j] = if u_next.is_finite() { u_next } else { u0 };
    });
}
