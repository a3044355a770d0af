//! Running work on a thread pool of a chosen size ([`with_threads`]).

/// The thread pool could not start.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("cannot start {threads} threads: {message}")]
pub struct ThreadPoolError {
    /// Threads asked for (0: one per core).
    pub threads: usize,
    /// What rayon reported.
    pub message: String,
}

/// Runs `f` on a rayon pool of `threads` threads (0: one per core), so every parallel loop
/// inside it uses that many.
pub fn with_threads<T: Send>(
    threads: usize,
    f: impl FnOnce() -> T + Send,
) -> Result<T, ThreadPoolError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| ThreadPoolError {
            threads,
            message: e.to_string(),
        })?;
    Ok(pool.install(f))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pool_has_the_threads_asked_for() {
        assert_eq!(with_threads(2, rayon::current_num_threads).unwrap(), 2);
        assert_eq!(with_threads(1, rayon::current_num_threads).unwrap(), 1);
    }
}
