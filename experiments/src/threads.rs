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

/// The most threads a pool may have: far more than any machine's cores, far fewer than would
/// exhaust the memory of their stacks (`--threads 100000` asked for gigabytes).
pub const MAX_THREADS: usize = 1024;

/// Runs `f` on a rayon pool of `threads` threads (0: one per core, at most [`MAX_THREADS`]),
/// so every parallel loop inside it uses that many.
pub fn with_threads<T: Send>(
    threads: usize,
    f: impl FnOnce() -> T + Send,
) -> Result<T, ThreadPoolError> {
    if threads > MAX_THREADS {
        return Err(ThreadPoolError {
            threads,
            message: format!("more than the limit of {MAX_THREADS} threads"),
        });
    }
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
    fn a_pool_over_the_thread_limit_is_refused_before_any_thread_starts() {
        let e = with_threads(100_000, || ()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "cannot start 100000 threads: more than the limit of 1024 threads"
        );
    }

    #[test]
    fn the_pool_has_the_threads_asked_for() {
        assert_eq!(with_threads(2, rayon::current_num_threads).unwrap(), 2);
        assert_eq!(with_threads(1, rayon::current_num_threads).unwrap(), 1);
    }
}
