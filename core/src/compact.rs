//! Numbers in messages: [`Compact`] prints a float in its shortest decimal form when that is
//! short, in scientific notation otherwise, so an absurd value (`1e-300`) is named as given
//! instead of as 300 digits.

use std::fmt;

/// A float as a message prints it: `0.0001`, `159`, `0.4` as they are; `1e-300`, `1e15`,
/// `1.5e-7` in scientific notation (outside 10⁻⁴ ≤ |x| < 10¹⁵).
///
/// ```
/// use neurotac_core::Compact;
/// assert_eq!(Compact(0.076).to_string(), "0.076");
/// assert_eq!(Compact(1e-300).to_string(), "1e-300");
/// assert_eq!(Compact(f64::NAN).to_string(), "NaN");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compact(pub f64);

impl fmt::Display for Compact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        let a = x.abs();
        if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&a) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}
