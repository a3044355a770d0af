//! facade
pub use neurotac_core as core;
