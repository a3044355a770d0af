//! The DAVIS240 camera (davis240.md §1, libcaer 3.3 semantics): the USB event-stream decoder
//! ([`UsbDecoder`]), the protocol constants and default configuration ([`protocol`]), the driver
//! ([`Davis`] → [`DavisStream`], [`record`] to a file) and the raw USB calls it makes ([`Transport`], implemented by
//! [`RusbTransport`] for a real camera and [`ReplayTransport`] for recorded byte streams).
//!
//! ```no_run
//! use neurotac_core::EventBuffer;
//! use neurotac_sensor::davis::{Davis, RusbTransport, StartOptions};
//! use std::time::Duration;
//! let (transport, usb) = RusbTransport::open_first()?; // DeviceError::NotFound without a camera
//! let davis = Davis::open(transport, usb)?;
//! davis.send_default_config()?;
//! let mut stream = davis.start(StartOptions::default())?;
//! let mut events = EventBuffer::new();
//! stream.next_events(&mut events, Duration::from_millis(100))?;
//! stream.stop()?;
//! # Ok::<(), neurotac_sensor::DeviceError>(())
//! ```

mod decode;
mod device;
pub mod protocol;
mod record;
mod stream;
mod transport;

pub use decode::{DecodeStats, DecoderConfig, SpecialEvent, SpecialKind, UsbDecoder};
pub use device::{Davis, DavisInfo, StartOptions};
pub use record::{Recording, record};
pub use stream::DavisStream;
pub use transport::{
    CONTROL_TIMEOUT, ControlRecord, DeviceInfo, ReplayEnd, ReplayTransport, RusbTransport,
    Transport, TransportError, list_devices,
};
