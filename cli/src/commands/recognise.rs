//! `neurotac recognise`: online texture recognition while the sensor slides — from an event
//! file or the live camera, one line per decision change and a final line — and
//! `recognise --eval`: accuracy against time since the slide start on a simulated set.

use super::inputs::load_labelled;
use super::options::{ForceOption, OutOption, SeedOption, SetArg, SetOption, ThreadsOption, help};
use super::outputs::{Output, cache_folder, check_outputs, refuse_nested};
use crate::commands::args::{self, Time};
use anyhow::{Context, bail};
use clap::{ArgGroup, Args, ValueEnum};
use neurotac_cli::report::folder::{write, write_csv, write_figure, write_folder_atomically};
use neurotac_cli::report::png::PngRenderer;
use neurotac_cli::report::svg::{Axis, Chart, Marker, PALETTE, Series};
use neurotac_core::io::csv;
use neurotac_experiments::afferents::AfferentConfig;
use neurotac_experiments::coding::{Coding, CodingName, CodingParameters};
use neurotac_experiments::datasets::metadata::transduction_of;
use neurotac_experiments::datasets::simulated::TextureSet;
use neurotac_experiments::menu::Menu;
use neurotac_experiments::neuron_setup::NeuronKind;
use neurotac_experiments::online::eval::{OnlineEval, OnlineEvalConfig, evaluate_online};
use neurotac_experiments::online::{
    Decision, OnlineClassifier, OnlineTraining, Recogniser, ReplaySpeed, latency_percentiles,
    recognise_stream, replay,
};
use neurotac_experiments::threads::with_threads;
use neurotac_sensor::davis::{Davis, RusbTransport, StartOptions};
use neurotac_sensor::sim::SimParams;
use neurotac_sensor::taxel::TransductionConfig;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum SpeedArg {
    /// As recorded.
    Realtime,
    /// As fast as possible.
    Max,
}

#[derive(Debug, Args)]
#[command(
    mut_args(help("set", "With --eval: the texture set")),
    mut_args(help("seed", "With --eval: seed of the dataset and of the split")),
    mut_args(help(
        "out",
        "With --eval: the report folder (summary.md, summary.json, accuracy_vs_time.csv/.svg/.png)"
    )),
    mut_args(help("force", "Replace an existing --out folder")),
    // One source: clap's error for none names all three (`<--input <INPUT>|--device|--eval>`).
    group(ArgGroup::new("source").args(["input", "device", "eval"]).required(true)),
    mut_args(help(
        "threads",
        "With --eval: worker threads over the held-out slides (0 = one per core); each slide's decisions run on one thread"
    ))
)]
pub struct RecogniseArgs {
    /// Labelled spike dataset of training slides (JSON or binary), transduced with the
    /// settings stored in its metadata (those of `neurotac simulate` / `transduce`).
    #[arg(long, required_unless_present = "eval")]
    train: Option<PathBuf>,
    /// Coding to classify with (default spatial; with --eval every coding is evaluated).
    #[arg(long, value_parser = args::menu::<CodingName>())]
    coding: Option<CodingName>,
    /// Event file to replay (AEDAT 2/3.1/4, ECD text, CSV).
    #[arg(long)]
    input: Option<PathBuf>,
    /// Recognise from the first DAVIS240 attached over USB.
    #[arg(long)]
    device: bool,
    /// Replay speed of --input.
    #[arg(long, value_enum, default_value = "max")]
    speed: SpeedArg,
    /// Run the taxel spikes through a population of afferent neurons (one per taxel), in
    /// training and online alike.
    #[arg(long, value_parser = args::menu::<NeuronKind>())]
    afferents: Option<NeuronKind>,
    /// Print every window's decision as a JSON line, then the final decision.
    #[arg(long)]
    json: bool,
    /// Temporal-coding window Δt, a whole number of ms (ms, or with a unit: 20ms, 0.02s).
    /// Default 159 ms, the paper's choice for the artificial textures (not fitted here).
    #[arg(value_parser = args::time_window, allow_negative_numbers = true, long, default_value = "159ms")]
    dt: Time,
    /// Van Rossum τ (ms, or with a unit: 20ms, 0.02s). Default 76 ms, the paper's choice for
    /// the artificial textures.
    #[arg(value_parser = args::time_tau, allow_negative_numbers = true, long, default_value = "76ms")]
    tau: Time,
    /// Van Rossum cos θ. Default 0.4, the paper's choice for the artificial textures.
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long, default_value_t = 0.4)]
    cos: f64,
    /// Neighbours.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 4)]
    k: usize,
    /// Windows (20 ms each) a class must hold to be reported stable.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 5)]
    stable: usize,
    /// Instead: train on 80 % of a simulated set and replay the held-out slides' pixel events
    /// through the online path with every coding (needs --set and --out).
    #[arg(long, requires_all = ["set", "out"])]
    eval: bool,
    #[command(flatten)]
    set: SetOption,
    /// With --eval: slides per texture (default: the paper's, 100 artificial / 50 natural).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long)]
    trials: Option<usize>,
    #[command(flatten)]
    seed: SeedOption,
    #[command(flatten)]
    out: OutOption,
    #[command(flatten)]
    force: ForceOption,
    #[command(flatten)]
    threads: ThreadsOption,
    /// With --eval: the cache of simulated datasets (as `reproduce`).
    #[arg(long)]
    cache: Option<PathBuf>,
}

impl RecogniseArgs {
    /// `name` with the parameters of the flags (each coding reads only its own).
    fn coding(&self, name: CodingName) -> anyhow::Result<Coding> {
        let parameters = CodingParameters {
            window_ms: Some(self.dt.whole_ms("--dt")?),
            duration_ms: None,
            tau_s: Some(self.tau.s()),
            cos: Some(self.cos),
        };
        Ok(Coding { name, parameters })
    }
}

pub fn run(a: RecogniseArgs) -> anyhow::Result<()> {
    if a.eval {
        return run_eval(&a);
    }
    let path = a.train.as_ref().expect("clap requires --train");
    let data = load_labelled(path)?;
    if let Some(unit) = data.meta().get("time_unit").and_then(|u| u.as_str())
        && unit != "s"
    {
        bail!(
            "{}: spike times are in '{unit}', but recognition compares them with the stream in seconds",
            path.display()
        );
    }
    let transduction = transduction_of(&data)?.with_context(|| {
        format!(
            "{}: the dataset does not say how it was transduced (meta.transduction), so the stream cannot be transduced the same way",
            path.display()
        )
    })?;
    let coding = a.coding(a.coding.unwrap_or(CodingName::Spatial))?;
    let training = OnlineTraining::new(&data, a.afferents.map(AfferentConfig::of))
        .with_context(|| format!("preparing the training set {}", path.display()))?;
    // A live stream has its own origin: its first event.
    let stream_transduction = TransductionConfig {
        origin_us: None,
        ..transduction
    };
    let classifier = OnlineClassifier::new(&training, coding, a.k)?;
    let mut recogniser = Recogniser::new(&classifier, stream_transduction, a.stable)?;
    if !a.json {
        println!(
            "training: {} slides of {} textures ({} ms each); {} coding{}; k = {}; a decision every {} ms",
            training.len(),
            training.class_names().len(),
            training.duration_ms(),
            coding.name,
            match coding.describe_parameters() {
                p if p.is_empty() => String::new(),
                p => format!(" ({p})"),
            },
            a.k,
            transduction.pool_window_us / 1000
        );
    }
    let names = training.class_names().to_vec();
    // What a decision says: its class, or that the vote was a tie.
    let said = |d: &Decision| -> String {
        match d.tie {
            true => TIE.into(),
            false => names[d.class].clone(),
        }
    };
    let (json, stable) = (a.json, a.stable);
    let mut last_class: Option<(Option<usize>, bool)> = None;
    let mut print = |d: &Decision| {
        if json {
            println!("{}", decision_json(d, &names));
            return;
        }
        // One line per change of class (a tie counts as one), and one when it becomes stable.
        let class = (!d.tie).then_some(d.class);
        let changed = last_class.map(|l| l.0) != Some(class);
        let newly_stable = d.stable && last_class != Some((class, true));
        if changed || newly_stable {
            println!(
                "{:8.3} s  {:<24} vote {:>3.0} %{}",
                d.t_s,
                said(d),
                100.0 * d.vote_share,
                if d.stable {
                    format!("  stable for {stable} windows")
                } else {
                    String::new()
                }
            );
        }
        last_class = Some((class, d.stable));
    };
    let result = if a.device {
        let (transport, usb) = RusbTransport::open_first()?;
        let davis = Davis::open(transport, usb).context("opening the DAVIS camera")?;
        let (w, h) = (davis.info().dvs_size_x, davis.info().dvs_size_y);
        check_size(&transduction, (w, h), "the camera")?;
        davis
            .send_default_config()
            .context("configuring the camera")?;
        let mut stream = davis.start(StartOptions::default())?;
        recognise_stream(&mut recogniser, &mut stream, &mut print)
            .context("recognising from the camera")
    } else {
        let input = a.input.as_ref().expect("clap requires --input or --device");
        let mut reader = neurotac_sensor::format::open_reader(input)?;
        if let Some(size) = reader.sensor_size() {
            check_size(&transduction, size, &input.display().to_string())?;
        }
        let speed = match a.speed {
            SpeedArg::Realtime => ReplaySpeed::Realtime,
            SpeedArg::Max => ReplaySpeed::Max,
        };
        replay(&mut recogniser, &mut *reader, speed, &mut print)
            .with_context(|| format!("recognising {}", input.display()))
    };
    let decisions = recogniser.decisions();
    let last = match result {
        Ok(last) => last,
        Err(e) => {
            // What was decided so far is kept and said.
            if let Some(d) = decisions.last() {
                eprintln!(
                    "decided so far: {} (vote {:.0} %) at {:.3} s after {} windows",
                    said(d),
                    100.0 * d.vote_share,
                    d.t_s,
                    decisions.len()
                );
            }
            return Err(e);
        }
    };
    if a.json {
        println!(
            "{}",
            serde_json::json!({ "final": decision_json(&last, &names) })
        );
        return Ok(());
    }
    let latency = latency_percentiles(decisions).unwrap_or_default();
    println!(
        "final: {} (vote {:.0} %) after {} windows; decision latency p50 {:.3} ms, p99 {:.3} ms, max {:.3} ms{}",
        said(&last),
        100.0 * last.vote_share,
        decisions.len(),
        latency.p50_ms,
        latency.p99_ms,
        latency.max_ms,
        match recogniser.events_dropped() {
            0 => String::new(),
            n => format!(
                "; {n} events after the training slides' {} ms were not used",
                training.duration_ms()
            ),
        }
    );
    Ok(())
}

/// The training set's sensor size must be the stream's.
fn check_size(t: &TransductionConfig, size: (u16, u16), what: &str) -> anyhow::Result<()> {
    if (t.width, t.height) != size {
        bail!(
            "the training set was transduced for a {}×{} sensor, but {what} is {}×{}",
            t.width,
            t.height,
            size.0,
            size.1
        );
    }
    Ok(())
}

/// What a tied decision is printed as.
const TIE: &str = "tie (no class yet)";

/// One decision as a JSON line: its class and name (the tie-rule pick when `tie` is true).
fn decision_json(d: &Decision, names: &[String]) -> serde_json::Value {
    serde_json::json!({
        "t_s": d.t_s,
        "class": d.class,
        "class_name": names[d.class],
        "vote_share": d.vote_share,
        "tie": d.tie,
        "same_for_windows": d.same_for_windows,
        "stable": d.stable,
        "latency_s": d.latency_s,
    })
}

fn run_eval(a: &RecogniseArgs) -> anyhow::Result<()> {
    let out = a.out.out.as_ref().expect("clap requires --out");
    let cache = cache_folder(a.cache.as_deref(), true);
    neurotac_experiments::afferents::use_crossovers_in(&cache);
    refuse_nested([out.as_path()], &[cache.as_path()])?;
    check_outputs([Output::folder("--out", out)], a.force.force)?;
    let set = match a.set.set.expect("clap requires --set") {
        SetArg::Artificial => TextureSet::Artificial,
        SetArg::Natural => TextureSet::Natural,
        SetArg::Both => bail!("--eval runs one set at a time: --set artificial or natural"),
    };
    let codings = match a.coding {
        Some(c) => vec![a.coding(c)?],
        None => CodingName::ALL
            .iter()
            .map(|&c| a.coding(c))
            .collect::<anyhow::Result<_>>()?,
    };
    let config = OnlineEvalConfig {
        set,
        trials: a.trials.unwrap_or_else(|| set.paper_trials()),
        seed: a.seed.seed,
        params: SimParams::default(),
        codings,
        k: a.k,
        stable_windows: a.stable,
        test_fraction: 0.2,
    };
    let bar = super::progress::bar(
        "held-out slides",
        (config.trials as f64 * set.textures().len() as f64 * 0.2).round() as u64,
        "slides",
    );
    let eval = with_threads(a.threads.threads, || {
        evaluate_online(&config, &cache, &|| bar.inc(1))
    })??;
    bar.finish_and_clear();
    let summary = summary_md(&eval);
    let mut json = serde_json::to_value(&eval)?;
    json["files"] = serde_json::json!(EVAL_FILES);
    write_folder_atomically(out, a.force.force, |dir| {
        write(dir, "summary.md", &summary)?;
        write(
            dir,
            "summary.json",
            &serde_json::to_string_pretty(&json).expect("serialisable"),
        )?;
        write_csv(dir, "accuracy_vs_time.csv", accuracy_csv(&eval))?;
        write_figure(
            dir,
            "accuracy_vs_time",
            &accuracy_chart(&eval).to_svg(),
            &PngRenderer::new(),
        )
    })?;
    print!("{summary}");
    println!("written to {}", out.display());
    Ok(())
}

/// Every file `recognise --eval` writes into its report folder, as the summaries list them.
const EVAL_FILES: [&str; 5] = [
    "summary.md",
    "summary.json",
    "accuracy_vs_time.csv",
    "accuracy_vs_time.svg",
    "accuracy_vs_time.png",
];

fn summary_md(e: &OnlineEval) -> String {
    let mut s = format!(
        "# Online recognition, {} set\n\nTrained on {} slides, {} held-out slides replayed as pixel events through the online path (transducer → taxel input → readout → KNN, k = {}); a decision after every 20 ms window.\n\n| coding | parameters | final accuracy | reaches 90 % of it at | decision latency p50 / p99 / max | replay speed |\n|---|---|---|---|---|---|\n",
        e.set, e.n_train, e.n_test, e.k
    );
    for c in &e.codings {
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} % | {} | {:.3} / {:.3} / {:.3} ms | {:.0}× real time |",
            c.coding,
            c.parameters,
            100.0 * c.final_accuracy,
            c.t90_s.map_or("never".into(), |t| format!("{:.2} s", t)),
            c.latency.p50_ms,
            c.latency.p99_ms,
            c.latency.max_ms,
            c.replay_speed
        );
    }
    s.push_str("\nAccuracy against the time since the slide start: `accuracy_vs_time.csv`, `accuracy_vs_time.svg`, `accuracy_vs_time.png`.\n\nFiles written: ");
    s.push_str(&EVAL_FILES.map(|f| format!("`{f}`")).join(", "));
    s.push_str(".\n");
    s
}

/// `accuracy_vs_time.csv`: per window end (`t_s`), the accuracy of each coding (a column each).
fn accuracy_csv(e: &OnlineEval) -> Result<String, csv::Error> {
    let header = std::iter::once("t_s").chain(e.codings.iter().map(|c| c.coding));
    let rows = e.window_end_s.iter().enumerate().map(|(w, t)| {
        std::iter::once(format!("{t:.3}")).chain(
            e.codings
                .iter()
                .map(move |c| format!("{:.4}", c.accuracy[w])),
        )
    });
    csv::table(header, rows)
}

fn accuracy_chart(e: &OnlineEval) -> Chart {
    Chart {
        title: format!("{}: online accuracy ({} held-out slides)", e.set, e.n_test),
        x: Axis::linear("time since slide start (s)"),
        y: Axis::linear("accuracy (%)"),
        series: e
            .codings
            .iter()
            .enumerate()
            .map(|(i, c)| Series {
                label: c.coding.into(),
                points: e
                    .window_end_s
                    .iter()
                    .zip(&c.accuracy)
                    .map(|(&t, &a)| (t, 100.0 * a))
                    .collect(),
                color: PALETTE[i % PALETTE.len()].into(),
                marker: Marker::None,
                filled: false,
                line: true,
                y_ranges: Vec::new(),
            })
            .collect(),
    }
}
