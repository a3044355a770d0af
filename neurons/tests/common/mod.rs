//! Inputs shared by the event-driven and automatic-stepping tests.

use rand::{Rng, RngExt};

/// Appends the spike times of a Poisson process at `rate_hz` on `[from_s, to_s)`, drawn from
/// `rng`, to `train`.
pub fn push_poisson(
    train: &mut Vec<f64>,
    rng: &mut impl Rng,
    rate_hz: f64,
    from_s: f64,
    to_s: f64,
) {
    let mut t = from_s - (1.0 - rng.random::<f64>()).ln() / rate_hz;
    while t < to_s {
        train.push(t);
        t += -(1.0 - rng.random::<f64>()).ln() / rate_hz;
    }
}
