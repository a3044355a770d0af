//! Where in a simulated slide the taxel spikes fall. A slide's recording is cut into four phases
//! by its slide's start `t₀` and end `t₁` (s from the recording start):
//!
//! | phase | interval |
//! |---|---|
//! | press | `[0, t₀)`: the press and the dwell before the slide ([`neurotac_sensor::sim::kinematics`]) |
//! | onset | `[t₀, t₀ + 200 ms)` ([`ONSET_S`]) |
//! | sliding | `[t₀ + 200 ms, t₁)` |
//! | stop | `[t₁, end of recording]` |
//!
//! [`phase_shares`] gives, per class, the mean over its samples of each phase's share of the
//! sample's taxel spikes. A recorded dataset carries no motion times, so its phases are
//! [`Phases::Unknown`].

use crate::coding::class_means_of;
use neurotac_core::{MultiSpikeTrain, SpikeDataset};
use neurotac_sensor::sim::SimParams;
use neurotac_sensor::sim::kinematics::Recording;
use serde::Serialize;

/// Length of the onset phase after the motion start (s).
pub const ONSET_S: f64 = 0.2;

/// Why a recorded dataset has no phase table.
pub const RECORDED_HAS_NO_PHASES: &str = "a recorded dataset stores no motion start or end per \
     slide, so its spikes cannot be assigned to slide phases";

/// One phase of a slide (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SlidePhase {
    /// Before the slide starts: the press and the dwell.
    Press,
    /// The first [`ONSET_S`] of the motion.
    Onset,
    /// The rest of the motion.
    Sliding,
    /// From the motion's end to the end of the recording.
    Stop,
}

impl SlidePhase {
    /// The four phases in time order.
    pub const ALL: [SlidePhase; 4] = [
        SlidePhase::Press,
        SlidePhase::Onset,
        SlidePhase::Sliding,
        SlidePhase::Stop,
    ];

    /// `press`, `onset`, `sliding`, `stop`.
    pub fn key(self) -> &'static str {
        match self {
            SlidePhase::Press => "press",
            SlidePhase::Onset => "onset",
            SlidePhase::Sliding => "sliding",
            SlidePhase::Stop => "stop",
        }
    }
}

/// When a slide's motion starts and stops (s from the recording start).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SlideTiming {
    /// Motion start `t₀` (s).
    pub motion_start_s: f64,
    /// Motion end `t₁` (s).
    pub motion_end_s: f64,
}

impl SlideTiming {
    /// The nominal timing of a slide simulated with `params`: its recording loop at the mean
    /// latencies ([`Recording::nominal`]). A simulated slide's own start differs by the loop's
    /// timing (about `kinematics.loop_jitter_s·√(6/8)`, a few ms).
    pub fn nominal(params: &SimParams) -> Self {
        let recording = Recording::nominal(params);
        Self {
            motion_start_s: recording.slide_start_s,
            motion_end_s: recording.slide_end_s(),
        }
    }

    /// The phase of a spike at `t_s` (s from the recording start).
    pub fn phase_of(&self, t_s: f64) -> SlidePhase {
        if t_s < self.motion_start_s {
            SlidePhase::Press
        } else if t_s < (self.motion_start_s + ONSET_S).min(self.motion_end_s) {
            SlidePhase::Onset
        } else if t_s < self.motion_end_s {
            SlidePhase::Sliding
        } else {
            SlidePhase::Stop
        }
    }
}

/// The share of taxel spikes in each phase (fractions; they sum to 1).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct PhaseShare {
    /// Before the slide: the press and the dwell.
    pub press: f64,
    /// The motion's first [`ONSET_S`].
    pub onset: f64,
    /// The rest of the motion.
    pub sliding: f64,
    /// After the motion.
    pub stop: f64,
}

impl PhaseShare {
    /// The share of `phase`.
    pub fn of(&self, phase: SlidePhase) -> f64 {
        match phase {
            SlidePhase::Press => self.press,
            SlidePhase::Onset => self.onset,
            SlidePhase::Sliding => self.sliding,
            SlidePhase::Stop => self.stop,
        }
    }

    /// From shares in [`SlidePhase::ALL`] order.
    fn from_array([press, onset, sliding, stop]: [f64; 4]) -> Self {
        Self {
            press,
            onset,
            sliding,
            stop,
        }
    }
}

/// The phase shares of a set's taxel spikes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseShares {
    /// The motion times the phases were cut at.
    pub timing: SlideTiming,
    /// Where the motion times come from.
    pub timing_source: String,
    /// Per class (index = label): the mean over its samples of each phase's share of the
    /// sample's spikes (samples without spikes left out; 0 for a class without spikes).
    pub per_class: Vec<PhaseShare>,
    /// The mean of the class means.
    pub all_classes: PhaseShare,
    /// Samples without any spike (left out of the means).
    pub samples_without_spikes: usize,
}

/// A set's phase shares, or why it has none.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phases {
    /// The motion times are known (a simulated set).
    Known(PhaseShares),
    /// They are not: why.
    Unknown(String),
}

impl Phases {
    /// The phases of a set simulated with `params`, cut at its nominal motion times
    /// ([`SlideTiming::nominal`]: the dataset stores no per-slide motion times).
    pub fn of_simulated(data: &SpikeDataset, params: &SimParams) -> Self {
        let mut shares = phase_shares(data, SlideTiming::nominal(params));
        shares.timing_source = format!(
            "the nominal recording loop of the simulator parameters (the dataset stores no \
             per-slide motion times; each slide's start varies with the loop's timing, σ ≈ {:.1} ms)",
            params.kinematics.loop_jitter_s * 0.75f64.sqrt() * 1e3
        );
        Phases::Known(shares)
    }

    /// A recorded dataset's: unknown ([`RECORDED_HAS_NO_PHASES`]).
    pub fn recorded() -> Self {
        Phases::Unknown(RECORDED_HAS_NO_PHASES.to_owned())
    }
}

/// The share of `sample`'s spikes in each phase ([`SlidePhase::ALL`] order); `None` without
/// spikes.
pub fn sample_phase_shares(sample: &MultiSpikeTrain, timing: SlideTiming) -> Option<[f64; 4]> {
    let mut counts = [0usize; 4];
    for &t in sample.channels().flatten() {
        counts[timing.phase_of(t) as usize] += 1;
    }
    let total: usize = counts.iter().sum();
    (total > 0).then(|| counts.map(|c| c as f64 / total as f64))
}

/// The phase shares of every class of `data`, its phases cut at `timing` (see the module
/// docs); `timing_source` is left empty for the caller to say.
pub fn phase_shares(data: &SpikeDataset, timing: SlideTiming) -> PhaseShares {
    let n_classes = data.n_classes();
    let (mut labels, mut shares) = (Vec::new(), Vec::new());
    for (sample, &label) in data.observations().iter().zip(data.labels()) {
        if let Some(s) = sample_phase_shares(sample, timing) {
            labels.push(label);
            shares.push(s);
        }
    }
    let mut per_class = vec![[0.0; 4]; n_classes];
    let mut all_classes = [0.0; 4];
    for phase in 0..4 {
        let (_, means) = class_means_of(shares.iter().map(|s| s[phase]), &labels, n_classes);
        for (class, mean) in means.iter().enumerate() {
            per_class[class][phase] = *mean;
        }
        all_classes[phase] = means.iter().sum::<f64>() / n_classes.max(1) as f64;
    }
    PhaseShares {
        timing,
        timing_source: String::new(),
        per_class: per_class.into_iter().map(PhaseShare::from_array).collect(),
        all_classes: PhaseShare::from_array(all_classes),
        samples_without_spikes: data.len() - labels.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TIMING: SlideTiming = SlideTiming {
        motion_start_s: 0.25,
        motion_end_s: 4.25,
    };

    fn sample(channels: Vec<Vec<f64>>) -> MultiSpikeTrain {
        MultiSpikeTrain::from_channels(channels).unwrap()
    }

    #[test]
    fn spikes_fall_in_the_phase_of_their_half_open_interval() {
        let phase = |t| TIMING.phase_of(t);
        assert_eq!(phase(0.0), SlidePhase::Press);
        assert_eq!(phase(0.249), SlidePhase::Press);
        assert_eq!(phase(0.25), SlidePhase::Onset);
        assert_eq!(phase(0.449), SlidePhase::Onset);
        assert_eq!(phase(0.45), SlidePhase::Sliding);
        assert_eq!(phase(4.249), SlidePhase::Sliding);
        assert_eq!(phase(4.25), SlidePhase::Stop);
        assert_eq!(phase(9.0), SlidePhase::Stop);
        // A motion shorter than the onset has no sliding phase.
        let short = SlideTiming {
            motion_start_s: 0.1,
            motion_end_s: 0.2,
        };
        assert_eq!(short.phase_of(0.15), SlidePhase::Onset);
        assert_eq!(short.phase_of(0.2), SlidePhase::Stop);
    }

    #[test]
    fn phase_shares_of_known_spike_times_sum_to_one_and_land_in_their_phases() {
        let observations = vec![
            // Class 0: one spike per phase, then all in the sliding phase.
            sample(vec![vec![0.1, 0.3], vec![1.0, 4.3]]),
            sample(vec![vec![1.0, 2.0], vec![3.0, 4.0]]),
            // Class 1: 3 onset + 1 stop, and a sample without spikes (left out).
            sample(vec![vec![0.26, 0.3, 0.44], vec![4.4]]),
            sample(vec![vec![], vec![]]),
        ];
        let names = vec!["a".to_owned(), "b".to_owned()];
        let data =
            SpikeDataset::new(observations, vec![0, 0, 1, 1], names, Default::default()).unwrap();
        let s = phase_shares(&data, TIMING);
        assert_eq!(s.samples_without_spikes, 1);
        let close = |a: PhaseShare, b: [f64; 4]| {
            SlidePhase::ALL
                .iter()
                .zip(b)
                .all(|(&p, v)| (a.of(p) - v).abs() < 1e-12)
        };
        assert!(
            close(s.per_class[0], [0.125, 0.125, 0.625, 0.125]),
            "{:?}",
            s.per_class[0]
        );
        assert!(close(s.per_class[1], [0.0, 0.75, 0.0, 0.25]));
        assert!(close(s.all_classes, [0.0625, 0.4375, 0.3125, 0.1875]));
        for share in s.per_class.iter().chain([&s.all_classes]) {
            let sum: f64 = SlidePhase::ALL.iter().map(|&p| share.of(p)).sum();
            assert!((sum - 1.0).abs() < 1e-12, "{share:?}");
        }
    }

    #[test]
    fn nominal_timing_is_the_press_then_the_slide_of_the_parameters() {
        let params = SimParams::default();
        let t = SlideTiming::nominal(&params);
        assert_eq!(t.motion_start_s, Recording::nominal(&params).slide_start_s);
        assert!((t.motion_end_s - t.motion_start_s - params.motion_duration_s()).abs() < 1e-12);
        assert!(matches!(Phases::recorded(), Phases::Unknown(why) if why.contains("recorded")));
    }
}
