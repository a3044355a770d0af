//! Outputs for numpy: `.npy` matrices and `.npz` archives of matrices and spike datasets.
//!
//! The output format follows the file's extension ([`OutputFormat::from_path`]); an extension a
//! command does not write is an error naming the file and the ones it does. Every file is
//! written through a temporary file beside the target and renamed when complete.
//!
//! An `.npz` is numpy's format: a zip archive (stored, uncompressed, as `numpy.savez` writes)
//! of `.npy` arrays, read with `numpy.load(path)`. A spike dataset ([`dataset_npz_bytes`])
//! holds flat arrays and one JSON member:
//!
//! | member | dtype, shape | what |
//! |---|---|---|
//! | `times` | float64, (S,) | every spike time (s), sample by sample, unit by unit |
//! | `units` | uint32, (S,) | the unit (taxel) of each spike |
//! | `offsets` | int64, (N+1,) | sample `i`'s spikes are `times[offsets[i]:offsets[i+1]]` |
//! | `labels` | int64, (N,) | class index of each sample (empty when unlabelled) |
//! | `meta.json` | bytes | `{"format", "n_units", "class_names", "meta"}` — `json.loads(np.load(p)["meta.json"])` |

use ndarray::{Array1, ArrayView2};
use ndarray_npy::WriteNpyExt;
use neurotac_core::SpikeDataset;
pub use neurotac_core::io::Replace;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The `format` entry of a dataset archive's `meta.json`.
pub const DATASET_NPZ_FORMAT: &str = "neurotac-spike-dataset-npz/1";

/// A failed export.
#[derive(Debug, Error)]
pub enum ExportError {
    /// The file's extension names no format the command writes.
    #[error("{path}: unknown output extension (this command writes {accepted})", path = .path.display())]
    UnknownExtension {
        /// The output file.
        path: PathBuf,
        /// The extensions accepted, e.g. ".json, .npy or .npz".
        accepted: String,
    },
    /// Writing failed.
    #[error("cannot write {path}", path = .path.display())]
    Io {
        /// The output file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: io::Error,
    },
}

/// What an output file holds, by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    /// `.json`.
    Json,
    /// `.npy`: one numpy array.
    Npy,
    /// `.npz`: numpy arrays in a zip archive.
    Npz,
    /// `.bin` (or `.ntspk`): neurotac's binary spike dataset.
    Binary,
}

impl OutputFormat {
    /// The extensions of the format, without their dot, the usual one first.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            OutputFormat::Json => &["json"],
            OutputFormat::Npy => &["npy"],
            OutputFormat::Npz => &["npz"],
            OutputFormat::Binary => &["bin", "ntspk"],
        }
    }

    /// The format of `path`'s extension (case-insensitive) among `accepted`.
    pub fn from_path(path: &Path, accepted: &[OutputFormat]) -> Result<Self, ExportError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        accepted
            .iter()
            .copied()
            .find(|f| f.extensions().iter().any(|&n| ext.as_deref() == Some(n)))
            .ok_or_else(|| ExportError::UnknownExtension {
                path: path.to_owned(),
                accepted: list(accepted),
            })
    }
}

/// ".json, .npy or .npz".
fn list(formats: &[OutputFormat]) -> String {
    let names: Vec<String> = formats
        .iter()
        .flat_map(|f| f.extensions().iter().map(|e| format!(".{e}")))
        .collect();
    match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => "nothing".to_owned(),
    }
}

fn io_error(path: &Path) -> impl FnOnce(io::Error) -> ExportError + '_ {
    move |source| ExportError::Io {
        path: path.to_owned(),
        source,
    }
}

/// `array` in `.npy` bytes.
fn npy_bytes(array: &impl WriteNpyExt) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    array
        .write_npy(&mut bytes)
        .map_err(|e| io::Error::other(e.to_string()))?;
    Ok(bytes)
}

/// The formats a matrix is written in ([`write_matrix`]).
pub const MATRIX_FORMATS: [OutputFormat; 3] =
    [OutputFormat::Json, OutputFormat::Npy, OutputFormat::Npz];

/// Writes a matrix in the format of `path`'s extension ([`MATRIX_FORMATS`]): `.json` as
/// `{"matrix": [[…], …]}`, `.npy` as one float64 array, `.npz` as an archive with the member
/// `matrix`. `replace` decides whether an existing file may be replaced ([`Replace`]).
pub fn write_matrix(
    path: &Path,
    matrix: ArrayView2<f64>,
    replace: Replace,
) -> Result<(), ExportError> {
    match OutputFormat::from_path(path, &MATRIX_FORMATS)? {
        OutputFormat::Npy => write_npy(path, matrix, replace),
        OutputFormat::Npz => write_npz(path, &[("matrix", matrix)], replace),
        _ => {
            let rows: Vec<Vec<f64>> = matrix.outer_iter().map(|r| r.to_vec()).collect();
            let text = serde_json::json!({ "matrix": rows }).to_string();
            neurotac_core::io::write(path, text, replace).map_err(io_error(path))
        }
    }
}

/// Writes one matrix as `.npy` (float64, C order).
pub fn write_npy(
    path: &Path,
    matrix: ArrayView2<f64>,
    replace: Replace,
) -> Result<(), ExportError> {
    let bytes = npy_bytes(&matrix).map_err(io_error(path))?;
    neurotac_core::io::write(path, bytes, replace).map_err(io_error(path))
}

/// Writes named members into an `.npz` archive: `.npy` arrays (`name` gets the `.npy`
/// suffix numpy expects) and raw files (`name` as given).
pub struct NpzMembers {
    members: Vec<(String, Vec<u8>)>,
}

impl NpzMembers {
    /// No members yet.
    pub fn new() -> Self {
        Self {
            members: Vec::new(),
        }
    }

    /// Adds the array `name` (read back as `np.load(path)[name]`).
    pub fn array(mut self, name: &str, array: &impl WriteNpyExt) -> io::Result<Self> {
        self.members
            .push((format!("{name}.npy"), npy_bytes(array)?));
        Ok(self)
    }

    /// Adds a raw member (numpy returns its bytes).
    pub fn raw(mut self, name: &str, bytes: Vec<u8>) -> Self {
        self.members.push((name.to_owned(), bytes));
        self
    }

    /// The archive's bytes.
    pub fn into_bytes(self) -> io::Result<Vec<u8>> {
        let mut zip = zip::ZipWriter::new(io::Cursor::new(Vec::new()));
        // Stored, with zip64 only where a member needs it, as numpy.savez writes.
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored);
        for (name, bytes) in &self.members {
            let options = options.large_file(bytes.len() as u64 >= u32::MAX as u64);
            zip.start_file(name.as_str(), options)
                .map_err(io::Error::other)?;
            zip.write_all(bytes)?;
        }
        Ok(zip.finish().map_err(io::Error::other)?.into_inner())
    }

    /// Writes the archive to `path` atomically.
    pub fn write(self, path: &Path, replace: Replace) -> Result<(), ExportError> {
        let bytes = self.into_bytes().map_err(io_error(path))?;
        neurotac_core::io::write(path, bytes, replace).map_err(io_error(path))
    }
}

impl Default for NpzMembers {
    fn default() -> Self {
        Self::new()
    }
}

/// Writes named matrices (float64) into an `.npz` archive.
pub fn write_npz(
    path: &Path,
    matrices: &[(&str, ArrayView2<f64>)],
    replace: Replace,
) -> Result<(), ExportError> {
    let mut members = NpzMembers::new();
    for (name, m) in matrices {
        members = members.array(name, m).map_err(io_error(path))?;
    }
    members.write(path, replace)
}

/// The formats a spike dataset is written in ([`write_dataset`]).
pub const DATASET_FORMATS: [OutputFormat; 3] =
    [OutputFormat::Binary, OutputFormat::Json, OutputFormat::Npz];

/// Writes a spike dataset in the format of `path`'s extension ([`DATASET_FORMATS`]): `.bin`
/// (neurotac's checksummed binary), `.json`, or `.npz` ([`dataset_npz_bytes`]). `replace`
/// decides whether an existing file may be replaced ([`Replace`]).
pub fn write_dataset(
    dataset: &SpikeDataset,
    path: &Path,
    replace: Replace,
) -> Result<(), ExportError> {
    let format = OutputFormat::from_path(path, &DATASET_FORMATS)?;
    let bytes = dataset_bytes(dataset, format).map_err(io_error(path))?;
    neurotac_core::io::write(path, bytes, replace).map_err(io_error(path))
}

/// A spike dataset's bytes in `format` (binary, JSON or `.npz`; a `.npy` holds one array, not
/// a dataset, and is refused).
pub fn dataset_bytes(dataset: &SpikeDataset, format: OutputFormat) -> io::Result<Vec<u8>> {
    Ok(match format {
        OutputFormat::Json => dataset.to_json_string().into_bytes(),
        OutputFormat::Npz => dataset_npz_bytes(dataset)?,
        OutputFormat::Binary => dataset.to_binary(),
        OutputFormat::Npy => {
            return Err(io::Error::other(
                "a .npy file holds one array; write a spike dataset as .npz",
            ));
        }
    })
}

/// A spike dataset as an `.npz` archive of flat arrays (see the [module docs](self)).
pub fn dataset_npz_bytes(dataset: &SpikeDataset) -> io::Result<Vec<u8>> {
    let spikes: usize = dataset
        .observations()
        .iter()
        .map(|o| o.total_spikes())
        .sum();
    let mut times = Vec::with_capacity(spikes);
    let mut units = Vec::with_capacity(spikes);
    let mut offsets = Vec::with_capacity(dataset.len() + 1);
    offsets.push(0i64);
    for sample in dataset.observations() {
        for (unit, channel) in sample.channels().enumerate() {
            times.extend_from_slice(channel);
            units.extend(std::iter::repeat_n(unit as u32, channel.len()));
        }
        offsets.push(times.len() as i64);
    }
    let labels: Vec<i64> = dataset.labels().iter().map(|&l| l as i64).collect();
    let meta = serde_json::json!({
        "format": DATASET_NPZ_FORMAT,
        "n_units": dataset.n_channels(),
        "class_names": dataset.class_names(),
        "meta": dataset.meta(),
    });
    NpzMembers::new()
        .array("times", &Array1::from(times))?
        .array("units", &Array1::from(units))?
        .array("offsets", &Array1::from(offsets))?
        .array("labels", &Array1::from(labels))?
        .raw("meta.json", meta.to_string().into_bytes())
        .into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::{Array2, array};
    use ndarray_npy::ReadNpyExt;
    use neurotac_core::MultiSpikeTrain;
    use std::io::Read;

    fn member(path: &Path, name: &str) -> Vec<u8> {
        let mut zip = zip::ZipArchive::new(std::fs::File::open(path).unwrap()).unwrap();
        let mut bytes = Vec::new();
        zip.by_name(name).unwrap().read_to_end(&mut bytes).unwrap();
        bytes
    }

    #[test]
    fn the_extension_chooses_the_format_and_an_unknown_one_is_an_error() {
        use OutputFormat::*;
        let all = [Json, Npy, Npz];
        assert_eq!(
            OutputFormat::from_path(Path::new("a/vr.NPY"), &all).unwrap(),
            Npy
        );
        assert_eq!(
            OutputFormat::from_path(Path::new("vr.npz"), &all).unwrap(),
            Npz
        );
        assert_eq!(
            OutputFormat::from_path(Path::new("vr.json"), &all).unwrap(),
            Json
        );
        for bad in ["vr.txt", "vr", "vr.npy.gz"] {
            let e = OutputFormat::from_path(Path::new(bad), &all).unwrap_err();
            assert_eq!(
                e.to_string(),
                format!(
                    "{bad}: unknown output extension (this command writes .json, .npy or .npz)"
                )
            );
        }
    }

    #[test]
    fn matrices_and_datasets_read_back_as_numpy_arrays() {
        let dir = tempfile::tempdir().unwrap();
        let m: Array2<f64> = array![[0.0, 1.5], [1.5, 0.0]];
        let npy = dir.path().join("m.npy");
        write_npy(&npy, m.view(), Replace::No).unwrap();
        let back = Array2::<f64>::read_npy(std::fs::File::open(&npy).unwrap()).unwrap();
        assert_eq!(back, m);

        let npz = dir.path().join("m.npz");
        write_npz(
            &npz,
            &[("ll2", m.view()), ("sp2", (&m * 2.0).view())],
            Replace::No,
        )
        .unwrap();
        let sp = Array2::<f64>::read_npy(&member(&npz, "sp2.npy")[..]).unwrap();
        assert_eq!(sp, &m * 2.0);

        let a = MultiSpikeTrain::from_channels(vec![vec![0.1, 0.2], vec![], vec![0.05]]).unwrap();
        let b = MultiSpikeTrain::from_channels(vec![vec![], vec![0.3], vec![]]).unwrap();
        let data = SpikeDataset::new(
            vec![a, b],
            vec![1, 0],
            vec!["x".into(), "y".into()],
            Default::default(),
        )
        .unwrap();
        let path = dir.path().join("d.npz");
        write_dataset(&data, &path, Replace::No).unwrap();
        let f64s = |name| {
            Array1::<f64>::read_npy(&member(&path, name)[..])
                .unwrap()
                .to_vec()
        };
        let i64s = |name| {
            Array1::<i64>::read_npy(&member(&path, name)[..])
                .unwrap()
                .to_vec()
        };
        assert_eq!(f64s("times.npy"), vec![0.1, 0.2, 0.05, 0.3]);
        let units = Array1::<u32>::read_npy(&member(&path, "units.npy")[..]).unwrap();
        assert_eq!(units.to_vec(), vec![0, 0, 2, 1]);
        assert_eq!(i64s("offsets.npy"), vec![0, 3, 4]);
        assert_eq!(i64s("labels.npy"), vec![1, 0]);
        let meta: serde_json::Value = serde_json::from_slice(&member(&path, "meta.json")).unwrap();
        assert_eq!(meta["format"], DATASET_NPZ_FORMAT);
        assert_eq!(meta["n_units"], 3);
        assert_eq!(meta["class_names"], serde_json::json!(["x", "y"]));
    }
}
