//! # neurotac-view
//!
//! The live view of a sensor stream (`neurotac view`): pixel events in, a page of pictures out.
//!
//! ```text
//! StreamSource ─ Player (pace, controls) ─┬─ StreamMonitor ─ Frame ─ Hub ─ draw_frame (SVG) ─ Server ─ browser tabs
//!  (file, camera, simulator)              └─ StreamObserver (the recogniser's decisions) ─┘
//! ```
//!
//! A frame of a few events at one taxel, drawn as the page and `--snapshot` draw it:
//!
//! ```
//! use neurotac_core::{Event, EventBuffer, Timestamp};
//! use neurotac_sensor::taxel::TaxelLayout;
//! use neurotac_view::{MonitorConfig, PlayState, StreamMonitor, draw_frame};
//! let layout = TaxelLayout::neurotac_default();
//! let mut monitor = StreamMonitor::new(&layout, MonitorConfig::default())?;
//! let (x, y) = layout.centres()[0];
//! let events: EventBuffer = (0..50)
//!     .map(|i| Event { t: Timestamp(i * 1000), x: x as u16, y: y as u16, polarity: true })
//!     .collect();
//! monitor.push(&events)?;
//! monitor.finish(); // the end of the stream closes the last pooling window
//! let frame = monitor.frame(1, "example", PlayState::Ended, None);
//! assert_eq!(frame.counts.events_in, 50);
//! assert!(frame.raster.spikes.iter().all(|&(taxel, _)| taxel == 0));
//! assert!(draw_frame(&frame).starts_with("<svg"));
//! # Ok::<(), neurotac_view::ViewError>(())
//! ```
//!
//! | module | what it holds |
//! |---|---|
//! | [`frame`] | [`Frame`]: everything drawn at one moment — the decaying event image, receptive fields, taxel rates, the spike raster, the recogniser's decisions, what was left out of the drawing |
//! | [`monitor`] | [`StreamMonitor`]: pixel events → the state a frame shows (the transduction `neurotac transduce` runs, so the counts agree) |
//! | [`source`] | [`StreamSource`]: a recorded file ([`FileSource`]), a DAVIS camera ([`CameraSource`]) |
//! | [`player`] | [`Player`]: pacing (`realtime`, `N×`, `max`), pause, step, seek; a frame every [`FRAME_INTERVAL`](player::FRAME_INTERVAL) |
//! | [`hub`] | [`Hub`]: frames drawn on their own thread and handed to every viewer; [`Control`]s back |
//! | [`server`] | [`Server`]: the embedded HTTP server, the page and its Server-Sent Events, and its security model |
//! | [`request`] | reading one request within a deadline; [`AllowedHosts`], the `Host` values it answers |
//! | [`draw`] | [`draw_frame`]: a [`Frame`] as one standalone SVG (event image with fields, taxel hexagons, raster and population rate, decisions, what is left out); [`event_image_png`] |
//! | [`snapshot`] | [`frame_at`]: the frame at a chosen time, without a browser (`--snapshot`) |
//! | [`error`] | [`ViewError`] |
#![deny(missing_docs)]

pub mod draw;
pub mod error;
pub mod frame;
pub mod hub;
pub mod monitor;
pub mod player;
pub mod request;
pub mod server;
pub mod snapshot;
pub mod source;

pub use draw::{draw_frame, event_image_png};
pub use error::ViewError;
pub use frame::{
    CodingDecisions, Decimation, DecisionPoint, EventImage, Frame, PlayState, Raster, StageCounts,
};
pub use hub::{Control, Hub, Speed};
pub use monitor::{MonitorConfig, StreamMonitor};
pub use player::{NoObserver, Player, PlayerEnd, PlayerOptions, StreamObserver};
pub use request::AllowedHosts;
pub use server::{CONTROL_CONTENT_TYPE, Server, ServerLimits};
pub use snapshot::frame_at;
pub use source::{CameraSource, FileSource, SourceError, SourceRead, StreamSource};
