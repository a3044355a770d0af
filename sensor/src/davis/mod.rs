//! The DAVIS240 camera: the USB event-stream decoder ([`UsbDecoder`]) and the USB driver.
//!
//! Facts from davis240.md §1 (libcaer 3.3 semantics).

mod decode;

pub use decode::{DecodeStats, DecoderConfig, SpecialEvent, SpecialKind, UsbDecoder};
