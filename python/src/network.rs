//! Networks from Python: `neurotac.Network`, made from a saved network file or a JSON network
//! description (what `neurotac.NetworkBuilder` and `neurotac.nir.from_nir` build), run with
//! input spike trains; its recorded spikes, sampled state variables and population rates, its
//! weights (projections by index or by name) and its learning switch.

use crate::errors::{OrRaise, invalid};
use neurotac_core::{
    GraphError, InputId, MultiSpikeTrain, Network as CoreNetwork, NetworkBuilder, NetworkConfig,
    NetworkDescription, OneProcess, PopulationId, ProjectionId, ReadoutId, SpikeArrayInput,
    SpikeRecorder, StateRecorder, Weights,
};
use neurotac_neurons::BuiltinModels;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard, PoisonError};

/// A runnable spiking network (populations, spike inputs, projections, recorded nodes).
///
/// Made with ``NetworkBuilder(...).build()``, ``Network.load(path)`` (a file ``Network::save``
/// wrote, in Rust or Python) or ``Network.from_description(json)`` (the JSON of
/// ``description()``; ``neurotac.nir.from_nir`` makes one from a NIR graph).
/// ``run(duration_s, inputs=...)`` advances it, continuing from where the last run stopped
/// (``reset()`` returns to time 0); ``spikes(name)`` gives the spikes of any population or
/// spike input since time 0 (or since loading), ``population_rate(name, bin_s)`` their rate,
/// ``state_trace(name, variable)`` a state variable sampled by a monitor. A projection is named
/// by its index in the description's ``projections``, by ``"pre->post"`` (``projections`` lists
/// the names) or by the name of its presynaptic node when that node has only one.
#[pyclass(name = "Network", module = "neurotac")]
pub(crate) struct Network {
    /// The network (behind a lock: a Python object may be shared between threads, a network
    /// is only `Send`; `&mut self` methods reach it without locking).
    net: Mutex<CoreNetwork>,
    /// The spike sources by name, for `run(inputs=…)`.
    inputs: Vec<(String, InputId)>,
    /// The populations by name, for `state`.
    populations: Vec<(String, PopulationId)>,
    /// A spike recorder on every population and spike source (so nothing is pruned), by name.
    recorders: Vec<(String, ReadoutId<SpikeRecorder>)>,
    /// The state monitors, by `(population, variable)`.
    monitors: Vec<((String, String), ReadoutId<StateRecorder>)>,
    /// The projections, in the description's order, with their names (`pre->post`, `_2`… for
    /// a repeated pair).
    projections: Vec<(String, ProjectionId)>,
    /// The presynaptic node's name of each projection.
    projection_pre: Vec<String>,
    /// The number of neurons (channels) of every node, by name.
    sizes: Vec<(String, usize)>,
}

/// A state variable to sample: population, variable, every how many steps, which neurons
/// (all: `None`).
pub(crate) type StateMonitor = (String, String, u64, Option<Vec<u32>>);

/// The names of projections from `pairs` of `(pre, post)`: `pre->post`, and `pre->post_2`,
/// `_3`… for a pair connected again.
fn projection_names(pairs: &[(String, String)]) -> Vec<String> {
    let mut names: Vec<String> = Vec::with_capacity(pairs.len());
    for (pre, post) in pairs {
        let base = format!("{pre}->{post}");
        let mut name = base.clone();
        let mut k = 2;
        while names.contains(&name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        names.push(name);
    }
    names
}

impl Network {
    /// Builds `b` at `dt_s`, recording the spikes of every population and spike source and
    /// sampling the `monitors`' state variables.
    fn assemble(
        mut b: NetworkBuilder,
        dt_s: f64,
        monitors: &[StateMonitor],
    ) -> Result<Self, GraphError> {
        let names: Vec<String> = b.node_names().into_iter().map(str::to_owned).collect();
        let sizes = (names.iter())
            .map(|n| Ok((n.clone(), b.node_size(n)?)))
            .collect::<Result<Vec<_>, GraphError>>()?;
        let pairs: Vec<(String, String)> = (b.projection_ends().into_iter())
            .map(|(pre, post)| (pre.to_owned(), post.to_owned()))
            .collect();
        let (mut inputs, mut populations, mut recorders) = (Vec::new(), Vec::new(), Vec::new());
        for name in names {
            if let Ok(p) = b.population(&name) {
                recorders.push((name.clone(), b.record_spikes(p)?));
                populations.push((name, p));
            } else if let Ok(i) = b.spike_input(&name) {
                recorders.push((name.clone(), b.record_spikes(i)?));
                inputs.push((name, i));
            }
        }
        let mut recorded_state = Vec::new();
        for (population, variable, every_steps, neurons) in monitors {
            let id = b.population(population)?;
            let readout = b.record_state(id, variable, neurons.clone(), *every_steps)?;
            recorded_state.push(((population.clone(), variable.clone()), readout));
        }
        let projections = projection_names(&pairs)
            .into_iter()
            .zip(b.projections())
            .collect();
        let net = b.build(NetworkConfig { dt_s })?;
        Ok(Self {
            net: Mutex::new(net),
            inputs,
            populations,
            recorders,
            monitors: recorded_state,
            projections,
            projection_pre: pairs.into_iter().map(|(pre, _)| pre).collect(),
            sizes,
        })
    }


    /// The network, for a method that only reads it.
    fn net(&self) -> MutexGuard<'_, CoreNetwork> {
        self.net.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The network, for a method that changes it.
    fn net_mut(&mut self) -> &mut CoreNetwork {
        self.net.get_mut().unwrap_or_else(PoisonError::into_inner)
    }

    /// The projection `which` names — an index of the description's order, a name
    /// (`"pre->post"`), or the name of a node that is the presynaptic node of exactly one
    /// projection — or a `NeurotacValueError` listing the projections there are.
    fn projection(&self, which: &Bound<'_, PyAny>) -> PyResult<ProjectionId> {
        let listed = || {
            format!(
                "the network has {} projections: {}",
                self.projections.len(),
                names(&self.projections)
            )
        };
        if let Ok(index) = which.extract::<usize>() {
            return (self.projections.get(index).map(|(_, id)| *id)).ok_or_else(|| {
                invalid(format!("projection {index}: {} (0 to {})", listed(), self.projections.len().saturating_sub(1)))
            });
        }
        let Ok(name) = which.extract::<String>() else {
            return Err(invalid(format!(
                "projection: expected an index or a name (str), got {}",
                which.get_type().name()?
            )));
        };
        if let Some((_, id)) = self.projections.iter().find(|(n, _)| *n == name) {
            return Ok(*id);
        }
        let from: Vec<usize> = (0..self.projection_pre.len())
            .filter(|&i| self.projection_pre[i] == name)
            .collect();
        match from[..] {
            [one] => Ok(self.projections[one].1),
            [] => Err(invalid(format!("projection '{name}': no such projection; {}", listed()))),
            _ => Err(invalid(format!(
                "projection '{name}': '{name}' feeds {} projections, name one: {}",
                from.len(),
                from.iter().map(|&i| self.projections[i].0.as_str()).collect::<Vec<_>>().join(", ")
            ))),
        }
    }
}

/// How often a run looks for Ctrl-C.
const SIGNAL_CHECK_EVERY: std::time::Duration = std::time::Duration::from_millis(50);

/// Runs `net` for `steps` steps without the interpreter lock, checking for signals every
/// [`SIGNAL_CHECK_EVERY`] (Ctrl-C: the run ends there, with the steps done kept, and
/// `KeyboardInterrupt` is raised); the steps done.
fn run_interruptibly(py: Python<'_>, net: &mut CoreNetwork, steps: u64) -> PyResult<u64> {
    let mut signal: Option<PyErr> = None;
    let mut last_check = std::time::Instant::now();
    let summary = py
        .detach(|| {
            let mut interrupted = || {
                if last_check.elapsed() < SIGNAL_CHECK_EVERY {
                    return false;
                }
                last_check = std::time::Instant::now();
                signal = Python::attach(|py| py.check_signals().err());
                signal.is_some()
            };
            net.run_steps_until(steps, &OneProcess, &mut interrupted)
        })
        .or_raise()?;
    match signal {
        Some(e) => Err(e),
        None => Ok(summary.steps),
    }
}

/// The id called `name` in `list`, or a `NeurotacValueError` listing the names there are.
fn find<T: Copy>(list: &[(String, T)], name: &str, what: &str) -> PyResult<T> {
    list.iter()
        .find(|(n, _)| n == name)
        .map(|(_, id)| *id)
        .ok_or_else(|| {
            invalid(format!(
                "'{name}' is not a {what} of the network (its {what}s: {})",
                names(list)
            ))
        })
}

/// Spike times (s) and neuron indices, as `spikes` returns them.
type SpikeArrays<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<u32>>);

/// `a, b, c` of the names, or `none`.
fn names<T>(list: &[(String, T)]) -> String {
    if list.is_empty() {
        return "none".into();
    }
    list.iter()
        .map(|(n, _)| n.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The spike trains of input `name`: one sequence of spike times (s) per channel, shifted by
/// `offset_s` (the network's time when the run starts).
fn trains_from(name: &str, value: &Bound<'_, PyAny>, offset_s: f64) -> PyResult<MultiSpikeTrain> {
    let channels = value.try_iter().map_err(|_| {
        invalid(format!(
            "inputs['{name}']: expected one sequence of spike times (s) per channel"
        ))
    })?;
    let mut trains = Vec::new();
    for (c, channel) in channels.enumerate() {
        let times = channel?.extract::<Vec<f64>>().map_err(|_| {
            invalid(format!(
                "inputs['{name}'], channel {c}: expected a sequence of spike times (s)"
            ))
        })?;
        if let Some(t) = times.iter().find(|t| !t.is_finite()) {
            return Err(invalid(format!(
                "inputs['{name}'], channel {c}: spike time {t} is not finite"
            )));
        }
        trains.push(times.into_iter().map(|t| t + offset_s).collect::<Vec<_>>());
    }
    MultiSpikeTrain::from_unsorted_channels(&trains).or_value_error()
}

#[pymethods]
impl Network {
    /// The network a saved network file holds (``Network::save`` in Rust, ``save`` here), in
    /// the state it was saved in: runs continue bit for bit as the saved network would have.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let b = py
            .detach(|| NetworkBuilder::load(&path, &BuiltinModels))
            .or_raise()?;
        let dt_s = b
            .saved_dt_s()
            .expect("a loaded builder has its saved time step");
        Self::assemble(b, dt_s, &[]).or_raise()
    }

    /// The network a JSON network description describes (the schema of ``description()``),
    /// at time 0. ``state_monitors``: state variables to sample, as ``(population, variable,
    /// every_steps, neurons)`` tuples (``neurons`` a list of indices, or ``None`` for all);
    /// ``NetworkBuilder.monitor_state`` makes them.
    #[staticmethod]
    #[pyo3(signature = (description, state_monitors=None))]
    fn from_description(
        description: &str,
        state_monitors: Option<Vec<StateMonitor>>,
    ) -> PyResult<Self> {
        let d: NetworkDescription = serde_json::from_str(description)
            .map_err(|e| invalid(format!("the network description is not valid: {e}")))?;
        let b = NetworkBuilder::from_description(&d, &BuiltinModels).or_value_error()?;
        let monitors = state_monitors.unwrap_or_default();
        if let Some((p, v, _, _)) = monitors.iter().find(|m| m.2 == 0) {
            return Err(invalid(format!(
                "state monitor of '{p}'.{v}: every_steps = 0, expected ≥ 1"
            )));
        }
        Self::assemble(b, d.dt_s, &monitors).or_value_error()
    }

    /// The network's JSON description: nodes, projections with their current weights,
    /// recorded nodes, time step (``neurotac.nir.to_nir`` reads it).
    fn description(&self) -> PyResult<String> {
        let d = self.net().describe().or_value_error()?;
        serde_json::to_string(&d).or_raise()
    }

    /// Saves the network and its whole state (potentials, currents, learned weights and
    /// traces, spikes in flight) to `path`, replaced atomically.
    fn save(&mut self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let net = self.net_mut();
        py.detach(move || net.save(&path)).or_raise()
    }

    /// Advances the network by `duration_s` seconds (rounded to whole steps), continuing from
    /// where the last run stopped; returns the number of steps.
    ///
    /// ``inputs`` replaces spike inputs before the run: ``{name: trains}`` with one sequence of
    /// spike times per channel, in seconds from the start of this run (so sample after sample
    /// can be fed without resetting); the other inputs keep theirs. A replaced input plays
    /// only the new trains. ``reset()`` first to start from time 0 with fresh state.
    #[pyo3(signature = (duration_s, inputs=None))]
    fn run(
        &mut self,
        py: Python<'_>,
        duration_s: f64,
        inputs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<u64> {
        if !(duration_s.is_finite() && duration_s >= 0.0) {
            return Err(invalid(format!(
                "duration_s = {duration_s}: expected a finite number of seconds ≥ 0"
            )));
        }
        if let Some(inputs) = inputs {
            let start_s = self.net_mut().time_s();
            let mut replacements = Vec::new();
            for (name, trains) in inputs.iter() {
                let name: String = name.extract().map_err(|_| {
                    invalid("inputs: expected a dict from input names (str) to spike trains")
                })?;
                let id = find(&self.inputs, &name, "spike input")?;
                replacements.push((id, trains_from(&name, &trains, start_s)?));
            }
            for (id, trains) in replacements {
                self.net_mut()
                    .replace_spike_input(id, SpikeArrayInput::new(trains))
                    .or_value_error()?;
            }
        }
        let net = self.net_mut();
        // Refused up front: a duration that is not finite, or more steps than a run may take.
        let steps = net.steps_for(duration_s).or_value_error()?;
        run_interruptibly(py, net, steps)
    }

    /// Returns to time 0: potentials and synaptic currents start anew, inputs replay from
    /// time 0 (a replaced input: at the network times its trains were given for), recorded
    /// spikes are cleared when the next run starts; weights (learned ones too) stay.
    fn reset(&mut self) {
        self.net_mut().reset();
    }

    /// The time step (s).
    #[getter]
    fn dt_s(&self) -> f64 {
        self.net().dt_s()
    }

    /// The network's time (s): steps done since time 0 × dt.
    #[getter]
    fn time_s(&self) -> f64 {
        self.net().time_s()
    }

    /// The names of the populations.
    #[getter]
    fn populations(&self) -> Vec<String> {
        self.populations.iter().map(|(n, _)| n.clone()).collect()
    }

    /// The names of the spike inputs (``run(inputs=…)`` replaces them).
    #[getter]
    fn inputs(&self) -> Vec<String> {
        self.inputs.iter().map(|(n, _)| n.clone()).collect()
    }

    /// The number of projections.
    #[getter]
    fn n_projections(&self) -> usize {
        self.projections.len()
    }

    /// The names of the projections, in order (``"pre->post"``; ``weights`` takes them).
    #[getter]
    fn projections(&self) -> Vec<String> {
        self.projections.iter().map(|(n, _)| n.clone()).collect()
    }

    /// The nodes whose spikes are recorded (every population and spike input: ``spikes``
    /// and ``population_rate`` take them).
    #[getter]
    fn recorded(&self) -> Vec<String> {
        self.recorders.iter().map(|(n, _)| n.clone()).collect()
    }

    /// The sampled state variables, as ``(population, variable)`` pairs (``state_trace``
    /// takes them).
    #[getter]
    fn state_monitors(&self) -> Vec<(String, String)> {
        self.monitors.iter().map(|(k, _)| k.clone()).collect()
    }

    /// State variable ``variable`` of population ``name`` as its monitor sampled it since time
    /// 0 (at the end of every ``every_steps``-th step): ``(times, values)``, float64 seconds
    /// of shape ``(samples,)`` and the values of shape ``(samples, neurons)`` (the monitor's
    /// neurons, in its order).
    fn state_trace<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        variable: &str,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>)> {
        let key = (name.to_owned(), variable.to_owned());
        let Some((_, id)) = self.monitors.iter().find(|(k, _)| *k == key) else {
            let sampled: Vec<String> = self.monitors.iter().map(|((p, v), _)| format!("{p}.{v}")).collect();
            return Err(invalid(format!(
                "'{name}'.{variable} has no state monitor (sampled: {}); add one with NetworkBuilder.monitor_state",
                if sampled.is_empty() { "none".to_owned() } else { sampled.join(", ") }
            )));
        };
        let net = self.net();
        let r = net.readout(*id).or_raise()?;
        let columns = r.neurons().len();
        let rows = r.times().len();
        let values = ndarray::Array2::from_shape_vec((rows, columns), r.values().to_vec())
            .map_err(|e| invalid(format!("state trace of '{name}'.{variable}: {e}")))?;
        Ok((r.times().to_vec().into_pyarray(py), values.into_pyarray(py)))
    }

    /// The population rate of population or spike input ``name``: its spikes since time 0 in
    /// bins ``[k·bin_s, (k + 1)·bin_s)`` from 0 to the network's time, divided by the bin and
    /// the number of neurons (a population's spikes are stamped at the end of their step; one
    /// at the run's end counts in the last bin). ``(bin_start_s, rate_hz)``: float64 arrays, one
    /// entry per whole bin (a last partial bin is left out).
    fn population_rate<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        bin_s: f64,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>)> {
        let id = find(&self.recorders, name, "population or spike input")?;
        let net = self.net();
        let bins = net.time_s() / bin_s;
        if !(bin_s.is_finite() && bin_s > 0.0 && bins <= 1e8) {
            return Err(invalid(format!(
                "bin_s = {bin_s}: expected a number of seconds > 0, at most 10⁸ bins over the {} s run",
                net.time_s()
            )));
        }
        // A whole bin up to a rounding of the network's time (k steps × dt).
        let bins = (bins + 1e-9).floor() as usize;
        let size = find(&self.sizes, name, "node")?.max(1) as f64;
        let mut rate_hz = vec![0.0; bins];
        for &(_, t) in net.readout(id).or_raise()?.spikes() {
            // [k·bin_s, (k + 1)·bin_s), up to rounding; a spike stamped at the run's very end
            // (a population's, at the end of its last step) in the last bin.
            let bin = (t / bin_s + 1e-9).floor() as usize;
            let bin = if bin == bins && bins > 0 { bins - 1 } else { bin };
            if bin < bins {
                rate_hz[bin] += 1.0 / (bin_s * size);
            }
        }
        let starts: Vec<f64> = (0..bins).map(|k| k as f64 * bin_s).collect();
        Ok((starts.into_pyarray(py), rate_hz.into_pyarray(py)))
    }

    /// The spikes of population or spike input `name` since time 0 (or since loading), in
    /// time order: ``(times, indices)``,
    /// float64 seconds and uint32 neuron (channel) indices.
    fn spikes<'py>(&self, py: Python<'py>, name: &str) -> PyResult<SpikeArrays<'py>> {
        let id = find(&self.recorders, name, "population or spike input")?;
        let net = self.net();
        let spikes = net.readout(id).or_raise()?.spikes();
        let times: Vec<f64> = spikes.iter().map(|&(_, t)| t).collect();
        let indices: Vec<u32> = spikes.iter().map(|&(j, _)| j).collect();
        Ok((times.into_pyarray(py), indices.into_pyarray(py)))
    }

    /// The weights of projection `projection` now (learned ones for a plastic projection).
    /// ``dense=True``: the ``n_pre × n_post`` matrix ``W[i, j]`` (row = presynaptic neuron;
    /// pairs without a synapse are 0; NIR's ``Linear`` weight is its transpose).
    /// ``dense=False``: ``(pre, post, weight)`` arrays, one entry per synapse, sorted by
    /// presynaptic then postsynaptic index — the order ``set_weights`` takes.
    #[pyo3(signature = (projection, dense=true))]
    fn weights<'py>(
        &self,
        py: Python<'py>,
        projection: &Bound<'py, PyAny>,
        dense: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let id = self.projection(projection)?;
        let w = self.net().weights(id).or_raise()?;
        if dense {
            return Ok(w.dense().into_pyarray(py).into_any());
        }
        let Weights {
            pre, post, weight, ..
        } = w;
        Ok(PyTuple::new(
            py,
            [
                pre.into_pyarray(py).into_any(),
                post.into_pyarray(py).into_any(),
                weight.into_pyarray(py).into_any(),
            ],
        )?
        .into_any())
    }

    /// Sets the weights of projection `projection`'s synapses, from the next delivered spike:
    /// ``weights`` is either the ``n_pre × n_post`` matrix of ``weights(p)`` (each synapse takes
    /// its pair's entry; an entry ≠ 0 where there is no synapse is refused) or one weight per
    /// synapse in the order of ``weights(p, dense=False)``. Plastic projections keep their
    /// bounds. Nothing changes when a weight is refused.
    fn set_weights(
        &mut self,
        projection: &Bound<'_, PyAny>,
        weights: PyReadonlyArrayDyn<'_, f64>,
    ) -> PyResult<()> {
        let id = self.projection(projection)?;
        let mut w = self.net_mut().weights(id).or_raise()?;
        let given = weights.as_array();
        match given.ndim() {
            1 => {
                if given.len() != w.len() {
                    return Err(invalid(format!(
                        "set_weights: {} weights for {} synapses (one per synapse, in the order of weights(p, dense=False))",
                        given.len(),
                        w.len()
                    )));
                }
                w.weight
                    .iter_mut()
                    .zip(given.iter())
                    .for_each(|(x, &g)| *x = g);
            }
            2 => {
                let shape = (given.shape()[0], given.shape()[1]);
                if shape != (w.n_pre, w.n_post) {
                    return Err(invalid(format!(
                        "set_weights: the matrix is {}×{}, the projection's is {}×{} (n_pre × n_post)",
                        shape.0, shape.1, w.n_pre, w.n_post
                    )));
                }
                let mut covered = ndarray::Array2::from_elem((w.n_pre, w.n_post), false);
                for s in 0..w.len() {
                    let (i, j) = (w.pre[s] as usize, w.post[s] as usize);
                    w.weight[s] = given[[i, j]];
                    covered[(i, j)] = true;
                }
                if let Some(((i, j), &x)) = given
                    .indexed_iter()
                    .map(|(ix, x)| ((ix[0], ix[1]), x))
                    .find(|((i, j), x)| **x != 0.0 && !covered[(*i, *j)])
                {
                    return Err(invalid(format!(
                        "set_weights: W[{i}, {j}] = {x}, but projection {projection} has no synapse {i} → {j}",
                        projection = projection.str()?
                    )));
                }
            }
            n => {
                return Err(invalid(format!(
                    "set_weights: expected an n_pre × n_post matrix or one weight per synapse, got {n} dimensions"
                )));
            }
        }
        self.net_mut().set_weights(id, &w).or_value_error()
    }

    /// Turns learning of the plastic projection `projection` on or off (off: its weights stay
    /// as they are, its traces still follow the spikes).
    fn set_learning(&mut self, projection: &Bound<'_, PyAny>, on: bool) -> PyResult<()> {
        let id = self.projection(projection)?;
        self.net_mut().set_learning(id, on).or_value_error()
    }

    /// The state variable `variable` (``"v"``…) of every neuron of population `name`, now.
    fn state<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        variable: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let id = find(&self.populations, name, "population")?;
        Ok(self
            .net()
            .state(id, variable)
            .or_value_error()?
            .into_pyarray(py))
    }

    fn __repr__(&self) -> String {
        let net = self.net();
        format!(
            "Network(dt_s={}, time_s={}, inputs=[{}], populations=[{}], projections={})",
            net.dt_s(),
            net.time_s(),
            names(&self.inputs),
            names(&self.populations),
            self.projections.len()
        )
    }
}
