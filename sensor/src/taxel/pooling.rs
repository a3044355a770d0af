//! Pooling pixel events into taxel events (the paper's spikes), and re-centring the fields.
//!
//! Time is cut into windows of `window` µs aligned to the recording origin (the first event,
//! unless given). When a window closes, every taxel with at least `min_events` pixel events in
//! it emits one [`TaxelEvent`]: the count, the mean position and the mean time of those events.
//! A taxel therefore spikes at most once per window (50 times per second at 20 ms).

use super::fields::{ReceptiveFields, TaxelPixelEvent};
use crate::error::TransductionError;
use crate::stage::Stage;

/// One taxel event: a spike of taxel `taxel` in window `window`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaxelEvent {
    /// Taxel index.
    pub taxel: u16,
    /// Window index since the origin.
    pub window: u64,
    /// Pixel events pooled.
    pub count: u32,
    /// Mean column (px).
    pub x: f64,
    /// Mean row (px).
    pub y: f64,
    /// Mean time (µs, same clock as the events; fractional).
    pub t_us: f64,
}

/// A taxel's sums over the open window, all exact in integers (the means divide once, at the
/// close).
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    count: u32,
    x: u64,
    y: u64,
    /// Σ (t − window start).
    t: i64,
}

/// Stage: labelled pixel events in, taxel events out.
#[derive(Debug, Clone)]
pub struct TaxelPooling {
    window_us: i64,
    min_events: u32,
    origin_us: Option<i64>,
    current: Option<u64>,
    /// Start of the open window (µs; meaningless while none is open).
    start_us: i64,
    sums: Vec<Sums>,
    touched: Vec<u16>,
    index: u64,
}

impl TaxelPooling {
    /// Pools for `n_taxels` taxels in windows of `window_us` (> 0), emitting taxels with at
    /// least `min_events` (≥ 1) events; windows start at `origin_us`, or at the first event.
    pub fn new(
        n_taxels: usize,
        window_us: i64,
        min_events: u32,
        origin_us: Option<i64>,
    ) -> Result<Self, TransductionError> {
        if window_us <= 0 {
            return Err(TransductionError::InvalidParameter {
                what: "pooling window (µs)",
                value: window_us as f64,
                expected: "> 0",
            });
        }
        if min_events == 0 {
            return Err(TransductionError::InvalidParameter {
                what: "minimum events per taxel event",
                value: 0.0,
                expected: "≥ 1",
            });
        }
        Ok(Self {
            window_us,
            min_events,
            origin_us,
            current: None,
            start_us: 0,
            sums: vec![Sums::default(); n_taxels],
            touched: Vec::new(),
            index: 0,
        })
    }

    /// The origin windows are aligned to (known once the first event arrived, if not given).
    pub fn origin_us(&self) -> Option<i64> {
        self.origin_us
    }

    /// The window length (µs).
    pub fn window_us(&self) -> i64 {
        self.window_us
    }

    /// Fixes the origin to `t_us` unless it is already known.
    pub(crate) fn fix_origin(&mut self, t_us: i64) {
        self.origin_us.get_or_insert(t_us);
    }

    /// The window index of time `t_us`, fixing the origin at the first call if needed.
    pub(crate) fn window_of(&mut self, t_us: i64) -> Result<u64, TransductionError> {
        let origin = *self.origin_us.get_or_insert(t_us);
        if t_us < origin {
            return Err(TransductionError::BeforeOrigin {
                index: self.index,
                origin_us: origin,
                got_us: t_us,
            });
        }
        Ok(((t_us - origin) / self.window_us) as u64)
    }

    /// Closes the open window into `out` and opens the one containing `t_us`; returns the new
    /// window's end (µs).
    pub(crate) fn roll_to(
        &mut self,
        t_us: i64,
        out: &mut Vec<TaxelEvent>,
    ) -> Result<i64, TransductionError> {
        let w = self.window_of(t_us)?;
        self.close(out);
        self.open(w);
        Ok(self.start_us + self.window_us)
    }

    /// Opens window `w` (the origin is known).
    fn open(&mut self, w: u64) {
        self.current = Some(w);
        self.start_us = self.origin_us.unwrap_or(0) + w as i64 * self.window_us;
    }

    /// Adds an event of the open window (the caller guarantees it belongs there).
    #[inline]
    pub(crate) fn accumulate(&mut self, taxel: u16, t_us: i64, x: u16, y: u16) {
        debug_assert!(self.current.is_some(), "a window is open");
        let s = &mut self.sums[taxel as usize];
        if s.count == 0 {
            self.touched.push(taxel);
        }
        s.count += 1;
        s.x += x as u64;
        s.y += y as u64;
        s.t += t_us - self.start_us;
    }

    /// Adds one labelled event (its window must not be earlier than the open one); a later
    /// window first closes the open one into `out`.
    pub fn add(
        &mut self,
        e: &TaxelPixelEvent,
        out: &mut Vec<TaxelEvent>,
    ) -> Result<(), TransductionError> {
        let w = self.window_of(e.event.t.0)?;
        self.index += 1;
        match self.current {
            Some(c) if c == w => {}
            Some(c) if c > w => {
                return Err(TransductionError::Backwards {
                    index: self.index - 1,
                    previous_us: self.origin_us.unwrap_or(0) + c as i64 * self.window_us,
                    got_us: e.event.t.0,
                });
            }
            _ => {
                self.close(out);
                self.open(w);
            }
        }
        self.accumulate(e.taxel, e.event.t.0, e.event.x, e.event.y);
        Ok(())
    }

    /// Closes the open window (if any) into `out`, taxels in index order.
    pub fn close(&mut self, out: &mut Vec<TaxelEvent>) {
        let Some(w) = self.current.take() else { return };
        let start = self.start_us;
        self.touched.sort_unstable();
        for &t in &self.touched {
            let s = std::mem::take(&mut self.sums[t as usize]);
            if s.count >= self.min_events {
                let n = s.count as f64;
                out.push(TaxelEvent {
                    taxel: t,
                    window: w,
                    count: s.count,
                    // Sums below 2⁵³ convert exactly: the means are those of f64 sums.
                    x: s.x as f64 / n,
                    y: s.y as f64 / n,
                    t_us: start as f64 + s.t as f64 / n,
                });
            }
        }
        self.touched.clear();
    }

    /// Closes the open window if time `t_us` is past its end (live streams: bounded latency
    /// even when no event arrives).
    pub fn advance_to(&mut self, t_us: i64, out: &mut Vec<TaxelEvent>) {
        if let (Some(w), Some(origin)) = (self.current, self.origin_us)
            && t_us >= origin + (w as i64 + 1) * self.window_us
        {
            self.close(out);
        }
    }
}

impl Stage for TaxelPooling {
    type Input = Vec<TaxelPixelEvent>;
    type Output = Vec<TaxelEvent>;

    fn push(
        &mut self,
        input: &Vec<TaxelPixelEvent>,
        out: &mut Vec<TaxelEvent>,
    ) -> Result<(), TransductionError> {
        input.iter().try_for_each(|e| self.add(e, out))
    }

    fn finish(&mut self, out: &mut Vec<TaxelEvent>) -> Result<(), TransductionError> {
        self.close(out);
        Ok(())
    }
}

/// Re-centring: each taxel event moves its field's centre towards the events' mean position,
/// `c ← c + gain·(x̄ − c)`, bounded as in [`ReceptiveFields::move_centre`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionUpdate {
    /// Gain in [0, 1] (0 disables re-centring). The paper does not give its value; default 0.5.
    pub gain: f64,
}

impl Default for PositionUpdate {
    fn default() -> Self {
        Self { gain: 0.5 }
    }
}

impl PositionUpdate {
    /// Moves the centres of the taxels in `events`.
    pub fn apply(&self, events: &[TaxelEvent], fields: &mut ReceptiveFields) {
        if self.gain == 0.0 {
            return;
        }
        for e in events {
            let t = e.taxel as usize;
            let (cx, cy) = fields.centres()[t];
            fields.move_centre(
                t,
                (cx + self.gain * (e.x - cx), cy + self.gain * (e.y - cy)),
            );
        }
    }
}
