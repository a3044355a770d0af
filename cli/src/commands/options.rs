//! The option groups several commands share, each flag declared once: a command takes one with
//! `#[command(flatten)]`. The group fixes the flag's name, type, value parser and default; a
//! command whose help says more about what the flag means there (what the seed seeds, which
//! output is replaced) gives its own line with [`help`], and one that cannot run without the flag
//! makes it [`required`]:
//!
//! ```ignore
//! #[derive(Debug, Args)]
//! #[command(mut_args(help("seed", "Seed of the taxel spike trains")))]
//! pub struct DemoArgs {
//!     #[command(flatten)]
//!     seed: SeedOption,
//! }
//! ```
//!
//! | group | flag | used by |
//! |---|---|---|
//! | [`ForceOption`] | `--force` | every command that writes |
//! | [`SeedOption`] | `--seed <SEED>` (default 1) | every seeded command |
//! | [`ThreadsOption`] | `--threads <THREADS>` (default 0: one per core) | the parallel commands |
//! | [`SetOption`] | `--set <SET>`, no default | `simulate` (required), `recognise --eval` |
//! | [`SetsOption`] | `--set <SET>` (default both) | `reproduce` |
//! | [`OutOption`] | `--out <OUT>`, optional | `simulate`, `simulate check`/`calibrate`, `layout`, `recognise --eval` |
//! | [`OutPathOption`] | `--out <OUT>`, required | `transduce`, `record` |
//! | [`TradeoffOutOption`] | `--out <OUT>` (default `tradeoff`) | `tradeoff` and its trades that write |
//!
//! `reproduce --out` (a report folder with its own default) is declared by `reproduce`.

use super::args;
use clap::{Arg, Args, ValueEnum};
use neurotac_experiments::datasets::simulated::TextureSet;
use std::path::PathBuf;

/// A command's own help line for the shared flag `id`, for
/// `#[command(mut_args(help("seed", "…")))]` (in place: the flag keeps its position in the help
/// and the usage line). Written as clap shows a doc comment: without the final period.
pub fn help(id: &'static str, text: &'static str) -> impl FnMut(Arg) -> Arg {
    move |arg| match arg.get_id() == id {
        true => arg.help(text),
        false => arg,
    }
}

/// Makes the shared flag `id` required in a command, for `#[command(mut_args(required("out")))]`.
pub fn required(id: &'static str) -> impl FnMut(Arg) -> Arg {
    move |arg| match arg.get_id() == id {
        true => arg.required(true),
        false => arg,
    }
}

/// `--force`: replace existing outputs (the overwrite rule of
/// [`check_outputs`](super::outputs::check_outputs)).
#[derive(Debug, Clone, Copy, Args)]
pub struct ForceOption {
    /// Replace existing output files (without it, an existing output is refused).
    #[arg(long)]
    pub force: bool,
}

/// `--seed`: the seed of everything random the command does (default 1).
#[derive(Debug, Clone, Copy, Args)]
pub struct SeedOption {
    /// Seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `--threads`: worker threads, 0 for one per core (the command runs in a pool of that size,
/// `neurotac_experiments::threads::with_threads`).
#[derive(Debug, Clone, Copy, Args)]
pub struct ThreadsOption {
    /// Worker threads (0 = one per core).
    #[arg(value_parser = args::count, allow_negative_numbers = true, long, default_value_t = 0)]
    pub threads: usize,
}

/// The values of `--set`: which simulated texture set(s).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SetArg {
    /// The 11 bump grids (paper: 100 slides each; Table 1).
    Artificial,
    /// The 20 natural textures (paper: 50 slides each; Table 2).
    Natural,
    /// Both, artificial first.
    Both,
}

impl SetArg {
    /// The sets, in run order.
    pub fn sets(self) -> Vec<TextureSet> {
        match self {
            SetArg::Artificial => vec![TextureSet::Artificial],
            SetArg::Natural => vec![TextureSet::Natural],
            SetArg::Both => vec![TextureSet::Artificial, TextureSet::Natural],
        }
    }
}

/// `--set` without a default: a command that needs it says so (`required`, or `requires` on
/// the flag that needs it).
#[derive(Debug, Clone, Copy, Args)]
pub struct SetOption {
    /// The texture set.
    #[arg(long, value_enum)]
    pub set: Option<SetArg>,
}

/// `--set`, both sets by default.
#[derive(Debug, Clone, Copy, Args)]
pub struct SetsOption {
    /// Which simulated texture set(s) to run.
    #[arg(long, value_enum, default_value = "both")]
    pub set: SetArg,
}

/// `--out`, optional: a file or folder the command writes only when given (or that another
/// flag requires); its help says which.
#[derive(Debug, Clone, Args)]
pub struct OutOption {
    /// Write the output here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `--out`, required: the file the command writes; its help says which.
#[derive(Debug, Clone, Args)]
pub struct OutPathOption {
    /// Output file.
    #[arg(long)]
    pub out: PathBuf,
}

/// `--out` of the trade-offs: the folder they write into, created if needed (default
/// `tradeoff`).
#[derive(Debug, Clone, Args)]
pub struct TradeoffOutOption {
    /// Output folder (created if needed).
    #[arg(long, default_value = "tradeoff")]
    pub out: PathBuf,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_override_changes_only_the_flag_it_names() {
        let mut seed_help = help("seed", "Seed of the taxel spike trains");
        let seed = seed_help(Arg::new("seed").help("Seed"));
        assert_eq!(
            seed.get_help().map(ToString::to_string).as_deref(),
            Some("Seed of the taxel spike trains")
        );
        assert!(seed_help(Arg::new("force")).get_help().is_none());
        let mut out_required = required("out");
        assert!(out_required(Arg::new("out")).is_required_set());
        assert!(!out_required(Arg::new("set")).is_required_set());
    }
}
