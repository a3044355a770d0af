//! `neurotac neuron`: one neuron under a constant current; prints its spike times.

use crate::cli::args;
use anyhow::bail;
use clap::Args;
use neurotac_experiments::neuron_setup::{NeuronKind, NeuronSetup, Precision};
use neurotac_neurons::{Integrator, IzhikevichParams};

#[derive(Debug, Args)]
pub struct NeuronArgs {
    /// Model.
    #[arg(long, value_enum, default_value = "lif")]
    model: NeuronKind,
    /// Izhikevich preset: rs, ib, ch, fs, lts, tc, rz.
    #[arg(long, default_value = "rs")]
    preset: String,
    /// Constant input current (LIF: potential units; Izhikevich: mV/ms).
    #[arg(value_parser = args::finite_f64, allow_negative_numbers = true, long)]
    current: f64,
    /// Simulated duration (s).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 1.0)]
    duration: f64,
    /// Time step (s).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 1e-4)]
    dt: f64,
    /// Integrator (default: exact for LIF, izhikevich2003 for Izhikevich).
    #[arg(long)]
    integrator: Option<Integrator>,
    /// Floating-point precision.
    #[arg(long, value_enum, default_value = "f64")]
    precision: Precision,
    /// Interpolate spike times inside the step (linear threshold crossing).
    #[arg(long)]
    interpolate: bool,
    /// Print `{"spike_times_s": [...]}` instead of one time per line.
    #[arg(long)]
    json: bool,
}

pub fn run(args: NeuronArgs) -> anyhow::Result<()> {
    let Some(preset) = IzhikevichParams::named(&args.preset) else {
        bail!(
            "unknown Izhikevich preset '{}' (expected rs, ib, ch, fs, lts, tc or rz)",
            args.preset
        );
    };
    if !(args.duration.is_finite() && args.duration >= 0.0) {
        bail!("--duration {} must be finite and ≥ 0", args.duration);
    }
    let setup = NeuronSetup {
        preset,
        integrator: args.integrator.unwrap_or(args.model.default_integrator()),
        interpolate: args.interpolate,
        ..NeuronSetup::single(args.model, args.precision)
    };
    let times = setup.spike_times(args.current, args.dt, args.duration)?;
    if args.json {
        println!("{}", serde_json::json!({ "spike_times_s": times }));
    } else {
        times.iter().for_each(|t| println!("{t}"));
    }
    Ok(())
}
