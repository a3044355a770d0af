//! `neurotac transduce`, `neurotac filter` and `neurotac layout`: the NeuroTac transduction
//! (BA filter → receptive fields → pooling → re-centring) on any event file.

use super::options::{ForceOption, OutOption, OutPathOption, help};
use super::outputs::{Output, check_outputs};
use crate::commands::args::{self, Time};
use anyhow::{Context, bail};
use clap::Args;
use neurotac_cli::report::figures::spike_train_figure;
use neurotac_cli::report::png::PngRenderer;
use neurotac_core::io::{AtomicFileSet, Replace, check_distinct};
use neurotac_experiments::export::{DATASET_FORMATS, OutputFormat, dataset_bytes};
use neurotac_experiments::transduce::{
    LayoutSpec, check_reliable, filter_file, resolve_layout, transduce_file,
};
use neurotac_sensor::filter::MapStart;
use neurotac_sensor::taxel::{TaxelLayout, TransductionConfig};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What to do with an automatic layout below [`LayoutDetection::RELIABLE_CONFIDENCE`](neurotac_sensor::taxel::LayoutDetection::RELIABLE_CONFIDENCE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Uncertain {
    /// `neurotac layout`: print it, with a warning.
    Warn,
    /// `neurotac transduce --layout auto`: stop, naming the alternatives.
    Refuse,
    /// `--accept-uncertain-layout`: use it, with a warning.
    Accept,
}

/// The layout of `--layout` for `input`, printing how an automatic one was found and what an
/// unreliable one means.
fn layout_from(
    spec: &str,
    input: &Path,
    calibration_ms: f64,
    radius_px: f64,
    uncertain: Uncertain,
) -> anyhow::Result<TaxelLayout> {
    let spec = LayoutSpec::parse(spec, calibration_ms);
    let (layout, detection) = resolve_layout(&spec, input, radius_px)?;
    if let Some(d) = detection {
        eprintln!(
            "layout: found {} of {} taxels in the first {calibration_ms} ms (confidence {:.2}, {} pins active, {:.0} % of events inside the fields)",
            d.found,
            d.expected,
            d.confidence,
            d.active,
            100.0 * d.captured_fraction
        );
        if let Err(why) = check_reliable(&d, input) {
            match uncertain {
                Uncertain::Refuse => bail!(
                    "{why}; pass a layout file (--layout FILE) or the default layout (--layout default), or --accept-uncertain-layout to use it anyway"
                ),
                Uncertain::Warn => eprintln!(
                    "warning: {why}; check it before use, or transduce with --layout default"
                ),
                Uncertain::Accept => {
                    eprintln!("warning: {why}; used anyway (--accept-uncertain-layout)")
                }
            }
        }
    }
    Ok(layout)
}

fn ba_start(empty: bool) -> MapStart {
    match empty {
        true => MapStart::Empty,
        false => MapStart::Zero,
    }
}

#[derive(Debug, Args)]
#[command(mut_args(help(
    "out",
    "Output spike dataset, format by extension: `.json`, `.bin` (or `.ntspk`, compact binary) or `.npz` (numpy arrays)"
)))]
pub struct TransduceArgs {
    /// Event file (AEDAT 2/3.1/4, ECD text, CSV; detected from its first bytes).
    input: PathBuf,
    /// Taxel layout: `default` (49 pins, rings 1+8+16+24), a JSON file of [x, y] centres, or
    /// `auto` (detected from the first --calibration of the recording; refused when its
    /// confidence is below the calibrated threshold, see --accept-uncertain-layout).
    #[arg(long, default_value = "default")]
    layout: String,
    /// Background-activity window, rounded to the µs (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_event_window, allow_negative_numbers = true, long, default_value = "5ms")]
    ba_window: Time,
    /// Start the BA time surface empty instead of at t = 0 (dv-processing's choice).
    #[arg(long)]
    ba_empty_start: bool,
    /// Receptive-field radius (px); the paper's fields are 6 px in diameter.
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 3.0)]
    rf_radius_px: f64,
    /// Pooling window (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_window, allow_negative_numbers = true, long, alias = "pool-ms", default_value = "20ms")]
    pool: Time,
    /// Re-centring gain in [0, 1] (0: fixed fields).
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long, default_value_t = 0.5)]
    gain: f64,
    /// Calibration time for --layout auto (ms, or with a unit: 20ms, 0.02s); the default first
    /// second of a NeuroTac recording holds the press and the slide's onset, when every pin
    /// moves.
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, alias = "calibration-ms", default_value = "1s")]
    calibration: Time,
    /// Use a --layout auto layout even when its confidence is below the calibrated threshold
    /// (by default `transduce` then stops).
    #[arg(long)]
    accept_uncertain_layout: bool,
    /// Class label name stored in the dataset.
    #[arg(long)]
    label: Option<String>,
    #[command(flatten)]
    out: OutPathOption,
    /// Also write a raster plot with spatial and temporal distributions: SVG at this path and
    /// PNG beside it (`r.svg` → `r.svg`, `r.png`).
    #[arg(long)]
    raster: Option<PathBuf>,
    #[command(flatten)]
    force: ForceOption,
}

pub fn run_transduce(a: TransduceArgs) -> anyhow::Result<()> {
    // Every output is checked against the input and created (hidden) before any work, and all
    // are committed together at the end (AtomicFileSet): a failure leaves each as it was.
    let out = &a.out.out;
    check_distinct(&a.input, out)?;
    let format = OutputFormat::from_path(out, &DATASET_FORMATS)?;
    // The raster as SVG at the path given and as PNG beside it (`r.svg` → `r.png`); a path
    // ending in `.png` gets the PNG only.
    let raster: Vec<PathBuf> = match &a.raster {
        Some(path) => {
            let png = path.with_extension("png");
            let svg = (png != *path).then(|| path.clone());
            svg.into_iter().chain([png]).collect()
        }
        None => Vec::new(),
    };
    if let Some(same) = raster.iter().find(|p| *p == out) {
        bail!("--raster would write {} as well as --out", same.display());
    }
    let outputs: Vec<&Path> = std::iter::once(out.as_path())
        .chain(raster.iter().map(PathBuf::as_path))
        .collect();
    for p in &raster {
        check_distinct(&a.input, p)?;
    }
    let checked =
        std::iter::once(Output::file("--out", out)).chain(Output::files("--raster", &raster));
    check_outputs(checked, a.force.force)?;
    let mut files = AtomicFileSet::new(Replace::when(a.force.force));
    for p in &outputs {
        files
            .file(p)
            .with_context(|| format!("creating {}", p.display()))?;
    }
    let uncertain = match a.accept_uncertain_layout {
        true => Uncertain::Accept,
        false => Uncertain::Refuse,
    };
    let layout = layout_from(
        &a.layout,
        &a.input,
        a.calibration.ms(),
        a.rf_radius_px,
        uncertain,
    )?;
    let config = TransductionConfig {
        ba_window_us: Some(a.ba_window.us()),
        ba_start: ba_start(a.ba_empty_start),
        rf_radius_px: a.rf_radius_px,
        pool_window_us: neurotac_core::time::s_to_us(a.pool.s()),
        recentre_gain: a.gain,
        ..TransductionConfig::default()
    };
    let t = transduce_file(&a.input, &layout, &a.layout, config, a.label.as_deref())?;
    if let Some(warning) = t.read.warning(&a.input) {
        eprintln!("{warning}");
    }
    let bytes = dataset_bytes(&t.dataset, format)?;
    files
        .write(out, &bytes)
        .with_context(|| format!("writing {}", out.display()))?;
    if !raster.is_empty() {
        let title = format!(
            "{}: {} taxel spikes",
            a.input.display(),
            t.trains.total_spikes()
        );
        let svg = spike_train_figure(&t.trains, &title, 0.159);
        for path in &raster {
            let bytes = match path.extension().is_some_and(|e| e == "png") {
                true => PngRenderer::new()
                    .render(&svg, 1.5)
                    .with_context(|| format!("drawing {}", path.display()))?,
                false => svg.clone().into_bytes(),
            };
            files
                .write(path, &bytes)
                .with_context(|| format!("writing {}", path.display()))?;
        }
    }
    let written: Vec<String> = outputs.iter().map(|p| p.display().to_string()).collect();
    files
        .commit()
        .with_context(|| format!("writing {}", written.join(", ")))?;
    let c = t.counts;
    println!(
        "{} pixel events → {} after filters → {} in receptive fields → {} taxel spikes ({:.2} per taxel); transduction {:.1} M events/s, with reading the file {:.1} M events/s",
        c.events_in,
        c.after_filters,
        c.in_fields,
        c.taxel_events,
        c.taxel_events as f64 / layout.len() as f64,
        c.events_in as f64 / t.transducing.as_secs_f64() / 1e6,
        c.events_in as f64 / t.wall.as_secs_f64() / 1e6
    );
    println!("wrote {}", out.display());
    Ok(())
}

#[derive(Debug, Args)]
pub struct FilterArgs {
    /// Event file to read.
    input: PathBuf,
    /// Event file to write (format from its extension).
    output: PathBuf,
    /// Background-activity window, rounded to the µs (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_event_window, allow_negative_numbers = true, long, default_value = "5ms")]
    ba_window: Time,
    /// Start the BA time surface empty instead of at t = 0.
    #[arg(long)]
    ba_empty_start: bool,
    /// Also drop events within this refractory period of their own pixel's last event,
    /// rounded to the µs (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_event_window, allow_negative_numbers = true, long)]
    refractory: Option<Time>,
    #[command(flatten)]
    force: ForceOption,
}

pub fn run_filter(a: FilterArgs) -> anyhow::Result<()> {
    check_distinct(&a.input, &a.output)?;
    check_outputs([Output::file("OUTPUT", &a.output)], a.force.force)?;
    let start = Instant::now();
    let start_mode = ba_start(a.ba_empty_start);
    let c = filter_file(
        &a.input,
        &a.output,
        Replace::when(a.force.force),
        a.ba_window.us(),
        start_mode,
        a.refractory.map(Time::us),
    )?;
    if let Some(warning) = c.read.warning(&a.input) {
        eprintln!("{warning}");
    }
    let wall = start.elapsed().as_secs_f64();
    println!(
        "kept {} of {} events ({:.1} %) → {}; {:.1} M events/s",
        c.kept,
        c.seen,
        100.0 * c.kept as f64 / c.seen.max(1) as f64,
        a.output.display(),
        c.seen as f64 / wall / 1e6
    );
    Ok(())
}

#[derive(Debug, Args)]
#[command(mut_args(help("out", "Write the 49 centres as a JSON list of [x, y] (px)")))]
pub struct LayoutArgs {
    /// Calibration recording (any event file).
    input: PathBuf,
    /// Use the first this long of the recording (ms, or with a unit: 20ms, 0.02s); the default
    /// first second of a NeuroTac recording holds the press and the slide's onset, when every
    /// pin moves.
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, alias = "calibration-ms", default_value = "1s")]
    calibration: Time,
    /// Receptive-field radius (px); the paper's fields are 6 px in diameter.
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 3.0)]
    rf_radius_px: f64,
    #[command(flatten)]
    out: OutOption,
    #[command(flatten)]
    force: ForceOption,
}

pub fn run_layout(a: LayoutArgs) -> anyhow::Result<()> {
    let out = a.out.out.as_deref();
    if let Some(path) = out {
        check_distinct(&a.input, path)?;
    }
    check_outputs(out.map(|p| Output::file("--out", p)), a.force.force)?;
    let layout = layout_from(
        "auto",
        &a.input,
        a.calibration.ms(),
        a.rf_radius_px,
        Uncertain::Warn,
    )?;
    if let Some(path) = out {
        neurotac_core::io::write(path, layout.to_json(), Replace::when(a.force.force))
            .with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    } else {
        println!("{}", layout.to_json());
    }
    Ok(())
}
