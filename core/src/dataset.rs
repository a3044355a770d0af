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
//! absent (an unlabelled dataset).
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
//! bytes left before anything is allocated.
//!
//! Both forms are written through [`crate::io::AtomicFile`]: a failed or interrupted save
//! leaves the old file (or none), never a truncated one.

use crate::error::DatasetError;
use crate::spikes::MultiSpikeTrain;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Observations (multi-channel spike trains), their class labels, class names and metadata.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpikeDataset {
    labels: Vec<usize>,
    class_names: Vec<String>,
    observations: Vec<MultiSpikeTrain>,
    meta: serde_json::Map<String, serde_json::Value>,
}

/// The on-disk JSON shape, with the optional fields defaulted.
#[derive(Deserialize)]
struct JsonDataset {
    #[serde(default)]
    labels: Vec<usize>,
    #[serde(default)]
    class_names: Vec<String>,
    observations: Vec<serde_json::Value>,
    #[serde(default)]
    meta: serde_json::Map<String, serde_json::Value>,
}

const MAGIC: &[u8; 8] = b"NTSPIKES";
/// The metadata key of [`SpikeDataset::duration_s`].
pub const DURATION_S_KEY: &str = "duration_s";
/// The version written: the layout of version 1 followed by a CRC-32.
const VERSION: u32 = 2;
/// The first version, without a checksum (still read).
const VERSION_WITHOUT_CHECKSUM: u32 = 1;
/// Bytes of the trailing CRC-32.
const CHECKSUM_BYTES: usize = 4;

impl SpikeDataset {
    /// Builds a dataset, checking that labels (if any) match the observations one to one, that
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
        if !class_names.is_empty() {
            if let Some((observation, &label)) = labels
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

    /// Number of classes: the number of names, or one more than the largest label.
    pub fn n_classes(&self) -> usize {
        let from_labels = self.labels.iter().max().map_or(0, |m| m.saturating_add(1));
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
    pub fn from_json_str(text: &str, path: &Path) -> Result<Self, DatasetError> {
        let json_err = |source| DatasetError::Json {
            path: path.to_owned(),
            source,
        };
        let raw: JsonDataset = serde_json::from_str(text).map_err(json_err)?;
        let mut observations = Vec::with_capacity(raw.observations.len());
        for (observation, value) in raw.observations.into_iter().enumerate() {
            let channels: Vec<Vec<f64>> = serde_json::from_value(value).map_err(json_err)?;
            let trains = MultiSpikeTrain::from_channels(&channels).map_err(|source| {
                DatasetError::Spikes {
                    observation,
                    source,
                }
            })?;
            observations.push(trains);
        }
        Self::new(observations, raw.labels, raw.class_names, raw.meta)
    }

    /// The JSON form as text.
    pub fn to_json_string(&self) -> String {
        serde_json::to_string(self).expect("a dataset of finite floats always serialises")
    }

    /// Writes the JSON form to `path`.
    pub fn save_json(&self, path: impl AsRef<Path>) -> Result<(), DatasetError> {
        write_file(path.as_ref(), self.to_json_string().as_bytes())
    }

    /// Writes the compact binary form to `path`.
    pub fn save_binary(&self, path: impl AsRef<Path>) -> Result<(), DatasetError> {
        write_file(path.as_ref(), &self.to_binary())
    }

    /// Reads a dataset in either form; the binary magic decides which.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, DatasetError> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| DatasetError::Io {
            path: path.to_owned(),
            source,
        })?;
        if bytes.starts_with(MAGIC) {
            Self::from_binary(&bytes, path)
        } else {
            let text = std::str::from_utf8(&bytes).map_err(|e| DatasetError::Binary {
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
                let at = r.pos;
                let l = r.u64("label")?;
                let l = u32::try_from(l)
                    .map_err(|_| r.error(at, &format!("label {l} is not a class index")))?;
                labels.push(l as usize);
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
            let times: Vec<f64> = (0..total).map(|_| r.f64()).collect();
            let trains = MultiSpikeTrain::from_parts(times, offsets).map_err(|source| {
                DatasetError::Spikes {
                    observation,
                    source,
                }
            })?;
            observations.push(trains);
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

/// Writes `bytes` to `path` atomically (old content or nothing on failure).
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), DatasetError> {
    crate::io::write(path, bytes).map_err(|source| DatasetError::Io {
        path: path.to_owned(),
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
mod tests {
    use super::*;

    #[test]
    fn duration_is_typed_metadata_that_old_files_may_lack() {
        let mut d = sample();
        assert_eq!(d.duration_s(), None);
        d.set_duration_s(4.5).unwrap();
        assert_eq!(d.duration_s(), Some(4.5));
        let back = SpikeDataset::from_binary(&d.to_binary(), Path::new("x.bin")).unwrap();
        assert_eq!(back.duration_s(), Some(4.5));
        assert!(matches!(
            d.set_duration_s(f64::NAN),
            Err(DatasetError::Meta {
                field: "duration_s",
                ..
            })
        ));
        let bad = r#"{"observations":[[[0.1]]],"meta":{"duration_s":"long"}}"#;
        let e = SpikeDataset::from_json_str(bad, Path::new("bad.json")).unwrap_err();
        assert_eq!(
            e.to_string(),
            r#"meta.duration_s = "long": a finite number of seconds > 0"#
        );
    }

    fn sample() -> SpikeDataset {
        let obs = vec![
            MultiSpikeTrain::from_channels(vec![vec![0.001, 0.5], vec![]]).unwrap(),
            MultiSpikeTrain::from_channels(vec![vec![], vec![0.25, 0.25, 4.5]]).unwrap(),
        ];
        let mut meta = serde_json::Map::new();
        meta.insert("sensor".into(), "neurotac-sim".into());
        SpikeDataset::new(obs, vec![1, 0], vec!["smooth".into(), "5 mm".into()], meta).unwrap()
    }

    #[test]
    fn json_has_the_documented_shape_and_round_trips() {
        let d = sample();
        let text = d.to_json_string();
        assert_eq!(
            text,
            r#"{"labels":[1,0],"class_names":["smooth","5 mm"],"observations":[[[0.001,0.5],[]],[[],[0.25,0.25,4.5]]],"meta":{"sensor":"neurotac-sim"}}"#
        );
        let back = SpikeDataset::from_json_str(&text, Path::new("x.json")).unwrap();
        assert_eq!(back, d);
    }

    #[test]
    fn json_round_trips_full_precision_times_bit_for_bit() {
        // Times with all 17 significant digits (serde_json's exact float parsing is required).
        let channels: Vec<Vec<f64>> = (0..49)
            .map(|c| {
                (1..30)
                    .map(|k| (k as f64 * 0.1 + c as f64 * 1e-3).sqrt() / 3.0)
                    .collect()
            })
            .collect();
        let d = SpikeDataset::unlabelled(vec![MultiSpikeTrain::from_channels(&channels).unwrap()])
            .unwrap();
        let back = SpikeDataset::from_json_str(&d.to_json_string(), Path::new("x")).unwrap();
        let bits = |d: &SpikeDataset| {
            d.observations()[0]
                .flat_times()
                .iter()
                .map(|t| t.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&back), bits(&d));
    }

    #[test]
    fn json_with_only_observations_is_accepted() {
        let d = SpikeDataset::from_json_str(
            r#"{"observations": [[[0.1], [0.2, 0.3]]]}"#,
            Path::new("o.json"),
        )
        .unwrap();
        assert_eq!(d.len(), 1);
        assert!(d.labels().is_empty());
        assert_eq!(d.n_channels(), 2);
    }

    #[test]
    fn json_errors_name_the_observation_and_the_problem() {
        let e = SpikeDataset::from_json_str(
            r#"{"observations": [[[0.1]], [[0.3, 0.2]]]}"#,
            Path::new("d.json"),
        )
        .unwrap_err();
        assert!(
            matches!(e, DatasetError::Spikes { observation: 1, .. }),
            "{e}"
        );
        let e = SpikeDataset::from_json_str(
            r#"{"observations": [[[0.1]], [[0.2], []]]}"#,
            Path::new("d.json"),
        )
        .unwrap_err();
        assert!(matches!(
            e,
            DatasetError::ChannelCount {
                observation: 1,
                expected: 1,
                got: 2
            }
        ));
        let e = SpikeDataset::from_json_str(
            r#"{"labels": [0], "observations": []}"#,
            Path::new("d.json"),
        )
        .unwrap_err();
        assert!(matches!(
            e,
            DatasetError::LabelCount {
                labels: 1,
                observations: 0
            }
        ));
        let e = SpikeDataset::from_json_str(
            r#"{"labels": [2], "class_names": ["a"], "observations": [[[]]]}"#,
            Path::new("d.json"),
        )
        .unwrap_err();
        assert!(matches!(
            e,
            DatasetError::LabelOutOfRange {
                observation: 0,
                label: 2,
                n_classes: 1
            }
        ));
        let e = SpikeDataset::from_json_str(r#"{"labels": []}"#, Path::new("d.json")).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("d.json: invalid spike-dataset JSON"),
            "{e}"
        );
    }

    #[test]
    fn binary_round_trips_and_files_load_by_magic() {
        let d = sample();
        let dir = tempfile::tempdir().unwrap();
        let (bin, json) = (dir.path().join("d.ntspk"), dir.path().join("d.json"));
        d.save_binary(&bin).unwrap();
        d.save_json(&json).unwrap();
        assert_eq!(SpikeDataset::load(&bin).unwrap(), d);
        assert_eq!(SpikeDataset::load(&json).unwrap(), d);
        // On realistic data (49 taxels, full-precision times) the binary form is the compact one.
        let slide = MultiSpikeTrain::from_channels((0..49).map(|c| {
            (0..40)
                .map(|i| (c * 40 + i) as f64 * 1.234_567e-3)
                .collect::<Vec<_>>()
        }))
        .unwrap();
        let big = SpikeDataset::unlabelled(vec![slide]).unwrap();
        assert!(big.to_binary().len() < big.to_json_string().len());
    }

    /// The version-1 form of a dataset (no checksum), as files written before the format had a
    /// checksum hold it.
    fn version_1(d: &SpikeDataset) -> Vec<u8> {
        let mut bytes = d.to_binary();
        bytes.truncate(bytes.len() - CHECKSUM_BYTES);
        bytes[8..12].copy_from_slice(&VERSION_WITHOUT_CHECKSUM.to_le_bytes());
        bytes
    }

    #[test]
    fn every_one_bit_flip_is_a_checksum_error_naming_the_file() {
        let bytes = sample().to_binary();
        assert_eq!(&bytes[8..12], &VERSION.to_le_bytes());
        // Past magic and version, every flipped bit is caught by the checksum.
        for byte in 12..bytes.len() {
            for bit in 0..8 {
                let mut flipped = bytes.clone();
                flipped[byte] ^= 1 << bit;
                match SpikeDataset::from_binary(&flipped, Path::new("cache/a.bin")) {
                    Err(e @ DatasetError::Checksum { .. }) => {
                        assert!(e.to_string().starts_with("cache/a.bin: checksum mismatch"))
                    }
                    other => panic!("byte {byte} bit {bit}: {other:?}"),
                }
            }
        }
        for cut in 0..bytes.len() {
            assert!(
                SpikeDataset::from_binary(&bytes[..cut], Path::new("t")).is_err(),
                "cut {cut}"
            );
        }
        // In the magic or the version it is a typed error too.
        for byte in 0..12 {
            let mut flipped = bytes.clone();
            flipped[byte] ^= 1;
            assert!(SpikeDataset::from_binary(&flipped, Path::new("a")).is_err());
        }
    }

    #[test]
    fn version_1_files_without_a_checksum_still_load() {
        let d = sample();
        let old = version_1(&d);
        assert_eq!(SpikeDataset::from_binary(&old, Path::new("v1")).unwrap(), d);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("v1.bin");
        std::fs::write(&path, &old).unwrap();
        assert_eq!(SpikeDataset::load(&path).unwrap(), d);
    }

    #[test]
    fn corrupt_binary_is_a_typed_error_never_a_huge_allocation() {
        // Version 1 has no checksum: its structural checks are what guards it.
        let bytes = version_1(&sample());
        // Every truncation fails cleanly.
        for cut in 0..bytes.len() {
            assert!(
                SpikeDataset::from_binary(&bytes[..cut], Path::new("t")).is_err(),
                "cut {cut}"
            );
        }
        // An observation count of 2⁶³ is rejected before allocating.
        let mut huge = bytes.clone();
        huge[12..20].copy_from_slice(&(1u64 << 63).to_le_bytes());
        match SpikeDataset::from_binary(&huge, Path::new("h")) {
            Err(DatasetError::Binary {
                offset: 12, what, ..
            }) => assert!(what.contains("observation count")),
            other => panic!("{other:?}"),
        }
        // A spike count beyond the file is rejected.
        let mut counts = bytes.clone();
        let n = counts.len();
        counts[n - 8 * 3 - 8..n - 8 * 3].copy_from_slice(&(u64::MAX / 2).to_le_bytes());
        assert!(SpikeDataset::from_binary(&counts, Path::new("c")).is_err());
        let mut trailing = bytes;
        trailing.push(0);
        assert!(SpikeDataset::from_binary(&trailing, Path::new("t")).is_err());
    }
}
