//! # neurotac-sensor
//!
//! The NeuroTac sensor side of neurotac: from camera pixel events to taxel spike trains.
//!
//! | concept | types |
//! |---|---|
//! | sensor geometry (49 pins, DAVIS240 image) | [`geometry::PinGeometry`] |
//! | the push interface of pipeline stages | [`stage::Stage`], [`stage::EventFilter`], [`stage::Filtered`], [`stage::Chain`] |
//! | noise filters | [`filter::BackgroundActivityFilter`] (dv-processing semantics), [`filter::RefractoryFilter`] |
//! | taxels | [`taxel::TaxelLayout`], [`taxel::ReceptiveFields`], [`taxel::TaxelPooling`], [`taxel::PositionUpdate`], [`taxel::Transducer`] |
//! | the NeuroTac simulator (spec `simulator.md`) | [`sim::Simulator`], [`sim::SimParams`], [`sim::Texture`], [`sim::Camera`] |
//! | errors | [`error::TransductionError`], [`sim::SimulationError`] |
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
//! # Ok::<(), neurotac_sensor::error::TransductionError>(())
//! ```
#![deny(missing_docs)]

pub mod error;
pub mod filter;
pub mod geometry;
pub mod sim;
pub mod stage;
pub mod taxel;
