//! Taxel spike datasets and where they come from.
//!
//! | module | what it holds |
//! |---|---|
//! | [`simulated`] | the bundled texture sets from the NeuroTac simulator ([`TextureSet`]), cached on disk, and [`simulated::generate`] (`neurotac simulate`) |
//! | [`recorded`] | a folder of event files per class → taxel spike dataset ([`recorded::load_recorded`]) |
//! | [`synthetic`] | seeded NeuroTac-like spike datasets for benchmarks and trials |
//! | [`metadata`] | the typed metadata every dataset carries: `duration_s` and the transduction settings |

mod error;
pub mod metadata;
pub mod recorded;
pub mod simulated;
pub mod synthetic;
mod texture_set;

// The simulated sets are what most callers (the simulator check, the trade-offs) use.
pub use simulated::{
    DatasetsError, TextureSet, TrialJob, camera_seed, jobs_for, map_trials, prepare_textures,
    trial_seed,
};
