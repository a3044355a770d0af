//! One recording as the lab's loop makes it: press, dwell, slide, with the recording's start and
//! end where the host program puts them.
//!
//! **The protocol (a decision, from two sources).** The lab's DAVIS240 slide script
//! (`bward-cherrier/neuromorphic-data-gathering`, `experiments/NeuroTac/NeuroTac_DAVIS240/ABB_slides.py`,
//! with the sensor class `source_code/tactile-core-neuro/python/core/sensor/tactile_sensor_neuro.py`)
//! starts a logging thread, whose first act is to read the host clock (`starttime = dv.now()`:
//! the recording's zero), and then, on the main thread, sets the robot's frame (two frame
//! commands and a pose query) and makes blocking moves, each a socket call that returns when the
//! controller has reached its fine point (`MoveL` with zone `z0`, `cri/abb/abb_server.mod`):
//! press 5 mm down at the linear speed, `sleep(0.1)`, slide, `sleep(0.1)`, lift, return, then
//! stops the logging. That script slides 20 mm at 10 mm/s; the paper slides 60 mm at 15 mm/s.
//! The paper's source text keeps five sample durations in a comment (13.177 / 6.688 / 4.528 /
//! 3.439 / 2.784 s at 5 / 10 / 15 / 20 / 25 mm/s), which a least-squares fit puts at
//! T = 64.93 mm / v + 0.193 s (residuals ≤ 6.4 ms): exactly **one 5 mm move and the 60 mm slide
//! at the linear speed plus about one dwell**. A recording that also held the lift (or the
//! return) would grow by 5 (or 60) mm / v more. So the ICRA recordings are taken as the script's
//! loop cut after the slide: logging starts, press, dwell, slide, logging stops; the lift and
//! return happen after the recording. What is taken from the script: the order, the 5 mm
//! press at the linear speed, the 0.1 s dwell, the host-clock zero and the blocking calls;
//! from the paper: 60 mm at 15 mm/s; from the durations: which moves lie inside.
//!
//! **Timeline** (s from the recording's zero; `ℓ_k` are the latencies of the loop's blocking
//! steps, below):
//!
//! ```text
//! press starts   t_p = ℓ₁ + ℓ₂ + ℓ₃ + ℓ₄                 (3 frame calls, then MoveL's start)
//! press ends     t_p + T(travel)                          T(d) = d/v + v/a (trapezoid; triangle if short)
//! slide starts   t_s = t_p + T(travel) + ℓ₅ + dwell + ℓ₆   (fine point and reply; sleep; MoveL's start)
//! slide ends     t_s + T(distance)
//! recording ends t_s + T(distance) + ℓ₇ + ℓ₈               (fine point and reply; the thread's next batch)
//! ```
//!
//! **Latencies.** Eight blocking steps share the loop's overhead, which the paper's durations
//! measure: with the two moves (5 + 60 mm) and their ramps at the IRB 120's acceleration, the
//! durations leave 0.0855 s beside the 0.1 s dwell (`kinematics.loop_overhead_s`), and they
//! scatter about that law with a standard deviation of 6.4 ms (`kinematics.loop_jitter_s`, four
//! degrees of freedom: uncertain by a factor of about 2). Each step takes `overhead/8` on
//! average and jitters independently by `jitter/√8` (clipped at four standard deviations), an
//! assumption: nothing says how the overhead splits. So the slide's onset, six steps after the
//! zero, spreads by `jitter·√(6/8)` ≈ 5.5 ms, and the press's start by ≈ 4.5 ms — a spread
//! *derived* from the loop's structure and the durations' scatter, not measured on onsets.
//!
//! **Acceleration.** The durations show no ramp: the fit `T = 65/v + c + k·v` gives
//! k = 0.0003 ± 0.0004 s²/mm, where two moves at acceleration a add k = 2/a; so a ≳ 1.7 m/s² at
//! two standard deviations, and a 300 mm/s² ramp (k = 0.0067) is excluded. The default is the
//! IRB 120's maximum TCP acceleration, 28 m/s² (ABB product specification).

use super::params::{KinematicsParams, SimParams};
use super::random::gaussian;
use rand_chacha::ChaCha8Rng;

/// Blocking steps of the loop before the press moves (two frame commands, a pose query, the
/// press's `MoveL` start).
pub const STEPS_BEFORE_PRESS: usize = 4;
/// Blocking steps between the press's end and the slide's start, besides the dwell (the press's
/// fine point and reply, the slide's `MoveL` start).
pub const STEPS_BETWEEN_MOVES: usize = 2;
/// Blocking steps after the slide's end (its fine point and reply, the logging thread's last
/// batch).
pub const STEPS_AFTER_SLIDE: usize = 2;
/// All blocking steps of one recording.
pub const LOOP_STEPS: usize = STEPS_BEFORE_PRESS + STEPS_BETWEEN_MOVES + STEPS_AFTER_SLIDE;

/// Standard deviations a step's latency may stray from its mean (clipped beyond): keeps every
/// recording within [`SimParams::duration_s`].
const LATENCY_CLIP_SD: f64 = 4.0;

/// The paper's sample durations (s) at the slide speeds (mm/s), from the comment in its source
/// text (`shared/paper/neurotac.tex`, section Results).
pub const PAPER_DURATIONS: [(f64, f64); 5] = [
    (5.0, 13.177),
    (10.0, 6.688),
    (15.0, 4.528),
    (20.0, 3.439),
    (25.0, 2.784),
];

/// A trapezoidal speed profile over `distance` at cruise speed `v` and acceleration `a` (a
/// triangle when the distance is too short to reach `v`), with its constants worked out once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trapezoid {
    /// Acceleration (mm/s²) and distance (mm).
    a: f64,
    d: f64,
    /// Peak speed: v, or √(a·d) for a triangular profile (mm/s).
    peak: f64,
    /// Ramp, cruise and total durations (s).
    ramp_s: f64,
    cruise_s: f64,
    total_s: f64,
}

impl Trapezoid {
    /// The profile of a move of `distance_mm` at `speed_mm_s` with `acceleration_mm_s2`.
    pub fn new(distance_mm: f64, speed_mm_s: f64, acceleration_mm_s2: f64) -> Self {
        let (d, v, a) = (distance_mm.max(0.0), speed_mm_s, acceleration_mm_s2);
        let peak = v.min((a * d).sqrt());
        let ramp_s = peak / a;
        let total_s = if d <= 0.0 {
            0.0
        } else if d >= v * v / a {
            d / v + v / a
        } else {
            2.0 * (d / a).sqrt()
        };
        Self {
            a,
            d,
            peak,
            ramp_s,
            cruise_s: total_s - 2.0 * ramp_s,
            total_s,
        }
    }

    /// Duration of the move (s).
    pub fn duration_s(&self) -> f64 {
        self.total_s
    }

    /// Position (mm from the start) and speed (mm/s) at `t_s` after the move's start.
    #[inline]
    pub fn at(&self, t: f64) -> (f64, f64) {
        let (a, d, ta) = (self.a, self.d, self.ramp_s);
        if t <= 0.0 || d <= 0.0 {
            return (0.0, 0.0);
        }
        if t >= self.total_s {
            return (d, 0.0);
        }
        if t < ta {
            (0.5 * a * t * t, a * t)
        } else if t < ta + self.cruise_s {
            (0.5 * a * ta * ta + self.peak * (t - ta), self.peak)
        } else {
            let r = self.total_s - t;
            (d - 0.5 * a * r * r, a * r)
        }
    }
}

/// One recording's timeline (see the module docs): when the press and the slide start and the
/// recording ends, and the two moves' profiles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recording {
    /// When the press starts moving down (s).
    pub press_start_s: f64,
    /// When the slide starts (s).
    pub slide_start_s: f64,
    /// When the recording ends (s): events lie in `[0, end_s)`.
    pub end_s: f64,
    press: Trapezoid,
    slide: Trapezoid,
}

impl Recording {
    /// The timeline with every step at its mean latency.
    pub fn nominal(params: &SimParams) -> Self {
        Self::with_latencies(params, &[mean_latency_s(params); LOOP_STEPS])
    }

    /// The timeline with each step's latency drawn from `rng` (mean and spread in the module
    /// docs).
    pub fn draw(params: &SimParams, rng: &mut ChaCha8Rng) -> Self {
        let (mean, sd) = (mean_latency_s(params), step_jitter_s(params));
        let lo = (mean - LATENCY_CLIP_SD * sd).max(0.0);
        let hi = mean + LATENCY_CLIP_SD * sd;
        let latencies: [f64; LOOP_STEPS] =
            std::array::from_fn(|_| (mean + sd * gaussian(rng)).clamp(lo, hi));
        Self::with_latencies(params, &latencies)
    }

    /// The timeline with every step at its longest latency: the longest recording `params`
    /// make ([`SimParams::duration_s`]).
    pub fn longest(params: &SimParams) -> Self {
        let longest = mean_latency_s(params) + LATENCY_CLIP_SD * step_jitter_s(params);
        Self::with_latencies(params, &[longest; LOOP_STEPS])
    }

    fn with_latencies(params: &SimParams, latencies: &[f64; LOOP_STEPS]) -> Self {
        let k = &params.kinematics;
        let press = Trapezoid::new(k.press_travel_mm, k.speed_mm_s, k.acceleration_mm_s2);
        let slide = Trapezoid::new(k.distance_mm, k.speed_mm_s, k.acceleration_mm_s2);
        let (before, rest) = latencies.split_at(STEPS_BEFORE_PRESS);
        let (between, after) = rest.split_at(STEPS_BETWEEN_MOVES);
        let sum = |s: &[f64]| s.iter().sum::<f64>();
        let press_start_s = sum(before);
        let slide_start_s = press_start_s + press.duration_s() + sum(between) + k.dwell_s;
        Self {
            press_start_s,
            slide_start_s,
            end_s: slide_start_s + slide.duration_s() + sum(after),
            press,
            slide,
        }
    }

    /// When the press reaches its depth (s).
    pub fn press_end_s(&self) -> f64 {
        self.press_start_s + self.press.duration_s()
    }

    /// When the slide stops (s).
    pub fn slide_end_s(&self) -> f64 {
        self.slide_start_s + self.slide.duration_s()
    }

    /// How far the press has moved down at `t_s` (mm, 0 … travel).
    #[inline]
    pub fn press_travel_at(&self, t_s: f64) -> f64 {
        self.press.at(t_s - self.press_start_s).0
    }

    /// The base's slide position (mm) and speed (mm/s) at `t_s`.
    #[inline]
    pub fn slide_at(&self, t_s: f64) -> (f64, f64) {
        self.slide.at(t_s - self.slide_start_s)
    }
}

/// Mean latency of one blocking step (s): the loop's overhead over its [`LOOP_STEPS`].
fn mean_latency_s(params: &SimParams) -> f64 {
    params.kinematics.loop_overhead_s / LOOP_STEPS as f64
}

/// Standard deviation of one step's latency (s): the recordings' duration scatter over
/// √[`LOOP_STEPS`] (independent steps).
fn step_jitter_s(params: &SimParams) -> f64 {
    params.kinematics.loop_jitter_s / (LOOP_STEPS as f64).sqrt()
}

/// A recording's length and its parts, from the parameters.
impl SimParams {
    /// Duration of the slide alone (s): its trapezoidal profile over the slide distance.
    pub fn motion_duration_s(&self) -> f64 {
        let k = &self.kinematics;
        Trapezoid::new(k.distance_mm, k.speed_mm_s, k.acceleration_mm_s2).duration_s()
    }

    /// The kinematics field (and its value) behind the longest part of a recording, to name in
    /// an error when the recording is too long: the dwell, the loop's latencies, the moves'
    /// acceleration ramps, or a cruise at full speed — the slide's blamed on the distance or the
    /// speed, whichever lies further from its default by ratio, the press's on its travel.
    pub(crate) fn longest_part_of_trial(&self) -> (&'static str, f64) {
        let k = &self.kinematics;
        let (v, a, d) = (k.speed_mm_s, k.acceleration_mm_s2, k.distance_mm);
        let ramps = |d: f64| 2.0 * (v / a).min((d / a).sqrt());
        let slide = Trapezoid::new(d, v, a).duration_s();
        let press = Trapezoid::new(k.press_travel_mm, v, a).duration_s();
        let default = KinematicsParams::default();
        let cruise_field = if d / default.distance_mm >= default.speed_mm_s / v {
            ("kinematics.distance_mm", d)
        } else {
            ("kinematics.speed_mm_s", v)
        };
        let latencies =
            Recording::longest(self).end_s - Recording::nominal(self).end_s + k.loop_overhead_s;
        [
            (k.dwell_s, ("kinematics.dwell_s", k.dwell_s)),
            (latencies, ("kinematics.loop_overhead_s", k.loop_overhead_s)),
            (
                ramps(d) + ramps(k.press_travel_mm),
                ("kinematics.acceleration_mm_s2", a),
            ),
            (slide - ramps(d), cruise_field),
            (
                press - ramps(k.press_travel_mm),
                ("kinematics.press_travel_mm", k.press_travel_mm),
            ),
        ]
        .into_iter()
        .max_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, named)| named)
        .expect("five parts")
    }

    /// The longest recording these parameters make (s): every blocking step of the loop at its
    /// longest latency ([`Recording::longest`]). Every simulated recording ends before it, so a
    /// dataset's samples all fit in it.
    pub fn duration_s(&self) -> f64 {
        Recording::longest(self).end_s
    }
}

/// The duration law of recordings at speed `speed_mm_s` with every other parameter from
/// `params`: the nominal recording's length (s).
pub fn nominal_duration_at(params: &SimParams, speed_mm_s: f64) -> f64 {
    let mut p = *params;
    p.kinematics.speed_mm_s = speed_mm_s;
    Recording::nominal(&p).end_s
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn a_trapezoid_covers_its_distance_at_the_cruise_speed() {
        let t = Trapezoid::new(60.0, 15.0, 300.0);
        assert_eq!(t.at(-0.1), (0.0, 0.0));
        let (x, v) = t.at(2.0);
        assert!((v - 15.0).abs() < 1e-12 && x > 20.0 && x < 40.0);
        assert_eq!(t.at(t.duration_s()), (60.0, 0.0));
        assert!((t.at(t.duration_s() - 1e-9).0 - 60.0).abs() < 1e-6);
        assert!((t.duration_s() - (4.0 + 0.05)).abs() < 1e-12);
        // Too short to reach the cruise speed: a triangle.
        let short = Trapezoid::new(0.1, 15.0, 300.0);
        assert!((short.duration_s() - 2.0 * (0.1f64 / 300.0).sqrt()).abs() < 1e-12);
        assert_eq!(Trapezoid::new(0.0, 15.0, 300.0).duration_s(), 0.0);
    }

    #[test]
    fn the_nominal_recording_presses_dwells_slides_and_stops() {
        let p = SimParams::default();
        let r = Recording::nominal(&p);
        let step = p.kinematics.loop_overhead_s / 8.0;
        assert!((r.press_start_s - 4.0 * step).abs() < 1e-12);
        // 5 mm at 15 mm/s plus the ramps.
        let press = 5.0 / 15.0 + 15.0 / p.kinematics.acceleration_mm_s2;
        assert!((r.press_end_s() - r.press_start_s - press).abs() < 1e-12);
        assert!((r.slide_start_s - r.press_end_s() - 2.0 * step - 0.1).abs() < 1e-12);
        assert!((r.end_s - r.slide_end_s() - 2.0 * step).abs() < 1e-12);
        assert_eq!(r.press_travel_at(r.press_start_s - 0.01), 0.0);
        assert_eq!(r.press_travel_at(r.press_end_s() + 0.01), 5.0);
        assert_eq!(r.slide_at(r.slide_start_s), (0.0, 0.0));
        assert_eq!(r.slide_at(r.end_s), (60.0, 0.0));
    }

    #[test]
    fn the_duration_law_matches_the_papers_five_durations() {
        // The paper's durations scatter about the law by 6.4 ms (standard deviation): every one
        // lies within three of them of the nominal recording at its speed.
        let p = SimParams::default();
        for (v, paper) in PAPER_DURATIONS {
            let simulated = nominal_duration_at(&p, v);
            assert!(
                (simulated - paper).abs() < 3.0 * p.kinematics.loop_jitter_s,
                "{v} mm/s: {simulated} s vs {paper} s"
            );
        }
    }

    #[test]
    fn drawn_recordings_spread_as_the_loop_predicts_and_never_outlast_the_longest() {
        let p = SimParams::default();
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let draws: Vec<Recording> = (0..4000).map(|_| Recording::draw(&p, &mut rng)).collect();
        let sd = |f: fn(&Recording) -> f64| {
            let m = draws.iter().map(f).sum::<f64>() / draws.len() as f64;
            (draws.iter().map(|r| (f(r) - m).powi(2)).sum::<f64>() / draws.len() as f64).sqrt()
        };
        let jitter = p.kinematics.loop_jitter_s;
        let onset = sd(|r| r.slide_start_s);
        assert!(
            (onset / (jitter * 0.75f64.sqrt()) - 1.0).abs() < 0.05,
            "{onset}"
        );
        let total = sd(|r| r.end_s);
        assert!((total / jitter - 1.0).abs() < 0.05, "{total}");
        let longest = Recording::longest(&p).end_s;
        assert!(draws.iter().all(|r| r.end_s <= longest));
        assert!((longest - p.duration_s()).abs() < 1e-12);
    }
}
