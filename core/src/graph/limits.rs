//! The limits a network — built in code, from a [`NetworkDescription`](super::NetworkDescription)
//! or from a saved file — must keep, checked before anything they size is allocated:
//!
//! | what | limit | why |
//! |---|---|---|
//! | neurons of a population, channels of a spike source | [`MAX_NODE_SIZE`] (2³² − 1) | spike indices are `u32` |
//! | delay of a projection | [`MAX_DELAY_STEPS`] (2²⁰ steps) | each step of delay is one slot of the presynaptic node's spike history |
//! | steps a network has done | [`MAX_STEPS`] (2⁵³) | its time `step·dt` stays exact |
//! | steps of one run | [`MAX_RUN_STEPS`] (2⁴⁰) | a run that long is a mistake (a `dt` of 10⁻³⁰⁰ s), not a simulation |
//!
//! A part whose size is within these limits but more than the machine can give (a population
//! of 2³¹ neurons, a plastic all-to-all projection of 4·10¹⁰ synapses) is refused with
//! [`GraphError::TooLarge`] when its memory cannot be reserved, before it is built — never an
//! abort of the process.

use crate::error::GraphError;

/// The most neurons in a population, or channels of a spike source: indices are `u32`.
pub const MAX_NODE_SIZE: usize = u32::MAX as usize;

/// The longest delay of a projection, in steps (2²⁰: 105 s at dt = 0.1 ms, 1 s at 1 µs).
pub const MAX_DELAY_STEPS: u32 = 1 << 20;

/// The most steps a network may have done (2⁵³): its time `step·dt` stays exact.
pub const MAX_STEPS: u64 = 1 << 53;

/// The most steps one [`Network::run`](super::Network::run) may take (2⁴⁰ ≈ 1.1·10¹²: more
/// than a day at ten million steps per second).
pub const MAX_RUN_STEPS: u64 = 1 << 40;

/// Checks that `count` items of `bytes_each` bytes (the part `what` names) can be allocated:
/// the product is representable and the allocator grants a reservation of that size (taken and
/// given back at once), so a legal but huge size is a [`GraphError::TooLarge`] instead of an
/// abort when the part is built.
pub(crate) fn check_allocatable(
    what: impl FnOnce() -> String,
    count: u64,
    bytes_each: u64,
) -> Result<(), GraphError> {
    let bytes = count.checked_mul(bytes_each);
    let granted = bytes
        .and_then(|b| usize::try_from(b).ok())
        .is_some_and(|b| Vec::<u8>::new().try_reserve_exact(b).is_ok());
    match granted {
        true => Ok(()),
        false => Err(GraphError::TooLarge {
            what: what(),
            bytes: bytes.map_or(f64::INFINITY, |b| b as f64),
        }),
    }
}

/// Checks that node `name` has at most [`MAX_NODE_SIZE`] neurons or channels.
pub(crate) fn check_node_size(name: &str, size: usize) -> Result<(), GraphError> {
    match size <= MAX_NODE_SIZE {
        true => Ok(()),
        false => Err(GraphError::InvalidParameter {
            what: format!("size of '{name}'"),
            value: size as f64,
            expected: "at most 2³² − 1 neurons or channels (indices are u32)",
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_size_the_machine_cannot_hold_is_an_error_not_an_abort() {
        assert!(check_allocatable(|| "small".into(), 1000, 8).is_ok());
        let e = check_allocatable(|| "a plastic projection".into(), 1 << 40, 1 << 20).unwrap_err();
        assert!(
            e.to_string().contains("a plastic projection") && e.to_string().contains("bytes"),
            "{e}"
        );
        assert!(check_allocatable(|| "overflow".into(), u64::MAX, 2).is_err());
        assert!(check_node_size("x", MAX_NODE_SIZE).is_ok());
        assert!(check_node_size("x", MAX_NODE_SIZE + 1).is_err());
    }
}
