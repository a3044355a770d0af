//! Saved networks: [`Network::save`] writes a network — its description and where every part
//! of it is — so that [`NetworkBuilder::load`] and a build continue it bit for bit as the
//! uninterrupted run would have: models (event-driven bookkeeping included), synaptic
//! currents, the spikes still in flight in the delay lines, sources' positions, plastic weights
//! and their traces, automatic stepping's counts.
//!
//! Readouts are not saved (they watch a run; add them again after loading).

use super::builder::NetworkBuilder;
use super::description::{NetworkDescription, NodeDescription};
use super::input::SourceDescription;
use super::limits::MAX_STEPS;
use super::network::{Network, active_neurons};
use super::running::RunningKind;
use super::snapshot::{NetworkState, NodeState, ProjectionState, TraceState};
use super::stepping::SteppingState;
use crate::error::{GraphError, IoAction};
use crate::io::{AtomicFile, Replace};
use crate::model::ModelFactory;
use crate::model::SpikeBuffer;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The first bytes of a saved network.
pub const NETWORK_FILE_MAGIC: &[u8; 8] = b"NTNETWRK";
/// The file version written; versions 1 to this are read.
pub const NETWORK_FILE_VERSION: u32 = 1;
/// Magic, version and body length.
const HEADER_BYTES: usize = 8 + 4 + 8;
/// The trailing CRC-32.
const CHECKSUM_BYTES: usize = 4;

/// A saved network that cannot be written or read.
#[derive(Debug, Error)]
pub enum NetworkFileError {
    /// The file could not be opened, read or written.
    #[error("cannot {action} the network file {}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Reading or writing.
        action: IoAction,
        /// The system's reason.
        source: std::io::Error,
    },
    /// The file does not start with [`NETWORK_FILE_MAGIC`].
    #[error("{}: not a saved neurotac network (it does not start with \"NTNETWRK\")", path.display())]
    NotANetwork {
        /// The file.
        path: PathBuf,
    },
    /// A version this neurotac does not read.
    #[error("{}: saved network version {found}; this neurotac reads versions 1 to {NETWORK_FILE_VERSION} (was it written by a newer neurotac?)", path.display())]
    Version {
        /// The file.
        path: PathBuf,
        /// The version in the file.
        found: u32,
    },
    /// The file ends before its header, body or checksum does (or has bytes after them).
    #[error("{}: {what} (the file has {size} bytes)", path.display())]
    Length {
        /// The file.
        path: PathBuf,
        /// What does not fit.
        what: String,
        /// The file's size.
        size: u64,
    },
    /// The stored CRC-32 does not match the bytes: the file is corrupt.
    #[error("{}: checksum mismatch (stored CRC-32 {stored:08x}, computed {computed:08x}): the file is corrupt", path.display())]
    Checksum {
        /// The file.
        path: PathBuf,
        /// The CRC-32 stored in the last 4 bytes.
        stored: u32,
        /// The CRC-32 of the bytes before them.
        computed: u32,
    },
    /// The body is not a saved network (its checksum matched: written by something else).
    #[error("{}: the saved network cannot be decoded: {reason}", path.display())]
    Decode {
        /// The file.
        path: PathBuf,
        /// The decoder's reason.
        reason: String,
    },
    /// The network cannot be saved, or the saved one does not build.
    #[error("{}: {source}", path.display())]
    Graph {
        /// The file.
        path: PathBuf,
        /// What the graph refuses.
        source: Box<GraphError>,
    },
}

/// What a saved file holds.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SavedNetwork {
    description: NetworkDescription,
    state: NetworkState,
}

impl Network {
    /// Where this network is ([`NetworkState`]), for [`save`](Self::save).
    fn saved_state(&self) -> Result<NetworkState, GraphError> {
        let mut nodes = Vec::new();
        for n in &self.nodes {
            let len = n.history.len() as u64;
            let history = (1..=len.min(self.step))
                .map(|back| &n.history[((self.step - back) % len) as usize])
                .map(|b| (b.indices().to_vec(), b.fractions().to_vec()))
                .collect();
            let not_saveable = |reason: &str| GraphError::NotSaveable {
                node: n.name.clone(),
                reason: reason.into(),
            };
            let (model, position) = match &n.kind {
                RunningKind::Population(m) => (
                    Some(
                        m.save_state()
                            .ok_or_else(|| not_saveable("its model has no saved state"))?,
                    ),
                    None,
                ),
                RunningKind::Spikes(s) => (
                    None,
                    Some(
                        s.position()
                            .ok_or_else(|| not_saveable("its source has no saved position"))?,
                    ),
                ),
            };
            nodes.push(NodeState {
                model,
                position,
                history,
                stepping: n.active.as_ref().map(|a| a.saved()),
            });
        }
        let projections = (self.projections.iter())
            .filter(|p| p.post.is_some())
            .map(|p| ProjectionState {
                current: p.current.clone(),
                plasticity: p.plasticity.as_ref().map(|pl| TraceState {
                    learning: pl.learning,
                    pre: (pl.pre.value.clone(), pl.pre.at.clone()),
                    post: (pl.post.value.clone(), pl.post.at.clone()),
                }),
            })
            .collect();
        Ok(NetworkState {
            step: self.step,
            neuron_updates: self.neuron_updates,
            nodes,
            projections,
        })
    }

    /// Saves this network to `path`: its description ([`describe`](Self::describe)) and where
    /// every part of it is now — models (event-driven bookkeeping included), synaptic
    /// currents, the spikes still in flight in the delay lines, sources' positions, plastic
    /// weights and their traces, automatic stepping's counts — so that
    /// [`NetworkBuilder::load`] continues it bit for bit. Readouts are not saved (they watch
    /// a run; add them again after loading). Replaces `path` atomically. Errors: what
    /// [`describe`](Self::describe) refuses, a model or source without a saved state, a
    /// network partitioned over ranks, the file not writable.
    ///
    /// # File format (version 1)
    /// Little-endian: magic `NTNETWRK`, `u32` version, `u64` length `L` of the body, the body (`L`
    /// bytes: [CBOR](https://www.rfc-editor.org/rfc/rfc8949) of `{description, state}`, the
    /// description as [`NetworkDescription`]), and last a `u32` CRC-32 (IEEE, as zlib's `crc32`)
    /// of every byte before it. The magic and the version are read first (a newer file is a
    /// [`NetworkFileError::Version`]), then the length is checked against the file's size and the
    /// checksum verified before anything is decoded: a file cut anywhere or with a flipped bit is
    /// a typed error naming the file, never a different network. Numbers are stored as they are
    /// (CBOR floats are exact). Written through [`AtomicFile`](crate::AtomicFile): never half-written.
    ///
    /// Reading checks the state against the description before anything is built: one state per
    /// population (its model's arrays, at least as long as the population) and per spike source
    /// (its position; a Poisson source's, its channels + 2 numbers), spikes in the delay lines of
    /// neurons that exist, finite synaptic currents, finite traces ≥ 0 of steps not after the
    /// saved one. The description keeps the [limits](super::limits) of any network: at most
    /// 2³² − 1 neurons or channels per node, delays of at most 2²⁰ steps, at most 2⁵³ steps
    /// done; a part whose memory cannot be reserved is refused before it is built. Every error
    /// names the file, those of the build included ([`GraphError::Saved`]).
    ///
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), NetworkFileError> {
        let path = path.as_ref();
        let graph = |source| NetworkFileError::Graph {
            path: path.to_owned(),
            source: Box::new(source),
        };
        let saved = SavedNetwork {
            description: self.describe().map_err(graph)?,
            state: self.saved_state().map_err(graph)?,
        };
        let mut body = Vec::new();
        ciborium::ser::into_writer(&saved, &mut body)
            .expect("serialising into memory does not fail");
        let mut bytes = Vec::with_capacity(HEADER_BYTES + body.len() + CHECKSUM_BYTES);
        bytes.extend_from_slice(NETWORK_FILE_MAGIC);
        bytes.extend_from_slice(&NETWORK_FILE_VERSION.to_le_bytes());
        bytes.extend_from_slice(&(body.len() as u64).to_le_bytes());
        bytes.extend_from_slice(&body);
        bytes.extend_from_slice(&crc32fast::hash(&bytes).to_le_bytes());
        let write = || -> std::io::Result<()> {
            let mut f = AtomicFile::create(path, Replace::Yes)?;
            f.write_all(&bytes)?;
            f.commit()
        };
        write().map_err(|source| NetworkFileError::Io {
            path: path.to_owned(),
            action: IoAction::Write,
            source,
        })
    }

    /// Puts this network, just built from a saved description, where `state` says (see
    /// [`NetworkBuilder::load`]). Nodes and projections pruned by this build are skipped.
    pub(super) fn restore(&mut self, state: &NetworkState) -> Result<(), GraphError> {
        let misfit = |what: String| GraphError::Description(format!("saved state: {what}"));
        self.step = state.step;
        self.neuron_updates = state.neuron_updates;
        for (i, saved) in state.nodes.iter().enumerate() {
            let Some(r) = self.node_index.get(i).copied().flatten() else {
                continue;
            };
            let n = &mut self.nodes[r];
            match (&mut n.kind, &saved.model, &saved.position) {
                (RunningKind::Population(m), Some(model), _) => {
                    m.restore_state(model).map_err(|source| GraphError::Model {
                        population: n.name.clone(),
                        source,
                    })?
                }
                (RunningKind::Spikes(s), _, Some(position)) => s.seek(state.step, position)?,
                _ => {
                    return Err(misfit(format!(
                        "node {i} ('{}') is not of its saved kind",
                        n.name
                    )));
                }
            }
            let len = n.history.len() as u64;
            let depth = len.min(state.step) as usize;
            for (back, (indices, fractions)) in (1..).zip(&saved.history).take(depth) {
                if indices.len() != fractions.len() {
                    return Err(misfit(format!(
                        "the spikes of '{}' {back} steps back",
                        n.name
                    )));
                }
                let slot = &mut n.history[((state.step - back) % len) as usize];
                *slot = SpikeBuffer::new();
                indices
                    .iter()
                    .zip(fractions)
                    .for_each(|(&j, &phi)| slot.push_at(j, phi));
            }
            if let (Some(a), Some(s)) = (&mut n.active, &saved.stepping) {
                a.restore(s);
            }
            // A population saved event-driven and built clock-driven (or the other way, e.g.
            // with a state readout added) is brought up to date, or marked current.
            let was_event = saved.stepping.as_ref().is_some_and(SteppingState::event);
            let is_event = n.active.as_ref().is_some_and(|a| a.event);
            if let RunningKind::Population(m) = &mut n.kind {
                match (was_event, is_event) {
                    (true, false) => m.settle(),
                    (false, true) => m.resume_event_driven(),
                    _ => {}
                }
            }
        }
        for (i, saved) in state.projections.iter().enumerate() {
            let Some(p) = self.projection_index.get(i).copied().flatten() else {
                continue;
            };
            let p = &mut self.projections[p];
            if saved.current.len() != p.current.len() {
                return Err(misfit(format!(
                    "projection {i} has {} currents, expected {}",
                    saved.current.len(),
                    p.current.len()
                )));
            }
            p.current.copy_from_slice(&saved.current);
            match (&mut p.plasticity, &saved.plasticity) {
                (Some(pl), Some(t)) => {
                    let ((pre, pre_at), (post, post_at)) = (&t.pre, &t.post);
                    let fits = pre.len() == pl.pre.value.len()
                        && pre_at.len() == pre.len()
                        && post.len() == pl.post.value.len()
                        && post_at.len() == post.len();
                    if !fits {
                        return Err(misfit(format!("projection {i}'s traces")));
                    }
                    pl.learning = t.learning;
                    pl.pre.value.clone_from(pre);
                    pl.pre.at.clone_from(pre_at);
                    pl.post.value.clone_from(post);
                    pl.post.at.clone_from(post_at);
                }
                (None, None) => {}
                _ => {
                    return Err(misfit(format!(
                        "projection {i} is plastic on one side only"
                    )));
                }
            }
        }
        // The event-driven populations' active sets: the neurons with synaptic current.
        for n in &mut self.nodes {
            if let Some(a) = n.active.as_mut().filter(|a| a.event) {
                a.set.clear();
                let len = a.set.flag.len();
                for j in active_neurons(&self.projections, &n.incoming, len) {
                    a.set.mark(j);
                }
            }
        }
        Ok(())
    }
}

impl NetworkBuilder {
    /// Reads the network saved at `path` ([`Network::save`]) into a builder, its models made
    /// by `models` (`neurotac_neurons::BuiltinModels` for LIF and Izhikevich). Add readouts
    /// (find nodes by name: [`population`](Self::population),
    /// [`spike_input`](Self::spike_input), [`projections`](Self::projections)), then
    /// [`build`](Self::build) at the saved time step ([`saved_dt_s`](Self::saved_dt_s)): the
    /// network continues from the saved step exactly as the saved one would have.
    ///
    /// Errors (nothing is half-built): the file unreadable, not a saved network, a newer
    /// version, cut short or with bytes flipped ([`NetworkFileError::Length`],
    /// [`NetworkFileError::Checksum`]), a body that does not decode, a description that does
    /// not build ([`NetworkFileError::Graph`]).
    pub fn load(
        path: impl AsRef<Path>,
        models: &dyn ModelFactory,
    ) -> Result<NetworkBuilder, NetworkFileError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| NetworkFileError::Io {
            path: path.to_owned(),
            action: IoAction::Read,
            source,
        })?;
        Self::from_saved_bytes(&bytes, path, models)
    }

    /// [`load`](Self::load) of a saved network's bytes (`path` names them in errors).
    pub fn from_saved_bytes(
        bytes: &[u8],
        path: &Path,
        models: &dyn ModelFactory,
    ) -> Result<NetworkBuilder, NetworkFileError> {
        let saved = decode(bytes, path)?;
        check_state_fits(&saved).map_err(|what| NetworkFileError::Graph {
            path: path.to_owned(),
            source: Box::new(GraphError::Description(format!("saved state: {what}"))),
        })?;
        let mut b =
            NetworkBuilder::from_description(&saved.description, models).map_err(|source| {
                NetworkFileError::Graph {
                    path: path.to_owned(),
                    source: Box::new(source),
                }
            })?;
        b.saved = Some(super::builder::Saved {
            dt_s: saved.description.dt_s,
            state: Box::new(saved.state),
            path: path.to_owned(),
        });
        Ok(b)
    }

    /// The description in a saved network's bytes, checked as [`load`](Self::load) checks the
    /// file (header, length, checksum, decoding) but not built: what a tool reads to look at a
    /// saved network before making it.
    pub fn saved_description(
        bytes: &[u8],
        path: &Path,
    ) -> Result<NetworkDescription, NetworkFileError> {
        Ok(decode(bytes, path)?.description)
    }

    /// The time step of the saved network this builder was loaded from ([`load`](Self::load)).
    pub fn saved_dt_s(&self) -> Option<f64> {
        self.saved.as_ref().map(|saved| saved.dt_s)
    }
}

/// The neurons or channels of a described node (a current source: its values).
fn node_size(node: &NodeDescription) -> usize {
    match node {
        NodeDescription::Population { model, .. } => model.size,
        NodeDescription::Source { source, .. } => match source {
            SourceDescription::SpikeArray { trains } => trains.len(),
            SourceDescription::Poisson { size, .. } => *size,
        },
        NodeDescription::Current { current, .. } => current.len(),
    }
}

/// Checks, before anything is made, that the saved state fits its description: one entry per
/// described node (populations with their model's state, spike sources with their position)
/// and projection; no population larger than its longest saved array, no Poisson source with
/// more channels than its saved position (a corrupt size never sizes an allocation: the arrays
/// are in the file); a step count within [`MAX_STEPS`]; spikes in the delay lines of neurons
/// that exist, at fractions of a step in [0, 1]; finite synaptic currents; plastic traces
/// finite, ≥ 0 and last updated no later than the saved step.
fn check_state_fits(saved: &SavedNetwork) -> Result<(), String> {
    let (d, s) = (&saved.description, &saved.state);
    if s.step > MAX_STEPS {
        return Err(format!(
            "step {} is beyond the {MAX_STEPS} steps a network may do",
            s.step
        ));
    }
    let nodes = (d.nodes.iter())
        .filter(|n| !matches!(n, NodeDescription::Current { .. }))
        .count();
    if s.nodes.len() != nodes || s.projections.len() != d.projections.len() {
        return Err(format!(
            "{} node and {} projection states for {nodes} nodes and {} projections",
            s.nodes.len(),
            s.projections.len(),
            d.projections.len()
        ));
    }
    let described = (d.nodes.iter()).filter(|n| !matches!(n, NodeDescription::Current { .. }));
    for (node, state) in described.clone().zip(&s.nodes) {
        let name = node.name();
        let kind_fits = match node {
            NodeDescription::Population { .. } => state.model.is_some() && state.position.is_none(),
            _ => state.model.is_none() && state.position.is_some(),
        };
        if !kind_fits {
            return Err(format!(
                "node '{name}' is saved without its {} (or with another kind's)",
                match node {
                    NodeDescription::Population { .. } => "model's state",
                    _ => "source's position",
                }
            ));
        }
        let size = node_size(node);
        for (back, (indices, fractions)) in (1..).zip(&state.history) {
            let spikes = || format!("the spikes of '{name}' {back} steps back");
            if indices.len() != fractions.len() {
                return Err(format!(
                    "{}: {} indices and {} fractions",
                    spikes(),
                    indices.len(),
                    fractions.len()
                ));
            }
            if let Some(&j) = indices.iter().find(|&&j| j as usize >= size) {
                return Err(format!("{}: neuron {j} of {size}", spikes()));
            }
            if let Some(phi) = fractions.iter().find(|f| !(0.0..=1.0).contains(*f)) {
                return Err(format!(
                    "{}: in-step fraction {phi}, expected in [0, 1]",
                    spikes()
                ));
            }
        }
    }
    for (i, p) in s.projections.iter().enumerate() {
        if let Some((j, c)) = p.current.iter().enumerate().find(|(_, c)| !c.is_finite()) {
            return Err(format!(
                "projection {i}: synaptic current {j} is {c}, expected finite"
            ));
        }
        if let Some(t) = &p.plasticity {
            for (side, (value, at)) in [("pre", &t.pre), ("post", &t.post)] {
                if let Some((j, x)) = value
                    .iter()
                    .enumerate()
                    .find(|(_, x)| !(x.is_finite() && **x >= 0.0))
                {
                    return Err(format!(
                        "projection {i}: STDP {side} trace {j} is {x}, expected finite and ≥ 0"
                    ));
                }
                if let Some((j, k)) = at.iter().enumerate().find(|(_, k)| **k > s.step) {
                    return Err(format!(
                        "projection {i}: STDP {side} trace {j} was updated at step {k}, after the saved step {}",
                        s.step
                    ));
                }
            }
        }
    }
    for (node, state) in described.zip(&s.nodes) {
        // A firing Poisson source's position holds each channel's next spike.
        if let (
            NodeDescription::Source {
                name,
                source: SourceDescription::Poisson { size, rate_hz, .. },
            },
            Some(position),
        ) = (node, &state.position)
            && *rate_hz > 0.0
            && position.len() != size.saturating_add(2)
        {
            return Err(format!(
                "Poisson source '{name}' has {size} channels but its saved position {} numbers",
                position.len()
            ));
        }
        if let (NodeDescription::Population { name, model }, Some(m)) = (node, &state.model) {
            let longest = m.arrays.iter().map(|(_, a)| a.len()).max();
            if longest.is_some_and(|l| model.size > l) {
                return Err(format!(
                    "population '{name}' has {} neurons but its longest saved array {} values",
                    model.size,
                    longest.unwrap_or(0)
                ));
            }
        }
    }
    Ok(())
}

/// The saved network in `bytes` (the file `path`), checked as [`Network::save`] says.
fn decode(bytes: &[u8], path: &Path) -> Result<SavedNetwork, NetworkFileError> {
    let size = bytes.len() as u64;
    let length = |what: String| NetworkFileError::Length {
        path: path.to_owned(),
        what,
        size,
    };
    if bytes.len() < NETWORK_FILE_MAGIC.len() || &bytes[..8] != NETWORK_FILE_MAGIC {
        return Err(NetworkFileError::NotANetwork {
            path: path.to_owned(),
        });
    }
    if bytes.len() < HEADER_BYTES + CHECKSUM_BYTES {
        return Err(length(format!(
            "cut short: a saved network has at least {} bytes",
            HEADER_BYTES + CHECKSUM_BYTES
        )));
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
    if version == 0 || version > NETWORK_FILE_VERSION {
        return Err(NetworkFileError::Version {
            path: path.to_owned(),
            found: version,
        });
    }
    let body_len = u64::from_le_bytes(bytes[12..20].try_into().expect("8 bytes"));
    let expected = (HEADER_BYTES + CHECKSUM_BYTES) as u64;
    if body_len.checked_add(expected) != Some(size) {
        return Err(length(format!(
            "the header (byte 12) gives a body of {body_len} bytes, so the file should have {} bytes",
            body_len.saturating_add(expected)
        )));
    }
    let (data, stored) = bytes.split_at(bytes.len() - CHECKSUM_BYTES);
    let stored = u32::from_le_bytes(stored.try_into().expect("4 bytes"));
    let computed = crc32fast::hash(data);
    if stored != computed {
        return Err(NetworkFileError::Checksum {
            path: path.to_owned(),
            stored,
            computed,
        });
    }
    ciborium::de::from_reader(&data[HEADER_BYTES..]).map_err(|e| NetworkFileError::Decode {
        path: path.to_owned(),
        reason: e.to_string(),
    })
}
