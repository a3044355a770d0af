//! `neurotac demo`: 49 taxels (Poisson spike trains) → exponential synapses → 49 afferents.

use super::options::{SeedOption, help};
use crate::commands::args::{self, Time};
use anyhow::Context;
use clap::Args;
use neurotac_core::PoissonInput;
use neurotac_experiments::afferents::{AfferentConfig, build_afferent_network};
use neurotac_experiments::neuron_setup::NeuronKind;

#[derive(Debug, Args)]
#[command(mut_args(help("seed", "Seed of the taxel spike trains")))]
pub struct DemoArgs {
    /// Afferent model.
    #[arg(long, value_parser = args::menu::<NeuronKind>(), default_value = "lif")]
    model: NeuronKind,
    /// Number of taxels (the NeuroTac has 49).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 49)]
    taxels: usize,
    /// Firing rate of each taxel's Poisson spike train (Hz).
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 20.0)]
    rate_hz: f64,
    /// Simulated duration (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long, default_value = "1s")]
    duration: Time,
    #[command(flatten)]
    seed: SeedOption,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

pub fn run(args: DemoArgs) -> anyhow::Result<()> {
    let config = AfferentConfig::of(args.model);
    let source = PoissonInput::new(args.taxels, args.rate_hz, args.seed.seed);
    let mut net =
        build_afferent_network(source, config).context("building the afferent network")?;
    let start = std::time::Instant::now();
    net.network
        .run(args.duration.s(), &neurotac_core::OneProcess)
        .context("running the afferent network")?;
    let wall_s = start.elapsed().as_secs_f64();
    let inputs = net.network.readout(net.taxel_spikes)?.counts();
    let counts = net.network.readout(net.spikes)?.counts();
    let (total_in, total): (usize, usize) = (inputs.iter().sum(), counts.iter().sum());
    if args.json {
        let out = serde_json::json!({
            "model": format!("{:?}", args.model).to_lowercase(),
            "taxels": args.taxels,
            "duration_s": args.duration.s(),
            "taxel_spike_counts": inputs,
            "afferent_spike_counts": counts,
            "total_taxel_spikes": total_in,
            "total_afferent_spikes": total,
            "afferent_spikes_per_taxel_spike": total as f64 / total_in.max(1) as f64,
            "wall_s": wall_s,
        });
        println!("{out}");
    } else {
        println!(
            "{} taxels at {} Hz → {} {:?} afferents, {} s simulated in {:.3} s",
            args.taxels,
            args.rate_hz,
            args.taxels,
            args.model,
            args.duration.s(),
            wall_s
        );
        println!("  neuron   taxel spikes → afferent spikes");
        for (i, (a, b)) in inputs.iter().zip(&counts).enumerate() {
            println!("  {i:6}   {a:12} → {b}");
        }
        println!("  total    {total_in:12} → {total}");
        println!(
            "{:.2} afferent spikes per taxel spike (a lone taxel spike makes exactly one; spikes \
             closer than ≈ 10 ms interact — see neurotac_experiments::afferents)",
            total as f64 / total_in.max(1) as f64
        );
    }
    Ok(())
}
