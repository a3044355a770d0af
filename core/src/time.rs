//! Time: the one place where camera time and spike time meet.
//!
//! Two clocks exist in neurotac and they never mix silently:
//!
//! | what | type | unit | why |
//! |---|---|---|---|
//! | raw camera / pixel events | [`Timestamp`] (`i64`) | microseconds | the DAVIS240 clock ticks in 1 µs; integers keep event streams exact and ordered |
//! | spike trains, network time | `f64` | seconds | the unit of every time constant and of the paper's codings |
//!
//! [`us_to_s`] and [`s_to_us`] are the only conversions; everything else calls them.

use serde::{Deserialize, Serialize};

/// An event time in integer microseconds (the camera's clock).
///
/// The origin is whatever the source uses (start of recording, device reset, Unix epoch);
/// only differences matter to the pipeline.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize,
)]
#[serde(transparent)]
pub struct Timestamp(pub i64);

impl Timestamp {
    /// This timestamp in seconds, via [`us_to_s`].
    #[inline]
    pub fn to_seconds(self) -> f64 {
        us_to_s(self.0)
    }

    /// The timestamp nearest to `seconds`, via [`s_to_us`].
    #[inline]
    pub fn from_seconds(seconds: f64) -> Self {
        Timestamp(s_to_us(seconds))
    }
}

/// Converts integer microseconds to seconds: `t_s = t_us / 10⁶`.
///
/// Division (not multiplication by `1e-6`, which is not exactly representable) makes the
/// result the correctly rounded double nearest the true value, so `s_to_us(us_to_s(t)) == t`
/// for every |t| < 2⁵³ µs (about 285 years).
#[inline]
pub fn us_to_s(t_us: i64) -> f64 {
    t_us as f64 / 1e6
}

/// Converts seconds to the nearest integer microsecond: `t_us = round(t_s · 10⁶)`.
///
/// Non-finite input saturates (NaN → 0, ±∞ → `i64::MIN`/`i64::MAX`), following Rust's
/// float-to-int `as` semantics; validate times before converting when that matters.
#[inline]
pub fn s_to_us(t_s: f64) -> i64 {
    (t_s * 1e6).round() as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn microsecond_round_trip_is_exact() {
        for t in [
            0i64,
            1,
            3,
            999_999,
            1_390_419,
            2_148_174_067,
            1_700_000_000_000_000,
        ] {
            assert_eq!(s_to_us(us_to_s(t)), t);
            assert_eq!(Timestamp(t).to_seconds(), us_to_s(t));
        }
        assert_eq!(us_to_s(1_500_000), 1.5);
        assert_eq!(Timestamp::from_seconds(0.000_003), Timestamp(3));
    }
}
