//! # neurotac-view
//!
//! The live view of a sensor stream (`neurotac view`): pixel events in, a page of pictures out.
//!
//! | module | what it holds |
//! |---|---|
//! | [`frame`] | [`Frame`]: everything drawn at one moment — the decaying event image, receptive fields, taxel rates, the spike raster, the recogniser's decisions, what was left out of the drawing |
//! | [`draw`] | [`draw_frame`]: a [`Frame`] as one standalone SVG (event image with fields, taxel hexagons, raster and population rate, decisions, what is left out); [`event_image_png`] |
#![deny(missing_docs)]

pub mod draw;
pub mod frame;

pub use draw::{draw_frame, event_image_png};

pub use frame::{
    CodingDecisions, Decimation, DecisionPoint, EventImage, Frame, PlayState, Raster, StageCounts,
};
