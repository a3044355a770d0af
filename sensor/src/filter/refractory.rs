//! A refractory filter (libcaer `caerFilterDVSNoise` refractory option, `davis240.md` §3.2):
//! drop an event when its own pixel fired less than `period_us` before; the pixel's time is
//! updated for every event. The map starts empty (no pixel is refractory at start).

use super::NEVER;
use crate::error::{TransductionError, check_in_sensor};
use crate::stage::EventFilter;
use neurotac_core::Event;

/// Drops events that follow their own pixel's previous event by less than a period.
#[derive(Debug, Clone)]
pub struct RefractoryFilter {
    width: u16,
    height: u16,
    period_us: i64,
    map: Vec<i64>,
    index: u64,
}

impl RefractoryFilter {
    /// A filter for a `width × height` sensor with a refractory period of `period_us` (> 0).
    pub fn new(width: u16, height: u16, period_us: i64) -> Result<Self, TransductionError> {
        if period_us <= 0 {
            return Err(TransductionError::InvalidParameter {
                what: "refractory period (µs)",
                value: period_us as f64,
                expected: "> 0",
            });
        }
        Ok(Self {
            width,
            height,
            period_us,
            map: vec![NEVER; width as usize * height as usize],
            index: 0,
        })
    }
}

impl EventFilter for RefractoryFilter {
    #[inline]
    fn retain(&mut self, e: Event) -> Result<bool, TransductionError> {
        let index = self.index;
        self.index += 1;
        check_in_sensor(index, e.x, e.y, self.width, self.height)?;
        Ok(self.keep_and_update(e.t.0, e.x, e.y))
    }
}

impl RefractoryFilter {
    /// The decision for an event already known to be inside the sensor; updates the map.
    #[inline]
    pub(crate) fn keep_and_update(&mut self, t: i64, x: u16, y: u16) -> bool {
        let c = y as usize * self.width as usize + x as usize;
        let keep = t - self.map[c] >= self.period_us;
        self.map[c] = t;
        keep
    }
}
