//! One statistic of the check: what was measured, the bound it is held to, and whether it holds.

use serde::Serialize;

/// One acceptance statistic.
#[derive(Debug, Clone, Serialize)]
pub struct Statistic {
    /// Number: the spec's §5 for 1–10, the check's own from 11.
    pub number: u8,
    /// Name.
    pub name: &'static str,
    /// What was measured.
    pub measured: String,
    /// The bound it is held to.
    pub bound: String,
    /// Whether every part of the bound holds.
    pub pass: bool,
}
