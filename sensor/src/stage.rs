//! The one push interface shared by every pipeline stage, and how stages compose.
//!
//! A [`Stage`] takes a batch of input and appends what it produces to an output batch; a stage
//! with memory (a pooling window) emits the rest on [`finish`](Stage::finish). Stages chain
//! with [`Chain`] (or [`Stage::then`]) when one's output is the next one's input. Pixel-event
//! filters only decide per event ([`EventFilter::retain`]); batching comes from [`Filtered`].

use crate::error::TransductionError;
use neurotac_core::{Event, EventBuffer};

/// A batch a stage can append to and reuse.
pub trait Batch: Default {
    /// Empties the batch, keeping its capacity.
    fn clear(&mut self);
}

impl Batch for EventBuffer {
    fn clear(&mut self) {
        EventBuffer::clear(self);
    }
}

impl<T> Batch for Vec<T> {
    fn clear(&mut self) {
        Vec::clear(self);
    }
}

/// A pipeline stage: batches in, batches out.
pub trait Stage {
    /// What the stage consumes.
    type Input: Batch;
    /// What the stage produces.
    type Output: Batch;

    /// Processes `input`, appending results to `out`.
    fn push(
        &mut self,
        input: &Self::Input,
        out: &mut Self::Output,
    ) -> Result<(), TransductionError>;

    /// Flushes whatever the stage still holds (e.g. an open pooling window). Default: nothing.
    fn finish(&mut self, out: &mut Self::Output) -> Result<(), TransductionError> {
        let _ = out;
        Ok(())
    }

    /// This stage followed by `next`.
    fn then<B: Stage<Input = Self::Output>>(self, next: B) -> Chain<Self, B>
    where
        Self: Sized,
    {
        Chain {
            first: self,
            second: next,
            between: Default::default(),
        }
    }
}

/// Two stages in a row; the intermediate batch is reused between pushes.
#[derive(Debug, Default)]
pub struct Chain<A: Stage, B: Stage<Input = A::Output>> {
    /// The first stage.
    pub first: A,
    /// The second stage.
    pub second: B,
    between: A::Output,
}

impl<A: Stage, B: Stage<Input = A::Output>> Stage for Chain<A, B> {
    type Input = A::Input;
    type Output = B::Output;

    fn push(&mut self, input: &A::Input, out: &mut B::Output) -> Result<(), TransductionError> {
        self.between.clear();
        self.first.push(input, &mut self.between)?;
        self.second.push(&self.between, out)
    }

    fn finish(&mut self, out: &mut B::Output) -> Result<(), TransductionError> {
        self.between.clear();
        self.first.finish(&mut self.between)?;
        self.second.push(&self.between, out)?;
        self.second.finish(out)
    }
}

/// A per-event decision on pixel events (dv-processing style). Implementors decide; batching,
/// counting and chaining come from [`Filtered`].
pub trait EventFilter {
    /// `Ok(true)` keeps the event. An event the filter cannot handle (e.g. outside the sensor)
    /// is an error naming it.
    fn retain(&mut self, event: Event) -> Result<bool, TransductionError>;
}

/// Turns an [`EventFilter`] into a [`Stage`] on [`EventBuffer`]s, counting what it keeps.
#[derive(Debug, Default, Clone)]
pub struct Filtered<F> {
    /// The filter.
    pub filter: F,
    /// Events seen.
    pub seen: u64,
    /// Events kept.
    pub kept: u64,
}

impl<F> Filtered<F> {
    /// Wraps `filter`.
    pub fn new(filter: F) -> Self {
        Self {
            filter,
            seen: 0,
            kept: 0,
        }
    }

    /// Fraction of events removed so far (dv-processing's reduction factor).
    pub fn reduction_factor(&self) -> f64 {
        if self.seen == 0 {
            0.0
        } else {
            1.0 - self.kept as f64 / self.seen as f64
        }
    }
}

impl<F: EventFilter> Stage for Filtered<F> {
    type Input = EventBuffer;
    type Output = EventBuffer;

    fn push(
        &mut self,
        input: &EventBuffer,
        out: &mut EventBuffer,
    ) -> Result<(), TransductionError> {
        for e in input.iter() {
            self.seen += 1;
            if self.filter.retain(e)? {
                self.kept += 1;
                out.push(e);
            }
        }
        Ok(())
    }
}
