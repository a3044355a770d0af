//! `neurotac classify`: KNN classification of a dataset under one coding and protocol.

use super::coding_parameters::coding_parameters;
use super::inputs::load_labelled;
use super::options::{ForceOption, SeedOption, help};
use super::outputs::{Output, check_outputs};
use crate::commands::args::{self, Time};
use clap::{Args, ValueEnum};
use neurotac_core::{Knn, Ranks};
use neurotac_experiments::coding::{CodingName, coding_distances};
use neurotac_experiments::export::{MATRIX_FORMATS, OutputFormat, Replace, write_matrix};
use neurotac_experiments::protocols::{Protocol, evaluate};
use neurotac_experiments::timing::timed;
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum ProtocolArg {
    /// Leave-one-out (the paper's table).
    Loo,
    /// Seeded stratified split (default 80/20, the paper's confusion matrices).
    Split,
    /// Seeded stratified k-fold.
    Kfold,
}

#[derive(Debug, Args)]
#[command(
    mut_args(help("seed", "Seed of the split / fold assignment")),
    mut_args(help("force", "Replace an existing `--matrix` file"))
)]
pub struct ClassifyArgs {
    /// Spike dataset (JSON or binary), labelled.
    #[arg(long)]
    input: PathBuf,
    /// Coding.
    #[arg(long, value_parser = args::menu::<CodingName>())]
    coding: CodingName,
    /// Temporal-coding window Δt, a whole number of ms (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_window, allow_negative_numbers = true, long)]
    dt: Option<Time>,
    /// Van Rossum kernel time constant τ (ms, or with a unit: 20ms, 0.02s).
    #[arg(value_parser = args::time_tau, allow_negative_numbers = true, long)]
    tau: Option<Time>,
    /// Van Rossum cos θ in [0, 1].
    #[arg(value_parser = args::unit_interval, allow_negative_numbers = true, long)]
    cos: Option<f64>,
    /// Protocol.
    #[arg(long, value_enum, default_value = "loo")]
    protocol: ProtocolArg,
    /// Neighbours.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 4)]
    k: usize,
    /// Test fraction of the split protocol.
    #[arg(value_parser = args::open_fraction, allow_negative_numbers = true, long, default_value_t = 0.2)]
    test_fraction: f64,
    /// Folds of the k-fold protocol.
    #[arg(value_parser = args::positive_count, allow_negative_numbers = true, long, default_value_t = 10)]
    folds: usize,
    #[command(flatten)]
    seed: SeedOption,
    /// Sample duration, a whole number of ms (ms, or with a unit: 20ms, 0.02s); default:
    /// meta.duration_s, else one ms past the latest spike.
    #[arg(value_parser = args::time_duration, allow_negative_numbers = true, long)]
    duration: Option<Time>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Also write the N×N distance matrix the KNN used; format by extension: `.json`, `.npy`
    /// or `.npz` (member `matrix`).
    #[arg(long)]
    matrix: Option<PathBuf>,
    #[command(flatten)]
    force: ForceOption,
}

/// On several ranks the distance matrix's rows are split over them ([`coding_distances`]);
/// rank 0 alone runs the protocol on it and prints.
pub fn run(args: ClassifyArgs, ranks: &dyn Ranks) -> anyhow::Result<()> {
    if let Some(path) = &args.matrix {
        neurotac_core::io::check_distinct(&args.input, path)?;
        OutputFormat::from_path(path, &MATRIX_FORMATS)?;
        check_outputs([Output::file("--matrix", path)], args.force.force)?;
    }
    let data = load_labelled(&args.input)?;
    let knn = Knn::new(args.k)?;
    let protocol = match args.protocol {
        ProtocolArg::Loo => Protocol::LeaveOneOut,
        ProtocolArg::Split => Protocol::Split {
            test_fraction: args.test_fraction,
            seed: args.seed.seed,
        },
        ProtocolArg::Kfold => Protocol::KFold {
            folds: args.folds,
            seed: args.seed.seed,
        },
    };
    let coding = coding_parameters(&data, args.dt, args.duration, args.tau, args.cos)?;
    let (distances, distance_time) =
        timed(|| coding_distances(data.observations(), args.coding, &coding, ranks));
    let distances = distances?;
    if !ranks.is_root() {
        return Ok(());
    }
    if let Some(path) = &args.matrix {
        write_matrix(path, distances.view(), Replace::when(args.force.force))?;
    }
    let (evaluation, knn_time) = timed(|| {
        evaluate(
            distances.view(),
            data.labels(),
            data.n_classes(),
            knn,
            protocol,
        )
    });
    let e = evaluation?;
    let a = e.accuracy;
    if args.json {
        let out = serde_json::json!({
            "coding": format!("{:?}", args.coding).to_lowercase(),
            "protocol": format!("{:?}", args.protocol).to_lowercase(),
            "k": args.k,
            "accuracy": a,
            "fold_accuracies": e.fold_accuracies,
            "confusion_matrix": e.confusion.counts,
            "class_names": data.class_names(),
            "timing": { "distances": distance_time, "knn": knn_time },
        });
        println!("{out}");
        return Ok(());
    }
    println!(
        "{:?} coding, {:?}, k = {}: accuracy {:.1} ± {:.1} % ({} / {}; Wilson 95 % [{:.1}, {:.1}] %)",
        args.coding,
        args.protocol,
        args.k,
        100.0 * a.mean,
        100.0 * a.std,
        a.hits,
        a.n,
        100.0 * a.wilson_low,
        100.0 * a.wilson_high
    );
    if let Some((m, s)) = e.fold_mean_std() {
        println!(
            "per fold: {:.1} ± {:.1} % over {} folds",
            100.0 * m,
            100.0 * s,
            e.fold_accuracies.len()
        );
    }
    print_confusion(&e.confusion.counts, data.class_names());
    println!("distances: {distance_time}; KNN: {knn_time}");
    Ok(())
}

fn print_confusion(counts: &[Vec<usize>], class_names: &[String]) {
    print!("{}", confusion_text(counts, class_names));
}

/// The confusion matrix as aligned text: one row per true class, named on the left (padded to
/// the longest name), columns numbered 0, 1, … in class order (the key maps numbers to names
/// when they differ), every column as wide as its widest entry.
fn confusion_text(counts: &[Vec<usize>], class_names: &[String]) -> String {
    use std::fmt::Write;
    let name = |i: usize| class_names.get(i).cloned().unwrap_or_else(|| i.to_string());
    let names: Vec<String> = (0..counts.len()).map(name).collect();
    let name_width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
    let widths: Vec<usize> = (0..counts.len())
        .map(|j| {
            let widest = counts.iter().filter_map(|r| r.get(j)).max().copied();
            widest
                .unwrap_or(0)
                .to_string()
                .len()
                .max(j.to_string().len())
        })
        .collect();
    let mut out = String::from("confusion matrix (rows: true class, columns: predicted class):\n");
    let _ = write!(out, "  {:name_width$}", "");
    for (j, w) in widths.iter().enumerate() {
        let _ = write!(out, " {j:>w$}");
    }
    out.push('\n');
    for (i, row) in counts.iter().enumerate() {
        let pad = name_width - names[i].chars().count();
        let _ = write!(out, "  {}{:pad$}", names[i], "");
        for (c, w) in row.iter().zip(&widths) {
            let _ = write!(out, " {c:>w$}");
        }
        let _ = writeln!(out, "   ({i})");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::confusion_text;

    #[test]
    fn confusion_columns_line_up_with_long_class_names() {
        let names = [
            "grid_0.0_mm".to_owned(),
            "a-much-longer-texture-name".to_owned(),
        ];
        let text = confusion_text(&[vec![12, 3], vec![0, 100]], &names);
        let rows: Vec<&str> = text.lines().skip(1).collect();
        assert_eq!(rows.len(), 3);
        // Every line has the same width, and the last count ends in the same column.
        let ends: Vec<usize> = rows
            .iter()
            .map(|r| r.find("   (").unwrap_or(r.len()))
            .collect();
        assert_eq!(ends[1], ends[2], "{text}");
        assert_eq!(rows[0].chars().count(), ends[1], "{text}");
        assert!(rows[1].starts_with("  grid_0.0_mm "), "{text}");
    }
}
