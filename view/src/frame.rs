//! One [`Frame`]: everything the page (and a snapshot) draws at one moment of the stream, as
//! plain owned data, taken from the [`StreamMonitor`](crate::monitor::StreamMonitor) and drawn by
//! [`draw_frame`](crate::draw_frame) — the browser and `--snapshot` show the same SVG.

use serde::Serialize;

/// What each transduction stage passed so far (as `neurotac transduce` prints them).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct StageCounts {
    /// Pixel events read.
    pub events_in: u64,
    /// Of those, kept by the noise filters.
    pub after_filters: u64,
    /// Of those, inside a receptive field.
    pub in_fields: u64,
    /// Taxel spikes (pooled taxel events).
    pub taxel_spikes: u64,
}

/// The decaying event image: per pixel, `+a` for an ON and `−a` for an OFF event, with
/// `a = exp(−(t − t_last)/τ)` of the pixel's last event at the frame time `t`
/// (0 where no event is recent), row-major, `width × height`.
#[derive(Debug, Clone, PartialEq)]
pub struct EventImage {
    /// Columns (px).
    pub width: u16,
    /// Rows (px).
    pub height: u16,
    /// Signed intensity in `[−1, 1]` per pixel, row-major.
    pub intensity: Vec<f32>,
    /// The decay time τ (ms).
    pub decay_ms: f64,
}

/// The scrolling raster of taxel spikes over the last `window_s` of the stream.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Raster {
    /// Stream time (s since the stream origin) of the raster's left edge: the frame time less
    /// the raster window, or 0 while the stream is shorter than the window.
    pub from_s: f64,
    /// Stream time of its right edge: `from_s` + the raster window (the frame time once the
    /// stream is longer than the window).
    pub to_s: f64,
    /// Every taxel spike in the window: `(taxel, t_s)` (49 taxels pooled every 20 ms give at
    /// most a few thousand, so none is left out).
    pub spikes: Vec<(u16, f64)>,
    /// Population rate: mean spike rate per taxel (Hz) in consecutive bins of `bin_s` from
    /// `from_s`, counted from every spike.
    pub population_rate_hz: Vec<f64>,
    /// Width of a population-rate bin (s): the pooling window.
    pub bin_s: f64,
}

/// One coding's online decisions over the current slide.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CodingDecisions {
    /// The coding's name (`intensive`, `spatial`, `temporal`, `spatiotemporal`).
    pub coding: String,
    /// Its decision after each closed window of the slide, oldest first.
    pub history: Vec<DecisionPoint>,
    /// The final decision, once the slide (or the kept duration) is over.
    pub final_decision: Option<DecisionPoint>,
}

/// One decision as the page shows it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DecisionPoint {
    /// Elapsed time since the slide start (s): the end of its window.
    pub t_s: f64,
    /// The class (an index into [`Frame::class_names`]); meaningless when `tie`.
    pub class: usize,
    /// Share of the neighbours that voted for it.
    pub vote_share: f64,
    /// No class yet: the nearest training samples are equally far.
    pub tie: bool,
    /// The class has held for the recogniser's stability count.
    pub stable: bool,
}

/// Whether the stream moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PlayState {
    /// Events are being read and shown.
    Playing,
    /// Paused by a viewer (a recording or a simulated slide waits; a camera is never paused).
    Paused,
    /// The source ended (a recording's end).
    Ended,
    /// A still picture of the stream at a chosen time (`neurotac view --snapshot --at T`).
    Snapshot,
    /// The source failed; [`Frame::notice`] says why.
    Failed,
}

/// What was left out of the drawing (never of the counts), said on the page.
///
/// Every event reaches the counts, the rates and the raster. The event image is a picture of
/// one instant: of the events since the previous frame it shows each pixel's latest, decayed
/// to the frame time, so when a frame covers much more stream time than the decay (a fast
/// replay, a burst) most of them are not drawn.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Decimation {
    /// Pixel events since the previous frame (all counted).
    pub events_since_last_frame: u64,
    /// Stream time (ms) since the previous frame.
    pub stream_ms_since_last_frame: f64,
    /// Of the events since the previous frame, the share the event image shows (each
    /// pixel's latest one within 5 decay times of the frame time): 1 = nothing left out.
    pub drawn_share: f64,
    /// How fast the stream went against the wall clock since the previous frame (1 = real
    /// time; 0 = not measured: paused, after a seek, a snapshot).
    pub speed_vs_realtime: f64,
}

/// Everything drawn at one moment of the stream.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Frame number (consecutive; a viewer that misses some sees a gap).
    pub seq: u64,
    /// What is shown: a file name, `DAVIS240 …`, `simulated <texture>, slide <n>`.
    pub source: String,
    /// Stream time of the frame (s since the stream origin, its first event).
    pub t_s: f64,
    /// The stream's stage counts up to `t_s`.
    pub counts: StageCounts,
    /// The decaying event image.
    pub image: EventImage,
    /// Receptive-field centres now (px; they follow the pins when re-centring is on).
    pub field_centres: Vec<(f64, f64)>,
    /// Receptive-field radius (px).
    pub field_radius_px: f64,
    /// The taxels' home positions (px): the sensor's layout, drawn as hexagons.
    pub taxel_home: Vec<(f64, f64)>,
    /// Each taxel's spike rate (Hz) over the last `rate_window_s`.
    pub taxel_rate_hz: Vec<f64>,
    /// The rate window (s).
    pub rate_window_s: f64,
    /// The raster and population rate.
    pub raster: Raster,
    /// Class names of the recogniser's training set (empty without a recogniser).
    pub class_names: Vec<String>,
    /// One entry per coding of the recogniser (empty without one).
    pub decisions: Vec<CodingDecisions>,
    /// Whether the stream moves.
    pub state: PlayState,
    /// The replay speed as set (`realtime`, `2×`, `max`, `live`); `None` for a snapshot,
    /// which has no speed.
    pub speed: Option<String>,
    /// What the drawing leaves out.
    pub decimation: Decimation,
    /// A one-line notice for the viewer (an error that ended the source, a device unplugged).
    pub notice: Option<String>,
    /// Wall-clock time (ms since the Unix epoch) at which the oldest event first shown in
    /// this frame was due (a recording at 1×: when its time came; a camera: when it was read);
    /// the page measures event-to-screen latency from it. `None` when no new event is shown.
    pub oldest_new_event_due_unix_ms: Option<f64>,
}
