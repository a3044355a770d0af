//! # neurotac-sensor
//!
//! The input side of the NeuroTac sensor: its DAVIS240 event camera and every event-file format a
//! DAVIS user has.
#![deny(missing_docs)]

pub mod davis;
pub mod error;

pub use error::{DeviceError, FormatError, SensorError};
pub mod format;
