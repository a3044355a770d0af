//! # neurotac-cli
//!
//! The `neurotac` command and the parts of it worth calling from Rust. The binary
//! (`src/main.rs`, one module per command under `src/commands/`) maps flags to the configs of
//! [`neurotac_experiments`], draws progress bars and prints; this library holds what it renders
//! and measures:
//!
//! | module | what it holds |
//! |---|---|
//! | [`report`] | a reproduction's report folder ([`report::write_report`]): Markdown tables, CSV, figures (SVG, PNG), atomic folder writing |
//! | [`tradeoff`] | speed ↔ accuracy trade-offs (neurons, Van Rossum, simulator), their shared table and writers, the summary page |
//! | [`bench`](mod@bench) | throughput benchmarks (neuron updates/s, the CUBA network, the afferent pipeline at an activity) |
//! | [`ceiling`] | this core's own ceilings (peak FMA throughput, read-modify-write bandwidth) and the share of them a loop reaches |
//! | [`peers`] | same-run comparisons against peer simulators (Brian2), as ratios |
//! | [`simulator_check`] | the simulator's acceptance statistics and calibration (`neurotac simulate check`, `calibrate`) |
//!
//! The paper's pipeline from Rust, with its report folder:
//!
//! ```no_run
//! use neurotac_experiments::datasets::simulated::TextureSet;
//! use neurotac_experiments::progress::NoProgress;
//! use neurotac_experiments::reproduce::{ReproduceConfig, Source, run};
//! let config = ReproduceConfig::quick(1, std::env::temp_dir().join("neurotac-cache"));
//! let artificial = [Source::Simulated(TextureSet::Artificial)];
//! let report = run(&config, &artificial, &NoProgress, &neurotac_core::OneProcess)?;
//! neurotac_cli::report::write_report("neurotac-report".as_ref(), &report, true)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

pub mod bench;
pub mod budget;
pub mod ceiling;
pub mod peers;
pub mod report;
pub mod simulator_check;
pub mod tradeoff;
