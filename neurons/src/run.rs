//! Running a population under a constant input for a given duration, the way `neurotac neuron`
//! does: a bounded number of whole steps ([`whole_steps`]) and spike times handed out as they
//! are found ([`stream_spike_times`]), so memory does not grow with the run.
//!
//! **A step never runs past the duration**: a run of `duration_s` at `dt_s` is
//! `⌊duration_s / dt_s⌋` steps (a quotient within 10⁻⁹ of a whole number counts as that number);
//! a partial last step is refused, not shortened, since a population's constants are prepared
//! for one `dt`. The last spike time is therefore at most `steps·dt ≤ duration_s`.

use crate::population::{DIVERGENCE_CHECK_STEPS, Population};
use neurotac_core::{Compact, ModelError, SpikeBuffer};
use std::ops::ControlFlow;

/// The default bound on the number of steps of one run (10⁸: a few seconds for one neuron).
pub const DEFAULT_MAX_STEPS: u64 = 100_000_000;

/// A run that cannot start or did not finish.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The duration is NaN, infinite or negative.
    #[error("duration {} s must be finite and ≥ 0", Compact(*duration_s))]
    InvalidDuration {
        /// The duration given (s).
        duration_s: f64,
    },
    /// The time step is NaN, infinite or not positive.
    #[error("time step {} s must be finite and > 0", Compact(*dt_s))]
    InvalidStep {
        /// The time step given (s).
        dt_s: f64,
    },
    /// The run needs more steps than allowed.
    #[error(
        "{} s at dt = {} s is {steps:.3e} steps, more than the limit of {max_steps} (raise the step limit or use a larger dt)",
        Compact(*duration_s),
        Compact(*dt_s)
    )]
    TooManySteps {
        /// The duration (s).
        duration_s: f64,
        /// The time step (s).
        dt_s: f64,
        /// Steps the run would need (may be +∞).
        steps: f64,
        /// The limit.
        max_steps: u64,
    },
    /// The model refused its set-up or input, or diverged.
    #[error(transparent)]
    Model(#[from] ModelError),
}

/// The number of whole steps of `dt_s` that fit in `duration_s` (see the module docs), at most
/// `max_steps`.
///
/// ```
/// use neurotac_neurons::run::whole_steps;
/// assert_eq!(whole_steps(1.0, 1e-4, 1_000_000).unwrap(), 10_000);
/// assert_eq!(whole_steps(1.0, 2.0, 10).unwrap(), 0); // a 2 s step does not fit in 1 s
/// assert!(whole_steps(1e5, 1e-6, 1_000_000).is_err()); // 10¹¹ steps
/// ```
pub fn whole_steps(duration_s: f64, dt_s: f64, max_steps: u64) -> Result<u64, RunError> {
    if !(duration_s.is_finite() && duration_s >= 0.0) {
        return Err(RunError::InvalidDuration { duration_s });
    }
    if !(dt_s.is_finite() && dt_s > 0.0) {
        return Err(RunError::InvalidStep { dt_s });
    }
    let ratio = duration_s / dt_s;
    let nearest = ratio.round();
    let steps = if (ratio - nearest).abs() <= 1e-9 * nearest.max(1.0) {
        nearest
    } else {
        ratio.floor()
    };
    if steps > max_steps as f64 {
        return Err(RunError::TooManySteps {
            duration_s,
            dt_s,
            steps,
            max_steps,
        });
    }
    Ok(steps as u64)
}

/// Runs `steps` steps of `dt_s` (preparing the population if needed) with the same `current`
/// for every neuron and hands each spike to `on_spike(neuron, time_s)` in time order; the
/// callback may stop the run early with [`ControlFlow::Break`].
///
/// Spikes are held back until the population has passed its divergence check, which runs every
/// [`DIVERGENCE_CHECK_STEPS`] steps and at the end: a run that diverges returns
/// [`ModelError::Diverged`] without having handed out the spurious spikes of the diverged block
/// (memory stays bounded by one block of steps).
pub fn stream_spike_times(
    pop: &mut dyn Population,
    current: f64,
    dt_s: f64,
    steps: u64,
    on_spike: &mut dyn FnMut(u32, f64) -> ControlFlow<()>,
) -> Result<(), ModelError> {
    pop.check_input(0, current)?;
    if pop.prepared_dt() != Some(dt_s) {
        pop.prepare(dt_s)?;
    }
    let input = vec![current; pop.len()];
    let mut spikes = SpikeBuffer::new();
    let mut pending: Vec<(u32, f64)> = Vec::new();
    for k in 0..steps {
        spikes.clear();
        pop.step(&input, &mut spikes);
        let times = spikes.fractions().iter().map(|phi| (k as f64 + phi) * dt_s);
        pending.extend(spikes.indices().iter().copied().zip(times));
        let last = k + 1 == steps;
        if last || (k + 1) % DIVERGENCE_CHECK_STEPS == 0 {
            pop.check_divergence()?;
            for &(i, t) in &pending {
                if on_spike(i, t).is_break() {
                    return Ok(());
                }
            }
            pending.clear();
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Lif, LifParams};

    #[test]
    fn a_step_never_runs_past_the_duration() {
        // `neuron --current 2 --dt 2 --duration 1` printed a spike at 2 s.
        assert_eq!(whole_steps(1.0, 2.0, 100).unwrap(), 0);
        assert_eq!(whole_steps(1.0, 3e-4, 1 << 20).unwrap(), 3333);
        // Rounding of the quotient does not lose or add the last whole step.
        assert_eq!(whole_steps(0.3, 0.1, 100).unwrap(), 3);
        assert_eq!(whole_steps(1.0, 1e-4, 1 << 20).unwrap(), 10_000);
        let mut lif = Lif::<f64>::new(1, LifParams::default());
        for (dt, duration) in [(2.0, 1.0), (0.7, 1.0), (3e-3, 0.1)] {
            let steps = whole_steps(duration, dt, 1000).unwrap();
            let mut last = 0.0f64;
            stream_spike_times(&mut lif, 2.0, dt, steps, &mut |_, t| {
                last = last.max(t);
                ControlFlow::Continue(())
            })
            .unwrap();
            assert!(last <= duration, "spike at {last} s after {duration} s");
        }
    }

    #[test]
    fn runs_are_bounded_by_a_step_limit() {
        // `--current 1e6 --dt 1e-6 --duration 1e5` grew to 8.7 GB; `--dt 1e-300` never ended.
        let e = whole_steps(1e5, 1e-6, DEFAULT_MAX_STEPS).unwrap_err();
        assert!(
            matches!(e, RunError::TooManySteps { max_steps, .. } if max_steps == DEFAULT_MAX_STEPS),
            "{e}"
        );
        assert!(e.to_string().contains("1.000e11 steps"), "{e}");
        let e = whole_steps(1.0, 1e-300, DEFAULT_MAX_STEPS).unwrap_err();
        assert!(matches!(e, RunError::TooManySteps { .. }), "{e}");
        assert!(whole_steps(f64::NAN, 1e-4, 10).is_err());
        assert!(whole_steps(1.0, 0.0, 10).is_err());
        assert_eq!(whole_steps(1e5, 1e-6, u64::MAX).unwrap(), 100_000_000_000);
    }

    #[test]
    fn streamed_spike_times_are_the_stepped_ones_and_can_stop_early() {
        let mut lif = Lif::<f64>::new(2, LifParams::default());
        let mut all = Vec::new();
        stream_spike_times(&mut lif, 1.5, 1e-4, 10_000, &mut |i, t| {
            all.push((i, t));
            ControlFlow::Continue(())
        })
        .unwrap();
        // Period ⌈τ·ln 3 / dt⌉ = 110 steps: 90 spikes per neuron in 1 s, both neurons alike.
        assert_eq!(all.len(), 2 * 90);
        assert!(all.windows(2).all(|w| w[0].1 <= w[1].1));
        assert!((all[0].1 - 110.0 * 1e-4).abs() < 1e-12);
        let mut seen = 0;
        let mut fresh = Lif::<f64>::new(1, LifParams::default());
        stream_spike_times(&mut fresh, 1.5, 1e-4, 10_000, &mut |_, _| {
            seen += 1;
            if seen == 3 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .unwrap();
        assert_eq!(seen, 3);
    }
}
