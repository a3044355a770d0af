//! What the coding readouts hold for every sample of a set ([`EncodedSet`]): the output spike
//! trains every coding can read, plus each coding's own readout ([`SetReadout`]), kept under
//! the coding's key.

use crate::neuron_setup::Precision;
use neurotac_core::MultiSpikeTrain;
use std::any::Any;
use std::fmt::Debug;

/// Where the spatiotemporal coding's Van Rossum distance comes from (`--vr-from`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VrFrom {
    /// The exact distance from the readout's spike trains.
    Exact,
    /// The trace-sampled distance from the readout's synaptic trace record at `trace_dt_s`,
    /// arithmetic in `precision` ([`neurotac_core::distance::trace_sampled`]).
    Traces {
        /// Trace step (s), a whole number of µs.
        trace_dt_s: f64,
        /// `f64` or `f32`.
        precision: Precision,
    },
}

impl VrFrom {
    /// `exact` or `traces (h = 0.1 ms, f64)`.
    pub fn describe(&self) -> String {
        match self {
            VrFrom::Exact => "exact, from the readout's spike trains".into(),
            VrFrom::Traces {
                trace_dt_s,
                precision,
            } => format!(
                "from the readout's synaptic traces at {} ms, {}",
                trace_dt_s * 1e3,
                precision.name()
            ),
        }
    }
}

/// What one coding's readout holds of one sample (a feature row, per-ms bins, a trace
/// record …); a set keeps one per sample, as a `Vec`.
pub trait Readout: Any + Send + Sync + Clone + Debug + PartialEq {}

impl<T: Any + Send + Sync + Clone + Debug + PartialEq> Readout for T {}

/// One coding's readouts of a set of samples, type-erased: a `Vec<T>` of some [`Readout`] `T`,
/// one per sample, in sample order. The coding that wrote it reads it back with
/// [`EncodedSet::readout`].
pub trait SetReadout: Send + Sync + Debug {
    /// Itself, to downcast to its `Vec<T>`.
    fn as_any(&self) -> &dyn Any;
    /// Itself, to downcast to its `Vec<T>`.
    fn as_any_mut(&mut self) -> &mut dyn Any;
    /// A copy.
    fn clone_box(&self) -> Box<dyn SetReadout>;
    /// `true` when `other` is a `Vec` of the same type with equal elements.
    fn same_as(&self, other: &dyn SetReadout) -> bool;
    /// Moves the samples of `other` (a `Vec` of the same type) after its own; `false` when
    /// the types differ (nothing moved).
    fn append(&mut self, other: &mut dyn SetReadout) -> bool;
}

impl<T: Readout> SetReadout for Vec<T> {
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
    fn clone_box(&self) -> Box<dyn SetReadout> {
        Box::new(self.clone())
    }
    fn same_as(&self, other: &dyn SetReadout) -> bool {
        other.as_any().downcast_ref::<Self>() == Some(self)
    }
    fn append(&mut self, other: &mut dyn SetReadout) -> bool {
        match other.as_any_mut().downcast_mut::<Self>() {
            Some(other) => {
                Vec::append(self, other);
                true
            }
            None => false,
        }
    }
}

/// What the coding readouts hold for every sample of a set, with its labels.
#[derive(Debug)]
pub struct EncodedSet {
    /// Class of each sample (empty for an unlabelled set).
    pub labels: Vec<usize>,
    /// Class names (index = label).
    pub class_names: Vec<String>,
    /// Sample duration the readouts cover (ms).
    pub duration_ms: u32,
    /// Channels per sample.
    pub n_channels: usize,
    /// Each sample's output spike trains (what every coding can read).
    pub trains: Vec<MultiSpikeTrain>,
    /// Each coding's own readouts, under its key, in menu order.
    pub readouts: Vec<(&'static str, Box<dyn SetReadout>)>,
    /// How the set was encoded (for the report): the network's path, or "offline".
    pub path: String,
    /// Van Rossum from traces or exact.
    pub vr_from: VrFrom,
    /// Neuron updates the readout network did over every sample
    /// ([`Network::neuron_updates`](neurotac_core::Network::neuron_updates)): 0 offline and
    /// without an afferent layer. A count of work, not of what was read: equality ignores it.
    pub neuron_updates: u64,
}

impl EncodedSet {
    /// The readouts the coding `key` wrote, one `T` per sample; `None` when it wrote none of
    /// that type.
    pub fn readout<T: Readout>(&self, key: &str) -> Option<&[T]> {
        self.readouts
            .iter()
            .find(|(k, _)| *k == key)
            .and_then(|(_, r)| r.as_any().downcast_ref::<Vec<T>>())
            .map(Vec::as_slice)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.trains.len()
    }

    /// `true` without samples.
    pub fn is_empty(&self) -> bool {
        self.trains.is_empty()
    }

    /// Number of classes.
    pub fn n_classes(&self) -> usize {
        self.class_names.len()
    }
}

impl Clone for EncodedSet {
    fn clone(&self) -> Self {
        Self {
            labels: self.labels.clone(),
            class_names: self.class_names.clone(),
            duration_ms: self.duration_ms,
            n_channels: self.n_channels,
            trains: self.trains.clone(),
            readouts: (self.readouts.iter())
                .map(|(k, r)| (*k, r.clone_box()))
                .collect(),
            path: self.path.clone(),
            vr_from: self.vr_from,
            neuron_updates: self.neuron_updates,
        }
    }
}

impl PartialEq for EncodedSet {
    fn eq(&self, other: &Self) -> bool {
        self.labels == other.labels
            && self.class_names == other.class_names
            && self.duration_ms == other.duration_ms
            && self.n_channels == other.n_channels
            && self.trains == other.trains
            && self.readouts.len() == other.readouts.len()
            && (self.readouts.iter().zip(&other.readouts))
                .all(|((a, x), (b, y))| a == b && x.same_as(y.as_ref()))
            && self.path == other.path
            && self.vr_from == other.vr_from
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_set_readout_is_read_back_as_its_own_type_only() {
        let mut a: Box<dyn SetReadout> = Box::new(vec![1.0f64, 2.0]);
        let mut b: Box<dyn SetReadout> = Box::new(vec![3.0f64]);
        assert!(a.append(b.as_mut()));
        assert!(a.same_as(&vec![1.0f64, 2.0, 3.0]));
        let mut wrong: Box<dyn SetReadout> = Box::new(vec![3u32]);
        assert!(!a.append(wrong.as_mut()));
        assert!(!a.same_as(wrong.as_ref()));
        assert!(a.as_any().downcast_ref::<Vec<u32>>().is_none());
    }
}
