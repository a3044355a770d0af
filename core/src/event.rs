//! Pixel events of an event camera, one by one ([`Event`]) or as a compact buffer ([`EventBuffer`]).
//!
//! Coordinates are top-left: `x` grows to the right, `y` grows downwards, as in dv-processing and
//! the files under `shared/data/davis240`. Polarity `true` is an ON event (brightness increased).

use crate::time::Timestamp;
use serde::{Deserialize, Serialize};

/// One pixel event: time, pixel address and polarity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Event {
    /// Event time (integer µs).
    pub t: Timestamp,
    /// Column, 0 at the left.
    pub x: u16,
    /// Row, 0 at the top.
    pub y: u16,
    /// `true` for ON (brighter), `false` for OFF (darker).
    pub polarity: bool,
}

/// A compact, reusable buffer of events in structure-of-arrays form.
///
/// Decoders and filters fill it chunk by chunk; [`EventBuffer::clear`] keeps the capacity so a
/// steady stream allocates nothing after warm-up.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EventBuffer {
    /// Times in µs.
    pub t: Vec<i64>,
    /// Columns.
    pub x: Vec<u16>,
    /// Rows.
    pub y: Vec<u16>,
    /// Polarities (`true` = ON).
    pub polarity: Vec<bool>,
}

impl EventBuffer {
    /// An empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty buffer with room for `n` events.
    pub fn with_capacity(n: usize) -> Self {
        Self {
            t: Vec::with_capacity(n),
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            polarity: Vec::with_capacity(n),
        }
    }

    /// Number of events.
    #[inline]
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// `true` when the buffer holds no event.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Removes every event, keeping the allocation.
    pub fn clear(&mut self) {
        self.t.clear();
        self.x.clear();
        self.y.clear();
        self.polarity.clear();
    }

    /// Appends one event.
    #[inline]
    pub fn push(&mut self, e: Event) {
        self.t.push(e.t.0);
        self.x.push(e.x);
        self.y.push(e.y);
        self.polarity.push(e.polarity);
    }

    /// The `i`-th event, or `None` past the end.
    #[inline]
    pub fn get(&self, i: usize) -> Option<Event> {
        Some(Event {
            t: Timestamp(*self.t.get(i)?),
            x: self.x[i],
            y: self.y[i],
            polarity: self.polarity[i],
        })
    }

    /// Iterates over the events in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Event> + '_ {
        (0..self.len()).map(move |i| Event {
            t: Timestamp(self.t[i]),
            x: self.x[i],
            y: self.y[i],
            polarity: self.polarity[i],
        })
    }
}

impl FromIterator<Event> for EventBuffer {
    fn from_iter<I: IntoIterator<Item = Event>>(iter: I) -> Self {
        let mut b = EventBuffer::new();
        b.extend(iter);
        b
    }
}

impl Extend<Event> for EventBuffer {
    fn extend<I: IntoIterator<Item = Event>>(&mut self, iter: I) {
        for e in iter {
            self.push(e);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffer_round_trips_events_and_keeps_capacity_on_clear() {
        let events = [
            Event {
                t: Timestamp(3),
                x: 102,
                y: 28,
                polarity: true,
            },
            Event {
                t: Timestamp(3),
                x: 5,
                y: 179,
                polarity: false,
            },
        ];
        let mut b: EventBuffer = events.iter().copied().collect();
        assert_eq!(b.len(), 2);
        assert_eq!(b.iter().collect::<Vec<_>>(), events);
        assert_eq!(b.get(1), Some(events[1]));
        assert_eq!(b.get(2), None);
        let cap = b.t.capacity();
        b.clear();
        assert!(b.is_empty());
        assert_eq!(b.t.capacity(), cap);
    }
}
