//! `neurotac transduce`, `neurotac filter` and `neurotac layout`: the NeuroTac transduction
//! (BA filter → receptive fields → pooling → re-centring) on any event file.

use anyhow::{Context, bail};
use clap::Args;
use neurotac_core::{EventBuffer, SpikeDataset};
use neurotac_experiments::figures::spike_train_figure;
use neurotac_sensor::filter::{BackgroundActivityFilter, MapStart, RefractoryFilter};
use neurotac_sensor::format::{create_writer, open_reader};
use neurotac_sensor::stage::{Filtered, Stage};
use neurotac_sensor::taxel::{TaxelLayout, Transducer, TransductionConfig};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where the taxel centres come from.
fn layout_from(
    spec: &str,
    input: &Path,
    calibration_ms: f64,
    radius_px: f64,
) -> anyhow::Result<TaxelLayout> {
    let layout = match spec {
        "default" => TaxelLayout::neurotac_default(),
        "auto" => {
            let events = read_head(input, calibration_ms)?;
            let d = TaxelLayout::detect(&events, 49, radius_px);
            eprintln!(
                "layout: found {} of {} taxels in the first {calibration_ms} ms (confidence {:.2}, {:.0} % of events inside the fields)",
                d.found,
                d.expected,
                d.confidence,
                100.0 * d.captured_fraction
            );
            if d.found != d.expected {
                bail!(
                    "found {} of {} taxels in the first {calibration_ms} ms of {}: record longer (--calibration-ms) or give a layout file",
                    d.found,
                    d.expected,
                    input.display()
                );
            }
            d.layout
        }
        file => TaxelLayout::from_json_file(Path::new(file))?,
    };
    layout.validate(radius_px, Some(49), 240, 180)?;
    Ok(layout)
}

/// The events of the first `ms` milliseconds of a file.
fn read_head(path: &Path, ms: f64) -> anyhow::Result<EventBuffer> {
    let mut reader = open_reader(path)?;
    let mut all = EventBuffer::new();
    let mut chunk = EventBuffer::new();
    let mut end = None;
    while reader.read_chunk(&mut chunk)? > 0 {
        let end_us = *end.get_or_insert(chunk.t[0] + (ms * 1e3) as i64);
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

#[derive(Debug, Args)]
pub struct TransduceArgs {
    /// Event file (AEDAT 2/3.1/4, ECD text, CSV; detected from its first bytes).
    input: PathBuf,
    /// Taxel layout: `default` (49 pins, rings 1+8+16+24), a JSON file of [x, y] centres, or
    /// `auto` (detected from the first --calibration-ms of the recording).
    #[arg(long, default_value = "default")]
    layout: String,
    /// Background-activity window (µs); 0 disables the filter.
    #[arg(long, default_value_t = 5000)]
    ba_window_us: i64,
    /// Start the BA time surface empty instead of at t = 0 (dv-processing's choice).
    #[arg(long)]
    ba_empty_start: bool,
    /// Receptive-field radius (px); the paper's fields are 6 px in diameter.
    #[arg(long, default_value_t = 3.0)]
    rf_radius_px: f64,
    /// Pooling window (ms).
    #[arg(long, default_value_t = 20.0)]
    pool_ms: f64,
    /// Re-centring gain in [0, 1] (0: fixed fields).
    #[arg(long, default_value_t = 0.5)]
    gain: f64,
    /// Calibration time for --layout auto (ms).
    #[arg(long, default_value_t = 500.0)]
    calibration_ms: f64,
    /// Class label name stored in the dataset.
    #[arg(long)]
    label: Option<String>,
    /// Output spike dataset (JSON, or compact binary with any other extension).
    #[arg(long)]
    out: PathBuf,
    /// Also write a raster plot with spatial and temporal distributions (SVG).
    #[arg(long)]
    raster: Option<PathBuf>,
}

pub fn run_transduce(a: TransduceArgs) -> anyhow::Result<()> {
    let layout = layout_from(&a.layout, &a.input, a.calibration_ms, a.rf_radius_px)?;
    if !(a.pool_ms.is_finite() && a.pool_ms > 0.0) {
        bail!("--pool-ms {} must be finite and > 0", a.pool_ms);
    }
    let config = TransductionConfig {
        ba_window_us: (a.ba_window_us > 0).then_some(a.ba_window_us),
        ba_start: if a.ba_empty_start {
            MapStart::Empty
        } else {
            MapStart::Zero
        },
        rf_radius_px: a.rf_radius_px,
        pool_window_us: (a.pool_ms * 1e3).round() as i64,
        recentre_gain: a.gain,
        ..TransductionConfig::default()
    };
    let mut transducer = Transducer::new(&layout, config)?;
    let start = Instant::now();
    let mut reader = open_reader(&a.input)?;
    let mut chunk = EventBuffer::new();
    // Transduction alone, without reading and decoding the file.
    let mut transducing = std::time::Duration::ZERO;
    while reader.read_chunk(&mut chunk)? > 0 {
        let t0 = Instant::now();
        transducer
            .push(&chunk)
            .with_context(|| format!("transducing {}", a.input.display()))?;
        transducing += t0.elapsed();
        chunk.clear();
    }
    let t0 = Instant::now();
    transducer.finish();
    transducing += t0.elapsed();
    let wall = start.elapsed().as_secs_f64();
    let counts = transducer.counts();
    let trains = transducer.spike_trains();
    let mut meta = serde_json::Map::new();
    meta.insert("source".into(), a.input.display().to_string().into());
    meta.insert("layout".into(), a.layout.clone().into());
    meta.insert("ba_window_us".into(), a.ba_window_us.into());
    meta.insert("rf_radius_px".into(), a.rf_radius_px.into());
    meta.insert("pool_ms".into(), a.pool_ms.into());
    meta.insert("recentre_gain".into(), a.gain.into());
    meta.insert(
        "origin_us".into(),
        transducer.origin_us().unwrap_or(0).into(),
    );
    meta.insert("pixel_events".into(), counts.events_in.into());
    meta.insert("after_filters".into(), counts.after_filters.into());
    meta.insert("in_fields".into(), counts.in_fields.into());
    let (labels, names) = match &a.label {
        Some(name) => (vec![0], vec![name.clone()]),
        None => (Vec::new(), Vec::new()),
    };
    let dataset = SpikeDataset::new(vec![trains.clone()], labels, names, meta)?;
    if a.out.extension().is_some_and(|e| e == "json") {
        dataset.save_json(&a.out)?;
    } else {
        dataset.save_binary(&a.out)?;
    }
    if let Some(path) = &a.raster {
        let title = format!(
            "{}: {} taxel spikes",
            a.input.display(),
            trains.total_spikes()
        );
        std::fs::write(path, spike_train_figure(&trains, &title, 0.159))
            .with_context(|| format!("writing {}", path.display()))?;
    }
    println!(
        "{} pixel events → {} after filters → {} in receptive fields → {} taxel spikes ({:.2} per taxel); transduction {:.1} M events/s, with reading the file {:.1} M events/s",
        counts.events_in,
        counts.after_filters,
        counts.in_fields,
        counts.taxel_events,
        counts.taxel_events as f64 / 49.0,
        counts.events_in as f64 / transducing.as_secs_f64() / 1e6,
        counts.events_in as f64 / wall / 1e6
    );
    println!("wrote {}", a.out.display());
    Ok(())
}

#[derive(Debug, Args)]
pub struct FilterArgs {
    /// Event file to read.
    input: PathBuf,
    /// Event file to write (format from its extension).
    output: PathBuf,
    /// Background-activity window (µs).
    #[arg(long, default_value_t = 5000)]
    ba_window_us: i64,
    /// Start the BA time surface empty instead of at t = 0.
    #[arg(long)]
    ba_empty_start: bool,
    /// Also drop events within this refractory period of their own pixel's last event (µs).
    #[arg(long)]
    refractory_us: Option<i64>,
}

pub fn run_filter(a: FilterArgs) -> anyhow::Result<()> {
    let start_mode = if a.ba_empty_start {
        MapStart::Empty
    } else {
        MapStart::Zero
    };
    let mut ba = Filtered::new(BackgroundActivityFilter::new(
        240,
        180,
        a.ba_window_us,
        start_mode,
    )?);
    let mut refractory = a
        .refractory_us
        .map(|p| RefractoryFilter::new(240, 180, p).map(Filtered::new))
        .transpose()?;
    let mut reader = open_reader(&a.input)?;
    let mut writer = create_writer(&a.output)?;
    let (mut chunk, mut kept, mut kept2) =
        (EventBuffer::new(), EventBuffer::new(), EventBuffer::new());
    let start = Instant::now();
    while reader.read_chunk(&mut chunk)? > 0 {
        kept.clear();
        ba.push(&chunk, &mut kept)
            .with_context(|| format!("filtering {}", a.input.display()))?;
        let out = match &mut refractory {
            Some(r) => {
                kept2.clear();
                r.push(&kept, &mut kept2)?;
                &kept2
            }
            None => &kept,
        };
        writer.write(out)?;
        chunk.clear();
    }
    writer.finish()?;
    let wall = start.elapsed().as_secs_f64();
    let out_count = refractory.as_ref().map_or(ba.kept, |r| r.kept);
    println!(
        "kept {} of {} events ({:.1} %) → {}; {:.1} M events/s",
        out_count,
        ba.seen,
        100.0 * out_count as f64 / ba.seen.max(1) as f64,
        a.output.display(),
        ba.seen as f64 / wall / 1e6
    );
    Ok(())
}

#[derive(Debug, Args)]
pub struct LayoutArgs {
    /// Calibration recording (any event file).
    input: PathBuf,
    /// Use the first this many milliseconds.
    #[arg(long, default_value_t = 500.0)]
    calibration_ms: f64,
    /// Receptive-field radius (px); the paper's fields are 6 px in diameter.
    #[arg(long, default_value_t = 3.0)]
    rf_radius_px: f64,
    /// Write the 49 centres as a JSON list of [x, y] (px).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run_layout(a: LayoutArgs) -> anyhow::Result<()> {
    let layout = layout_from("auto", &a.input, a.calibration_ms, a.rf_radius_px)?;
    if let Some(path) = &a.out {
        std::fs::write(path, layout.to_json())
            .with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    } else {
        println!("{}", layout.to_json());
    }
    Ok(())
}
