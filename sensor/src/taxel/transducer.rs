//! The whole NeuroTac transduction (paper, Methods, "Sensor operation"): pixel events →
//! background-activity filter → receptive-field mask → 20 ms pooling → position update, giving
//! the 49 taxel spike trains of a recording.

use super::fields::ReceptiveFields;
use super::layout::TaxelLayout;
use super::pooling::{PositionUpdate, TaxelEvent, TaxelPooling};
use crate::error::{ReaderTransductionError, TransductionError, check_in_sensor};
use crate::filter::{BackgroundActivityFilter, MapStart, RefractoryFilter};
use crate::format::{EventReader, ReadStats};
use crate::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH};
use neurotac_core::{EventBuffer, MultiSpikeTrain};
use std::path::Path;
use std::time::{Duration, Instant};

/// Transduction settings; the defaults are the paper's. Serialisable: datasets record the
/// settings that made them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TransductionConfig {
    /// Sensor width (px). Default 240.
    pub width: u16,
    /// Sensor height (px). Default 180.
    pub height: u16,
    /// Background-activity window (µs); `None` disables the filter. Default 5000 (paper).
    pub ba_window_us: Option<i64>,
    /// How the BA time surface starts. Default [`MapStart::Zero`] (dv-processing).
    pub ba_start: MapStart,
    /// Refractory period (µs); `None` (default) disables the refractory filter.
    pub refractory_us: Option<i64>,
    /// Receptive-field radius (px). Default 3: the paper's receptive field is 6 px in diameter.
    pub rf_radius_px: f64,
    /// How far a field may move from home (px). Default 10 (pins move 2–9 px).
    pub max_shift_px: f64,
    /// Pooling window (µs). Default 20 000 (paper).
    pub pool_window_us: i64,
    /// Pixel events needed for a taxel event. Default 1.
    pub min_events: u32,
    /// Re-centring gain in [0, 1]; 0 disables. Default 0.5 (the paper gives no value).
    pub recentre_gain: f64,
    /// Origin of the pooling windows and of spike times (µs); `None` = the first event of the
    /// recording (before filtering).
    pub origin_us: Option<i64>,
}

impl Default for TransductionConfig {
    fn default() -> Self {
        Self {
            width: DAVIS240_WIDTH,
            height: DAVIS240_HEIGHT,
            ba_window_us: Some(5000),
            ba_start: MapStart::Zero,
            refractory_us: None,
            rf_radius_px: 3.0,
            max_shift_px: 10.0,
            pool_window_us: 20_000,
            min_events: 1,
            recentre_gain: 0.5,
            origin_us: None,
        }
    }
}

/// Counts of what each stage passed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TransductionCounts {
    /// Pixel events in.
    pub events_in: u64,
    /// Events kept by the noise filters.
    pub after_filters: u64,
    /// Events inside a receptive field.
    pub in_fields: u64,
    /// Taxel events (spikes) out.
    pub taxel_events: u64,
}

/// What [`Transducer::transduce_reader`] read and produced.
#[derive(Debug, Clone)]
pub struct ReaderTransduction {
    /// One spike train per taxel, in seconds since the origin ([`Transducer::spike_trains`]).
    pub spike_trains: MultiSpikeTrain,
    /// What each stage passed ([`Transducer::counts`]: totals, events pushed before included).
    pub counts: TransductionCounts,
    /// What the reader delivered and skipped.
    pub read: ReadStats,
    /// Times of the first and the last event read (µs, the input's clock); `None` when the
    /// input held no event.
    pub first_last_us: Option<(i64, i64)>,
    /// Time spent transducing (pushing the events and closing the last window), without
    /// reading and decoding the input.
    pub transduce_time: Duration,
}

/// Pixel events in, taxel events out.
///
/// Events are processed one pooling window at a time: a window's taxel events re-centre the
/// fields before any event of the next window is assigned, so the result never depends on how
/// the input stream was cut into chunks (live USB transfers or file reads). Live use: call
/// [`Transducer::advance_to`] with the device clock to close a window without waiting for the
/// next event — taxel events then lag their window by at most one window. A whole file or
/// other [`EventReader`]: [`Transducer::transduce_reader`].
///
/// The transducer is the stage chain `Filtered<BackgroundActivityFilter>` →
/// `Filtered<RefractoryFilter>` → [`ReceptiveFieldMask`](super::ReceptiveFieldMask) →
/// [`TaxelPooling`] (composed with [`Stage::then`](crate::stage::Stage::then)) fused into one
/// pass over the events, with the re-centring
/// ([`PositionUpdate`]) fed back between windows, which a chain of independent stages cannot do.
/// It calls the stages' own per-event decisions, so without re-centring it gives the chain's
/// taxel events exactly (tested); fused, it makes no intermediate batches and checks each event
/// once.
#[derive(Debug, Clone)]
pub struct Transducer {
    ba: Option<BackgroundActivityFilter>,
    refractory: Option<RefractoryFilter>,
    fields: ReceptiveFields,
    pooling: TaxelPooling,
    update: PositionUpdate,
    width: u16,
    height: u16,
    last_t: i64,
    /// End of the open pooling window (µs); `i64::MIN` before the first window.
    window_end_us: i64,
    counts: TransductionCounts,
    closed: Vec<TaxelEvent>,
    taxel_events: Vec<TaxelEvent>,
}

impl Transducer {
    /// A transducer for `layout` with `config` (validated here).
    pub fn new(
        layout: &TaxelLayout,
        config: TransductionConfig,
    ) -> Result<Self, TransductionError> {
        let c = config;
        if !(0.0..=1.0).contains(&c.recentre_gain) {
            return Err(TransductionError::InvalidParameter {
                what: "re-centring gain",
                value: c.recentre_gain,
                expected: "in [0, 1]",
            });
        }
        let ba = c
            .ba_window_us
            .map(|w| BackgroundActivityFilter::new(c.width, c.height, w, c.ba_start))
            .transpose()?;
        let refractory = c
            .refractory_us
            .map(|p| RefractoryFilter::new(c.width, c.height, p))
            .transpose()?;
        Ok(Self {
            ba,
            refractory,
            fields: ReceptiveFields::new(
                layout,
                c.rf_radius_px,
                c.max_shift_px,
                c.width,
                c.height,
            )?,
            pooling: TaxelPooling::new(layout.len(), c.pool_window_us, c.min_events, c.origin_us)?,
            update: PositionUpdate {
                gain: c.recentre_gain,
            },
            width: c.width,
            height: c.height,
            last_t: i64::MIN,
            window_end_us: i64::MIN,
            counts: TransductionCounts::default(),
            closed: Vec::new(),
            taxel_events: Vec::new(),
        })
    }

    /// Checks a chunk as [`push`](Self::push) would (time order, continuing the previous chunk,
    /// and every event on the sensor) without processing it: on failure, the position in the
    /// chunk of the first bad event and the error `push` would give there, so a caller can
    /// process the good events before it and nothing after.
    pub fn check(&self, events: &EventBuffer) -> Result<(), (usize, TransductionError)> {
        let mut last = self.last_t;
        for (k, ((&t, &x), &y)) in events.t.iter().zip(&events.x).zip(&events.y).enumerate() {
            let index = self.counts.events_in + k as u64;
            if t < last {
                let e = TransductionError::Backwards {
                    index,
                    previous_us: last,
                    got_us: t,
                };
                return Err((k, e));
            }
            check_in_sensor(index, x, y, self.width, self.height).map_err(|e| (k, e))?;
            last = t;
        }
        Ok(())
    }

    /// Processes a chunk of events (time-ordered, continuing the previous chunk).
    pub fn push(&mut self, events: &EventBuffer) -> Result<(), TransductionError> {
        let (width, height) = (self.width, self.height);
        // Counters live in registers during the loop and are written back on every exit.
        let mut counts = self.counts;
        let result = (|| {
            for ((&t, &x), &y) in events.t.iter().zip(&events.x).zip(&events.y) {
                let index = counts.events_in;
                if t < self.last_t {
                    return Err(TransductionError::Backwards {
                        index,
                        previous_us: self.last_t,
                        got_us: t,
                    });
                }
                check_in_sensor(index, x, y, width, height)?;
                if index == 0 {
                    self.pooling.fix_origin(t);
                }
                self.last_t = t;
                counts.events_in += 1;
                let mut keep = true;
                if let Some(ba) = &mut self.ba {
                    keep &= ba.support_and_update(t, x, y);
                }
                if let Some(r) = &mut self.refractory {
                    keep &= r.keep_and_update(t, x, y);
                }
                if !keep {
                    continue;
                }
                counts.after_filters += 1;
                // A new window: close the open one and re-centre before assigning this event.
                if t >= self.window_end_us {
                    self.closed.clear();
                    self.window_end_us = self.pooling.roll_to(t, &mut self.closed)?;
                    counts.taxel_events += self.closed.len() as u64;
                    self.update.apply(&self.closed, &mut self.fields);
                    self.taxel_events.append(&mut self.closed);
                }
                if let Some(taxel) = self.fields.assign_cached(x, y) {
                    counts.in_fields += 1;
                    self.pooling.accumulate(taxel, t, x, y);
                }
            }
            Ok(())
        })();
        self.counts = counts;
        result
    }

    /// Reads `reader` to its end chunk by chunk, pushes every chunk ([`Self::push`]) and closes
    /// the last window ([`Self::finish`]). `path` names the input in transduction errors; read
    /// errors name it (and the byte offset) themselves. Events decoded before a read error are
    /// transduced first, as the reader delivers them.
    pub fn transduce_reader<R: EventReader + ?Sized>(
        &mut self,
        reader: &mut R,
        path: &Path,
    ) -> Result<ReaderTransduction, ReaderTransductionError> {
        let mut chunk = EventBuffer::new();
        let mut first_last_us: Option<(i64, i64)> = None;
        let mut transduce_time = Duration::ZERO;
        while reader.read_chunk(&mut chunk)? > 0 {
            if let (Some(&first), Some(&last)) = (chunk.t.first(), chunk.t.last()) {
                first_last_us = Some((first_last_us.map_or(first, |(f, _)| f), last));
            }
            let start = Instant::now();
            self.push(&chunk)
                .map_err(|source| ReaderTransductionError::Transduction {
                    path: path.to_path_buf(),
                    source,
                })?;
            transduce_time += start.elapsed();
            chunk.clear();
        }
        let start = Instant::now();
        self.finish();
        transduce_time += start.elapsed();
        Ok(ReaderTransduction {
            spike_trains: self.spike_trains(),
            counts: self.counts,
            read: reader.stats(),
            first_last_us,
            transduce_time,
        })
    }

    fn close_window(&mut self) {
        self.closed.clear();
        self.pooling.close(&mut self.closed);
        self.window_end_us = i64::MIN;
        self.finish_closed();
    }

    fn finish_closed(&mut self) {
        self.update.apply(&self.closed, &mut self.fields);
        self.counts.taxel_events += self.closed.len() as u64;
        self.taxel_events.append(&mut self.closed);
    }

    /// Closes the open window if `t_us` is past its end (live streams).
    pub fn advance_to(&mut self, t_us: i64) {
        if t_us >= self.window_end_us {
            self.close_window();
        }
    }

    /// Closes the last window (end of a recording).
    pub fn finish(&mut self) {
        self.close_window();
    }

    /// Taxel events so far, in window order (taxel order within a window).
    pub fn taxel_events(&self) -> &[TaxelEvent] {
        &self.taxel_events
    }

    /// Takes the taxel events so far (live use), leaving none.
    pub fn drain_taxel_events(&mut self) -> Vec<TaxelEvent> {
        std::mem::take(&mut self.taxel_events)
    }

    /// What each stage passed so far.
    pub fn counts(&self) -> TransductionCounts {
        self.counts
    }

    /// The receptive fields (current centres).
    pub fn fields(&self) -> &ReceptiveFields {
        &self.fields
    }

    /// The time origin of windows and spike times (µs), once known.
    pub fn origin_us(&self) -> Option<i64> {
        self.pooling.origin_us()
    }

    /// The taxel events so far as one spike train per taxel, in seconds since the origin
    /// (`(t̄ − origin) / 10⁶`).
    pub fn spike_trains(&self) -> MultiSpikeTrain {
        let origin = self.origin_us().unwrap_or(0) as f64;
        let spikes: Vec<(u32, f64)> = self
            .taxel_events
            .iter()
            .map(|e| (e.taxel as u32, (e.t_us - origin) / 1e6))
            .collect();
        MultiSpikeTrain::from_labelled_spikes(self.fields.centres().len(), &spikes)
            .expect("taxel indices are in range and mean times finite")
    }
}
