//! `neurotac search vr`: Bayesian optimisation of the spatiotemporal coding's (τ, cos θ).

use crate::commands::args::{self, Time};
use crate::commands::inputs::load_labelled;
use crate::commands::options::{ForceOption, SeedOption, help};
use crate::commands::outputs::{Output, check_outputs};
use anyhow::Context;
use clap::Args;
use neurotac_core::{Knn, Ranks};
use neurotac_experiments::search::bayes::{
    BayesConfig, VanRossumInput, VanRossumObjective, bayes_optimise,
};
use neurotac_experiments::timing::timed;
use std::path::PathBuf;

#[derive(Debug, Args)]
#[command(mut_args(help("seed", "Seed of the initial design")))]
pub struct VrArgs {
    /// Spike dataset (JSON or binary), labelled.
    #[arg(long)]
    input: PathBuf,
    /// Objective evaluations in all (the paper: 1000).
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 1000)]
    epochs: usize,
    /// Random initial evaluations.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 10)]
    initial: usize,
    #[command(flatten)]
    seed: SeedOption,
    /// Smallest τ (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_tau, allow_negative_numbers = true, long, default_value = "10ms")]
    tau_min: Time,
    /// Largest τ (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_tau, allow_negative_numbers = true, long, default_value = "100ms")]
    tau_max: Time,
    /// τ grid step (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_tau_step, allow_negative_numbers = true, long, default_value = "1ms")]
    tau_step: Time,
    /// cos θ grid step.
    #[arg(value_parser = args::positive_f64, allow_negative_numbers = true, long, default_value_t = 0.01)]
    cos_step: f64,
    /// Neighbours.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 4)]
    k: usize,
    /// LL²/SP² matrices kept in memory (one per τ; 16 N² doubles each… times 2).
    #[arg(value_parser = args::count, allow_negative_numbers = true, long, default_value_t = 16)]
    matrix_cache: usize,
    /// Write the convergence trace (JSON) here.
    #[arg(long)]
    trace: Option<PathBuf>,
    #[command(flatten)]
    force: ForceOption,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// On several ranks every Van Rossum matrix is computed by all of them together and the
/// optimiser runs identically on each ([`VanRossumObjective::on_ranks`]); every rank checks the
/// trace path first, rank 0 alone writes the trace and prints.
pub fn run(args: VrArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    if let Some(trace) = &args.trace {
        neurotac_core::io::check_distinct(&args.input, trace)?;
        check_outputs([Output::file("--trace", trace)], args.force.force)?;
    }
    let data = load_labelled(&args.input)?;
    let config = BayesConfig {
        epochs: args.epochs,
        initial: args.initial,
        seed: args.seed.seed,
        tau_min_s: args.tau_min.s(),
        tau_max_s: args.tau_max.s(),
        tau_step_s: args.tau_step.s(),
        cos_step: args.cos_step,
        ..Default::default()
    };
    let mut objective = VanRossumObjective::new(
        VanRossumInput::Exact(data.observations()),
        data.labels(),
        Knn::new(args.k)?,
        args.matrix_cache,
    )
    .on_ranks(ranks);
    let (result, timing) =
        timed(|| bayes_optimise(&config, |i, tau, cos| objective.accuracy(i, tau, cos)));
    let result = result?;
    if !ranks.is_root() {
        return Ok(());
    }
    if let Some(path) = &args.trace {
        let replace = neurotac_core::io::Replace::when(args.force.force);
        neurotac_core::io::write(path, serde_json::to_string(&result.trace)?, replace)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    if args.json {
        println!(
            "{}",
            serde_json::json!({ "result": result, "matrices_computed": objective.matrices_computed, "timing": timing })
        );
        return Ok(());
    }
    println!(
        "Bayesian optimisation, {} evaluations (seed {}): best τ = {:.3} s, cos θ = {:.2}, LOO accuracy {:.1} %",
        result.trace.len(),
        args.seed.seed,
        result.best_tau_s,
        result.best_cos,
        100.0 * result.best_value
    );
    println!(
        "{} Van Rossum matrices computed (one per τ visited, matrix cache {}); {timing}",
        objective.matrices_computed, args.matrix_cache
    );
    let mut last = f64::NEG_INFINITY;
    println!("  epoch   τ (s)  cos θ  best accuracy");
    for s in &result.trace {
        if s.best_value > last {
            println!(
                "  {:5}  {:.3}  {:5.2}  {:.1} %",
                s.epoch,
                s.best_tau_s,
                s.best_cos,
                100.0 * s.best_value
            );
            last = s.best_value;
        }
    }
    Ok(())
}
