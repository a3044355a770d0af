//! Networks from Python: `neurotac.Network`, made from a saved network file or a JSON network
//! description (what `neurotac.nir.from_nir` builds), run with input spike trains, its recorded
//! spikes, its weights and its learning switch.

use crate::errors::{OrRaise, invalid};
use neurotac_core::{
    GraphError, InputId, MultiSpikeTrain, Network as CoreNetwork, NetworkBuilder, NetworkConfig,
    NetworkDescription, OneProcess, PopulationId, ProjectionId, ReadoutId, SpikeArrayInput,
    SpikeRecorder, Weights,
};
use neurotac_neurons::BuiltinModels;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard, PoisonError};

/// A runnable spiking network (populations, spike inputs, projections, recorded nodes).
///
/// Made with ``Network.load(path)`` (a file ``Network::save`` wrote, in Rust or Python) or
/// ``Network.from_description(json)`` (the JSON of ``description()``; ``neurotac.nir.from_nir``
/// makes one from a NIR graph). ``run(duration_s, inputs=...)`` advances it, continuing from
/// where the last run stopped (``reset()`` returns to time 0); ``spikes(name)`` gives the spikes
/// of any population or spike input since time 0 (or since loading); projections are numbered
/// in the order of the description's ``projections``.
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
    /// The projections, in the description's order.
    projections: Vec<ProjectionId>,
}

impl Network {
    /// Builds `b` at `dt_s`, recording the spikes of every population and spike source.
    fn assemble(mut b: NetworkBuilder, dt_s: f64) -> Result<Self, GraphError> {
        let names: Vec<String> = b.node_names().into_iter().map(str::to_owned).collect();
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
        let projections = b.projections();
        let net = b.build(NetworkConfig { dt_s })?;
        Ok(Self {
            net: Mutex::new(net),
            inputs,
            populations,
            recorders,
            projections,
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

    /// Projection `index` of the description, or a `NeurotacValueError` saying how many there are.
    fn projection(&self, index: usize) -> PyResult<ProjectionId> {
        self.projections.get(index).copied().ok_or_else(|| {
            invalid(format!(
                "projection {index}: the network has {} projections (0 to {})",
                self.projections.len(),
                self.projections.len().saturating_sub(1)
            ))
        })
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
        Self::assemble(b, dt_s).or_raise()
    }

    /// The network a JSON network description describes (the schema of ``description()``),
    /// at time 0.
    #[staticmethod]
    fn from_description(description: &str) -> PyResult<Self> {
        let d: NetworkDescription = serde_json::from_str(description)
            .map_err(|e| invalid(format!("the network description is not valid: {e}")))?;
        let b = NetworkBuilder::from_description(&d, &BuiltinModels).or_value_error()?;
        Self::assemble(b, d.dt_s).or_value_error()
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
        projection: usize,
        dense: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let w = self
            .net()
            .weights(self.projection(projection)?)
            .or_raise()?;
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
        projection: usize,
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
                        "set_weights: W[{i}, {j}] = {x}, but projection {projection} has no synapse {i} → {j}"
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
    fn set_learning(&mut self, projection: usize, on: bool) -> PyResult<()> {
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
