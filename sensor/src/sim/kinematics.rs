//! The base's motion over a slide (spec §2.2 step 4): it rests for `rest_before_s`, slides
//! `distance_mm` with a trapezoidal speed profile (acceleration `a`, cruise speed `v`; a
//! triangle when the distance is too short to reach `v`), then rests.

use super::params::SimParams;

/// Base position (mm) and speed (mm/s) at time `t_s` of the trial.
pub fn base_motion(params: &SimParams, t_s: f64) -> (f64, f64) {
    Trapezoid::new(params).at(t_s)
}

/// The base's trapezoidal speed profile with its constants worked out once (a slide samples
/// it a hundred thousand times).
#[derive(Debug, Clone, Copy)]
pub(super) struct Trapezoid {
    rest_before_s: f64,
    /// Motion duration (s).
    total_s: f64,
    /// Acceleration (mm/s²) and distance (mm).
    a: f64,
    d: f64,
    /// Peak speed: v, or √(a·d) for a triangular profile (mm/s).
    peak: f64,
    /// Ramp and cruise durations (s).
    ramp_s: f64,
    cruise_s: f64,
}

impl Trapezoid {
    pub(super) fn new(params: &SimParams) -> Self {
        let k = &params.kinematics;
        let (v, a, d) = (k.speed_mm_s, k.acceleration_mm_s2, k.distance_mm);
        let total_s = params.motion_duration_s();
        let peak = v.min((a * d).sqrt());
        let ramp_s = peak / a;
        Self {
            rest_before_s: k.rest_before_s,
            total_s,
            a,
            d,
            peak,
            ramp_s,
            cruise_s: total_s - 2.0 * ramp_s,
        }
    }

    /// Base position (mm) and speed (mm/s) at `t_s`.
    #[inline]
    pub(super) fn at(&self, t_s: f64) -> (f64, f64) {
        let (a, d, ta) = (self.a, self.d, self.ramp_s);
        let t = t_s - self.rest_before_s;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trapezoid_covers_the_distance_at_the_cruise_speed() {
        let p = SimParams::default();
        assert_eq!(base_motion(&p, 0.1), (0.0, 0.0));
        let (x, v) = base_motion(&p, 2.0);
        assert!((v - 15.0).abs() < 1e-12 && x > 20.0 && x < 30.0);
        assert_eq!(base_motion(&p, p.duration_s()), (60.0, 0.0));
        let (x_end, _) = base_motion(
            &p,
            p.kinematics.rest_before_s + p.motion_duration_s() - 1e-9,
        );
        assert!((x_end - 60.0).abs() < 1e-6);
    }
}
