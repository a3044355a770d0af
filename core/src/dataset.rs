//! Labelled collections of multi-channel spike trains, saved as JSON or compact binary.
//!
//! A [`SpikeDataset`] is what transduction produces and what the codings and the KNN head
//! consume: one [`MultiSpikeTrain`] per observation (e.g. 49 taxel trains per slide), a class
//! label per observation, the class names and free-form metadata.
//!
//! # JSON form
//! ```json
//! {"labels": [0, 1], "class_names": ["smooth", "5 mm"],
//!  "observations": [[[0.012, 0.5], [], …], …], "meta": {"sensor": "neurotac-sim"}}
//! ```
//! Times are seconds. `observations` is required; `labels`, `class_names` and `meta` may be
//! absent (an unlabelled dataset). Errors give the line and column, and inside `observations`
//! the observation, channel and spike (see [`SpikeDataset::from_json_str`]). In either form a
//! dataset has at most [`MAX_CLASSES`] (1024) classes: labels below it, no more class names.
//!
//! # Typed metadata
//! `meta` is free-form JSON, except for the fields read through typed accessors, which are
//! checked whenever a dataset is built or read:
//!
//! | field | accessor | meaning |
//! |---|---|---|
//! | `duration_s` | [`SpikeDataset::duration_s`] | length of every sample (s, > 0); spikes lie in `[0, duration_s)`. Absent in older files: readers then take one ms past the latest spike |
//!
//! # Binary form
//! Little-endian: magic `NTSPIKES`, `u32` version (2), `u64` number of observations, `u64`
//! number of class names, each name as `u64` length + UTF-8, the metadata as `u64` length +
//! JSON text, `u8` 1 if labels follow then one `u64` label per observation, per
//! observation a `u64` channel count, one `u64` spike count per channel and the `f64` times,
//! and last a `u32` CRC-32 (IEEE, as zlib's `crc32`) of every byte before it. The checksum is
//! verified before anything else is decoded, so a flipped bit is a
//! [`DatasetError::Checksum`] naming the file, never a silently different dataset. Version 1
//! (the same layout without the checksum) still reads. Every length is checked against the
//! bytes left before anything is allocated. A spike time that is not finite or comes before the
//! previous one in its channel is a [`DatasetError::Spikes`] naming the observation, the channel,
//! the spike and its byte offset.
//!
//! Both forms are written through [`crate::io::AtomicFile`]: a failed or interrupted save
//! leaves the old file (or none), never a truncated one.

use crate::error::{DatasetError, FilePosition};
use crate::spikes::{MultiSpikeTrain, check_spike};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

mod json;

/// Observations (multi-channel spike trains), their class labels, class names and metadata.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpikeDataset {
    labels: Vec<usize>,
    class_names: Vec<String>,
    observations: Vec<MultiSpikeTrain>,
    meta: serde_json::Map<String, serde_json::Value>,
}

/// The first bytes of the binary form.
pub(crate) const MAGIC: &[u8; 8] = b"NTSPIKES";
/// The most classes a dataset may have: labels lie in `0..MAX_CLASSES` and there are at most
/// this many class names. Per-class tables (class means, a confusion matrix of
/// `MAX_CLASSES²` counts) are sized by [`SpikeDataset::n_classes`], so a corrupt label cannot
/// make them huge.
pub const MAX_CLASSES: usize = 1024;
/// The metadata key of [`SpikeDataset::duration_s`].
pub const DURATION_S_KEY: &str = "duration_s";
/// The version written: the layout of version 1 followed by a CRC-32.
pub(crate) const VERSION: u32 = 2;
/// The first version, without a checksum (still read).
pub(crate) const VERSION_WITHOUT_CHECKSUM: u32 = 1;
/// Bytes of the trailing CRC-32.
const CHECKSUM_BYTES: usize = 4;

impl SpikeDataset {
    /// Builds a dataset, checking that labels (if any) match the observations one to one, that
    /// there are at most [`MAX_CLASSES`] classes (labels below it, no more class names), that
    /// every label has a class name (when names are given) and that all observations have the
    /// same number of channels.
    pub fn new(
        observations: Vec<MultiSpikeTrain>,
        labels: Vec<usize>,
        class_names: Vec<String>,
        meta: serde_json::Map<String, serde_json::Value>,
    ) -> Result<Self, DatasetError> {
        if !labels.is_empty() && labels.len() != observations.len() {
            return Err(DatasetError::LabelCount {
                labels: labels.len(),
                observations: observations.len(),
            });
        }
        if class_names.len() > MAX_CLASSES {
            return Err(DatasetError::TooManyClassNames {
                names: class_names.len(),
                max: MAX_CLASSES,
            });
        }
        if let Some((observation, &label)) =
            labels.iter().enumerate().find(|(_, l)| **l >= MAX_CLASSES)
        {
            return Err(DatasetError::LabelBeyondLimit {
                observation,
                label,
                max: MAX_CLASSES,
            });
        }
        if !class_names.is_empty()
            && let Some((observation, &label)) = labels
                .iter()
                .enumerate()
                .find(|(_, l)| **l >= class_names.len())
        {
            return Err(DatasetError::LabelOutOfRange {
                observation,
                label,
                n_classes: class_names.len(),
            });
        }
        if let Some(first) = observations.first() {
            let expected = first.n_channels();
            if let Some((observation, o)) = observations
                .iter()
                .enumerate()
                .find(|(_, o)| o.n_channels() != expected)
            {
                return Err(DatasetError::ChannelCount {
                    observation,
                    expected,
                    got: o.n_channels(),
                });
            }
        }
        if let Some(value) = meta.get(DURATION_S_KEY) {
            duration_from_json(value)?;
        }
        Ok(Self {
            labels,
            class_names,
            observations,
            meta,
        })
    }

    /// The length of every sample (s), when the dataset states it (`meta.duration_s`).
    pub fn duration_s(&self) -> Option<f64> {
        self.meta.get(DURATION_S_KEY).and_then(|v| v.as_f64())
    }

    /// States the length of every sample (s): finite and > 0, else [`DatasetError::Meta`].
    pub fn set_duration_s(&mut self, duration_s: f64) -> Result<(), DatasetError> {
        let value = serde_json::Value::from(duration_s);
        duration_from_json(&value)?;
        self.meta.insert(DURATION_S_KEY.into(), value);
        Ok(())
    }

    /// An unlabelled dataset.
    pub fn unlabelled(observations: Vec<MultiSpikeTrain>) -> Result<Self, DatasetError> {
        Self::new(observations, Vec::new(), Vec::new(), serde_json::Map::new())
    }

    /// The observations.
    pub fn observations(&self) -> &[MultiSpikeTrain] {
        &self.observations
    }

    /// One label per observation, or empty when unlabelled.
    pub fn labels(&self) -> &[usize] {
        &self.labels
    }

    /// The class names (index = label); may be empty.
    pub fn class_names(&self) -> &[String] {
        &self.class_names
    }

    /// Number of classes: the number of names, or one more than the largest label; at most
    /// [`MAX_CLASSES`].
    pub fn n_classes(&self) -> usize {
        let from_labels = self.labels.iter().max().map_or(0, |m| m + 1);
        self.class_names.len().max(from_labels)
    }

    /// Free-form metadata.
    pub fn meta(&self) -> &serde_json::Map<String, serde_json::Value> {
        &self.meta
    }

    /// Mutable metadata.
    pub fn meta_mut(&mut self) -> &mut serde_json::Map<String, serde_json::Value> {
        &mut self.meta
    }

    /// Number of observations.
    pub fn len(&self) -> usize {
        self.observations.len()
    }

    /// `true` when there is no observation.
    pub fn is_empty(&self) -> bool {
        self.observations.is_empty()
    }

    /// Channels per observation (0 for an empty dataset).
    pub fn n_channels(&self) -> usize {
        self.observations
            .first()
            .map_or(0, MultiSpikeTrain::n_channels)
    }

    /// Parses the JSON form from text; `path` only names the source in errors.
    ///
    /// Errors keep serde_json's line and column, and an error inside `observations` names the
    /// observation, channel and spike: an invalid time (out of order, or `NaN`, `Infinity`,
    /// `1e999`) is a [`DatasetError::Spikes`], anything else a [`DatasetError::Json`].
    pub fn from_json_str(text: &str, path: &Path) -> Result<Self, DatasetError> {
        let raw = json::parse(text, path)?;
        Self::new(raw.observations, raw.labels, raw.class_names, raw.meta)
    }

    /// The JSON form as text.
    pub fn to_json_string(&self) -> String {
        serde_json::to_string(self).expect("a dataset of finite floats always serialises")
    }

    /// Writes the JSON form to `path`, replacing an existing file (a command's outputs that
    /// must not replace one are written through [`crate::io::AtomicFile`] with
    /// [`crate::io::Replace::No`] instead).
    pub fn save_json(&self, path: impl AsRef<Path>) -> Result<(), DatasetError> {
        write_file(path.as_ref(), self.to_json_string().as_bytes())
    }

    /// Writes the compact binary form to `path`, replacing an existing file (as
    /// [`save_json`](Self::save_json)).
    pub fn save_binary(&self, path: impl AsRef<Path>) -> Result<(), DatasetError> {
        write_file(path.as_ref(), &self.to_binary())
    }

    /// Reads a dataset in either form; the binary magic decides which
    /// ([`from_bytes`](Self::from_bytes)).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, DatasetError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| DatasetError::Io {
            path: path.to_owned(),
            action: crate::error::IoAction::Read,
            source,
        })?;
        Self::from_bytes(&bytes, path)
    }

    /// Decodes a file's bytes in either form: the binary form when they start with its magic,
    /// else the JSON form (UTF-8 text); `path` only names the source in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, DatasetError> {
        if bytes.starts_with(MAGIC) {
            Self::from_binary(bytes, path)
        } else {
            let text = std::str::from_utf8(bytes).map_err(|e| DatasetError::Binary {
                path: path.to_owned(),
                offset: e.valid_up_to(),
                what: "neither the binary dataset magic nor UTF-8 JSON text".into(),
            })?;
            Self::from_json_str(text, path)
        }
    }

    /// The compact binary form (see the module docs).
    pub fn to_binary(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(
            64 + 8 * self
                .observations
                .iter()
                .map(|o| o.total_spikes() + o.n_channels())
                .sum::<usize>(),
        );
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        put_u64(&mut out, self.observations.len());
        put_u64(&mut out, self.class_names.len());
        for name in &self.class_names {
            put_u64(&mut out, name.len());
            out.extend_from_slice(name.as_bytes());
        }
        let meta = serde_json::to_string(&self.meta).expect("JSON values always serialise");
        put_u64(&mut out, meta.len());
        out.extend_from_slice(meta.as_bytes());
        out.push(u8::from(!self.labels.is_empty()));
        for &l in &self.labels {
            put_u64(&mut out, l);
        }
        for o in &self.observations {
            put_u64(&mut out, o.n_channels());
            for c in 0..o.n_channels() {
                put_u64(&mut out, o.count(c));
            }
            for &t in o.flat_times() {
                out.extend_from_slice(&t.to_le_bytes());
            }
        }
        let crc = crc32fast::hash(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        out
    }

    /// Decodes the compact binary form; `path` only names the source in errors.
    pub fn from_binary(bytes: &[u8], path: &Path) -> Result<Self, DatasetError> {
        let mut r = ByteReader {
            bytes,
            pos: 0,
            path,
        };
        if r.take(8, "magic")? != MAGIC {
            return Err(r.error(0, "not a neurotac binary spike dataset (bad magic)"));
        }
        let version = u32::from_le_bytes(r.take(4, "version")?.try_into().expect("4 bytes"));
        match version {
            VERSION => {
                let body_len = bytes
                    .len()
                    .checked_sub(CHECKSUM_BYTES)
                    .ok_or_else(|| r.error(bytes.len(), "truncated: the checksum needs 4 bytes"))?;
                let (body, stored) = bytes.split_at(body_len);
                let stored = u32::from_le_bytes(stored.try_into().expect("4 bytes"));
                let computed = crc32fast::hash(body);
                if stored != computed {
                    return Err(DatasetError::Checksum {
                        path: path.to_owned(),
                        stored,
                        computed,
                    });
                }
                r.bytes = body;
            }
            VERSION_WITHOUT_CHECKSUM => {}
            _ => {
                return Err(r.error(
                    8,
                    &format!(
                        "unsupported version {version} (expected {VERSION_WITHOUT_CHECKSUM} or {VERSION})"
                    ),
                ));
            }
        }
        let n_obs = r.count(8, "observation count")?;
        let n_classes = r.count(8, "class-name count")?;
        let mut class_names = Vec::with_capacity(n_classes);
        for _ in 0..n_classes {
            let len = r.count(1, "class-name length")?;
            let at = r.pos;
            let s = std::str::from_utf8(r.take(len, "class name")?)
                .map_err(|_| r.error(at, "class name is not UTF-8"))?;
            class_names.push(s.to_owned());
        }
        let meta_len = r.count(1, "metadata length")?;
        let at = r.pos;
        let meta = serde_json::from_slice(r.take(meta_len, "metadata")?)
            .map_err(|e| r.error(at, &format!("metadata is not a JSON object: {e}")))?;
        let labelled = r.take(1, "label flag")?[0];
        let mut labels = Vec::new();
        if labelled == 1 {
            if n_obs > r.remaining() / 8 {
                return Err(r.error(r.pos, "labels exceed the bytes left in the file"));
            }
            for _ in 0..n_obs {
                // A label beyond MAX_CLASSES is refused by `new`, naming its observation.
                let l = r.u64("label")?;
                labels.push(usize::try_from(l).unwrap_or(usize::MAX));
            }
        } else if labelled != 0 {
            return Err(r.error(r.pos - 1, "label flag must be 0 or 1"));
        }
        let mut observations = Vec::with_capacity(n_obs.min(bytes.len() / 8));
        for observation in 0..n_obs {
            let n_channels = r.count(8, "channel count")?;
            let mut offsets = Vec::with_capacity(n_channels + 1);
            offsets.push(0usize);
            for _ in 0..n_channels {
                let c = r.count(8, "spike count")?;
                let total = offsets.last().copied().unwrap_or(0).saturating_add(c);
                offsets.push(total);
            }
            let total = *offsets.last().expect("offsets start with 0");
            if total > r.remaining() / 8 {
                return Err(r.error(r.pos, "spike counts exceed the bytes left in the file"));
            }
            let times_at = r.pos;
            let times: Vec<f64> = (0..total).map(|_| r.f64()).collect();
            for (channel, w) in offsets.windows(2).enumerate() {
                let mut previous = f64::NEG_INFINITY;
                for (index, &t) in times[w[0]..w[1]].iter().enumerate() {
                    check_spike(channel, index, previous, t).map_err(|source| {
                        DatasetError::Spikes {
                            observation,
                            position: Some(FilePosition::Byte {
                                offset: times_at + 8 * (w[0] + index),
                            }),
                            source,
                        }
                    })?;
                    previous = t;
                }
            }
            // Offsets from the counts (0, running sums, the total), every channel checked.
            observations.push(MultiSpikeTrain::from_checked_parts(times, offsets));
        }
        if r.remaining() != 0 {
            return Err(r.error(r.pos, "trailing bytes after the last observation"));
        }
        Self::new(observations, labels, class_names, meta)
    }
}

fn put_u64(out: &mut Vec<u8>, v: usize) {
    out.extend_from_slice(&(v as u64).to_le_bytes());
}

/// Writes `bytes` to `path` atomically (old content or nothing on failure), replacing it.
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), DatasetError> {
    crate::io::write(path, bytes, crate::io::Replace::Yes).map_err(|source| DatasetError::Io {
        path: path.to_owned(),
        action: crate::error::IoAction::Write,
        source,
    })
}

/// A bounds-checked little-endian cursor.
struct ByteReader<'a> {
    bytes: &'a [u8],
    pos: usize,
    path: &'a Path,
}

impl<'a> ByteReader<'a> {
    fn error(&self, offset: usize, what: &str) -> DatasetError {
        DatasetError::Binary {
            path: PathBuf::from(self.path),
            offset,
            what: what.to_owned(),
        }
    }

    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], DatasetError> {
        if n > self.remaining() {
            return Err(self.error(self.pos, &format!("truncated: {what} needs {n} bytes")));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn u64(&mut self, what: &str) -> Result<u64, DatasetError> {
        Ok(u64::from_le_bytes(
            self.take(8, what)?.try_into().expect("8 bytes"),
        ))
    }

    /// Reads a `u64` count and checks that `count × unit_bytes` bytes can still follow.
    fn count(&mut self, unit_bytes: usize, what: &str) -> Result<usize, DatasetError> {
        let at = self.pos;
        let n = self.u64(what)?;
        let fits = usize::try_from(n).ok().filter(|&n| {
            n.checked_mul(unit_bytes)
                .is_some_and(|b| b <= self.remaining())
        });
        fits.ok_or_else(|| {
            self.error(
                at,
                &format!("{what} {n} exceeds the bytes left in the file"),
            )
        })
    }

    /// Reads an `f64`; only called after the caller checked the bytes are there.
    fn f64(&mut self) -> f64 {
        let s = &self.bytes[self.pos..self.pos + 8];
        self.pos += 8;
        f64::from_le_bytes(s.try_into().expect("8 bytes"))
    }
}

/// A `duration_s` metadata value, checked: a finite number > 0.
fn duration_from_json(value: &serde_json::Value) -> Result<f64, DatasetError> {
    match value.as_f64() {
        Some(d) if d.is_finite() && d > 0.0 => Ok(d),
        _ => Err(DatasetError::Meta {
            field: DURATION_S_KEY,
            value: value.to_string(),
            expected: "a finite number of seconds > 0",
        }),
    }
}

#[cfg(test)]
mod tests;
