//! The background-activity (BA) noise filter with the exact semantics of dv-processing 2.0's
//! `dv::noise::BackgroundActivityNoiseFilter` (`shared/specs/davis240.md` §3.1).
//!
//! State: a time surface `T[y][x]` (µs). For each event `(t, x, y)` in input order:
//! 1. keep it iff one of its **8 neighbours** (its own pixel excluded; neighbours outside the
//!    array skipped) has `t − T[neighbour] < window` (strict);
//! 2. set `T[y][x] = t`, whether the event was kept or not.
//!
//! Polarity is ignored. **Start-up:** dv-processing's map starts at 0 ([`MapStart::Zero`]),
//! so with timestamps that start at 0 every event with `t < window` is kept (126 events of the
//! shared recording at 2 ms, 218 at 5 ms); with absolute timestamps the zero map supports
//! nothing. [`MapStart::Empty`] starts with no history at all, so the first event of every
//! cluster is dropped whatever the time origin.

use crate::error::{TransductionError, check_in_sensor};
use crate::stage::EventFilter;
use neurotac_core::Event;

/// How the time surface starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MapStart {
    /// Every pixel last fired at t = 0 (dv-processing; reproduces its keep masks).
    #[default]
    Zero,
    /// No pixel has fired yet.
    Empty,
}

/// A time-surface cell that never supports an event (stored relative to the base).
const NEVER_REL: i32 = i32::MIN / 2;
/// Largest |t − base| kept before the base moves; keeps `t − cell` inside `i32`.
const REBASE_AT: i64 = 1 << 29;
/// Largest window accepted (100 s), far below [`REBASE_AT`].
const MAX_WINDOW_US: i64 = 100_000_000;

/// dv-processing's background-activity filter (see the module docs).
///
/// The time surface stores `i32` times relative to a base that follows the stream (moved every
/// ~9 minutes of event time, cells saturating at "never"), half the memory of `i64` times, so
/// the 8-neighbour reads stay in cache; the decisions are those of the `i64` definition.
#[derive(Debug, Clone)]
pub struct BackgroundActivityFilter {
    width: u16,
    height: u16,
    window_us: i64,
    start: MapStart,
    /// Time surface with a one-pixel border that never supports: `(width + 2) × (height + 2)`,
    /// times relative to `base_us` (`None` before the first event).
    map: Vec<i32>,
    base_us: Option<i64>,
    index: u64,
}

impl BackgroundActivityFilter {
    /// A filter for a `width × height` sensor with a support window of `window_us` (> 0).
    pub fn new(
        width: u16,
        height: u16,
        window_us: i64,
        start: MapStart,
    ) -> Result<Self, TransductionError> {
        if !(1..=MAX_WINDOW_US).contains(&window_us) {
            return Err(TransductionError::InvalidParameter {
                what: "BA window (µs)",
                value: window_us as f64,
                expected: "> 0 and ≤ 10⁸ (100 s)",
            });
        }
        let stride = width as usize + 2;
        let map = vec![NEVER_REL; stride * (height as usize + 2)];
        Ok(Self {
            width,
            height,
            window_us,
            start,
            map,
            base_us: None,
            index: 0,
        })
    }

    /// The support window (µs).
    pub fn window_us(&self) -> i64 {
        self.window_us
    }

    /// How the time surface started.
    pub fn start(&self) -> MapStart {
        self.start
    }
}

impl BackgroundActivityFilter {
    /// Moves the base to `t_us`: every cell is re-expressed relative to it, saturating at never.
    /// At the first event this also lays down the zero start (`MapStart::Zero`).
    #[cold]
    fn rebase(&mut self, t_us: i64) {
        let stride = self.width as usize + 2;
        match self.base_us {
            None => {
                if self.start == MapStart::Zero {
                    let zero = (0 - t_us).clamp(NEVER_REL as i64, 0) as i32;
                    for y in 0..self.height as usize {
                        self.map[(y + 1) * stride + 1..(y + 1) * stride + 1 + self.width as usize]
                            .fill(zero);
                    }
                }
            }
            Some(old) => {
                let shift = t_us - old;
                for y in 0..self.height as usize {
                    for c in &mut self.map
                        [(y + 1) * stride + 1..(y + 1) * stride + 1 + self.width as usize]
                    {
                        *c = (*c as i64 - shift).clamp(NEVER_REL as i64, REBASE_AT) as i32;
                    }
                }
            }
        }
        self.base_us = Some(t_us);
    }

    /// The filter's decision for an event already known to be inside the sensor; updates the
    /// time surface.
    #[inline]
    pub(crate) fn support_and_update(&mut self, t: i64, x: u16, y: u16) -> bool {
        let mut rel = t - self.base_us.unwrap_or(i64::MIN / 4);
        if !(-REBASE_AT..=REBASE_AT).contains(&rel) {
            self.rebase(t);
            rel = 0;
        }
        let t = rel as i32;
        let stride = self.width as usize + 2;
        let c = (y as usize + 1) * stride + x as usize + 1;
        let w = self.window_us as i32;
        let m = &self.map;
        // All eight tests, no early exit: cheaper than branching on random data.
        let support = (t - m[c - stride - 1] < w)
            | (t - m[c - stride] < w)
            | (t - m[c - stride + 1] < w)
            | (t - m[c - 1] < w)
            | (t - m[c + 1] < w)
            | (t - m[c + stride - 1] < w)
            | (t - m[c + stride] < w)
            | (t - m[c + stride + 1] < w);
        self.map[c] = t;
        support
    }
}

impl EventFilter for BackgroundActivityFilter {
    #[inline]
    fn retain(&mut self, e: Event) -> Result<bool, TransductionError> {
        let index = self.index;
        self.index += 1;
        check_in_sensor(index, e.x, e.y, self.width, self.height)?;
        Ok(self.support_and_update(e.t.0, e.x, e.y))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_core::Timestamp;

    /// The definition, with `i64` times and no rebasing.
    fn reference(events: &[(i64, u16, u16)], window: i64, start: MapStart) -> Vec<bool> {
        let (w, h) = (16usize, 12usize);
        let mut map = vec![
            if start == MapStart::Zero {
                0
            } else {
                i64::MIN / 2
            };
            w * h
        ];
        events
            .iter()
            .map(|&(t, x, y)| {
                let mut keep = false;
                for dy in -1i64..=1 {
                    for dx in -1i64..=1 {
                        let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                        if (dx, dy) != (0, 0)
                            && (0..w as i64).contains(&nx)
                            && (0..h as i64).contains(&ny)
                        {
                            keep |= t - map[ny as usize * w + nx as usize] < window;
                        }
                    }
                }
                map[y as usize * w + x as usize] = t;
                keep
            })
            .collect()
    }

    #[test]
    fn relative_time_surface_equals_the_i64_definition_across_rebases() {
        // Dense bursts separated by jumps of up to ~40 minutes, from two time origins.
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        };
        for origin in [0i64, 1_700_000_000_000_000] {
            let mut t = origin;
            let events: Vec<(i64, u16, u16)> = (0..20_000)
                .map(|i| {
                    t += if i % 997 == 0 {
                        (next() % 2_400_000_000) as i64
                    } else {
                        (next() % 3000) as i64
                    };
                    (t, (next() % 16) as u16, (next() % 12) as u16)
                })
                .collect();
            for start in [MapStart::Zero, MapStart::Empty] {
                for window in [1, 2000, 5000, 100_000_000] {
                    let mut f = BackgroundActivityFilter::new(16, 12, window, start).unwrap();
                    let ours: Vec<bool> = events
                        .iter()
                        .map(|&(t, x, y)| {
                            f.retain(Event {
                                t: Timestamp(t),
                                x,
                                y,
                                polarity: true,
                            })
                            .unwrap()
                        })
                        .collect();
                    assert_eq!(
                        ours,
                        reference(&events, window, start),
                        "origin {origin}, {start:?}, {window} µs"
                    );
                }
            }
        }
        assert!(BackgroundActivityFilter::new(16, 12, 100_000_001, MapStart::Zero).is_err());
    }
}
