//! The DVS pixel (spec §3.2): per patch step, the lin-log input, the photoreceptor low-pass
//! integrated exactly for a linearly ramping input, threshold crossings at ESIM's interpolated
//! times, the hardware-like refractory reset, noise events resetting the pixel (v2e), and the
//! output time with latency and jitter (see the parent module's docs for the equations).

use super::PixelModel;
use super::event::{NOISE_LABEL, RawEvent};
use super::render::{PinSlots, Tables, integral_to_i32, render_offset, render_offsets};
use neurotac_core::seed_hash::splitmix64;
use neurotac_core::time::{s_to_us, us_to_s};

/// e^(−x) for x ≥ 0 in f32, inlined (absolute error < 3·10⁻⁷; flushes to ≈ 2⁻¹²⁵ beyond
/// x ≈ 86): 2^(−x·log₂e) split into an exponent and a degree-6 polynomial of the fraction.
#[inline(always)]
fn exp_neg(x: f32) -> f32 {
    let y = (-x * std::f32::consts::LOG2_E).max(-125.0);
    let n = (y + 0.5).floor();
    let f = y - n;
    // 2^f on [−½, ½]: Taylor series of e^(f·ln 2), degree 6 (remainder < 1.3·10⁻⁷).
    let l = std::f32::consts::LN_2 * f;
    let p = 1.0
        + l * (1.0
            + l * (0.5
                + l * (1.0 / 6.0 + l * (1.0 / 24.0 + l * (1.0 / 120.0 + l * (1.0 / 720.0))))));
    p * f32::from_bits(((integral_to_i32(n) + 127) as u32) << 23)
}

/// The largest of `values` (0 when empty; NaNs ignored, as by `f32::max`), in independent
/// lanes so the reduction vectorises; `max` is exact and order-free on non-NaN values, so the
/// result equals a sequential fold.
fn max_of(values: &[f32]) -> f32 {
    const LANES: usize = 16;
    let mut lanes = [0.0f32; LANES];
    let chunks = values.chunks_exact(LANES);
    let rest = chunks.remainder();
    for chunk in chunks {
        for (m, &v) in lanes.iter_mut().zip(chunk) {
            *m = m.max(v);
        }
    }
    rest.iter().chain(&lanes).fold(0.0f32, |m, &v| m.max(v))
}

/// What the first pass of a patch step reads: the tables, the pins, and the patch's slices
/// of pixel geometry, thresholds and state (all of one length).
struct PassInputs<'a> {
    tables: &'a Tables,
    pin_dx: &'a PinSlots,
    pin_dy: &'a PinSlots,
    /// The owner pin's displacement (px).
    own: (f32, f32),
    own_dx: &'a [f32],
    own_dy: &'a [f32],
    other: &'a [u8],
    other_dx: &'a [f32],
    other_dy: &'a [f32],
    c_on: &'a [f32],
    c_off: &'a [f32],
    l_ref: &'a [f32],
    dt: f32,
}

/// The first pass of a patch step over every pixel: renders L, integrates the low-pass
/// (updating L, L̃ and the rate in place), and records L̃ at the step's start, the filter rate
/// |L − L̃|/τ_p and whether the pixel can emit anything this step. Branch-free, and the
/// outputs are separate arguments (so the compiler knows they alias nothing it reads): it
/// vectorises.
///
/// `TWO_PINS`: whether a second pin renders into these pixels (else only the owner does).
#[inline(never)]
fn filter_pass<const TWO_PINS: bool>(
    inp: &PassInputs,
    l_in: &mut [f32],
    l_filt: &mut [f32],
    rate_old: &mut [f32],
    f_start: &mut [f32],
    filter_rate: &mut [f32],
    slow: &mut [bool],
) {
    let n = l_in.len();
    let (l_filt, rate_old, f_start) = (&mut l_filt[..n], &mut rate_old[..n], &mut f_start[..n]);
    let (filter_rate, slow) = (&mut filter_rate[..n], &mut slow[..n]);
    let (own_dx, own_dy, other) = (&inp.own_dx[..n], &inp.own_dy[..n], &inp.other[..n]);
    let (other_dx, other_dy) = (&inp.other_dx[..n], &inp.other_dy[..n]);
    let (c_on, c_off, l_ref) = (&inp.c_on[..n], &inp.c_off[..n], &inp.l_ref[..n]);
    let (own_x, own_y) = inp.own;
    let dt = inp.dt;
    for k in 0..n {
        let own = (own_dx[k] - own_x, own_dy[k] - own_y);
        let (l_new, rate) = if TWO_PINS {
            let o = other[k] as usize;
            let second = (other_dx[k] - inp.pin_dx[o], other_dy[k] - inp.pin_dy[o]);
            render_offsets(inp.tables, own, second)
        } else {
            render_offset(inp.tables, own)
        };
        let l_old = l_in[k];
        let f_old = l_filt[k];
        let x = dt * 0.5 * (rate + rate_old[k]);
        let a = exp_neg(x);
        // g = (1 − e^(−x))/x; its series below x = 0.1 (both computed: a select).
        let series = 1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x / 120.0)));
        let direct = (1.0 - a) / x.max(0.1);
        let g = if x > 0.1 { direct } else { series };
        // Exact first-order response to an input ramping from l_old to l_new.
        let f_new = l_new - (l_new - l_old) * g + (f_old - l_old) * a;
        filter_rate[k] = (l_new - f_new).abs() * rate;
        let r = l_ref[k];
        // Non-short-circuit `|`: one mask, no branches.
        slow[k] = (f_new - r >= c_on[k]) | (r - f_new >= c_off[k]);
        f_start[k] = f_old;
        l_in[k] = l_new;
        l_filt[k] = f_new;
        rate_old[k] = rate;
    }
}

/// Also marks for the slow path every pixel held in reset at `t0` or with a noise event due
/// before `t1` (a pass of its own: its f64 lanes would halve the width of the first pass).
fn mark_due(reset_until: &[f64], next_noise: &[f64], (t0, t1): (f64, f64), slow: &mut [bool]) {
    let n = slow.len();
    let (reset_until, next_noise) = (&reset_until[..n], &next_noise[..n]);
    for k in 0..n {
        slow[k] |= (reset_until[k] > t0) | (next_noise[k] < t1);
    }
}

impl PixelModel {
    /// The state of the pixels of `patch` at the start of slide `seed`: settled on the rendered
    /// image, with the reference level drawn between the thresholds
    /// (`PixelParams::random_initial_reference`) from a hash of (slide, pixel), so it does not
    /// depend on the order patches are simulated in.
    pub(super) fn init_patch(&mut self, patch: usize, seed: u64) {
        let (start, end) = self.patches.ranges[patch];
        let random = self.params.pixel.random_initial_reference;
        for j in start..end {
            let (l, rate) = self.render(j, patch);
            self.l_in[j] = l;
            self.l_filt[j] = l;
            self.l_ref[j] = if random {
                // A 24-bit uniform in [0, 1): L̃ − L_ref = u·(C⁺ + C⁻) − C⁻.
                let id = self.patches.seed_index[j] as u64;
                let u = (splitmix64(seed ^ splitmix64(0x7265_6600 ^ id)) >> 40) as f32
                    / (1u32 << 24) as f32;
                l + self.c_off[j] - u * (self.c_on[j] + self.c_off[j])
            } else {
                l
            };
            self.rate_old[j] = rate;
            self.reset_until[j] = f64::NEG_INFINITY;
            self.last_out_us[j] = i64::MIN;
            self.n_events[j] = 0;
        }
    }

    pub(super) fn patch_owner(&self, j: usize) -> usize {
        self.patches.ranges.partition_point(|&(_, end)| end <= j)
    }

    /// One step of the pixels of `patch` (= its owner pin) from `t0` to `t1`; returns the largest filter rate
    /// |L − L̃|/τ_p at `t1`.
    ///
    /// Two passes: a branch-free pass over every pixel (render, low-pass, "can this pixel
    /// emit anything this step?") that the compiler vectorises, then the slow path
    /// ([`events`](Self::events)) for the few pixels that can — a pixel that crosses no
    /// threshold, is not held in reset and has no noise event due emits nothing, and its step
    /// is complete after the first pass. Per pixel, the arithmetic is the same as one scalar
    /// update in the same order, so the result does not depend on the vector width.
    pub(super) fn step(
        &mut self,
        patch: usize,
        t0: f64,
        t1: f64,
        seed: u64,
        out: &mut Vec<RawEvent>,
    ) -> f32 {
        let (start, end) = self.patches.ranges[patch];
        let n = end - start;
        let dt = (t1 - t0) as f32;
        let second = self.patches.second[patch];
        for (from, to, two_pins) in [(start, second, false), (second, end, true)] {
            let p = &self.patches;
            let (pin_dx, pin_dy) = (&*self.pin_dx, &*self.pin_dy);
            let inputs = PassInputs {
                tables: &self.tables,
                pin_dx,
                pin_dy,
                own: (pin_dx[patch], pin_dy[patch]),
                own_dx: &p.own_dx[from..to],
                own_dy: &p.own_dy[from..to],
                other: &p.other[from..to],
                other_dx: &p.other_dx[from..to],
                other_dy: &p.other_dy[from..to],
                c_on: &self.c_on[from..to],
                c_off: &self.c_off[from..to],
                l_ref: &self.l_ref[from..to],
                dt,
            };
            let pass = if two_pins {
                filter_pass::<true>
            } else {
                filter_pass::<false>
            };
            let scratch = from - start..to - start;
            pass(
                &inputs,
                &mut self.l_in[from..to],
                &mut self.l_filt[from..to],
                &mut self.rate_old[from..to],
                &mut self.f_start[scratch.clone()],
                &mut self.filter_rate[scratch.clone()],
                &mut self.slow[scratch],
            );
        }
        mark_due(
            &self.reset_until[start..end],
            &self.next_noise[start..end],
            (t0, t1),
            &mut self.slow[..n],
        );
        for k in 0..n {
            let j = start + k;
            if self.slow[k] {
                let (f0, f1) = (self.f_start[k], self.l_filt[j]);
                self.events(j, t0, t1, f0, f1, seed, out);
            }
        }
        max_of(&self.filter_rate[..n])
    }

    /// The slow path of one pixel over one step: threshold crossings, refractory resets and
    /// noise events, in time order. L̃ is linear from `f0` at `t0` to `f1` at `t1`.
    #[allow(clippy::too_many_arguments)]
    #[cold]
    pub(super) fn events(
        &mut self,
        j: usize,
        t0: f64,
        t1: f64,
        f0: f32,
        f1: f32,
        seed: u64,
        out: &mut Vec<RawEvent>,
    ) {
        let t_ref = self.params.pixel.refractory_s;
        let dt = t1 - t0;
        let slope = (f1 - f0) as f64 / dt;
        let at = |t: f64| (f0 as f64 + slope * (t - t0)) as f32;
        let mut ta = t0;
        loop {
            if self.reset_until[j] > ta {
                // Held in reset: no events, noise included.
                let until = self.reset_until[j];
                while self.next_noise[j] < until.min(t1) {
                    self.advance_noise(j);
                }
                if until >= t1 {
                    self.l_ref[j] = f1;
                    return;
                }
                ta = until;
                self.l_ref[j] = at(ta);
                self.reset_until[j] = f64::NEG_INFINITY;
            }
            let tn = self.next_noise[j];
            let tb = tn.min(t1);
            let r = self.l_ref[j];
            let fb = at(tb);
            let crossing = if fb - r >= self.c_on[j] && slope > 0.0 {
                Some((true, r + self.c_on[j]))
            } else if r - fb >= self.c_off[j] && slope < 0.0 {
                Some((false, r - self.c_off[j]))
            } else {
                None
            };
            if let Some((on, level)) = crossing {
                let te = (t0 + (level - f0) as f64 / slope).clamp(ta, tb);
                let t_out = self.emit(j, te, on, seed, out);
                self.l_ref[j] = level;
                self.hold_reset(j, t_out, t_ref);
                ta = te;
                continue;
            }
            if tn < t1 {
                let idx = self.noise_cursor[j] as usize;
                let on = self.noise_on[idx];
                let t_out = self.push(j, tn, on, NOISE_LABEL, out);
                self.n_events[j] += 1;
                self.advance_noise(j);
                self.l_ref[j] = at(tn);
                self.hold_reset(j, t_out, t_ref);
                ta = tn;
                continue;
            }
            return;
        }
    }

    /// Holds pixel `j` in reset until `t_ref` after its event's readout at `t_out`.
    pub(super) fn hold_reset(&mut self, j: usize, t_out: f64, t_ref: f64) {
        self.reset_until[j] = if t_ref > 0.0 {
            t_out + t_ref
        } else {
            f64::NEG_INFINITY
        };
    }

    /// Emits a signal event crossing at `te`; returns its output time (s).
    pub(super) fn emit(
        &mut self,
        j: usize,
        te: f64,
        on: bool,
        seed: u64,
        out: &mut Vec<RawEvent>,
    ) -> f64 {
        let p = &self.params.pixel;
        let k = self.n_events[j];
        self.n_events[j] = k + 1;
        let id = self.patches.seed_index[j] as u64;
        let h = splitmix64(seed ^ splitmix64((id << 32) | k as u64));
        let u = ((h >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
        let t = te + p.latency_s - p.latency_jitter_s * u.ln();
        let owner = self.patch_owner(j) as u8;
        let label = self.signal_source(j, owner);
        self.push(j, t, on, label, out)
    }

    /// The pin an event of pixel `j` is attributed to: the one contributing more light now.
    pub(super) fn signal_source(&self, j: usize, owner: u8) -> u8 {
        let p = &self.patches;
        let other = p.other[j];
        if other == NOISE_LABEL {
            return owner;
        }
        let (o, w) = (other as usize, owner as usize);
        let d_own = (p.own_dx[j] - self.pin_dx[w]).powi(2) + (p.own_dy[j] - self.pin_dy[w]).powi(2);
        let d_other =
            (p.other_dx[j] - self.pin_dx[o]).powi(2) + (p.other_dy[j] - self.pin_dy[o]).powi(2);
        if d_other < d_own { other } else { owner }
    }

    /// Outputs an event of pixel `j` at `t` (whole µs, after the pixel's previous event);
    /// returns the output time (s).
    pub(super) fn push(
        &mut self,
        j: usize,
        t: f64,
        on: bool,
        label: u8,
        out: &mut Vec<RawEvent>,
    ) -> f64 {
        let t_us = s_to_us(t).max(self.last_out_us[j].saturating_add(1));
        self.last_out_us[j] = t_us;
        out.push(RawEvent {
            t_us,
            y: self.patches.y[j],
            x: self.patches.x[j],
            on,
            label,
        });
        us_to_s(t_us)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_exponential_matches_the_library() {
        for i in 0..20_000 {
            let x = i as f32 * 0.005;
            let (a, b) = (exp_neg(x), (-x).exp());
            // Absolute error (what the low-pass sees) and relative error (f32 rounding of
            // x·log₂e grows with x).
            assert!((a - b).abs() <= 3e-7, "{x}: {a} vs {b}");
            assert!(x > 80.0 || (a - b).abs() <= 1e-5 * b, "{x}: {a} vs {b}");
        }
        assert!(exp_neg(1e6) < 1e-37);
    }

    /// The pixel step as one scalar loop, written out independently: the lookups and the
    /// exponent through saturating casts, the second pin's coverage added only where there is
    /// one, the slow path taken inline.
    mod reference {
        use super::super::super::PixelModel;
        use super::super::super::event::{NOISE_LABEL, RawEvent};

        fn lookup(table: &[f32], x: f32) -> f32 {
            let i = x as usize;
            let f = x - i as f32;
            table[i] + f * (table[i + 1] - table[i])
        }

        fn exp_neg(x: f32) -> f32 {
            let y = (-x * std::f32::consts::LOG2_E).max(-125.0);
            let n = (y + 0.5).floor();
            let l = std::f32::consts::LN_2 * (y - n);
            let p = 1.0
                + l * (1.0
                    + l * (0.5
                        + l * (1.0 / 6.0
                            + l * (1.0 / 24.0 + l * (1.0 / 120.0 + l * (1.0 / 720.0))))));
            p * f32::from_bits((((n as i32) + 127) as u32) << 23)
        }

        pub(super) fn step(
            m: &mut PixelModel,
            patch: usize,
            t0: f64,
            t1: f64,
            seed: u64,
            out: &mut Vec<RawEvent>,
        ) -> f32 {
            let (start, end) = m.patches.ranges[patch];
            let dt = (t1 - t0) as f32;
            let mut max_rate = 0.0f32;
            for j in start..end {
                let (t, p) = (&m.tables, &m.patches);
                let n_cov = t.coverage.len() - 2;
                let coverage =
                    |rho2: f32| lookup(&t.coverage[..], (rho2 * t.rho2_inv_step).min(n_cov as f32));
                let (ex, ey) = (p.own_dx[j] - m.pin_dx[patch], p.own_dy[j] - m.pin_dy[patch]);
                let mut cover = coverage(ex * ex + ey * ey);
                if p.other[j] != NOISE_LABEL {
                    let o = p.other[j] as usize;
                    let (fx, fy) = (p.other_dx[j] - m.pin_dx[o], p.other_dy[j] - m.pin_dy[o]);
                    cover += coverage(fx * fx + fy * fy);
                }
                let x = (cover * t.s_inv_step).min((t.log_intensity.len() - 2) as f32);
                let (l_new, rate) = (lookup(&t.log_intensity[..], x), lookup(&t.inv_tau[..], x));
                let (l_old, f_old) = (m.l_in[j], m.l_filt[j]);
                let x = dt * 0.5 * (rate + m.rate_old[j]);
                let a = exp_neg(x);
                let g = if x > 0.1 {
                    (1.0 - a) / x.max(0.1)
                } else {
                    1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x / 120.0)))
                };
                let f_new = l_new - (l_new - l_old) * g + (f_old - l_old) * a;
                max_rate = max_rate.max((l_new - f_new).abs() * rate);
                let r = m.l_ref[j];
                if f_new - r >= m.c_on[j]
                    || r - f_new >= m.c_off[j]
                    || m.reset_until[j] > t0
                    || m.next_noise[j] < t1
                {
                    m.events(j, t0, t1, f_old, f_new, seed, out);
                }
                m.l_in[j] = l_new;
                m.l_filt[j] = f_new;
                m.rate_old[j] = rate;
            }
            max_rate
        }
    }

    #[test]
    fn vectorised_pixel_step_equals_the_scalar_step_bit_for_bit() {
        use crate::geometry::PinGeometry;
        use crate::sim::{Camera, SimParams};

        let mut params = SimParams::default();
        // Busy pixels: plenty of noise events and resets to take the slow path through.
        params.noise.shot_rate_hz = 40.0;
        let camera = Camera::new(&params, 3);
        let default = PinGeometry::default().pin_positions_px();
        // Also a pin doubled in place: its patch has no pixel that it alone renders into.
        let doubled: Vec<_> = default.iter().copied().chain([default[0]]).collect();
        let patches = &PixelModel::new(&params, &doubled, &camera).unwrap().patches;
        assert_eq!(patches.second[0], patches.ranges[0].0);
        for pins in [default, doubled] {
            step_both_ways(&params, &camera, &pins);
        }
    }

    fn step_both_ways(
        params: &crate::sim::SimParams,
        camera: &crate::sim::Camera,
        pins: &[(f64, f64)],
    ) {
        use rand::{RngExt, SeedableRng};
        use rand_chacha::ChaCha8Rng;
        let mut fast = PixelModel::new(params, pins, camera).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let (duration, seed) = (0.5, 77);
        let mut noise = Vec::new();
        fast.draw_noise(camera, duration, &mut rng, &mut noise);
        for patch in 0..pins.len() {
            fast.init_patch(patch, seed);
        }
        let mut slow = fast.clone();
        let (mut out_fast, mut out_slow) = (Vec::new(), Vec::new());
        let mut t = 0.0;
        while t < duration {
            // Random jumps and drifts of every pin (px), random step lengths (s).
            let t1 = (t + 10f64.powf(rng.random_range(-5.0..-2.0))).min(duration);
            for pin in 0..pins.len() {
                let (dx, dy) = (rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0));
                for m in [&mut fast, &mut slow] {
                    m.pin_dx[pin] = dx;
                    m.pin_dy[pin] = dy;
                }
            }
            for patch in 0..pins.len() {
                let a = fast.step(patch, t, t1, seed, &mut out_fast);
                let b = reference::step(&mut slow, patch, t, t1, seed, &mut out_slow);
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "largest rate of patch {patch} at {t}"
                );
            }
            t = t1;
        }
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let bits64 = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&fast.l_in), bits(&slow.l_in));
        assert_eq!(bits(&fast.l_filt), bits(&slow.l_filt));
        assert_eq!(bits(&fast.l_ref), bits(&slow.l_ref));
        assert_eq!(bits(&fast.rate_old), bits(&slow.rate_old));
        assert_eq!(bits64(&fast.reset_until), bits64(&slow.reset_until));
        assert_eq!(fast.n_events, slow.n_events);
        assert_eq!(fast.noise_cursor, slow.noise_cursor);
        // Signal and noise events of lone and shared pixels alike, in the same order.
        assert_eq!(out_fast, out_slow);
        let shared = |e: &RawEvent| {
            let j = fast.patches.index_of[e.y as usize * 240 + e.x as usize] as usize;
            fast.patches.other[j] != NOISE_LABEL
        };
        assert!(out_fast.iter().any(|e| e.label == NOISE_LABEL));
        assert!(out_fast.iter().any(|e| e.label != NOISE_LABEL && shared(e)));
        assert!(
            out_fast
                .iter()
                .any(|e| e.label != NOISE_LABEL && !shared(e))
        );
    }
}
