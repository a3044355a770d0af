//! `neurotac bench stdp`: Song, Miller & Abbott's Fig. 1 network (Poisson inputs → one LIF
//! neuron through additive STDP; `neurotac_experiments::song_abbott`) and, with `--brian2`,
//! Brian2's run of the same equations: final weights compared (two-sample KS, shares near each
//! bound), the speed ratio, and a figure.

use super::peer_runs::{PeerCase, add_peer, fastest_interleaved, print};
use crate::commands::args::{self, Time};
use crate::commands::options::{ForceOption, SeedOption, help};
use crate::commands::outputs::{Output, check_outputs};
use anyhow::Context;
use clap::Args;
use neurotac_cli::budget;
use neurotac_cli::peers::StdpPeerResult;
use neurotac_cli::report::figures::{StdpRunView, song_abbott_figure};
use neurotac_cli::report::png::PngRenderer;
use neurotac_core::io::{Replace, write};
use neurotac_experiments::neuron_setup::Precision;
use neurotac_experiments::song_abbott::{
    self, SongAbbottConfig, W_MAX_MV, compare_weights, final_rate_hz,
};
use neurotac_neurons::Integrator;
use serde_json::json;
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(mut_args(help("seed", "Seed of the initial weights and of the Poisson inputs")))]
pub(super) struct StdpArgs {
    /// Simulated duration (ms, or with a unit: 20ms, 0.02s; Brian2's example: 100s).
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, default_value = "100s")]
    duration: Time,
    /// Time step (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_step, allow_negative_numbers = true, long, default_value = "0.1ms")]
    dt: Time,
    /// Poisson inputs, each with one plastic synapse onto the neuron.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 1000)]
    inputs: usize,
    /// Rate of every input (Hz).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 15.0)]
    rate: f64,
    #[command(flatten)]
    seed: SeedOption,
    /// Also run the same network in Brian2 (C++ standalone, float64, exponential_euler, one
    /// thread) with this Python: final weights compared (two-sample KS), speed ratio.
    #[arg(long, value_name = "PYTHON")]
    brian2: Option<PathBuf>,
    /// Runs of each side, interleaved; the fastest of each is reported (every run of a side
    /// ends with the same weights: both are seeded).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 1)]
    repeats: usize,
    /// Draw the final weight histograms (and the output rate over time) of each side to this
    /// file, SVG or PNG by its extension.
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    figure: Option<PathBuf>,
    #[command(flatten)]
    force: ForceOption,
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
}

pub(super) fn run(a: StdpArgs) -> anyhow::Result<()> {
    // Refusals before any work: the figure's format and path, then the size of the run.
    let png = match &a.figure {
        None => false,
        Some(path) => {
            let png = match path.extension().and_then(|e| e.to_str()) {
                Some("png") => true,
                Some("svg") => false,
                _ => anyhow::bail!(
                    "--figure {}: the figure is written as SVG or PNG, name it FILE.svg or \
                     FILE.png",
                    path.display()
                ),
            };
            check_outputs([Output::file("--figure", path)], a.force.force)?;
            png
        }
    };
    let steps = budget::steps(a.duration.s(), a.dt.s())?;
    budget::at_most(
        "--inputs",
        a.inputs as f64,
        "input draws (--inputs × steps)",
        a.inputs as f64 * steps as f64,
        budget::MAX_UPDATES,
    )?;
    let config = SongAbbottConfig {
        inputs: a.inputs,
        rate_hz: a.rate,
        duration_s: a.duration.s(),
        dt_s: a.dt.s(),
        seed: a.seed.seed,
    };
    // neurotac: f64, v exact with the synaptic current held over each step and the current
    // decayed exactly, which is Brian2's exponential_euler on these equations.
    let (precision, method) = ("float64", Integrator::ExponentialEuler.name());
    let case = a.brian2.as_deref().map(|python| PeerCase {
        python,
        args: vec![
            "stdp".into(),
            config.duration_s.to_string(),
            config.dt_s.to_string(),
            precision.into(),
            method.into(),
            config.inputs.to_string(),
            config.rate_hz.to_string(),
            config.seed.to_string(),
        ],
        precision,
        method,
    });
    let ours = || song_abbott::run(&config).map_err(anyhow::Error::from);
    let (r, peer) =
        fastest_interleaved::<_, StdpPeerResult>(a.repeats, ours, |r| r.run_s, case.as_ref())?;
    let bounds = r.bounds();
    let mut report = json!({
        "inputs": config.inputs,
        "rate_hz": config.rate_hz,
        "duration_s": r.duration_s,
        "dt_s": config.dt_s,
        "seed": config.seed,
        "precision": Precision::F64,
        "method": method,
        "w_max_mv": W_MAX_MV,
        "build_s": r.build_s,
        "run_s": r.run_s,
        "spikes": r.spike_times_s.len(),
        "final_rate_hz": r.final_rate_hz(),
        "near_zero": bounds.near_zero,
        "near_max": bounds.near_max,
    });
    let line = format!(
        "Song–Abbott STDP (f64, {method}): {} Poisson inputs at {} Hz → 1 LIF, {} s simulated \
         in {:.4} s (build {:.3} s); {} output spikes, {:.1} Hz in the last tenth; final \
         weights within 10 % of 0: {:.1} %, of w_max = {W_MAX_MV} mV: {:.1} %",
        config.inputs,
        config.rate_hz,
        r.duration_s,
        r.run_s,
        r.build_s,
        r.spike_times_s.len(),
        r.final_rate_hz(),
        100.0 * bounds.near_zero,
        100.0 * bounds.near_max
    );
    let mut after = Vec::new();
    if let (Some(peer), Some(case)) = (&peer, &case) {
        add_peer(&mut report, &peer.run, case, r.run_s, r.duration_s);
        let c = compare_weights(&r.weights, &peer.weights)?;
        let peer_rate = final_rate_hz(&peer.spike_times_s, r.duration_s);
        report["peer_final_rate_hz"] = json!(peer_rate);
        report["peer_near_zero"] = json!(c.peer.near_zero);
        report["peer_near_max"] = json!(c.peer.near_max);
        report["ks"] = json!(c.ks);
        report["input_draws"] = json!({
            "neurotac": "one per spike (each input's geometric gap to its next spike)",
            "peer": "one per input and step (PoissonGroup)",
        });
        after.push(
            "inputs: neurotac draws each input's gap to its next spike (one draw per spike), \
             Brian2's PoissonGroup one number per input and step: the same law, not the same \
             work (with per-step draws neurotac was 1.9× Brian2, README \"Learning against \
             Brian2\")"
                .to_owned(),
        );
        after.push(format!(
            "{}: {:.1} Hz in the last tenth; final weights within 10 % of 0: {:.1} %, of w_max: \
             {:.1} %",
            peer.run.peer,
            peer_rate,
            100.0 * c.peer.near_zero,
            100.0 * c.peer.near_max
        ));
        after.push(format!(
            "final weights, two-sample Kolmogorov–Smirnov: D = {:.4}, p = {:.3} (n = {}, {})",
            c.ks.statistic, c.ks.p_value, c.ks.n_a, c.ks.n_b
        ));
    }
    if let Some(path) = &a.figure {
        let mut runs = vec![StdpRunView {
            label: "neurotac",
            weights: &r.weights,
            spike_times_s: &r.spike_times_s,
        }];
        if let Some(peer) = &peer {
            runs.push(StdpRunView {
                label: &peer.run.peer,
                weights: &peer.weights,
                spike_times_s: &peer.spike_times_s,
            });
        }
        let svg = song_abbott_figure(&runs, r.duration_s);
        let bytes = match png {
            true => PngRenderer::new()
                .render(&svg, 1.5)
                .with_context(|| format!("drawing {}", path.display()))?,
            false => svg.into_bytes(),
        };
        write(path, bytes, Replace::when(a.force.force))
            .with_context(|| format!("writing {}", path.display()))?;
        report["figure"] = json!(path);
        after.push(format!("wrote {}", path.display()));
    }
    print(&report, a.json, line);
    if !a.json {
        after.iter().for_each(|l| println!("{l}"));
    }
    Ok(())
}
