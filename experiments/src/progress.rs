//! Progress of long work ([`Progress`]): the library reports stages and steps, the CLI draws
//! them as progress bars, library users and tests pass [`NoProgress`].

/// Receives the progress of the long stages of a run (the CLI draws progress bars).
pub trait Progress: Sync {
    /// A stage named `name` starts, with `total` steps (0: unknown).
    fn stage(&self, name: &str, total: u64);
    /// `n` more steps of the current stage are done.
    fn advance(&self, n: u64);
    /// The current stage is over.
    fn finish(&self);
    /// A line worth showing between stages (e.g. `natural: 1000 samples, dataset ready`).
    /// Default: ignored.
    fn note(&self, _line: &str) {}
}

/// Ignores progress.
pub struct NoProgress;

impl Progress for NoProgress {
    fn stage(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
}
