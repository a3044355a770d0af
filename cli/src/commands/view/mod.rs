//! `neurotac view`: a live page of the sensor — events, receptive fields, taxel rates, the
//! spike raster and, with `--train`, the recogniser's decisions — served on localhost from a
//! recording, the camera or the simulator; `--snapshot` draws the same page to a file.

mod recognition;
mod simulated;

use super::inputs::load_labelled;
use super::options::{ForceOption, SeedOption};
use super::outputs::{Output, cache_folder, check_outputs};
use crate::commands::args::{self, Time};
use anyhow::{Context, bail};
use clap::{ArgGroup, Args};
use neurotac_cli::report::png::PngRenderer;
use neurotac_core::SpikeDataset;
use neurotac_core::io::{Replace, check_distinct};
use neurotac_experiments::coding::{Coding, CodingName, CodingParameters};
use neurotac_experiments::datasets::metadata::transduction_of;
use neurotac_experiments::datasets::simulated::{TextureSet, load_or_simulate};
use neurotac_experiments::menu::Menu;
use neurotac_experiments::online::{OnlineClassifier, OnlineTraining};
use neurotac_experiments::reproduce::paper;
use neurotac_sensor::davis::{Davis, RusbTransport, StartOptions};
use neurotac_sensor::sim::SimParams;
use neurotac_sensor::taxel::{TaxelLayout, TransductionConfig};
use neurotac_view::{
    CameraSource, FileSource, Hub, MonitorConfig, NoObserver, Player, PlayerOptions, Server, Speed,
    StreamObserver, StreamSource, draw_frame, frame_at,
};
use recognition::Recognition;
use simulated::SimulatedSlides;
use std::io::Write as _;
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(group(ArgGroup::new("source").args(["input", "device", "simulate"]).required(true)))]
pub struct ViewArgs {
    /// Event file to show (AEDAT 2/3.1/4, ECD text, CSV).
    input: Option<PathBuf>,
    /// Show the first DAVIS240 attached over USB, live.
    #[arg(long)]
    device: bool,
    /// Show the bundled simulator's slides over this texture (e.g. "grid 5 mm", "tweed"; an unknown name lists them all),
    /// one after another.
    #[arg(long, value_name = "TEXTURE")]
    simulate: Option<String>,
    /// Replay speed of a recording or the simulator: `realtime`, a factor (`2`, `0.5x`) or
    /// `max`; the page can change it.
    #[arg(long, default_value = "realtime", value_parser = speed)]
    speed: Speed,
    /// Start paused at the first frame.
    #[arg(long)]
    paused: bool,
    /// Port of the page on --host (0: any free port; the address is printed).
    #[arg(long, default_value_t = 8240)]
    port: u16,
    /// Address to listen on (the page has no authentication: keep it on this machine unless
    /// the network is yours; a non-loopback address gets a warning). The page answers only
    /// requests naming localhost, 127.0.0.1, [::1] or this address.
    #[arg(long, default_value = "127.0.0.1")]
    host: String,
    /// Recognise the texture online with every coding: a labelled spike dataset (as
    /// `recognise --train`), or `artificial` / `natural` for the bundled simulated set (from
    /// the cache, simulated if missing; with --seed and --trials).
    #[arg(long, value_name = "DATASET")]
    train: Option<String>,
    /// With --train artificial|natural: slides per texture (default 20).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 20)]
    trials: usize,
    /// Neighbours of the recogniser.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 4)]
    k: usize,
    #[command(flatten)]
    seed: SeedOption,
    /// Instead of serving the page, draw it at --at to this file (`.svg`, or `.png`).
    #[arg(long, value_name = "FILE")]
    snapshot: Option<PathBuf>,
    /// With --snapshot: the stream time to draw (ms, or with a unit: 20ms, 0.02s); default
    /// the stream's end.
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, requires = "snapshot")]
    at: Option<Time>,
    #[command(flatten)]
    force: ForceOption,
    /// The cache of simulated datasets (for --train artificial|natural).
    #[arg(long)]
    cache: Option<PathBuf>,
}

fn speed(text: &str) -> Result<Speed, String> {
    Speed::parse(text).ok_or_else(|| {
        format!(
            "{text:?} is not a speed: realtime, max, or a factor from {:e} to {:e} such as 2, 0.5x",
            Speed::MIN_FACTOR,
            Speed::MAX_FACTOR
        )
    })
}

/// What `--train` names: a dataset, and the transduction it was made with.
struct Training {
    data: SpikeDataset,
    transduction: TransductionConfig,
}

pub fn run(a: ViewArgs) -> anyhow::Result<()> {
    if a.device && a.snapshot.is_some() {
        bail!("--snapshot draws a recording or a simulated slide, not the live camera");
    }
    let snapshot_kind = a.snapshot.as_deref().map(snapshot_kind).transpose()?;
    if let Some(out) = &a.snapshot {
        if let Some(input) = &a.input {
            check_distinct(input, out)?;
        }
        check_outputs([Output::file("--snapshot", out)], a.force.force)?;
    }
    let mut source = open_source(&a)?;
    let training = a.train.as_deref().map(|t| training(&a, t)).transpose()?;
    let transduction = match &training {
        // The stream is transduced as the training set was (with its own origin).
        Some(t) => TransductionConfig {
            origin_us: None,
            ..t.transduction
        },
        None => TransductionConfig::default(),
    };
    let monitor = MonitorConfig {
        transduction,
        ..MonitorConfig::default()
    };
    let layout = TaxelLayout::neurotac_default();
    let prepared = training
        .as_ref()
        .map(|t| OnlineTraining::new(&t.data, None))
        .transpose()
        .context("preparing the training set")?;
    let classifiers = match &prepared {
        Some(p) => CodingName::ALL
            .iter()
            .map(|&name| OnlineClassifier::new(p, paper_coding(name), a.k))
            .collect::<Result<Vec<_>, _>>()?,
        None => Vec::new(),
    };
    let mut recognition = match prepared {
        Some(_) => Some(Recognition::new(&classifiers, transduction, 5)?),
        None => None,
    };
    let observer: &mut dyn StreamObserver = match &mut recognition {
        Some(r) => r,
        None => &mut NoObserver,
    };
    if let Some(out) = &a.snapshot {
        let at_s = a.at.map(Time::s);
        let frame = frame_at(&mut *source, observer, &layout, monitor, at_s)?;
        let svg = draw_frame(&frame);
        let bytes = match snapshot_kind {
            Some(SnapshotKind::Png) => PngRenderer::new()
                .render(&svg, 1.5)
                .with_context(|| format!("drawing {}", out.display()))?,
            _ => svg.into_bytes(),
        };
        neurotac_core::io::write(out, bytes, Replace::when(a.force.force))
            .with_context(|| format!("writing {}", out.display()))?;
        println!(
            "wrote {} (t = {:.3} s: {} events, {} taxel spikes)",
            out.display(),
            frame.t_s,
            frame.counts.events_in,
            frame.counts.taxel_spikes
        );
        return Ok(());
    }
    serve(&a, &mut *source, observer, &layout, monitor)
}

/// Serves the page until Ctrl-C.
fn serve(
    a: &ViewArgs,
    source: &mut dyn StreamSource,
    observer: &mut dyn StreamObserver,
    layout: &TaxelLayout,
    monitor: MonitorConfig,
) -> anyhow::Result<()> {
    let hub = Hub::start();
    let server = match Server::bind(&a.host, a.port, hub.clone()) {
        Ok(server) => server,
        Err(e) if a.port != 0 => {
            bail!("{e} (another program has it? pass --port 0 for any free port)")
        }
        Err(e) => return Err(e.into()),
    };
    let address = server.local_addr();
    if !address.ip().is_loopback() {
        eprintln!(
            "warning: --host {} is not a loopback address: anyone who can reach {address} can watch the stream (and its file's path) and control it; the page has no login",
            a.host
        );
    }
    server.spawn();
    let stopper = hub.clone();
    ctrlc::set_handler(move || stopper.stop()).context("catching Ctrl-C")?;
    println!("serving http://{address}/ (Ctrl-C stops)");
    std::io::stdout().flush()?;
    let options = PlayerOptions {
        speed: a.speed,
        paused: a.paused,
        monitor,
    };
    let end = Player::new(source, observer, &hub, layout, options)?.run();
    println!("stopped after {} events", end.events);
    match end.failure {
        Some(why) => bail!("{why}"),
        None => Ok(()),
    }
}

/// What `--snapshot` writes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum SnapshotKind {
    Svg,
    Png,
}

/// The kind `--snapshot`'s extension names (in any case); another extension is refused.
fn snapshot_kind(out: &std::path::Path) -> anyhow::Result<SnapshotKind> {
    let extension = out.extension().and_then(|e| e.to_str()).unwrap_or("");
    match extension.to_ascii_lowercase().as_str() {
        "svg" => Ok(SnapshotKind::Svg),
        "png" => Ok(SnapshotKind::Png),
        _ => bail!(
            "--snapshot {}: the file must end in .svg or .png (the picture is written as one of them)",
            out.display()
        ),
    }
}

fn open_source(a: &ViewArgs) -> anyhow::Result<Box<dyn StreamSource>> {
    if let Some(input) = &a.input {
        let file = FileSource::open(input).map_err(|e| anyhow::anyhow!("{e}"))?;
        if let Some(size) = file.sensor_size()
            && size != (240, 180)
        {
            bail!(
                "{}: a {}×{} sensor; the view shows a DAVIS240's 240×180",
                input.display(),
                size.0,
                size.1
            );
        }
        return Ok(Box::new(file));
    }
    if let Some(texture) = &a.simulate {
        return Ok(Box::new(SimulatedSlides::new(
            texture,
            SimParams::default(),
            a.seed.seed,
        )?));
    }
    let (transport, usb) = RusbTransport::open_first()?;
    let davis = Davis::open(transport, usb).context("opening the DAVIS camera")?;
    let (w, h) = (davis.info().dvs_size_x, davis.info().dvs_size_y);
    if (w, h) != (240, 180) {
        bail!("the camera is {w}×{h}; the view shows a DAVIS240's 240×180");
    }
    let label = match &davis.info().usb.serial {
        Some(serial) => format!("DAVIS240 {serial} (live)"),
        None => "DAVIS240 (live)".to_owned(),
    };
    davis
        .send_default_config()
        .context("configuring the camera")?;
    let stream = davis.start(StartOptions::default())?;
    Ok(Box::new(CameraSource::new(label, stream)))
}

/// The paper's choices for the artificial textures (`reproduce::paper`, as `recognise`'s
/// defaults; not fitted here).
fn paper_coding(name: CodingName) -> Coding {
    Coding {
        name,
        parameters: CodingParameters {
            window_ms: Some(paper::DT_MS as u32),
            duration_ms: None,
            tau_s: Some(paper::TAU_MS / 1e3),
            cos: Some(paper::COS_THETA),
        },
    }
}

/// The training set `--train` names.
fn training(a: &ViewArgs, name: &str) -> anyhow::Result<Training> {
    let path = PathBuf::from(name);
    let set = match name {
        "artificial" if !path.exists() => Some(TextureSet::Artificial),
        "natural" if !path.exists() => Some(TextureSet::Natural),
        _ => None,
    };
    let data = match set {
        Some(set) => {
            let cache = cache_folder(a.cache.as_deref(), true);
            eprintln!(
                "training on the simulated {} set: {} slides per texture, seed {} (cache {})",
                set.name(),
                a.trials,
                a.seed.seed,
                cache.display()
            );
            load_or_simulate(
                set,
                a.trials,
                a.seed.seed,
                &SimParams::default(),
                &cache,
                &|| {},
                &neurotac_core::OneProcess,
            )?
        }
        None => load_labelled(&path)?,
    };
    let transduction = transduction_of(&data)?.with_context(|| {
        format!(
            "{name}: the dataset does not say how it was transduced (meta.transduction), so the stream cannot be transduced the same way"
        )
    })?;
    Ok(Training { data, transduction })
}
