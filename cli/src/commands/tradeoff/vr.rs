//! `neurotac tradeoff vr`: the exact Van Rossum distance against the distance of synaptic
//! traces sampled at `--trace-dts` in f64/f32, as LOO accuracy, distance error and matrix time,
//! on a simulated set (`--set`) or a labelled dataset (`--input`).

use crate::commands::args::{self, Time};
use crate::commands::inputs::load_labelled;
use crate::commands::outputs::cache_folder;
use clap::Args;
use neurotac_cli::tradeoff::vr::{VrTradeoffConfig, measure, to_markdown};
use neurotac_experiments::datasets::simulated::{TextureSet, load_or_simulate};
use neurotac_experiments::neuron_setup::Precision;
use neurotac_sensor::sim::SimParams;
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum VrSet {
    /// The 11 bump grids, 100 slides each (seed 1, from the cache or simulated).
    Artificial,
    /// The 20 natural textures, 50 slides each.
    Natural,
}

#[derive(Debug, Args)]
pub struct VrArgs {
    /// A simulated texture set (the paper's slide counts, seed 1, default cache).
    #[arg(
        long,
        value_enum,
        conflicts_with = "input",
        required_unless_present = "input"
    )]
    set: Option<VrSet>,
    /// A labelled spike dataset (JSON or binary) instead.
    #[arg(long)]
    input: Option<PathBuf>,
    /// Kernel time constant τ (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_tau, allow_negative_numbers = true, long, default_value = "76ms")]
    tau: Time,
    /// cos θ in [0, 1].
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long, default_value_t = 0.4)]
    cos: f64,
    /// Trace steps to try, whole µs each (ms, or with a unit: 20ms, 0.02s), comma-separated.
    #[arg(
        value_parser = args::time_step, allow_negative_numbers = true,
        long,
        value_delimiter = ',',
        default_value = "0.1,1,5,20"
    )]
    trace_dts: Vec<Time>,
    /// Trace arithmetic to try, comma-separated.
    #[arg(long, value_parser = args::menu::<Precision>(), value_delimiter = ',', default_value = "f64,f32")]
    precisions: Vec<Precision>,
    /// Use about this many samples (every ⌈N/samples⌉-th; default: all).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long)]
    samples: Option<usize>,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

pub fn run(args: VrArgs) -> anyhow::Result<()> {
    let data = match (&args.input, args.set) {
        (Some(path), _) => load_labelled(path)?,
        (None, set) => {
            let set = match set {
                Some(VrSet::Natural) => TextureSet::Natural,
                _ => TextureSet::Artificial,
            };
            load_or_simulate(
                set,
                set.paper_trials(),
                1,
                &SimParams::default(),
                &cache_folder(None, true),
                &|| {},
                &neurotac_core::OneProcess,
            )?
        }
    };
    let config = VrTradeoffConfig {
        tau_s: args.tau.s(),
        cos: args.cos,
        trace_dts_s: args.trace_dts.iter().map(|t| t.s()).collect(),
        precisions: args.precisions.clone(),
        samples: args.samples,
        ..VrTradeoffConfig::default()
    };
    let sweep = measure(&data, &config)?;
    if args.json {
        println!("{}", serde_json::to_string(&sweep)?);
    } else {
        println!("{}", to_markdown(&sweep));
    }
    Ok(())
}
