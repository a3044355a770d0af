//! A simulated pixel event before sorting ([`RawEvent`]) and its ground truth ([`EventLabel`]):
//! the pin whose motion caused it, or [`NOISE_LABEL`].

/// Label of noise events (see [`EventLabel`]).
pub const NOISE_LABEL: u8 = u8::MAX;

/// Ground truth of one pixel event: the pin whose motion caused it, or noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct EventLabel(pub u8);

impl EventLabel {
    /// The noise label.
    pub const NOISE: EventLabel = EventLabel(NOISE_LABEL);

    /// `true` for a noise event.
    pub fn is_noise(self) -> bool {
        self.0 == NOISE_LABEL
    }

    /// The source pin of a signal event.
    pub fn pin(self) -> Option<usize> {
        (!self.is_noise()).then_some(self.0 as usize)
    }
}

/// One simulated event before sorting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct RawEvent {
    pub t_us: i64,
    pub y: u16,
    pub x: u16,
    pub on: bool,
    pub label: u8,
}
