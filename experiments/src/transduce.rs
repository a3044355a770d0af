//! One event file through the NeuroTac transduction (`neurotac transduce`, `layout`, `filter`):
//! [`transduce_file`] (BA filter → receptive fields → pooling → re-centring → a one-sample
//! [`SpikeDataset`] with its typed metadata), [`resolve_layout`] (the default, a JSON file, or
//! detected from the head of the recording) and [`filter_file`] (event file → event file).

use crate::datasets::metadata::write_metadata;
use neurotac_core::io::Replace;
use neurotac_core::{DatasetError, EventBuffer, MultiSpikeTrain, SpikeDataset};
use neurotac_sensor::filter::{BackgroundActivityFilter, MapStart, RefractoryFilter};
use neurotac_sensor::format::{DAVIS240_SIZE, ReadStats, create_writer, open_reader};
use neurotac_sensor::geometry::{DAVIS240_HEIGHT, DAVIS240_WIDTH};
use neurotac_sensor::stage::{Filtered, Stage};
use neurotac_sensor::taxel::{
    LayoutDetection, TaxelLayout, Transducer, TransductionConfig, TransductionCounts,
};
use neurotac_sensor::{FormatError, ReaderTransductionError, TransductionError};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Taxels of the NeuroTac layout.
pub const NEUROTAC_TAXELS: usize = 49;

/// Why a file could not be transduced or filtered.
#[derive(Debug, thiserror::Error)]
pub enum TransduceError {
    /// The event file could not be read or written.
    #[error(transparent)]
    Format(#[from] FormatError),
    /// The transduction settings, the layout or the events were refused.
    #[error("transducing {path}")]
    Transduction {
        /// The event file.
        path: PathBuf,
        /// Why.
        source: TransductionError,
    },
    /// The layout file or settings are invalid.
    #[error(transparent)]
    Layout(TransductionError),
    /// Layout detection found too few taxels.
    #[error(
        "found {found} of {expected} taxels in the first {calibration_ms} ms of {path}: record longer (--calibration) or give a layout file"
    )]
    LayoutNotFound {
        /// The recording.
        path: PathBuf,
        /// Taxels found.
        found: usize,
        /// Taxels expected.
        expected: usize,
        /// The calibration time (ms).
        calibration_ms: f64,
    },
    /// An automatic layout whose confidence is below
    /// [`LayoutDetection::RELIABLE_CONFIDENCE`] ([`check_reliable`]).
    #[error(
        "the layout found in {} is unreliable (confidence {confidence:.2} < {:.2}: the events do not show the NeuroTac's pin rings)",
        path.display(),
        LayoutDetection::RELIABLE_CONFIDENCE
    )]
    UnreliableLayout {
        /// The recording.
        path: PathBuf,
        /// The detection's confidence.
        confidence: f64,
    },
    /// The spike dataset could not be built or written.
    #[error(transparent)]
    Dataset(#[from] DatasetError),
}

/// `Err(`[`TransduceError::UnreliableLayout`]`)` when the layout detected in `path` is below the
/// confidence the layout-accuracy test calibrated; the caller decides whether to refuse it,
/// warn or use it anyway.
pub fn check_reliable(detection: &LayoutDetection, path: &Path) -> Result<(), TransduceError> {
    match detection.is_reliable() {
        true => Ok(()),
        false => Err(TransduceError::UnreliableLayout {
            path: path.to_owned(),
            confidence: detection.confidence,
        }),
    }
}

/// Where the taxel centres come from.
#[derive(Debug, Clone, PartialEq)]
pub enum LayoutSpec {
    /// The NeuroTac default (49 pins, rings 1 + 8 + 16 + 24).
    Default,
    /// Detected from the first `calibration_ms` of the recording itself.
    Auto {
        /// Calibration time (ms).
        calibration_ms: f64,
    },
    /// A JSON file of `[x, y]` centres.
    File(PathBuf),
}

impl LayoutSpec {
    /// `default`, `auto` or a file name (the CLI's `--layout`).
    pub fn parse(spec: &str, calibration_ms: f64) -> Self {
        match spec {
            "default" => LayoutSpec::Default,
            "auto" => LayoutSpec::Auto { calibration_ms },
            file => LayoutSpec::File(file.into()),
        }
    }
}

/// The layout of `spec` for the recording `input`, validated for `radius_px` on the DAVIS240
/// (49 taxels); an automatic layout also returns its detection (to report its confidence).
pub fn resolve_layout(
    spec: &LayoutSpec,
    input: &Path,
    radius_px: f64,
) -> Result<(TaxelLayout, Option<LayoutDetection>), TransduceError> {
    let (layout, detection) = match spec {
        LayoutSpec::Default => (TaxelLayout::neurotac_default(), None),
        LayoutSpec::File(path) => (
            TaxelLayout::from_json_file(path).map_err(TransduceError::Layout)?,
            None,
        ),
        LayoutSpec::Auto { calibration_ms } => {
            let events = read_head(input, *calibration_ms)?;
            let d = TaxelLayout::detect(&events, NEUROTAC_TAXELS, radius_px);
            if d.found != d.expected {
                return Err(TransduceError::LayoutNotFound {
                    path: input.to_owned(),
                    found: d.found,
                    expected: d.expected,
                    calibration_ms: *calibration_ms,
                });
            }
            (d.layout.clone(), Some(d))
        }
    };
    layout
        .validate(
            radius_px,
            Some(NEUROTAC_TAXELS),
            DAVIS240_WIDTH,
            DAVIS240_HEIGHT,
        )
        .map_err(TransduceError::Layout)?;
    Ok((layout, detection))
}

/// The events of the first `ms` milliseconds of a file.
fn read_head(path: &Path, ms: f64) -> Result<EventBuffer, FormatError> {
    let mut reader = open_reader(path)?;
    let mut all = EventBuffer::new();
    let mut chunk = EventBuffer::new();
    let mut end = None;
    while reader.read_chunk(&mut chunk)? > 0 {
        let end_us = *end.get_or_insert(chunk.t[0] + neurotac_core::time::s_to_us(ms * 1e-3));
        for e in chunk.iter().take_while(|e| e.t.0 < end_us) {
            all.push(e);
        }
        if chunk.t.last().is_some_and(|&t| t >= end_us) {
            break;
        }
        chunk.clear();
    }
    Ok(all)
}

/// One transduced file.
#[derive(Debug, Clone)]
pub struct TransducedFile {
    /// One observation (the taxel spike trains), labelled when a label was given; `meta` holds
    /// `source`, `layout`, the transduction settings, `origin_us` and the stage counts.
    pub dataset: SpikeDataset,
    /// The taxel spike trains.
    pub trains: MultiSpikeTrain,
    /// What each stage passed.
    pub counts: TransductionCounts,
    /// Time inside the transducer alone.
    pub transducing: Duration,
    /// Time with reading and decoding the file.
    pub wall: Duration,
    /// What the reader delivered and skipped ([`ReadStats::warning`] is the line to print).
    pub read: ReadStats,
}

/// Transduces the event file `input` with `layout` and `config` into a one-sample dataset,
/// labelled `label` when given; `layout_name` is recorded in the metadata.
pub fn transduce_file(
    input: &Path,
    layout: &TaxelLayout,
    layout_name: &str,
    config: TransductionConfig,
    label: Option<&str>,
) -> Result<TransducedFile, TransduceError> {
    let transduction = |source| TransduceError::Transduction {
        path: input.to_owned(),
        source,
    };
    let mut transducer = Transducer::new(layout, config).map_err(transduction)?;
    let start = Instant::now();
    let mut reader = open_reader(input)?;
    let t = transducer
        .transduce_reader(reader.as_mut(), input)
        .map_err(|e| match e {
            ReaderTransductionError::Read(e) => TransduceError::Format(e),
            ReaderTransductionError::Transduction { source, .. } => transduction(source),
        })?;
    let (transducing, read) = (t.transduce_time, t.read);
    let wall = start.elapsed();
    let (counts, trains) = (t.counts, t.spike_trains);
    let dataset = transduced_dataset(
        &transducer,
        trains.clone(),
        input,
        layout_name,
        config,
        label,
    )?;
    Ok(TransducedFile {
        dataset,
        trains,
        counts,
        transducing,
        wall,
        read,
    })
}

/// The one-sample dataset of a finished transduction of `trains` from `source`, labelled
/// `label` when given; `meta` holds `source`, `layout` (`layout_name`), the transduction
/// settings, `origin_us` and the stage counts of `transducer`.
pub fn transduced_dataset(
    transducer: &Transducer,
    trains: MultiSpikeTrain,
    source: &Path,
    layout_name: &str,
    config: TransductionConfig,
    label: Option<&str>,
) -> Result<SpikeDataset, DatasetError> {
    let counts = transducer.counts();
    let mut meta = serde_json::Map::new();
    meta.insert("source".into(), source.display().to_string().into());
    meta.insert("layout".into(), layout_name.into());
    write_metadata(&mut meta, &config, None);
    meta.insert(
        "origin_us".into(),
        transducer.origin_us().unwrap_or(0).into(),
    );
    meta.insert("pixel_events".into(), counts.events_in.into());
    meta.insert("after_filters".into(), counts.after_filters.into());
    meta.insert("in_fields".into(), counts.in_fields.into());
    let (labels, names) = match label {
        Some(name) => (vec![0], vec![name.to_owned()]),
        None => (Vec::new(), Vec::new()),
    };
    SpikeDataset::new(vec![trains], labels, names, meta)
}

/// What [`filter_file`] kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FilterCounts {
    /// Events read.
    pub seen: u64,
    /// Events written.
    pub kept: u64,
    /// What the reader delivered and skipped ([`ReadStats::warning`] is the line to print).
    pub read: ReadStats,
}

/// Event file → event file through the background-activity filter (`ba_window_us`, starting as
/// `start`) and, when given, a refractory filter (`refractory_us`), on the sensor the input
/// states (240 × 180 when it states none); the output states the same sensor. `replace` decides
/// whether an existing `output` may be replaced.
pub fn filter_file(
    input: &Path,
    output: &Path,
    replace: Replace,
    ba_window_us: i64,
    start: MapStart,
    refractory_us: Option<i64>,
) -> Result<FilterCounts, TransduceError> {
    let mut reader = open_reader(input)?;
    let (w, h) = reader.sensor_size().unwrap_or(DAVIS240_SIZE);
    let transduction = |source| TransduceError::Transduction {
        path: input.to_owned(),
        source,
    };
    let ba = BackgroundActivityFilter::new(w, h, ba_window_us, start).map_err(transduction)?;
    let mut ba = Filtered::new(ba);
    let mut refractory = refractory_us
        .map(|p| RefractoryFilter::new(w, h, p).map(Filtered::new))
        .transpose()
        .map_err(transduction)?;
    let mut writer = create_writer(output, (w, h), replace)?;
    let (mut chunk, mut kept, mut kept2) =
        (EventBuffer::new(), EventBuffer::new(), EventBuffer::new());
    while reader.read_chunk(&mut chunk)? > 0 {
        kept.clear();
        ba.push(&chunk, &mut kept).map_err(transduction)?;
        let out = match &mut refractory {
            Some(r) => {
                kept2.clear();
                r.push(&kept, &mut kept2).map_err(transduction)?;
                &kept2
            }
            None => &kept,
        };
        writer.write(out)?;
        chunk.clear();
    }
    writer.finish()?;
    Ok(FilterCounts {
        seen: ba.seen,
        kept: refractory.as_ref().map_or(ba.kept, |r| r.kept),
        read: reader.stats(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_core::{Event, Timestamp};

    /// A 5 × 5 px blob at the sensor's centre, each pixel firing every ms for 100 ms (CSV).
    fn recording(dir: &Path) -> PathBuf {
        let mut events = EventBuffer::new();
        for ms in 0..100i64 {
            for y in 88..93u16 {
                for x in 118..123u16 {
                    events.push(Event {
                        t: Timestamp(1_000 * ms + 17),
                        x,
                        y,
                        polarity: ms % 2 == 0,
                    });
                }
            }
        }
        let path = dir.join("blob.csv");
        neurotac_sensor::format::write_file(&path, &events, DAVIS240_SIZE).unwrap();
        path
    }

    #[test]
    fn a_file_becomes_a_one_sample_dataset_with_its_settings() {
        let dir = tempfile::tempdir().unwrap();
        let input = recording(dir.path());
        let (layout, detection) = resolve_layout(&LayoutSpec::Default, &input, 6.0).unwrap();
        assert!(detection.is_none());
        let config = TransductionConfig::default();
        let t = transduce_file(&input, &layout, "default", config, Some("blob")).unwrap();
        assert_eq!(t.counts.events_in, 2500);
        assert_eq!(t.dataset.len(), 1);
        assert_eq!(t.dataset.n_channels(), NEUROTAC_TAXELS);
        assert_eq!(t.dataset.class_names(), ["blob"]);
        let meta = t.dataset.meta();
        assert_eq!(meta["layout"], "default");
        assert_eq!(meta["pixel_events"], 2500);
        assert_eq!(meta["origin_us"], 17);
        assert_eq!(
            crate::datasets::metadata::transduction_of(&t.dataset).unwrap(),
            Some(config)
        );
        assert_eq!(t.trains.total_spikes() as u64, t.counts.taxel_events);
    }

    #[test]
    fn filtering_writes_what_it_keeps() {
        let dir = tempfile::tempdir().unwrap();
        let input = recording(dir.path());
        let output = dir.path().join("kept.csv");
        let c = filter_file(
            &input,
            &output,
            Replace::No,
            5000,
            MapStart::Empty,
            Some(2000),
        )
        .unwrap();
        assert_eq!(c.seen, 2500);
        assert!(c.kept > 0 && c.kept < c.seen, "{c:?}");
        let (kept, _) = neurotac_sensor::format::read_file(&output).unwrap();
        assert_eq!(kept.len() as u64, c.kept);
    }

    #[test]
    fn layout_specs_and_a_failed_detection() {
        assert_eq!(LayoutSpec::parse("default", 1.0), LayoutSpec::Default);
        assert_eq!(
            LayoutSpec::parse("auto", 250.0),
            LayoutSpec::Auto {
                calibration_ms: 250.0
            }
        );
        assert_eq!(
            LayoutSpec::parse("pins.json", 1.0),
            LayoutSpec::File("pins.json".into())
        );
        let dir = tempfile::tempdir().unwrap();
        let input = recording(dir.path());
        let auto = LayoutSpec::Auto {
            calibration_ms: 50.0,
        };
        // One blob is one taxel, not 49.
        assert!(matches!(
            resolve_layout(&auto, &input, 6.0),
            Err(TransduceError::LayoutNotFound { expected: 49, .. })
        ));
    }
}
