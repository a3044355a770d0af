//! # neurotac-sensor
//!
//! The input side of the NeuroTac sensor: its iniVation DAVIS240 event camera (240 × 180) and
//! every event-file format a DAVIS user has. Facts come from `shared/specs/davis240.md` (libcaer
//! 3.3 semantics); each item's documentation names the section it implements.
//!
//! | concern | principal types |
//! |---|---|
//! | USB word stream → events (§1.6–1.7) | [`davis::UsbDecoder`], [`davis::DecoderConfig`], [`davis::SpecialEvent`], [`davis::DecodeStats`] |
//! | the camera over USB (§1.1–1.5) | [`davis::Davis`] → [`davis::DavisStream`], [`davis::Transport`] ([`davis::RusbTransport`], [`davis::ReplayTransport`]), [`davis::list_devices`] |
//! | event files (§2) | [`format::open_reader`] / [`format::create_writer`], [`format::EventReader`], [`format::EventWriter`], [`format::Format`], [`format::ReadStats`], one reader/writer pair per format |
//! | errors | [`FormatError`], [`DeviceError`], [`SensorError`] |
//!
//! Events land in a reusable [`neurotac_core::EventBuffer`] (t in µs, x, y top-left, polarity).
//! Decoders and readers append chunk by chunk, so a stream or a 10 GB file is processed in
//! bounded memory; nothing in the hot loops allocates per event or per chunk after warm-up.
//!
//! ```
//! use neurotac_core::EventBuffer;
//! use neurotac_sensor::format::{self, EventReader};
//!
//! // Three events as CSV, then read back in chunks from any format.
//! let csv = b"t,x,y,on\n0,118,38,1\n3,102,28,0\n7,5,179,1\n";
//! let mut reader = format::reader_from_bytes(csv)?;
//! let mut events = EventBuffer::new();
//! while reader.read_chunk(&mut events)? > 0 {}
//! assert_eq!((events.len(), events.x[2], events.y[2]), (3, 5, 179));
//! assert_eq!(reader.stats().timestamps_backwards, 0);
//! # Ok::<(), neurotac_sensor::FormatError>(())
//! ```
#![deny(missing_docs)]

pub mod davis;
pub mod error;
pub mod format;

pub use error::{DeviceError, FormatError, SensorError};
