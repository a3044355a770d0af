//! # neurotac-view
//!
//! The live view of a sensor stream (`neurotac view`): pixel events in, a page of pictures out.
//!
//! | module | what it holds |
//! |---|---|
//! | [`frame`] | [`Frame`]: everything drawn at one moment — the decaying event image, receptive fields, taxel rates, the spike raster, the recogniser's decisions, what was left out of the drawing |
#![deny(missing_docs)]

pub mod frame;

pub use frame::{
    CodingDecisions, Decimation, DecisionPoint, EventImage, Frame, PlayState, Raster, StageCounts,
};
