//! `neurotac neuron`: one neuron under a constant current; prints its spike times as they are
//! found (streamed, so memory does not grow with the run).

use crate::commands::args;
use anyhow::{Context, bail};
use clap::Args;
use neurotac_core::Compact;
use neurotac_experiments::neuron_setup::{NeuronKind, NeuronSetup, Precision, PresetName};
use neurotac_neurons::{DEFAULT_MAX_STEPS, Integrator, stream_spike_times, whole_steps};
use std::io::Write;
use std::ops::ControlFlow;

#[derive(Debug, Args)]
pub struct NeuronArgs {
    /// Model.
    #[arg(long, value_parser = args::menu::<NeuronKind>(), default_value = "lif")]
    model: NeuronKind,
    /// Izhikevich preset: rs, ib, ch, fs, lts, tc, rz.
    #[arg(long, default_value = "rs")]
    preset: String,
    /// Constant input current (LIF: potential units; Izhikevich: mV/ms).
    #[arg(value_parser = args::finite_f64, allow_negative_numbers = true, long)]
    current: f64,
    /// Simulated duration (s). Only whole steps are run: a partial last step is refused, so no
    /// spike is ever stamped after the duration.
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 1.0)]
    duration: f64,
    /// Time step (s).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 1e-4)]
    dt: f64,
    /// Refuse runs of more steps than this.
    #[arg(long, default_value_t = DEFAULT_MAX_STEPS)]
    max_steps: u64,
    /// Integrator (default: exact for LIF, izhikevich2003 for Izhikevich).
    #[arg(long)]
    integrator: Option<Integrator>,
    /// Floating-point precision.
    #[arg(long, value_parser = args::menu::<Precision>(), default_value = "f64")]
    precision: Precision,
    /// Interpolate spike times inside the step (linear threshold crossing).
    #[arg(long)]
    interpolate: bool,
    /// Print `{"spike_times_s": [...]}` instead of one time per line.
    #[arg(long)]
    json: bool,
}

/// Refuses a value of `--flag` that overflows `precision` (only `f32` can: |x| > 3.4·10³⁸).
pub fn check_precision(flag: &str, value: f64, precision: Precision) -> anyhow::Result<()> {
    if precision == Precision::F32 && value.is_finite() && !(value as f32).is_finite() {
        bail!(
            "--{flag} {value:e} overflows f32 (largest magnitude {:e}); use --precision f64",
            f32::MAX
        );
    }
    Ok(())
}

/// `t_s` rounded to the picosecond (below 9000 s, where a double still holds it), so that a
/// spike at step 3 of 0.1 s prints as 0.3, not as the 0.30000000000000004 of `3 × 0.1`.
fn to_the_picosecond(t_s: f64) -> f64 {
    let ps = t_s * 1e12;
    if ps.abs() < 2f64.powi(53) {
        ps.round() / 1e12
    } else {
        t_s
    }
}

pub fn run(args: NeuronArgs) -> anyhow::Result<()> {
    let preset: PresetName = args.preset.parse()?;
    for (flag, value) in [
        ("current", args.current),
        ("duration", args.duration),
        ("dt", args.dt),
    ] {
        check_precision(flag, value, args.precision)?;
    }
    let steps = whole_steps(args.duration, args.dt, args.max_steps).with_context(|| {
        format!(
            "--duration {} --dt {} --max-steps {}",
            Compact(args.duration),
            Compact(args.dt),
            args.max_steps
        )
    })?;
    if (steps as f64 * args.dt - args.duration).abs() > 1e-9 * args.duration {
        eprintln!(
            "note: {steps} whole steps of {} s fit in {} s; simulating {} s",
            args.dt,
            args.duration,
            steps as f64 * args.dt
        );
    }
    let setup = NeuronSetup {
        preset: Some(preset),
        integrator: args.integrator.unwrap_or(args.model.default_integrator()),
        interpolate: args.interpolate,
        ..NeuronSetup::single(args.model, args.precision)
    };
    let mut pop = setup.population(1);
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    let mut written: std::io::Result<()> = Ok(());
    let mut first = true;
    if args.json {
        out.write_all(b"{\"spike_times_s\":[")?;
    }
    stream_spike_times(pop.as_mut(), args.current, args.dt, steps, &mut |_, t| {
        let t = to_the_picosecond(t);
        written = if args.json {
            let sep = if first { "" } else { "," };
            serde_json::to_string(&t)
                .map_err(std::io::Error::other)
                .and_then(|t| write!(out, "{sep}{t}"))
        } else {
            writeln!(out, "{t}")
        };
        first = false;
        if written.is_ok() {
            ControlFlow::Continue(())
        } else {
            ControlFlow::Break(())
        }
    })?;
    written?;
    if args.json {
        out.write_all(b"]}\n")?;
    }
    out.flush()?;
    Ok(())
}
