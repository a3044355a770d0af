//! # neurotac-sensor
//!
//! The NeuroTac sensor side of neurotac: its iniVation DAVIS240 event camera (240 × 180), every
//! event-file format a DAVIS user has, and the transduction from pixel events to the 49 taxel
//! spike trains (paper, Methods, "Sensor operation"). Camera and file facts come from
//! `shared/specs/davis240.md` (libcaer 3.3 semantics); each item's documentation names the
//! section it implements.
//!
//! | concern | principal types |
//! |---|---|
//! | USB word stream → events (§1.6–1.7) | [`davis::UsbDecoder`], [`davis::DecoderConfig`], [`davis::SpecialEvent`], [`davis::DecodeStats`] |
//! | the camera over USB (§1.1–1.5) | [`davis::Davis`] → [`davis::DavisStream`], [`davis::Transport`] ([`davis::RusbTransport`], [`davis::ReplayTransport`]), [`davis::list_devices`] |
//! | event files (§2) | [`format::open_reader`] / [`format::create_writer`], [`format::EventReader`], [`format::EventWriter`], [`format::Format`], [`format::ReadStats`], one reader/writer pair per format |
//! | sensor geometry (49 pins, DAVIS240 image) | [`geometry::PinGeometry`] |
//! | the push interface of pipeline stages | [`stage::Stage`], [`stage::EventFilter`], [`stage::Filtered`], [`stage::Chain`] |
//! | noise filters (§3) | [`filter::BackgroundActivityFilter`] (dv-processing semantics), [`filter::RefractoryFilter`] |
//! | taxels | [`taxel::TaxelLayout`], [`taxel::ReceptiveFields`], [`taxel::TaxelPooling`], [`taxel::PositionUpdate`], [`taxel::Transducer`] |
//! | the NeuroTac simulator (spec `simulator.md`) | [`sim::Simulator`], [`sim::SimParams`], [`sim::Texture`], [`sim::Camera`] |
//! | errors | [`FormatError`], [`DeviceError`], [`TransductionError`], [`ReaderTransductionError`], [`SensorError`], [`sim::SimulationError`] |
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
//!
//! Transduction of a stream into taxel spikes:
//!
//! ```
//! use neurotac_core::{Event, EventBuffer, Timestamp};
//! use neurotac_sensor::taxel::{TaxelLayout, Transducer, TransductionConfig};
//! let layout = TaxelLayout::neurotac_default();
//! let mut t = Transducer::new(&layout, TransductionConfig::default())?;
//! // Two neighbouring pixels at the centre pin (absolute µs): the BA filter drops the first
//! // (no support yet) and keeps the second (its neighbour fired 500 µs before).
//! let events: EventBuffer = [(10_000_000, 120, 90), (10_000_500, 121, 90)]
//!     .into_iter()
//!     .map(|(t, x, y)| Event { t: Timestamp(t), x, y, polarity: true })
//!     .collect();
//! t.push(&events)?;
//! t.finish();
//! let spikes = t.spike_trains();
//! assert_eq!(spikes.n_channels(), 49);
//! assert_eq!(spikes.count(0), 1); // one taxel event at the centre taxel
//! assert_eq!(t.taxel_events()[0].count, 1); // made of one pixel event
//! # Ok::<(), neurotac_sensor::TransductionError>(())
//! ```
#![deny(missing_docs)]

pub mod davis;
pub mod error;
pub mod filter;
pub mod format;
pub mod geometry;
pub mod sim;
pub mod stage;
pub mod taxel;
#[doc(hidden)]
pub mod testing;

pub use error::{
    DeviceError, FormatError, ReaderTransductionError, SensorError, TransductionError,
};
