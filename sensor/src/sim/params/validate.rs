//! Validation of the parameters: every field's domain and the relations between fields, the
//! error naming the first offending field as `group.field`.

use super::{MAX_NOISE_EVENTS, MAX_NOISE_RATE_HZ, SimParams};
use crate::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH};
use crate::sim::SimulationError;

/// What a value must satisfy.
#[derive(Clone, Copy)]
enum Domain {
    Positive,
    NonNegative,
    Between(f64, f64),
    AtMost(f64),
}

fn check(field: &'static str, value: f64, domain: Domain) -> Result<(), SimulationError> {
    let (ok, expected) = match domain {
        Domain::Positive => (value > 0.0, "finite and > 0"),
        Domain::NonNegative => (value >= 0.0, "finite and ≥ 0"),
        Domain::Between(lo, hi) => (
            (lo..=hi).contains(&value),
            "finite and within its documented range",
        ),
        Domain::AtMost(max) => (
            value > 0.0 && value <= max,
            "finite, > 0 and within its documented limit",
        ),
    };
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(SimulationError::InvalidParameter {
            field,
            value,
            expected,
        })
    }
}

impl SimParams {
    /// Checks every field (finite, signs, ranges) and the relations between them; the error
    /// names the first offending field as `group.field`.
    pub fn validate(&self) -> Result<(), SimulationError> {
        use Domain::*;
        let (k, c, o) = (&self.kinematics, &self.contact, &self.optics);
        let (p, n, s) = (&self.pixel, &self.noise, &self.solver);
        for (field, value, domain) in [
            ("kinematics.speed_mm_s", k.speed_mm_s, Positive),
            ("kinematics.distance_mm", k.distance_mm, NonNegative),
            (
                "kinematics.acceleration_mm_s2",
                k.acceleration_mm_s2,
                Positive,
            ),
            ("kinematics.press_travel_mm", k.press_travel_mm, NonNegative),
            ("kinematics.press_depth_mm", k.press_depth_mm, Positive),
            ("kinematics.normal_force_n", k.normal_force_n, Positive),
            ("kinematics.dwell_s", k.dwell_s, NonNegative),
            (
                "kinematics.loop_overhead_s",
                k.loop_overhead_s,
                Between(0.0, 10.0),
            ),
            (
                "kinematics.loop_jitter_s",
                k.loop_jitter_s,
                Between(0.0, 1.0),
            ),
            (
                "kinematics.lateral_offset_range_mm",
                k.lateral_offset_range_mm,
                NonNegative,
            ),
            (
                "kinematics.start_phase_range_mm",
                k.start_phase_range_mm,
                NonNegative,
            ),
            (
                "kinematics.position_repeatability_mm",
                k.position_repeatability_mm,
                Between(0.0, 5.0),
            ),
            (
                "kinematics.press_depth_sd_mm",
                k.press_depth_sd_mm,
                Between(0.0, 0.5),
            ),
            ("contact.skin_depth_mm", c.skin_depth_mm, Positive),
            ("contact.gap_conformity_mm", c.gap_conformity_mm, Positive),
            (
                "contact.foundation_stiffness_n_mm3",
                c.foundation_stiffness_n_mm3,
                NonNegative,
            ),
            ("contact.contact_edge_mm", c.contact_edge_mm, Positive),
            ("contact.lever_mm", c.lever_mm, NonNegative),
            ("contact.pin_shear_gain", c.pin_shear_gain, NonNegative),
            ("contact.bulge", c.bulge, NonNegative),
            (
                "contact.fabric_mount_span_mm",
                c.fabric_mount_span_mm,
                Between(1.0, 1000.0),
            ),
            (
                "contact.fabric_base_friction",
                c.fabric_base_friction,
                Between(0.0, 5.0),
            ),
            (
                "contact.skin_shear_stiffness_n_mm3",
                c.skin_shear_stiffness_n_mm3,
                Positive,
            ),
            ("contact.bump_height_mm", c.bump_height_mm, Positive),
            (
                "contact.tangential_stiffness_n_mm",
                c.tangential_stiffness_n_mm,
                Positive,
            ),
            ("contact.slip_time_s", c.slip_time_s, Positive),
            ("contact.slip_inertia_s", c.slip_inertia_s, Positive),
            (
                "contact.adhesion_mu_kinetic",
                c.adhesion_mu_kinetic,
                Positive,
            ),
            ("contact.static_excess", c.static_excess, Between(0.0, 5.0)),
            ("contact.loss_tangent", c.loss_tangent, Between(0.0, 2.0)),
            ("contact.micro_slope_rms", c.micro_slope_rms, Positive),
            ("contact.skin_modulus_mpa", c.skin_modulus_mpa, Positive),
            ("contact.microslip_min_mm", c.microslip_min_mm, NonNegative),
            ("contact.microslip_max_mm", c.microslip_max_mm, NonNegative),
            ("contact.microslip_time_s", c.microslip_time_s, Positive),
            (
                "contact.edge_catches_per_period",
                c.edge_catches_per_period,
                Between(0.0, 100.0),
            ),
            (
                "contact.stick_area_exponent",
                c.stick_area_exponent,
                Between(0.1, 10.0),
            ),
            (
                "contact.pin_footprint_radius_mm",
                c.pin_footprint_radius_mm,
                Between(0.0, 3.0),
            ),
            (
                "contact.friction_day_sd",
                c.friction_day_sd,
                Between(0.0, 0.3),
            ),
            (
                "contact.friction_drift_sd",
                c.friction_drift_sd,
                Between(0.0, 0.3),
            ),
            ("optics.pin_radius_px", o.pin_radius_px, Positive),
            ("optics.edge_blur_px", o.edge_blur_px, Positive),
            ("optics.background_dn", o.background_dn, Positive),
            ("optics.pin_dn", o.pin_dn, Positive),
            ("optics.linear_below_dn", o.linear_below_dn, Positive),
            ("optics.full_scale_dn", o.full_scale_dn, Positive),
            ("optics.patch_radius_px", o.patch_radius_px, AtMost(40.0)),
            ("pixel.threshold_on", p.threshold_on, Positive),
            ("pixel.threshold_off", p.threshold_off, Positive),
            ("pixel.threshold_sd", p.threshold_sd, NonNegative),
            ("pixel.refractory_s", p.refractory_s, NonNegative),
            ("pixel.bandwidth_hz", p.bandwidth_hz, Positive),
            ("pixel.latency_s", p.latency_s, NonNegative),
            ("pixel.latency_jitter_s", p.latency_jitter_s, NonNegative),
            ("noise.leak_rate_hz", n.leak_rate_hz, NonNegative),
            (
                "noise.leak_spread_decades",
                n.leak_spread_decades,
                NonNegative,
            ),
            ("noise.shot_rate_hz", n.shot_rate_hz, NonNegative),
            ("solver.step_tolerance", s.step_tolerance, AtMost(1.0)),
            ("solver.max_step_s", s.max_step_s, AtMost(1.0)),
            (
                "solver.mechanics_dt_s",
                s.mechanics_dt_s,
                Between(1e-6, 0.01),
            ),
            ("solver.shear_dt_s", s.shear_dt_s, Between(1e-7, 0.001)),
        ] {
            check(field, value, domain)?;
        }
        // Relations between fields.
        let relations = [
            {
                let (field, value) = self.longest_part_of_trial();
                (
                    field,
                    value,
                    self.duration_s() <= 600.0,
                    "a recording (press, dwell, slide and the loop's latencies) of at most 600 s",
                )
            },
            (
                "contact.microslip_max_mm",
                c.microslip_max_mm,
                c.microslip_max_mm >= c.microslip_min_mm,
                "≥ contact.microslip_min_mm",
            ),
            (
                "noise.leak_rate_hz",
                n.leak_rate_hz,
                n.leak_rate_hz + n.shot_rate_hz <= MAX_NOISE_RATE_HZ,
                "leak + shot noise of at most 1000 Hz per pixel",
            ),
            (
                "noise.leak_spread_decades",
                n.leak_spread_decades,
                self.noise.mean_leak_rate_hz() + n.shot_rate_hz <= MAX_NOISE_RATE_HZ,
                "a spread whose mean leak rate r₀·exp((spread·ln 10)²/2) plus shot noise \
                 is at most 1000 Hz per pixel",
            ),
            {
                let (leak, shot) = (self.noise.mean_leak_rate_hz(), n.shot_rate_hz);
                let pixels = f64::from(DAVIS240_WIDTH) * f64::from(DAVIS240_HEIGHT);
                let events = (leak + shot) * pixels * self.duration_s();
                let (field, value) = if leak >= shot {
                    ("noise.leak_rate_hz", n.leak_rate_hz)
                } else {
                    ("noise.shot_rate_hz", shot)
                };
                (
                    field,
                    value,
                    events <= MAX_NOISE_EVENTS,
                    "at most 2·10⁸ noise events per trial (mean rate × 43 200 pixels × trial \
                     duration)",
                )
            },
        ];
        match relations.into_iter().find(|r| !r.2) {
            Some((field, value, _, expected)) => Err(SimulationError::InvalidParameter {
                field,
                value,
                expected,
            }),
            None => Ok(()),
        }
    }
}
