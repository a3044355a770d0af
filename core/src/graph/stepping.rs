//! How a population is stepped ([`Stepping`]): every neuron every step (clock-driven), only
//! the neurons with synaptic input (event-driven), or whichever of the two its measured
//! activity makes cheaper ([`Stepping::Auto`]), re-decided as the run goes. See [`Stepping`]
//! for the measure, the decision and the switch.

use crate::io::{AtomicFile, Replace};
use std::collections::BTreeMap;
use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The window (steps) an automatic population averages its activity over; a clock-driven one
/// decides at its end.
pub const DECISION_WINDOW_STEPS: u64 = 256;

/// An event-driven automatic population checks its window's activity every this many steps.
pub const EVENT_CHECK_STEPS: u64 = 16;

/// A clock-driven automatic population counts its active neurons every this many steps.
pub const CLOCK_SAMPLE_STEPS: u64 = 64;

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
///
/// # Activity and the automatic choice
/// A population's *activity* in a step is the fraction of its (local) neurons whose synaptic
/// current is nonzero when it is integrated: exactly the neurons an event-driven step updates
/// (besides Izhikevich neurons still settling to rest). Event-driven stepping costs about
/// `c_e · activity · N` per step, clock-driven stepping `c_c · N`; they cost the same at the
/// model's *crossover* activity `c_c / c_e`, a number of the model and the machine
/// ([`Crossovers`], measured by `neurotac bench neurons --crossover`).
///
/// Event-driven, the activity is counted every step for free (the length of the active list).
/// Clock-driven, it is sampled every [`CLOCK_SAMPLE_STEPS`] steps by counting the nonzero
/// currents (one pass over the population's currents: about 1 % of the clock-driven stepping's
/// time for LIF afferents, the cheapest model). The population compares the mean activity of
/// its current window (the steps since its last switch or its last full window of
/// [`DECISION_WINDOW_STEPS`]) with its crossover `c`:
/// - event-driven, every [`EVENT_CHECK_STEPS`] steps: it turns clock-driven as soon as the
///   mean is above `c · `[`HYSTERESIS`] (an event-driven step at activity 1 costs ≈ 10 clock-driven
///   ones, so a burst is left within a few dozen steps);
/// - clock-driven, at the end of a full window: it turns event-driven when the mean is below
///   `c / `[`HYSTERESIS`] (a clock-driven step wastes at most itself, an event-driven one up to
///   ten times as much).
///
/// Between the two thresholds it keeps its mode, so noise around the crossover does not make it
/// flip, and it returns to event-driven stepping at most once per window. An automatic
/// population starts event-driven (at time 0 no neuron has input) and keeps its mode over a
/// [`Network::reset`](super::Network::reset) (the next sample is likely alike).
///
/// # Switching
/// A switch happens at the start of a step, before inputs are delivered. Event → clock: every
/// neuron skipped so far is brought up to the current step ([`NeuronModel::settle`], the same
/// closed form the event-driven path applies when input next reaches it) and the active list is
/// dropped (the clock-driven step drains every current). Clock → event: every neuron is marked
/// current as of now ([`NeuronModel::resume_event_driven`]) and the active list is rebuilt from
/// the nonzero currents, ascending. An idle stretch cut by a switch is advanced by the closed
/// form up to the switch and by clock-driven steps after it, both equal to the clock-driven
/// steps up to rounding, as the event-driven closed form alone is: the spikes are the
/// clock-driven ones exactly when the event-driven run's are (see
/// [`NetworkBuilder::event_driven`](super::NetworkBuilder::event_driven)).
///
/// ```
/// use neurotac_core::{Crossovers, NetworkBuilder, Stepping};
/// // LIF populations go event-driven below 8 % activity; other models use their own default.
/// let mut crossovers = Crossovers::default();
/// crossovers.set("lif", 0.08)?;
/// let mut b = NetworkBuilder::new();
/// b.stepping(Stepping::Auto(crossovers));
/// # Ok::<(), neurotac_core::SteppingFileError>(())
/// ```
///
/// [`NeuronModel::settle`]: crate::NeuronModel::settle
/// [`NeuronModel::resume_event_driven`]: crate::NeuronModel::resume_event_driven
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stepping {
    /// Every neuron every step.
    #[default]
    Clock,
    /// Only the neurons with synaptic input (and those still settling to rest).
    Event,
    /// Each population chooses from its measured activity (see above), with
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
    /// Its model's name ([`NeuronModel::model_name`](crate::NeuronModel::model_name): the key
    /// of its crossover).
    pub model: &'static str,
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
        check(crossover).map_err(|expected| SteppingFileError::Invalid {
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
    /// [`SteppingFileError`] naming the file when it cannot be read, is not a regular file of at
    /// most [`MAX_CROSSOVER_FILE_BYTES`] (a FIFO, a device, a folder: never waited on or read
    /// without end), is not the JSON above, or holds a crossover outside `(0, 1]`.
    pub fn load(path: &Path) -> Result<Option<Self>, SteppingFileError> {
        let text = match read_bounded(path) {
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
            check(c).map_err(|expected| SteppingFileError::Invalid {
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

/// The largest crossover file read (a few models' numbers take a hundred bytes).
pub const MAX_CROSSOVER_FILE_BYTES: u64 = 64 * 1024;

/// The text of `path` if it is a regular file of at most [`MAX_CROSSOVER_FILE_BYTES`]. Opened
/// without waiting (a FIFO is not waited for), then checked on the open handle.
fn read_bounded(path: &Path) -> std::io::Result<String> {
    use std::io::Read;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, libc::O_NONBLOCK);
    let file = options.open(path)?;
    let meta = file.metadata()?;
    let refuse = |what: String| std::io::Error::new(std::io::ErrorKind::InvalidData, what);
    if !meta.is_file() {
        return Err(refuse("not a regular file".into()));
    }
    if meta.len() > MAX_CROSSOVER_FILE_BYTES {
        return Err(refuse(format!(
            "{} bytes, more than the {MAX_CROSSOVER_FILE_BYTES} a crossover file may have",
            meta.len()
        )));
    }
    let mut text = String::new();
    file.take(MAX_CROSSOVER_FILE_BYTES + 1)
        .read_to_string(&mut text)?;
    if text.len() as u64 > MAX_CROSSOVER_FILE_BYTES {
        return Err(refuse("it grew while it was read".into()));
    }
    Ok(text)
}

/// A stored crossover file ([`Crossovers`]) that cannot be read,
/// written or used.
#[derive(Debug, Error)]
pub enum SteppingFileError {
    /// The file exists but cannot be read.
    #[error("cannot read the crossover file {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is not `{"crossovers": {"MODEL": activity, …}}`.
    #[error("the crossover file {} is not {{\"crossovers\": {{\"MODEL\": activity}}}}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The JSON error (with its line and column).
        source: serde_json::Error,
    },
    /// A crossover is not an activity.
    #[error("{}crossover of {model} is {value}, expected {expected}", path.as_ref().map(|p| format!("the crossover file {}: ", p.display())).unwrap_or_default())]
    Invalid {
        /// The file, when read from one.
        path: Option<PathBuf>,
        /// The model it is for.
        model: String,
        /// The value found.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// The file cannot be written.
    #[error("cannot write the crossover file {}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// `Err(expected)` unless `crossover` is an activity in `(0, 1]`.
fn check(crossover: f64) -> Result<(), &'static str> {
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
    pub(super) set: ActiveSet,
    /// `true` while stepped event-driven.
    pub(super) event: bool,
    /// The crossover of an automatic population; `None` when fixed event-driven.
    pub(super) crossover: Option<f64>,
    /// Active fractions counted in the current window, and how many.
    window: (f64, u64),
    /// The step the current window started at.
    window_from: u64,
    /// Active fractions counted since build or reset, and how many.
    total: (f64, u64),
    pub(super) switches: u64,
}

impl EventStepping {
    pub(super) fn new(n: usize, crossover: Option<f64>) -> Self {
        Self {
            set: ActiveSet::new(n),
            event: true,
            crossover,
            window: (0.0, 0),
            window_from: 0,
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

    /// `true` when a clock-driven automatic population counts its active neurons in step `k`
    /// (the last step of every [`CLOCK_SAMPLE_STEPS`] of its window).
    #[inline]
    pub(super) fn samples(&self, k: u64) -> bool {
        !self.event
            && self.crossover.is_some()
            && (k.saturating_sub(self.window_from) + 1).is_multiple_of(CLOCK_SAMPLE_STEPS)
    }

    /// At the start of step `k`: the mode to switch to, if the window so far calls for one (see
    /// [`Stepping`]). A switch or a full window starts a new window.
    pub(super) fn decide(&mut self, k: u64) -> Option<bool> {
        let crossover = self.crossover?;
        let elapsed = k.saturating_sub(self.window_from);
        let (sum, count) = self.window;
        let mean = (count > 0).then(|| sum / count as f64);
        let switch = if self.event {
            elapsed.is_multiple_of(EVENT_CHECK_STEPS)
                && mean.is_some_and(|m| m > crossover * HYSTERESIS)
        } else {
            elapsed >= DECISION_WINDOW_STEPS && mean.is_some_and(|m| m < crossover / HYSTERESIS)
        };
        if switch || elapsed >= DECISION_WINDOW_STEPS {
            self.window = (0.0, 0);
            self.window_from = k;
        }
        switch.then_some(!self.event)
    }

    /// Forgets the counts and starts a window at step 0 (the mode stays).
    pub(super) fn reset_counts(&mut self) {
        self.window = (0.0, 0);
        self.window_from = 0;
        self.total = (0.0, 0);
    }

    /// The mean activity since build or reset.
    pub(super) fn activity(&self) -> Option<f64> {
        (self.total.1 > 0).then(|| self.total.0 / self.total.1 as f64)
    }

    /// The mode and counts, for a saved network (the active set follows from the currents).
    pub(super) fn saved(&self) -> SteppingState {
        SteppingState {
            event: self.event,
            window: self.window,
            window_from: self.window_from,
            total: self.total,
            switches: self.switches,
        }
    }

    /// Takes the mode and counts of a saved network.
    pub(super) fn restore(&mut self, s: &SteppingState) {
        self.event = s.event;
        self.window = s.window;
        self.window_from = s.window_from;
        self.total = s.total;
        self.switches = s.switches;
    }
}

/// A population's stepping mode and activity counts in a saved network.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SteppingState {
    event: bool,
    window: (f64, u64),
    window_from: u64,
    total: (f64, u64),
    switches: u64,
}

impl SteppingState {
    /// `true` when the population was stepped event-driven.
    pub(super) fn event(&self) -> bool {
        self.event
    }
}

/// The neurons of an event-driven population whose synaptic current is nonzero, ascending.
pub(super) struct ActiveSet {
    pub(super) list: Vec<u32>,
    /// The neurons of `list` whose current is still nonzero after this step's decay.
    pub(super) next: Vec<u32>,
    pub(super) flag: Vec<bool>,
    pub(super) sorted: bool,
}

impl ActiveSet {
    pub(super) fn new(n: usize) -> Self {
        Self {
            list: Vec::new(),
            next: Vec::new(),
            flag: vec![false; n],
            sorted: true,
        }
    }

    #[inline]
    pub(super) fn mark(&mut self, j: u32) {
        if !std::mem::replace(&mut self.flag[j as usize], true) {
            self.sorted &= self.list.last().is_none_or(|&l| l < j);
            self.list.push(j);
        }
    }

    pub(super) fn clear(&mut self) {
        self.list
            .iter()
            .for_each(|&j| self.flag[j as usize] = false);
        self.list.clear();
        self.sorted = true;
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

    #[cfg(unix)]
    #[test]
    fn a_crossover_file_that_is_not_a_small_regular_file_is_refused_without_waiting() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(CROSSOVER_FILE_NAME);
        // A FIFO nobody writes to: opening it to read would wait for ever.
        let c = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        let e = Crossovers::load(&path).unwrap_err().to_string();
        assert!(e.contains(&path.display().to_string()), "{e}");
        std::fs::remove_file(&path).unwrap();
        // A link to an endless device.
        std::os::unix::fs::symlink("/dev/zero", &path).unwrap();
        let e = crate::error_chain(&Crossovers::load(&path).unwrap_err());
        assert!(e.contains("not a regular file"), "{e}");
        std::fs::remove_file(&path).unwrap();
        // A regular file too large to be one.
        std::fs::write(&path, vec![b' '; MAX_CROSSOVER_FILE_BYTES as usize + 1]).unwrap();
        let e = crate::error_chain(&Crossovers::load(&path).unwrap_err());
        assert!(e.contains("more than"), "{e}");
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
        let mut s = EventStepping::new(1000, Some(0.1));
        // Counts `active` of 1000 for steps `from..to`, deciding before each; the decisions.
        let steps = |s: &mut EventStepping, active: usize, from: u64, to: u64| {
            let mut switched = Vec::new();
            for k in from..to {
                if let Some(event) = s.decide(k) {
                    s.event = event;
                    switched.push((k, event));
                }
                if s.event || s.samples(k) {
                    s.count(active, 1000);
                }
            }
            switched
        };
        // Event-driven: stays at 0.108 (below c · 1.1) for whole windows.
        assert_eq!(steps(&mut s, 108, 0, 600), []);
        // Leaves for clock-driven at the next check once the window's mean is above it.
        let left = steps(&mut s, 1000, 600, 700);
        let k = left[0].0;
        assert_eq!(left, [(k, false)]);
        // (at a check of the window that started at 512, after two full ones)
        assert!(
            k - 600 <= EVENT_CHECK_STEPS && (k - 512) % EVENT_CHECK_STEPS == 0,
            "{k}"
        );
        // Clock-driven: stays at 0.092 (above c / 1.1) for whole windows.
        assert_eq!(steps(&mut s, 92, k, k + 3 * DECISION_WINDOW_STEPS), []);
        // Returns below c / 1.1, at the end of the first window counted quiet.
        let from = k + 3 * DECISION_WINDOW_STEPS;
        let back = steps(&mut s, 90, from, from + 2 * DECISION_WINDOW_STEPS);
        assert_eq!(back, [(from + DECISION_WINDOW_STEPS, true)]);
        // A fixed mode never changes.
        let mut fixed = EventStepping::new(1000, None);
        assert_eq!(steps(&mut fixed, 1000, 0, 1000), []);
        assert!(fixed.event);
    }
}
