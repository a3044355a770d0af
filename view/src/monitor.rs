//! [`StreamMonitor`]: pixel events in, the state the page shows out — the decaying event
//! image (one last-event time and polarity per pixel), the transduction's stage counts and
//! receptive fields, and the taxel spikes of the last raster window — taken as a [`Frame`] at
//! any moment.
//!
//! The transduction is the one `neurotac transduce` runs ([`Transducer`]), so the counts the
//! page shows for a recording equal that command's.

use crate::error::ViewError;
use crate::frame::{Decimation, EventImage, Frame, PlayState, Raster, StageCounts};
use neurotac_core::EventBuffer;
use neurotac_sensor::taxel::{TaxelLayout, Transducer, TransductionConfig};
use std::collections::VecDeque;

/// What the monitor keeps and how it pictures it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonitorConfig {
    /// The transduction (the paper's by default, as `neurotac transduce`).
    pub transduction: TransductionConfig,
    /// Decay time τ of the event image (ms). Default 30.
    pub decay_ms: f64,
    /// Stream time the raster shows (s). Default 2.
    pub raster_window_s: f64,
    /// Window of the taxel rates (s). Default 0.2 (ten pooling windows).
    pub rate_window_s: f64,
}

impl Default for MonitorConfig {
    fn default() -> Self {
        Self {
            transduction: TransductionConfig::default(),
            decay_ms: 30.0,
            raster_window_s: 2.0,
            rate_window_s: 0.2,
        }
    }
}

/// Pixel events → what one [`Frame`] shows (module docs).
#[derive(Debug, Clone)]
pub struct StreamMonitor {
    config: MonitorConfig,
    layout: TaxelLayout,
    transducer: Transducer,
    /// Per pixel, row-major: time of its last event (µs; `i64::MIN`: none yet).
    last_us: Vec<i64>,
    /// Per pixel: polarity of its last event.
    last_on: Vec<bool>,
    /// Time of the latest event (µs).
    now_us: Option<i64>,
    /// Taxel spikes of the raster window: `(taxel, t_s)`, in window order.
    spikes: VecDeque<(u16, f64)>,
    /// Events pushed since the last frame, and the stream time of the last frame.
    since_frame: u64,
    last_frame_us: Option<i64>,
}

impl StreamMonitor {
    /// A monitor of a stream on `layout`, transduced and pictured as `config` says.
    pub fn new(layout: &TaxelLayout, config: MonitorConfig) -> Result<Self, ViewError> {
        for (what, value) in [
            ("event-image decay (ms)", config.decay_ms),
            ("raster window (s)", config.raster_window_s),
            ("rate window (s)", config.rate_window_s),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(ViewError::InvalidParameter { what, value });
            }
        }
        let t = config.transduction;
        let pixels = t.width as usize * t.height as usize;
        Ok(Self {
            transducer: Transducer::new(layout, t)?,
            layout: layout.clone(),
            config,
            last_us: vec![i64::MIN; pixels],
            last_on: vec![false; pixels],
            now_us: None,
            spikes: VecDeque::new(),
            since_frame: 0,
            last_frame_us: None,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &MonitorConfig {
        &self.config
    }

    /// Pushes the next time-ordered events. An out-of-order or off-sensor event is a typed
    /// error naming its index in the stream; the events before it are shown and counted first.
    pub fn push(&mut self, events: &EventBuffer) -> Result<(), ViewError> {
        let (good, error) = match self.transducer.check(events) {
            Ok(()) => (events.len(), None),
            Err((good, e)) => (good, Some(e)),
        };
        let width = self.config.transduction.width as usize;
        for i in 0..good {
            let pixel = events.y[i] as usize * width + events.x[i] as usize;
            self.last_us[pixel] = events.t[i];
            self.last_on[pixel] = events.polarity[i];
        }
        if good > 0 {
            self.now_us = Some(events.t[good - 1]);
            self.since_frame += good as u64;
        }
        let result = if good == events.len() {
            self.transducer.push(events)
        } else {
            self.transducer.push(&events.iter().take(good).collect())
        };
        self.take_spikes();
        result?;
        match error {
            Some(e) => Err(e.into()),
            None => Ok(()),
        }
    }

    /// Moves the stream's clock to `t_us` without an event (a quiet stretch of a live or paced
    /// stream): closes the pooling window if `t_us` is past its end, so its spikes show
    /// without waiting for the next event. Times before the latest event are ignored.
    pub fn advance_to(&mut self, t_us: i64) {
        let Some(now) = self.now_us else { return };
        if t_us > now {
            self.transducer.advance_to(t_us);
            self.now_us = Some(t_us);
            self.take_spikes();
        }
    }

    /// The end of a recording: closes the last pooling window (as `neurotac transduce` does).
    pub fn finish(&mut self) {
        self.transducer.finish();
        self.take_spikes();
    }

    /// Stream time of the latest event (µs since the stream origin), once there is one.
    pub fn elapsed_us(&self) -> Option<i64> {
        Some(self.now_us? - self.transducer.origin_us()?)
    }

    /// The stream origin (µs): its first event's time, once there is one.
    pub fn origin_us(&self) -> Option<i64> {
        self.transducer.origin_us()
    }

    /// The stream's stage counts so far.
    pub fn counts(&self) -> StageCounts {
        let c = self.transducer.counts();
        StageCounts {
            events_in: c.events_in,
            after_filters: c.after_filters,
            in_fields: c.in_fields,
            taxel_spikes: c.taxel_events,
        }
    }

    /// Moves the closed windows' taxel spikes into the raster and drops those older than its
    /// window.
    fn take_spikes(&mut self) {
        let origin = self.transducer.origin_us().unwrap_or(0) as f64;
        for e in self.transducer.drain_taxel_events() {
            self.spikes.push_back((e.taxel, (e.t_us - origin) * 1e-6));
        }
        let from = self.elapsed_s() - self.config.raster_window_s;
        while self.spikes.front().is_some_and(|&(_, t)| t < from) {
            self.spikes.pop_front();
        }
    }

    fn elapsed_s(&self) -> f64 {
        self.elapsed_us().unwrap_or(0) as f64 * 1e-6
    }

    /// The picture now, numbered `seq`, with the player's `source`, `state` and `speed`; the
    /// decisions and the latency stamp are the caller's to fill in. Resets the "since the last
    /// frame" counts of [`Decimation`].
    pub fn frame(
        &mut self,
        seq: u64,
        source: &str,
        state: PlayState,
        speed: Option<&str>,
    ) -> Frame {
        let t = self.config.transduction;
        let now_us = self.now_us.unwrap_or(0);
        let t_s = self.elapsed_s();
        // The event image: |a| = exp(−Δt/τ) of each pixel's last event, cut at 5τ.
        let tau_us = self.config.decay_ms * 1e3;
        let cut_us = (5.0 * tau_us) as i64;
        let since_us = self.last_frame_us.unwrap_or(i64::MIN);
        let mut shown_new = 0u64;
        let intensity: Vec<f32> = (self.last_us.iter().zip(&self.last_on))
            .map(|(&last, &on)| {
                let age = now_us.saturating_sub(last);
                if last == i64::MIN || age > cut_us {
                    return 0.0;
                }
                shown_new += u64::from(last > since_us);
                let a = (-(age as f64) / tau_us).exp() as f32;
                if on { a } else { -a }
            })
            .collect();
        let stream_ms = match self.last_frame_us {
            Some(last) => (now_us - last).max(0) as f64 * 1e-3,
            None => t_s * 1e3,
        };
        let decimation = Decimation {
            events_since_last_frame: self.since_frame,
            stream_ms_since_last_frame: stream_ms,
            drawn_share: match self.since_frame {
                0 => 1.0,
                n => shown_new as f64 / n as f64,
            },
            speed_vs_realtime: 0.0,
        };
        self.since_frame = 0;
        self.last_frame_us = self.now_us;
        // Rates over the last rate window; the population rate in pooling-window bins.
        let n = self.layout.len();
        let rate_from = t_s - self.config.rate_window_s;
        let mut taxel_rate_hz = vec![0.0; n];
        // The window ends at the frame time once the stream is longer than it; before, it
        // starts at the stream origin (no negative times), spikes filling it from the left.
        let from_s = (t_s - self.config.raster_window_s).max(0.0);
        let bin_s = t.pool_window_us as f64 * 1e-6;
        let bins = (self.config.raster_window_s / bin_s).ceil() as usize;
        let mut population = vec![0.0; bins];
        for &(taxel, ts) in &self.spikes {
            if ts >= rate_from && (taxel as usize) < n {
                taxel_rate_hz[taxel as usize] += 1.0 / self.config.rate_window_s;
            }
            let bin = ((ts - from_s) / bin_s).floor();
            if bin >= 0.0 && (bin as usize) < bins {
                population[bin as usize] += 1.0 / (bin_s * n as f64);
            }
        }
        let fields = self.transducer.fields();
        Frame {
            seq,
            source: source.to_owned(),
            t_s,
            counts: self.counts(),
            image: EventImage {
                width: t.width,
                height: t.height,
                intensity,
                decay_ms: self.config.decay_ms,
            },
            field_centres: fields.centres().to_vec(),
            field_radius_px: fields.radius(),
            taxel_home: self.layout.centres().to_vec(),
            taxel_rate_hz,
            rate_window_s: self.config.rate_window_s,
            raster: Raster {
                from_s,
                to_s: from_s + self.config.raster_window_s,
                spikes: self.spikes.iter().copied().collect(),
                population_rate_hz: population,
                bin_s,
            },
            class_names: Vec::new(),
            decisions: Vec::new(),
            state,
            speed: speed.map(str::to_owned),
            decimation,
            notice: None,
            oldest_new_event_due_unix_ms: None,
        }
    }
}
