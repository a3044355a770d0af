//! What the cargo-fuzz targets (`fuzz/`) check, shared with the tests that replay their
//! committed corpus on stable: the checks of a reader's result, the corpus files, and an
//! allocator that measures the peak memory of a replay.
//!
//! A check panics when a reader breaks a promise (that is the fuzzer's crash); a typed error
//! is a pass.

use crate::SpikeDataset;
use crate::dataset::{DURATION_S_KEY, MAGIC, MAX_CLASSES, VERSION, VERSION_WITHOUT_CHECKSUM};
use crate::error::DatasetError;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The name a fuzzed input goes by in errors.
pub const FUZZ_PATH: &str = "<fuzz>";

/// `body` as a saved network file ([`Network::save`](crate::Network::save)'s format): magic,
/// version, length, `body`, and its CRC-32 — how a fuzzer, which cannot forge the checksum,
/// reaches the decoder behind it.
pub fn saved_network_file(body: &[u8]) -> Vec<u8> {
    let mut file = crate::graph::NETWORK_FILE_MAGIC.to_vec();
    file.extend_from_slice(&crate::graph::NETWORK_FILE_VERSION.to_le_bytes());
    file.extend_from_slice(&(body.len() as u64).to_le_bytes());
    file.extend_from_slice(body);
    let crc = crc32fast::hash(&file);
    file.extend_from_slice(&crc.to_le_bytes());
    file
}

/// Reads `bytes` as a spike-dataset file ([`SpikeDataset::from_bytes`], the reader of
/// `neurotac distances`, `classify` and `export`) and checks what it gives; see
/// [`check_dataset`]. A binary input is also read as version 1 (no checksum) and as version 2
/// with its CRC-32 appended — a fuzzer cannot forge the checksum, so this is how it reaches the
/// decoder behind it — and both must give the same dataset or the same error.
pub fn check_dataset_bytes(bytes: &[u8]) -> Result<SpikeDataset, DatasetError> {
    let read = read_dataset_checked(bytes);
    if bytes.len() >= MAGIC.len() + 4 && bytes.starts_with(MAGIC) {
        let with_version = |version: u32| {
            let mut b = bytes.to_vec();
            b[MAGIC.len()..MAGIC.len() + 4].copy_from_slice(&version.to_le_bytes());
            b
        };
        let without_checksum = read_dataset_checked(&with_version(VERSION_WITHOUT_CHECKSUM));
        let mut checksummed = with_version(VERSION);
        checksummed.extend_from_slice(&crc32fast::hash(&checksummed).to_le_bytes());
        let with_checksum = read_dataset_checked(&checksummed);
        match (without_checksum, with_checksum) {
            (Ok(a), Ok(b)) => assert_eq!(a, b, "versions 1 and 2 read different datasets"),
            (Err(a), Err(b)) => assert_eq!(
                a.to_string(),
                b.to_string(),
                "versions 1 and 2 fail differently"
            ),
            (a, b) => panic!("version 1 gives {a:?}, version 2 gives {b:?}"),
        }
    }
    read
}

fn read_dataset_checked(bytes: &[u8]) -> Result<SpikeDataset, DatasetError> {
    let read = SpikeDataset::from_bytes(bytes, Path::new(FUZZ_PATH));
    if let Ok(data) = &read {
        check_dataset(data);
    }
    read
}

/// What a dataset that was read promises its user: one label per observation (or none), each
/// with a class name when names are given, at most [`MAX_CLASSES`] classes; the same channels
/// in every observation; finite, non-decreasing spike times in every channel; a `duration_s`
/// (when stated) finite and > 0; and both forms written from it read back equal (what
/// `neurotac export` does).
pub fn check_dataset(data: &SpikeDataset) {
    let labels = data.labels();
    assert!(
        labels.is_empty() || labels.len() == data.len(),
        "{} labels for {} observations",
        labels.len(),
        data.len()
    );
    let n_classes = data.n_classes();
    assert!(n_classes <= MAX_CLASSES, "{n_classes} classes");
    assert!(labels.iter().all(|&l| l < n_classes));
    if !data.class_names().is_empty() {
        assert_eq!(n_classes, data.class_names().len());
    }
    let n_channels = data.n_channels();
    for (o, observation) in data.observations().iter().enumerate() {
        assert_eq!(observation.n_channels(), n_channels, "observation {o}");
        for (c, times) in observation.channels().enumerate() {
            assert!(
                times.iter().all(|t| t.is_finite()) && times.is_sorted(),
                "observation {o}, channel {c}: {times:?}"
            );
        }
    }
    if data.meta().contains_key(DURATION_S_KEY) {
        let d = data.duration_s();
        assert!(
            d.is_some_and(|d| d.is_finite() && d > 0.0),
            "duration {d:?}"
        );
    }
    let path = Path::new(FUZZ_PATH);
    let json = SpikeDataset::from_json_str(&data.to_json_string(), path);
    assert_eq!(
        json.as_ref().ok(),
        Some(data),
        "JSON form read back: {json:?}"
    );
    let binary = SpikeDataset::from_binary(&data.to_binary(), path);
    assert_eq!(
        binary.as_ref().ok(),
        Some(data),
        "binary form read back: {binary:?}"
    );
}

/// The committed corpus of the fuzz target `target` (`fuzz/corpus/<target>/`): every file's
/// name and bytes, sorted by name. `None` after printing why the calling test skips when the
/// folder is absent (the corpus is in a clone of the repository, not in a packaged crate);
/// panics then when `CI` is set, so that CI never passes without replaying it.
pub fn corpus(target: &str) -> Option<Vec<(String, Vec<u8>)>> {
    // This crate sits one level below the workspace root.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fuzz/corpus")
        .join(target);
    if !dir.is_dir() {
        let why = format!(
            "the fuzz corpus {} is absent (it is committed in the repository, not packaged with the crate)",
            dir.display()
        );
        assert!(!super::ci_is_set(), "CI is set: {why}");
        eprintln!("skipped: {why}");
        return None;
    }
    let read = |e: std::io::Result<std::fs::DirEntry>| -> Option<(String, Vec<u8>)> {
        let path: PathBuf = e.expect("corpus folder entry").path();
        path.is_file().then(|| {
            let name = path.file_name().expect("a file name").to_string_lossy();
            let bytes = std::fs::read(&path).expect("readable corpus file");
            (name.into_owned(), bytes)
        })
    };
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("readable corpus folder")
        .filter_map(read)
        .collect();
    files.sort();
    Some(files)
}

/// A global allocator that tracks the bytes allocated and still live, and their peak since
/// [`reset_peak`]: declare `#[global_allocator] static GLOBAL: PeakAllocator = PeakAllocator;`
/// in a test binary holding one test, and read [`peak_since`] after the measured part.
pub struct PeakAllocator;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grow(bytes: usize) {
    let live = LIVE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(live, Ordering::Relaxed);
}

// SAFETY: every call is forwarded unchanged to the system allocator; only two atomic counters
// are updated besides.
unsafe impl GlobalAlloc for PeakAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: `ptr` came from this allocator with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        grow(new_size);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Starts a measurement of [`PeakAllocator`]: returns the bytes live now, to pass to
/// [`peak_since`].
pub fn reset_peak() -> usize {
    let live = LIVE.load(Ordering::Relaxed);
    PEAK.store(live, Ordering::Relaxed);
    live
}

/// The most bytes [`PeakAllocator`] had live at once since [`reset_peak`] returned `start`,
/// beyond `start`.
pub fn peak_since(start: usize) -> usize {
    PEAK.load(Ordering::Relaxed).saturating_sub(start)
}
