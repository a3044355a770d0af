//! Pixel-event filters: [`BackgroundActivityFilter`] (dv-processing semantics) and
//! [`RefractoryFilter`]. Both are [`EventFilter`](crate::stage::EventFilter)s; wrap them in
//! [`Filtered`](crate::stage::Filtered) to use them as pipeline stages.

mod background_activity;
mod refractory;

pub use background_activity::{BackgroundActivityFilter, MapStart};
pub use refractory::RefractoryFilter;

/// Value of a time-surface cell that never supports an event: far in the past, yet far enough
/// from `i64::MIN` that `t − NEVER` cannot overflow for any |t| < 4·10¹⁸ µs.
pub(crate) const NEVER: i64 = i64::MIN / 2;
