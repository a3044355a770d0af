//! How a population is stepped ([`Stepping`]): every neuron every step (clock-driven), only
//! the neurons with synaptic input (event-driven), or whichever of the two its measured
//! activity makes cheaper ([`Stepping::Auto`]), re-decided as the run goes.
//!
//! # Activity and the automatic choice
//! A population's *activity* in a step is the fraction of its (local) neurons whose synaptic
//! current is nonzero when it is integrated: exactly the neurons an event-driven step updates
//! (besides Izhikevich neurons still settling to rest). Event-driven stepping costs about
//! `c_e · activity · N` per step, clock-driven stepping `c_c · N`; they cost the same at the
//! model's *crossover* activity `c_c / c_e`, a number of the model and the machine
//! ([`Crossovers`], measured by `neurotac bench neurons --crossover`).
//!
//! Event-driven, the activity is counted every step for free (the length of the active list).
//! Clock-driven, it is sampled every [`CLOCK_SAMPLE_STEPS`] steps by counting the nonzero
//! currents (one pass over the population's currents, `1/16` of a step's reads). Every
//! [`DECISION_WINDOW_STEPS`] steps the population compares the mean activity of the window with
//! its crossover `c`: clock-driven, it turns event-driven when the mean is below `c / `
//! [`HYSTERESIS`]; event-driven, it turns clock-driven when the mean is above
//! `c · `[`HYSTERESIS`]. Between the two it keeps its mode, so noise around the crossover
//! does not make it flip at every window. An automatic population starts event-driven (at time
//! 0 no neuron has input) and keeps its mode over a [`Network::reset`](super::Network::reset).
//!
//! # Switching
//! A switch happens at the start of a step, before inputs are delivered. Event → clock: every
//! neuron skipped so far is brought up to the current step ([`NeuronModel::settle`], the same
//! closed form the event-driven path applies when input next reaches it) and the active list is
//! dropped (the clock-driven step drains every current). Clock → event: every neuron is marked
//! current as of now ([`NeuronModel::resume_event_driven`]) and the active list is rebuilt from
//! the nonzero currents, ascending. So the state every step sees is the one the fixed modes
//! compute, and spikes are the clock-driven ones exactly when the event-driven run's are (see
//! [`NetworkBuilder::event_driven`](super::NetworkBuilder::event_driven)).
//!
//! [`NeuronModel::settle`]: crate::NeuronModel::settle
//! [`NeuronModel::resume_event_driven`]: crate::NeuronModel::resume_event_driven

use crate::error::SteppingFileError;
use crate::io::{AtomicFile, Replace};
use std::collections::BTreeMap;
use std::fmt;
use std::io::Write;
use std::path::Path;

/// Steps between two decisions of an automatic population (the window its activity is
/// averaged over).
pub const DECISION_WINDOW_STEPS: u64 = 256;

/// A clock-driven automatic population counts its active neurons every this many steps.
pub const CLOCK_SAMPLE_STEPS: u64 = 16;

/// The hysteresis factor around the crossover `c`: event-driven below `c / HYSTERESIS`,
/// clock-driven above `c · HYSTERESIS`, unchanged in between.
pub const HYSTERESIS: f64 = 1.1;

/// The name of the crossover file in the neurotac cache folder ([`Crossovers::load`]).
pub const CROSSOVER_FILE_NAME: &str = "stepping-crossovers.json";

/// How the populations of a network are stepped
/// ([`NetworkBuilder::stepping`](super::NetworkBuilder::stepping)). Applies to the populations
/// that can be stepped event-driven (see
/// [`NetworkBuilder::event_driven`](super::NetworkBuilder::event_driven)); the others are always
/// clock-driven. Default: [`Clock`](Self::Clock).
#[derive(Debug, Clone, Default, PartialEq)]
pub enum Stepping {
    /// Every neuron every step.
    #[default]
    Clock,
    /// Only the neurons with synaptic input (and those still settling to rest).
    Event,
    /// Each population chooses from its measured activity (see the [module docs](self)), with
    /// these crossovers (a model without one uses its
    /// [`default_crossover`](crate::NeuronModel::default_crossover)).
    Auto(Crossovers),
}

impl Stepping {
    /// [`Stepping::Auto`] with every model's built-in crossover.
    pub fn auto() -> Self {
        Self::Auto(Crossovers::default())
    }
}

/// The mode a population is stepped in now.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SteppingMode {
    /// Every neuron every step.
    Clock,
    /// Only the neurons with synaptic input.
    Event,
}

impl fmt::Display for SteppingMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Clock => "clock-driven",
            Self::Event => "event-driven",
        })
    }
}

/// One population's stepping, as [`Network::stepping_report`](super::Network::stepping_report)
/// reports it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PopulationStepping {
    /// The population's name.
    pub population: String,
    /// The mode it is stepped in now.
    pub mode: SteppingMode,
    /// The crossover activity it decides with; `None` when its mode is fixed.
    pub crossover: Option<f64>,
    /// Its mean activity (fraction of its neurons with synaptic current per step) since build
    /// or the last reset, over the steps it was counted in (every event-driven step, every
    /// [`CLOCK_SAMPLE_STEPS`]-th clock-driven one); `None` when never counted (a population that
    /// cannot be stepped event-driven, or none run yet).
    pub activity: Option<f64>,
    /// Mode switches since build.
    pub switches: u64,
}

/// Crossover activities by neuron model name ([`NeuronModel::model_name`]): below it a
/// population of that model is cheaper event-driven, above it clock-driven. Stored as JSON
/// (`{"crossovers": {"LIF": 0.021}}`) in [`CROSSOVER_FILE_NAME`] in the neurotac cache folder.
///
/// [`NeuronModel::model_name`]: crate::NeuronModel::model_name
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Crossovers {
    crossovers: BTreeMap<String, f64>,
}

impl Crossovers {
    /// The crossover of `model`, if set.
    pub fn get(&self, model: &str) -> Option<f64> {
        self.crossovers.get(model).copied()
    }

    /// Sets the crossover of `model`; refused unless it is in `(0, 1]` (an activity).
    pub fn set(&mut self, model: &str, crossover: f64) -> Result<(), SteppingFileError> {
        check(model, crossover).map_err(|expected| SteppingFileError::Invalid {
            path: None,
            model: model.to_owned(),
            value: crossover,
            expected,
        })?;
        self.crossovers.insert(model.to_owned(), crossover);
        Ok(())
    }

    /// The models with a crossover and their crossovers, by name.
    pub fn iter(&self) -> impl Iterator<Item = (&str, f64)> {
        self.crossovers.iter().map(|(m, &c)| (m.as_str(), c))
    }

    /// Reads the crossover file `path`: `Ok(None)` when it does not exist, a
    /// [`SteppingFileError`] naming the file when it cannot be read, is not the JSON above, or
    /// holds a crossover outside `(0, 1]`.
    pub fn load(path: &Path) -> Result<Option<Self>, SteppingFileError> {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => {
                return Err(SteppingFileError::Read {
                    path: path.to_owned(),
                    source,
                });
            }
        };
        let read: Self =
            serde_json::from_str(&text).map_err(|source| SteppingFileError::Parse {
                path: path.to_owned(),
                source,
            })?;
        for (model, c) in read.iter() {
            check(model, c).map_err(|expected| SteppingFileError::Invalid {
                path: Some(path.to_owned()),
                model: model.to_owned(),
                value: c,
                expected,
            })?;
        }
        Ok(Some(read))
    }

    /// Writes these crossovers to `path` atomically (never half-written), replacing the file.
    pub fn save(&self, path: &Path) -> Result<(), SteppingFileError> {
        let write = || -> std::io::Result<()> {
            let mut f = AtomicFile::create(path, Replace::Yes)?;
            let json = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
            writeln!(f, "{json}")?;
            f.commit()
        };
        write().map_err(|source| SteppingFileError::Write {
            path: path.to_owned(),
            source,
        })
    }
}

/// `Err(expected)` unless `crossover` is an activity in `(0, 1]`.
fn check(_model: &str, crossover: f64) -> Result<(), &'static str> {
    if crossover > 0.0 && crossover <= 1.0 {
        Ok(())
    } else {
        Err("a crossover activity in (0, 1]")
    }
}

/// The run-time stepping of a population that can be stepped event-driven: its active set, its
/// mode and its activity counts.
pub(super) struct EventStepping {
    /// The neurons with synaptic current (only kept while event-driven).
    pub(super) set: super::running::ActiveSet,
    /// `true` while stepped event-driven.
    pub(super) event: bool,
    /// The crossover of an automatic population; `None` when fixed event-driven.
    pub(super) crossover: Option<f64>,
    /// Active fractions counted in the current window, and how many.
    window: (f64, u64),
    /// Active fractions counted since build or reset, and how many.
    total: (f64, u64),
    pub(super) switches: u64,
}

impl EventStepping {
    pub(super) fn new(n: usize, crossover: Option<f64>) -> Self {
        Self {
            set: super::running::ActiveSet::new(n),
            event: true,
            crossover,
            window: (0.0, 0),
            total: (0.0, 0),
            switches: 0,
        }
    }

    /// Counts `active` of `n` neurons active in a step.
    #[inline]
    pub(super) fn count(&mut self, active: usize, n: usize) {
        let f = active as f64 / n.max(1) as f64;
        self.window.0 += f;
        self.window.1 += 1;
        self.total.0 += f;
        self.total.1 += 1;
    }

    /// `true` when a clock-driven automatic population counts its active neurons in step `k`.
    #[inline]
    pub(super) fn samples(&self, k: u64) -> bool {
        !self.event && self.crossover.is_some() && k.is_multiple_of(CLOCK_SAMPLE_STEPS)
    }

    /// At the start of step `k`: the mode to switch to, if the window just ended calls for one
    /// (and starts the next window).
    pub(super) fn decide(&mut self, k: u64) -> Option<bool> {
        let crossover = self.crossover?;
        if k == 0 || !k.is_multiple_of(DECISION_WINDOW_STEPS) {
            return None;
        }
        let (sum, count) = std::mem::take(&mut self.window);
        if count == 0 {
            return None;
        }
        let activity = sum / count as f64;
        let event = if self.event {
            activity <= crossover * HYSTERESIS
        } else {
            activity < crossover / HYSTERESIS
        };
        (event != self.event).then_some(event)
    }

    /// Forgets the counts (the mode stays).
    pub(super) fn reset_counts(&mut self) {
        self.window = (0.0, 0);
        self.total = (0.0, 0);
    }

    /// The mean activity since build or reset.
    pub(super) fn activity(&self) -> Option<f64> {
        (self.total.1 > 0).then(|| self.total.0 / self.total.1 as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stored_crossovers_round_trip_through_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(CROSSOVER_FILE_NAME);
        assert_eq!(Crossovers::load(&path).unwrap(), None);
        let mut c = Crossovers::default();
        c.set("LIF", 0.021).unwrap();
        c.set("Izhikevich", 0.5).unwrap();
        c.save(&path).unwrap();
        let back = Crossovers::load(&path).unwrap().unwrap();
        assert_eq!(back, c);
        assert_eq!(back.get("LIF"), Some(0.021));
        assert_eq!(back.get("QIF"), None);
    }

    #[test]
    fn a_corrupt_crossover_file_is_an_error_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(CROSSOVER_FILE_NAME);
        for (text, what) in [
            ("{\"crossovers\": {\"LIF\": 0.02", "not JSON"),
            ("{\"crossovers\": {\"LIF\": \"fast\"}}", "not a number"),
            ("[1, 2]", "not the record"),
            ("{\"crossovers\": {\"LIF\": 0.0}}", "not an activity"),
            ("{\"crossovers\": {\"LIF\": 2.5}}", "above 1"),
        ] {
            std::fs::write(&path, text).unwrap();
            let e = Crossovers::load(&path).expect_err(what);
            let message = e.to_string();
            assert!(
                message.contains(&path.display().to_string()),
                "{what}: {message}"
            );
        }
        let mut c = Crossovers::default();
        assert!(c.set("LIF", f64::NAN).is_err());
        assert!(c.set("LIF", -0.1).is_err());
    }

    #[test]
    fn the_mode_changes_only_outside_the_hysteresis_band() {
        let mut s = EventStepping::new(100, Some(0.1));
        let window = |s: &mut EventStepping, active: usize, k: u64| {
            (0..DECISION_WINDOW_STEPS).for_each(|_| s.count(active, 100));
            s.decide(k)
        };
        // Event-driven: stays up to 0.11, leaves above it.
        assert_eq!(window(&mut s, 11, DECISION_WINDOW_STEPS), None);
        assert_eq!(window(&mut s, 12, 2 * DECISION_WINDOW_STEPS), Some(false));
        s.event = false;
        // Clock-driven: stays down to 0.1/1.1, returns below it.
        assert_eq!(window(&mut s, 10, 3 * DECISION_WINDOW_STEPS), None);
        assert_eq!(window(&mut s, 9, 4 * DECISION_WINDOW_STEPS), Some(true));
        // Not at a window's end, and never when fixed.
        assert_eq!(window(&mut s, 100, 4 * DECISION_WINDOW_STEPS + 1), None);
        let mut fixed = EventStepping::new(100, None);
        assert_eq!(window(&mut fixed, 100, DECISION_WINDOW_STEPS), None);
    }
}
