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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
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
/// Besides the time surface `T` it keeps, per pixel, the time until which an event there is
/// supported: `S[p] = max over p's neighbours n of T[n] + window`, so step 1 is `t < S[p]`, one
/// read. While time does not decrease, an event at `p` raises `S` of its 8 neighbours to
/// `t + window` (8 stores, no reads); an event earlier than the latest one recomputes those 8
/// cells from `T` (slow, exact). Both maps store `i32` times relative to a base that follows the
/// stream (moved every ~9 minutes of event time, cells saturating at "never"), half the memory
/// of `i64` times. The decisions are those of the `i64` definition for timestamps ≥ 0 that never
/// fall more than 2²⁹ µs (~9 minutes) behind the latest one; a larger step back saturates
/// future cells, as a negative first timestamp moves the zero start to it.
#[derive(Debug, Clone)]
pub struct BackgroundActivityFilter {
    width: u16,
    height: u16,
    window_us: i64,
    start: MapStart,
    /// Time surface `T` with a one-pixel border that never supports: `(width + 2) × (height +
    /// 2)`, times relative to `base_us`. The border is never written.
    last: Vec<i32>,
    /// `S` on the same grid and base; its border cells are written (by events next to the edge)
    /// but never read.
    support_until: Vec<i32>,
    /// `None` before the first event.
    base_us: Option<i64>,
    /// The latest event time so far (`i64::MIN` before the first event).
    latest_us: i64,
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
        let cells = (width as usize + 2) * (height as usize + 2);
        Ok(Self {
            width,
            height,
            window_us,
            start,
            last: vec![NEVER_REL; cells],
            support_until: vec![NEVER_REL; cells],
            base_us: None,
            latest_us: i64::MIN,
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
    /// The grid's row stride (the sensor width plus the two border columns).
    #[inline]
    fn stride(&self) -> usize {
        self.width as usize + 2
    }

    /// Moves the base to `t_us`: every cell is re-expressed relative to it, saturating at never
    /// (and, for a base moved back in time, at a future no event before the next move reaches).
    /// At the first event this also lays down the zero start (`MapStart::Zero`).
    #[cold]
    fn rebase(&mut self, t_us: i64) {
        let (stride, width) = (self.stride(), self.width as usize);
        let w = self.window_us as i32;
        let interior = |y: usize| (y + 1) * stride + 1..(y + 1) * stride + 1 + width;
        match self.base_us {
            None => {
                if self.start == MapStart::Zero {
                    let zero = (0 - t_us).clamp(NEVER_REL as i64, 0) as i32;
                    // Every pixel has a neighbour inside the array unless the array is 1 × 1.
                    let has_neighbour = self.width as usize * self.height as usize > 1;
                    let support = if has_neighbour { zero + w } else { NEVER_REL };
                    for y in 0..self.height as usize {
                        self.last[interior(y)].fill(zero);
                        self.support_until[interior(y)].fill(support);
                    }
                }
            }
            Some(old) => {
                let shift = t_us - old;
                let shifted = |c: i32, high: i64| (c as i64 - shift).clamp(NEVER_REL as i64, high);
                for y in 0..self.height as usize {
                    for c in &mut self.last[interior(y)] {
                        *c = shifted(*c, REBASE_AT) as i32;
                    }
                    for c in &mut self.support_until[interior(y)] {
                        *c = shifted(*c, REBASE_AT + MAX_WINDOW_US) as i32;
                    }
                }
            }
        }
        self.base_us = Some(t_us);
    }

    /// Recomputes `S` of the pixels around cell `c` from `T` (an event earlier than the latest
    /// one: its neighbours' supports need not be its own time).
    #[cold]
    fn recompute_support_around(&mut self, c: usize) {
        let stride = self.stride();
        let w = self.window_us as i32;
        let (x, y) = (c % stride, c / stride);
        for ny in y - 1..=y + 1 {
            for nx in x - 1..=x + 1 {
                let interior = (1..=self.width as usize).contains(&nx)
                    && (1..=self.height as usize).contains(&ny);
                if (nx, ny) == (x, y) || !interior {
                    continue;
                }
                let n = ny * stride + nx;
                let newest = [
                    n - stride - 1,
                    n - stride,
                    n - stride + 1,
                    n - 1,
                    n + 1,
                    n + stride - 1,
                    n + stride,
                    n + stride + 1,
                ]
                .into_iter()
                .map(|m| self.last[m])
                .max()
                .expect("eight neighbours");
                // `NEVER_REL + w` still supports nothing: every relative time is ≥ −2²⁹.
                self.support_until[n] = newest + w;
            }
        }
    }

    /// The filter's decision for an event already known to be inside the sensor; updates the
    /// time surface. Always inlined: the call would cost as much as the work.
    #[inline(always)]
    pub(crate) fn support_and_update(&mut self, t_us: i64, x: u16, y: u16) -> bool {
        let mut rel = t_us - self.base_us.unwrap_or(i64::MIN / 4);
        if !(-REBASE_AT..=REBASE_AT).contains(&rel) {
            self.rebase(t_us);
            rel = 0;
        }
        let t = rel as i32;
        let stride = self.stride();
        let c = (y as usize + 1) * stride + x as usize + 1;
        // t − T[n] < w for some neighbour n  ⇔  t < max T[n] + w = S[c] (no overflow: |t| ≤ 2²⁹).
        let support = t < self.support_until[c];
        self.last[c] = t;
        if t_us >= self.latest_us {
            self.latest_us = t_us;
            let s = t + self.window_us as i32;
            let around = &mut self.support_until[c - stride - 1..=c + stride + 1];
            around[0] = s;
            around[1] = s;
            around[2] = s;
            around[stride] = s;
            around[stride + 2] = s;
            around[2 * stride] = s;
            around[2 * stride + 1] = s;
            around[2 * stride + 2] = s;
        } else {
            self.recompute_support_around(c);
        }
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
    fn reference(
        events: &[(i64, u16, u16)],
        window: i64,
        start: MapStart,
        w: usize,
        h: usize,
    ) -> Vec<bool> {
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

    /// `f`'s decision for each `(t, x, y)`.
    fn decisions(mut f: BackgroundActivityFilter, events: &[(i64, u16, u16)]) -> Vec<bool> {
        events
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
                    let f = BackgroundActivityFilter::new(16, 12, window, start).unwrap();
                    let ours = decisions(f, &events);
                    assert_eq!(
                        ours,
                        reference(&events, window, start, 16, 12),
                        "origin {origin}, {start:?}, {window} µs"
                    );
                }
            }
        }
        assert!(BackgroundActivityFilter::new(16, 12, 100_000_001, MapStart::Zero).is_err());
    }

    /// `retain` does not require ordered input: times that step back (by up to ~8 minutes)
    /// take the slow path and still give the definition's decisions, also across rebases.
    #[test]
    fn times_going_back_equal_the_i64_definition() {
        let mut state = 987654321u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        };
        for (w, h) in [(16u16, 12u16), (1, 1), (1, 5), (7, 1)] {
            let mut t = 1_000_000i64;
            let events: Vec<(i64, u16, u16)> = (0..20_000)
                .map(|i| {
                    // Back by up to ~8 minutes, then ahead of the latest time by ≥ 8 minutes.
                    let step = match i % 1009 {
                        0 => -((next() % 500_000_000) as i64),
                        500 => 500_000_000 + (next() % 2_000_000_000) as i64,
                        _ => (next() % 3000) as i64 - 600,
                    };
                    // Times stay ≥ 0 (the zero start treats negative times differently).
                    t = (t + step).max(0);
                    (t, (next() % w as u64) as u16, (next() % h as u64) as u16)
                })
                .collect();
            for start in [MapStart::Zero, MapStart::Empty] {
                for window in [1, 2000, 100_000_000] {
                    let f = BackgroundActivityFilter::new(w, h, window, start).unwrap();
                    let ours = decisions(f, &events);
                    let truth = reference(&events, window, start, w as usize, h as usize);
                    let first_difference = (0..events.len()).find(|&i| ours[i] != truth[i]);
                    assert_eq!(first_difference, None, "{w} × {h}, {start:?}, {window} µs");
                }
            }
        }
    }
}
