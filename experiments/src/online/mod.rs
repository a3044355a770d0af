//! Online texture recognition while the sensor slides: pixel events in, a decision after every
//! pooling window.
//!
//! ```text
//! pixel events ─ Transducer (window by window, advance_to) ─ taxel spike input ─┬─ (afferents) ─┐
//!                                                                                └───────────────┴─ SpatiotemporalCoding readout
//!     prefix [0, T) of the live output trains ─ coding ─ distances to the training prefixes [0, T) ─ KNN head
//! ```
//!
//! **Alignment.** Elapsed time `T` counts from the slide start, which is given: the
//! transduction origin (`origin_us` of the [`TransductionConfig`]; the first event when
//! `None`), as when the training set was transduced. After each pooling window `[T − w, T)` the
//! live sample's prefix `[0, T)` is compared with every training sample's prefix over the same
//! `[0, T)`: spike counts before `T` (intensive, spatial), the rolling-window features whose
//! windows end by `T` (temporal), or the multi-unit Van Rossum distance of the prefixes
//! (spatiotemporal). The training side is prepared once ([`OnlineClassifier`]); each window
//! then costs work in proportion to its new spikes: counts move on by cursors, the temporal
//! distances grow in the lanes of [`squared_euclidean`](neurotac_core::distance::squared_euclidean) (so the last one equals the offline
//! distance bit for bit), the Van Rossum sums grow spike by spike ([`GrowingVanRossum`](neurotac_core::distance::GrowingVanRossum); within
//! 10⁻⁹ of [`PreparedVanRossum::cross_matrices_until`](neurotac_core::distance::PreparedVanRossum::cross_matrices_until)). The final decision compares whole
//! samples exactly as the offline classifier does.
//!
//! **Bounded memory.** The live sample is kept only up to the training samples' duration `D`
//! (rounded up to a whole window): later events are counted and dropped, and the decision at
//! that point is final ([`Recogniser::finish`] reports it).

pub mod eval;

use crate::afferents::{AfferentConfig, afferent_population, afferent_stepping};
use crate::coding::Coding;
use crate::coding::scheme::{LiveScorer, OnlineScorer};
use crate::error::ExperimentError;
use crate::readouts::{EncodedSet, VrFrom, encode_through_graph};
use neurotac_core::coding::SpatiotemporalCoding;
use neurotac_core::knn::FittedKnn;
use neurotac_core::{
    EventBuffer, InputId, MultiSpikeTrain, Network, NetworkBuilder, NetworkConfig, ReadoutId,
    ReadoutSource, SpikeArrayInput, SpikeDataset,
};
use neurotac_sensor::davis::{DavisStream, Transport};
use neurotac_sensor::format::EventReader;
use neurotac_sensor::taxel::{TaxelLayout, Transducer, TransductionConfig};
use std::time::{Duration, Instant};

/// A labelled training set as the recogniser's network sees it: the output spike trains of
/// each sample (taxel trains, or afferent trains with afferents), encoded once through the
/// graph ([`encode_through_graph`]).
#[derive(Debug, Clone)]
pub struct OnlineTraining {
    encoded: EncodedSet,
    n_channels: usize,
    afferents: Option<AfferentConfig>,
}

impl OnlineTraining {
    /// Encodes `data` (labelled) through the readout network, with `afferents` if given.
    pub fn new(
        data: &SpikeDataset,
        afferents: Option<AfferentConfig>,
    ) -> Result<Self, ExperimentError> {
        if data.is_empty() || data.labels().len() != data.len() {
            return Err(neurotac_core::KnnError::Unlabelled.into());
        }
        Ok(Self {
            encoded: encode_through_graph(data, afferents, VrFrom::Exact, &|| {})?,
            n_channels: data.n_channels(),
            afferents,
        })
    }

    /// Number of training samples.
    pub fn len(&self) -> usize {
        self.encoded.len()
    }

    /// `true` without samples (never, once built).
    pub fn is_empty(&self) -> bool {
        self.encoded.len() == 0
    }

    /// Class of each sample.
    pub fn labels(&self) -> &[usize] {
        &self.encoded.labels
    }

    /// Class names (index = label).
    pub fn class_names(&self) -> &[String] {
        &self.encoded.class_names
    }

    /// The samples' duration `D` (ms): one past the latest spike's 1-ms bin.
    pub fn duration_ms(&self) -> u32 {
        self.encoded.duration_ms
    }

    /// Channels (taxels) per sample.
    pub fn n_channels(&self) -> usize {
        self.n_channels
    }

    /// The samples' output trains.
    pub fn trains(&self) -> &[MultiSpikeTrain] {
        &self.encoded.trains
    }
}

/// One decision of the recogniser.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Decision {
    /// Elapsed time since the slide start at which it was made (s): the end of its window.
    pub t_s: f64,
    /// The predicted class (an index into the training set's class names).
    pub class: usize,
    /// The share of the k neighbours that voted for it.
    pub vote_share: f64,
    /// The neighbours, hence the class, were picked by index among equally far training
    /// samples of several classes, not by the data ([`FittedKnn::is_distance_tie`]): e.g.
    /// before the first spike, when every training prefix is equally far. A tie is never
    /// stable.
    pub tie: bool,
    /// For how many consecutive windows, this one included, the class has been the same (and
    /// not a tie).
    pub same_for_windows: usize,
    /// `same_for_windows ≥` the recogniser's stability count.
    pub stable: bool,
    /// Wall time from the window's close (its last event pushed) to this decision (s).
    pub latency_s: f64,
}

/// A KNN head on a training set for one coding, prepared once (training features, the Van
/// Rossum index: the coding's [`OnlineScorer`]) and shared by any number of [`Recogniser`]s.
pub struct OnlineClassifier<'a> {
    training: &'a OnlineTraining,
    coding: Coding,
    scorer: Box<dyn OnlineScorer + 'a>,
    knn: FittedKnn,
}

impl<'a> OnlineClassifier<'a> {
    /// Classifies with `coding` by the `k` nearest neighbours among `training`.
    pub fn new(
        training: &'a OnlineTraining,
        coding: Coding,
        k: usize,
    ) -> Result<Self, ExperimentError> {
        let knn = neurotac_core::Knn::new(k)?.fit(training.labels())?;
        let scorer = coding
            .name
            .scheme()
            .online(&training.encoded, &coding.parameters)?;
        Ok(Self {
            training,
            coding,
            scorer,
            knn,
        })
    }

    /// The coding.
    pub fn coding(&self) -> Coding {
        self.coding
    }

    /// The training set.
    pub fn training(&self) -> &'a OnlineTraining {
        self.training
    }
}

/// The online recogniser (module docs): push pixel events, get a decision after every pooling
/// window.
pub struct Recogniser<'a> {
    classifier: &'a OnlineClassifier<'a>,
    stable_windows: usize,
    transducer: Transducer,
    window_us: i64,
    network: Network,
    input: InputId,
    readout: ReadoutId<SpatiotemporalCoding>,
    live: Box<dyn LiveScorer + 'a>,
    /// Windows closed so far.
    windows: u64,
    /// Last window that is kept (the training duration rounded up to a window).
    last_window: u64,
    chunk: EventBuffer,
    events_dropped: u64,
    decisions: Vec<Decision>,
    final_decision: Option<Decision>,
}

impl<'a> Recogniser<'a> {
    /// A recogniser for one stream, deciding with `classifier`, the events transduced with
    /// `transduction` on the paper's taxel layout; a decision is `stable` once the class has
    /// held for `stable_windows` windows.
    pub fn new(
        classifier: &'a OnlineClassifier<'a>,
        transduction: TransductionConfig,
        stable_windows: usize,
    ) -> Result<Self, ExperimentError> {
        let training = classifier.training;
        let layout = TaxelLayout::neurotac_default();
        if layout.len() != training.n_channels() {
            return Err(ExperimentError::InvalidParameter {
                what: "training channels",
                value: training.n_channels() as f64,
                expected: "one per taxel of the NeuroTac layout (49)",
            });
        }
        let transducer = Transducer::new(&layout, transduction)?;
        let (network, input, readout) = live_network(training)?;
        let window_us = transduction.pool_window_us;
        let last_window = (training.duration_ms() as u64 * 1000).div_ceil(window_us as u64);
        let live = classifier.scorer.live();
        Ok(Self {
            classifier,
            live,
            stable_windows: stable_windows.max(1),
            transducer,
            window_us,
            network,
            input,
            readout,
            windows: 0,
            last_window,
            chunk: EventBuffer::new(),
            events_dropped: 0,
            decisions: Vec::new(),
            final_decision: None,
        })
    }

    /// Every decision so far, one per closed window.
    pub fn decisions(&self) -> &[Decision] {
        &self.decisions
    }

    /// `true` once the kept duration is over: later events are dropped and the next
    /// [`finish`](Self::finish) gives the final decision.
    pub fn is_done(&self) -> bool {
        self.windows >= self.last_window
    }

    /// The training set's class names.
    pub fn class_names(&self) -> &[String] {
        self.classifier.training.class_names()
    }

    /// The kept duration (µs): the training samples' duration rounded up to a whole window;
    /// events later than this after the slide start are dropped.
    pub fn kept_us(&self) -> i64 {
        self.last_window as i64 * self.window_us
    }

    /// Events after the kept duration (counted, not processed).
    pub fn events_dropped(&self) -> u64 {
        self.events_dropped
    }

    /// Pushes the next time-ordered events; returns how many windows they closed (their
    /// decisions are the last ones of [`decisions`](Self::decisions)). An out-of-order or
    /// off-sensor event is a typed error naming it; the events before it are processed first,
    /// and what was decided stays.
    pub fn push(&mut self, events: &EventBuffer) -> Result<usize, ExperimentError> {
        let before = self.decisions.len();
        match self.transducer.check(events) {
            Ok(()) => self.push_checked(events, events.len())?,
            Err((good, e)) => {
                self.push_checked(events, good)?;
                return Err(e.into());
            }
        }
        Ok(self.decisions.len() - before)
    }

    /// Pushes the first `len` events of `events`, already checked.
    fn push_checked(&mut self, events: &EventBuffer, len: usize) -> Result<(), ExperimentError> {
        let mut i = 0;
        while i < len {
            if self.is_done() {
                self.events_dropped += (len - i) as u64;
                break;
            }
            // Events of the open window go to the transducer; an event past its end closes it.
            let end = self.window_end_us(events.t[i]);
            self.chunk.clear();
            while i < len && events.t[i] < end {
                self.chunk.push(events.get(i).expect("in range"));
                i += 1;
            }
            self.transducer.push(&self.chunk)?;
            if i < len {
                self.close_window()?;
            }
        }
        Ok(())
    }

    /// End of the stream: closes the open window and returns the final decision (the live
    /// sample compared whole with the whole training samples); an error when no event arrived.
    pub fn finish(&mut self) -> Result<Decision, ExperimentError> {
        if let Some(d) = self.final_decision {
            return Ok(d);
        }
        if self.transducer.counts().events_in == 0 {
            return Err(ExperimentError::EmptyStream);
        }
        if !self.is_done() {
            self.close_window()?;
        }
        let start = Instant::now();
        let decision = Decision {
            // Stamped at the end of the last window.
            t_s: self.windows as f64 * self.window_us as f64 * 1e-6,
            ..self.decide(f64::INFINITY, start)?
        };
        self.final_decision = Some(decision);
        Ok(decision)
    }

    /// The end (µs) of the open window (the origin fixed by the first event, `t_us`, when not
    /// configured).
    fn window_end_us(&self, t_us: i64) -> i64 {
        let origin = self.transducer.origin_us().unwrap_or(t_us);
        origin + (self.windows as i64 + 1) * self.window_us
    }

    /// Closes window `self.windows`, runs the network to its end and decides.
    fn close_window(&mut self) -> Result<(), ExperimentError> {
        let origin = self.transducer.origin_us().unwrap_or(0);
        let end_us = origin + (self.windows as i64 + 1) * self.window_us;
        let start = Instant::now();
        self.transducer.advance_to(end_us);
        let events = self.transducer.drain_taxel_events();
        let spikes: Vec<(u32, f64)> = events
            .iter()
            .map(|e| (e.taxel as u32, (e.t_us - origin as f64) / 1e6))
            .collect();
        let n = self.classifier.training.n_channels();
        let window = MultiSpikeTrain::from_labelled_spikes(n, &spikes)
            .expect("taxel indices are in range and mean times finite");
        self.network
            .replace_spike_input(self.input, SpikeArrayInput::new(window))?;
        let t_end_s = (self.windows + 1) as f64 * self.window_us as f64 * 1e-6;
        let target = (t_end_s / self.network.dt_s()).round() as u64;
        self.network.run_steps(
            target.saturating_sub(self.network.steps_done()),
            &neurotac_core::OneProcess,
        )?;
        self.windows += 1;
        let decision = self.decide(t_end_s, start)?;
        self.decisions.push(decision);
        Ok(())
    }

    /// The decision at elapsed time `t_end_s` (`+∞`: whole samples).
    fn decide(&mut self, t_end_s: f64, start: Instant) -> Result<Decision, ExperimentError> {
        let live = self.network.readout(self.readout)?.trains();
        let distances = self.live.distances(&live, t_end_s)?;
        let (knn, tie) = self.classifier.knn.decide_noting_distance_tie(&distances)?;
        let class = knn.class;
        let same_for_windows = match self.decisions.last() {
            _ if tie => 0,
            Some(last) if last.class == class && !last.tie => last.same_for_windows + 1,
            _ => 1,
        };
        Ok(Decision {
            t_s: t_end_s,
            class,
            vote_share: knn.vote_share(),
            tie,
            same_for_windows,
            stable: !tie && same_for_windows >= self.stable_windows,
            latency_s: start.elapsed().as_secs_f64(),
        })
    }
}

/// How fast [`replay`] feeds a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReplaySpeed {
    /// As recorded: each chunk waits until its last event's time has passed since the start.
    Realtime,
    /// As fast as the recogniser goes.
    Max,
}

/// Replays `reader` into `recogniser` until the stream or the kept duration ends, calling
/// `on_decision` with every window's decision as it is made; returns the final decision. A
/// read error (naming the file and offset) or an out-of-order event ends the replay with the
/// error; the decisions made before stay in the recogniser.
pub fn replay(
    recogniser: &mut Recogniser<'_>,
    reader: &mut dyn EventReader,
    speed: ReplaySpeed,
    on_decision: &mut dyn FnMut(&Decision),
) -> Result<Decision, ExperimentError> {
    let mut chunk = EventBuffer::new();
    let start = Instant::now();
    let mut first_us = None;
    while !recogniser.is_done() && reader.read_chunk(&mut chunk)? > 0 {
        if let (ReplaySpeed::Realtime, Some(&last)) = (speed, chunk.t.last()) {
            let first = *first_us.get_or_insert(chunk.t[0]);
            // Nothing after the kept duration is used: an event far later (a gap of years)
            // is not waited for.
            let since_first = last.saturating_sub(first).clamp(0, recogniser.kept_us());
            let due = Duration::from_micros(since_first as u64);
            if let Some(wait) = due.checked_sub(start.elapsed()) {
                std::thread::sleep(wait);
            }
        }
        let n = recogniser.push(&chunk)?;
        report_last(recogniser, n, on_decision);
        chunk.clear();
    }
    finish_reporting(recogniser, on_decision)
}

/// Recognises from a live camera `stream` (the DAVIS driver over any [`Transport`]) until the
/// kept duration is over, calling `on_decision` with every window's decision; returns the
/// final decision. An unplugged camera ends it with [`DeviceError::Disconnected`](neurotac_sensor::DeviceError::Disconnected); the
/// decisions made before stay in the recogniser.
pub fn recognise_stream<T: Transport>(
    recogniser: &mut Recogniser<'_>,
    stream: &mut DavisStream<T>,
    on_decision: &mut dyn FnMut(&Decision),
) -> Result<Decision, ExperimentError> {
    let mut chunk = EventBuffer::new();
    while !recogniser.is_done() {
        chunk.clear();
        stream.next_events(&mut chunk, Duration::from_millis(20))?;
        let n = recogniser.push(&chunk)?;
        report_last(recogniser, n, on_decision);
    }
    finish_reporting(recogniser, on_decision)
}

/// Calls `on_decision` with the last `n` decisions.
fn report_last(recogniser: &Recogniser<'_>, n: usize, on_decision: &mut dyn FnMut(&Decision)) {
    let decisions = recogniser.decisions();
    decisions[decisions.len() - n..]
        .iter()
        .for_each(on_decision);
}

/// [`Recogniser::finish`], reporting the decision of the window it closes.
fn finish_reporting(
    recogniser: &mut Recogniser<'_>,
    on_decision: &mut dyn FnMut(&Decision),
) -> Result<Decision, ExperimentError> {
    let before = recogniser.decisions().len();
    let last = recogniser.finish()?;
    report_last(
        recogniser,
        recogniser.decisions().len() - before,
        on_decision,
    );
    Ok(last)
}

/// Percentiles of the decision latency (the wall time from a window's end to its decision),
/// named so that a `summary.json` reads without the code: `{"p50_ms": …, "p99_ms": …,
/// "max_ms": …}`.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct LatencyPercentiles {
    /// Median latency (ms), nearest-rank.
    pub p50_ms: f64,
    /// 99th-percentile latency (ms), nearest-rank.
    pub p99_ms: f64,
    /// Largest latency (ms).
    pub max_ms: f64,
}

/// The decisions' latency percentiles, nearest-rank; `None` without decisions.
pub fn latency_percentiles(decisions: &[Decision]) -> Option<LatencyPercentiles> {
    let mut l: Vec<f64> = decisions.iter().map(|d| d.latency_s * 1e3).collect();
    l.sort_by(f64::total_cmp);
    let at = |q: f64| l[((q * l.len() as f64).ceil() as usize).clamp(1, l.len()) - 1];
    (!l.is_empty()).then(|| LatencyPercentiles {
        p50_ms: at(0.5),
        p99_ms: at(0.99),
        max_ms: l[l.len() - 1],
    })
}

/// The live network: taxel spike input → (afferents) → spatiotemporal readout (the trains).
fn live_network(
    training: &OnlineTraining,
) -> Result<(Network, InputId, ReadoutId<SpatiotemporalCoding>), ExperimentError> {
    let n = training.n_channels();
    let mut b = NetworkBuilder::new();
    b.stepping(afferent_stepping());
    let input = b.add_spike_input("taxels", SpikeArrayInput::new(MultiSpikeTrain::empty(n)))?;
    let source: ReadoutSource = match training.afferents {
        None => input.into(),
        Some(config) => afferent_population(&mut b, input, n, config)?.into(),
    };
    let readout = b.add_readout(source, SpatiotemporalCoding::new(1.0)?)?;
    let dt_s = training
        .afferents
        .map_or(NetworkConfig::default().dt_s, |a| a.dt_s);
    Ok((b.build(NetworkConfig { dt_s })?, input, readout))
}
