//! Bounds on the work and memory one number of a command line can ask for. Every size, count,
//! step and rate that sets how much is allocated or run is checked against a stated limit
//! before anything starts, and refused with one line naming the flag and the limit: a typo
//! (`--dt 1e-30`, `--n 1e12`) must not run for years, fill the memory or abort.
//!
//! | limit | value | why |
//! |---|---|---|
//! | [`MAX_STEPS`] | 10⁹ steps of one run | 10⁹ steps of the CUBA network take hours |
//! | [`MAX_NEURONS`] | 2²⁷ ≈ 1.3 × 10⁸ neurons | their state alone is gigabytes |
//! | [`MAX_UPDATES`] | 10¹² neuron updates of one run | minutes to an hour at 10⁹ updates/s |
//! | [`MAX_SYNAPSES`] | 5 × 10⁸ synapses | ≈ 6 GB of connectivity |
//! | [`MAX_SPIKES`] | 2 × 10⁸ generated input spikes | 1.6 GB of spike times |

/// The most time steps one run may take.
pub const MAX_STEPS: u64 = 1_000_000_000;
/// The most neurons of one population or network.
pub const MAX_NEURONS: usize = 1 << 27;
/// The most neuron updates (neurons × steps) of one run.
pub const MAX_UPDATES: f64 = 1e12;
/// The most synapses of one network.
pub const MAX_SYNAPSES: f64 = 5e8;
/// The most input spikes generated for one run.
pub const MAX_SPIKES: f64 = 2e8;

/// A command line asking for more than a limit allows, or for nothing at all.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BudgetError {
    /// The duration is shorter than one step.
    #[error(
        "--duration {duration_s:e} s is shorter than one step of --dt {dt_s:e} s: nothing to run"
    )]
    NoStep {
        /// The duration (s).
        duration_s: f64,
        /// The step (s).
        dt_s: f64,
    },
    /// More steps than [`MAX_STEPS`].
    #[error(
        "--duration {duration_s:e} s at --dt {dt_s:e} s is {steps:.1e} steps, more than the limit of {MAX_STEPS:.0e}: use a larger --dt or a shorter --duration"
    )]
    TooManySteps {
        /// The duration (s).
        duration_s: f64,
        /// The step (s).
        dt_s: f64,
        /// The steps it would take.
        steps: f64,
    },
    /// A quantity set by `flag` over its limit.
    #[error("{flag} {value:e}: {what} {amount:.1e}, more than the limit of {limit:.1e}")]
    OverLimit {
        /// The flag that sets it (`--n`).
        flag: &'static str,
        /// The flag's value.
        value: f64,
        /// What would be too much (`neurons`, `neuron updates (--n × steps)`).
        what: &'static str,
        /// How much it would be.
        amount: f64,
        /// The limit.
        limit: f64,
    },
}

/// The whole steps of `dt_s` in `duration_s` (rounded to the nearest, as the benchmarks run
/// them): at least one, at most [`MAX_STEPS`].
pub fn steps(duration_s: f64, dt_s: f64) -> Result<u64, BudgetError> {
    let steps = (duration_s / dt_s).round();
    // NaN (a NaN duration or step) counts as no step.
    if steps.is_nan() || steps < 1.0 {
        return Err(BudgetError::NoStep { duration_s, dt_s });
    }
    if steps > MAX_STEPS as f64 {
        return Err(BudgetError::TooManySteps {
            duration_s,
            dt_s,
            steps,
        });
    }
    Ok(steps as u64)
}

/// Refuses `amount` of `what` over `limit`, naming `flag` and its `value`.
pub fn at_most(
    flag: &'static str,
    value: f64,
    what: &'static str,
    amount: f64,
    limit: f64,
) -> Result<(), BudgetError> {
    if amount > limit || amount.is_nan() {
        return Err(BudgetError::OverLimit {
            flag,
            value,
            what,
            amount,
            limit,
        });
    }
    Ok(())
}

/// A population of `n` neurons (set by `flag`) run for `steps` steps: at most
/// [`MAX_NEURONS`] neurons and [`MAX_UPDATES`] updates.
pub fn population(flag: &'static str, n: usize, steps: u64) -> Result<(), BudgetError> {
    let n_f = n as f64;
    at_most(flag, n_f, "neurons", n_f, MAX_NEURONS as f64)?;
    let updates = n_f * steps as f64;
    at_most(
        flag,
        n_f,
        "neuron updates (neurons × steps)",
        updates,
        MAX_UPDATES,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_has_at_least_one_step_and_at_most_the_limit() {
        assert_eq!(steps(1.0, 1e-4), Ok(10_000));
        let none = steps(0.01, 1.0).unwrap_err();
        assert_eq!(
            none.to_string(),
            "--duration 1e-2 s is shorter than one step of --dt 1e0 s: nothing to run"
        );
        let many = steps(1.0, 1e-300).unwrap_err().to_string();
        assert!(
            many.starts_with("--duration 1e0 s at --dt 1e-300 s is 1.0e300 steps"),
            "{many}"
        );
        assert!(matches!(
            steps(f64::NAN, 1e-4),
            Err(BudgetError::NoStep { .. })
        ));
    }

    #[test]
    fn a_population_over_its_neurons_or_updates_is_refused_naming_the_flag() {
        assert!(population("--n", 100_000, 10_000).is_ok());
        let e = population("--n", 1_000_000_000_000, 1)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "--n 1e12: neurons 1.0e12, more than the limit of 1.3e8");
        let e = population("--n", 1_000_000, 10_000_000)
            .unwrap_err()
            .to_string();
        assert!(e.contains("neuron updates (neurons × steps) 1.0e13"), "{e}");
    }
}
