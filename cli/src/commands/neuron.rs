//! `neurotac neuron`: one neuron under a constant current; prints its spike times as they are
//! found (streamed, so memory does not grow with the run). With `--json` the times are kept
//! and the object is printed whole once the run has succeeded, so a refused or diverged run
//! prints nothing on stdout rather than half an object.

use crate::commands::args::{self, Time};
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
    /// Simulated duration (ms, or with a unit: 20ms, 0.02s). Only whole steps are run: a
    /// partial last step is refused, so no spike is ever stamped after the duration.
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, default_value = "1s")]
    duration: Time,
    /// Time step (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_step, allow_negative_numbers = true, long, default_value = "0.1ms")]
    dt: Time,
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
    /// Print `{"spike_times_s": [...]}` (seconds) instead of one time per line (`11 ms`: the
    /// unit the time flags read bare).
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

/// `t_s` in milliseconds, the unit the time flags read bare, rounded to the picosecond as
/// [`to_the_picosecond`] (a spike at step 110 of 0.1 ms prints as 11, not 11.000000000000002).
fn in_ms(t_s: f64) -> f64 {
    let ps = t_s * 1e12;
    if ps.abs() < 2f64.powi(53) {
        ps.round() / 1e9
    } else {
        t_s * 1e3
    }
}

pub fn run(args: NeuronArgs) -> anyhow::Result<()> {
    let preset: PresetName = args.preset.parse()?;
    check_precision("current", args.current, args.precision)?;
    let (duration_s, dt_s) = (args.duration.s(), args.dt.s());
    let steps = whole_steps(duration_s, dt_s, args.max_steps).with_context(|| {
        format!(
            "--duration {} --dt {} --max-steps {}",
            args.duration, args.dt, args.max_steps
        )
    })?;
    if (steps as f64 * dt_s - duration_s).abs() > 1e-9 * duration_s {
        eprintln!(
            "note: {steps} whole steps of {} fit in {}; simulating {} s",
            args.dt,
            args.duration,
            Compact(steps as f64 * dt_s)
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
    let mut times = Vec::new();
    stream_spike_times(pop.as_mut(), args.current, dt_s, steps, &mut |_, t| {
        written = match args.json {
            true => {
                times.push(to_the_picosecond(t));
                Ok(())
            }
            false => writeln!(out, "{} ms", in_ms(t)),
        };
        match written.is_ok() {
            true => ControlFlow::Continue(()),
            false => ControlFlow::Break(()),
        }
    })?;
    written?;
    if args.json {
        let object = serde_json::json!({ "spike_times_s": times });
        writeln!(out, "{object}")?;
    }
    out.flush()?;
    Ok(())
}
