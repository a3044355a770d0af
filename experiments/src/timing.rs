//! Wall-clock and process CPU time of a piece of work (the timing every command and report
//! prints next to its results).

use std::time::Instant;

/// Process CPU time (user + system, all threads) in seconds, from `/proc/self/stat` (Linux;
/// `None` elsewhere). Resolution: one clock tick (10 ms).
pub fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((utime + stime) / 100.0)
}

/// Wall and CPU time of a piece of work.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Timing {
    /// Wall-clock seconds.
    pub wall_s: f64,
    /// Process CPU seconds (all threads), if known.
    pub cpu_s: Option<f64>,
    /// Worker threads available.
    pub threads: usize,
}

/// Runs `f` and measures it (wall time, and process CPU time of all threads when known).
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, Timing) {
    let (cpu0, wall0) = (cpu_seconds(), Instant::now());
    let out = f();
    let wall_s = wall0.elapsed().as_secs_f64();
    let cpu_s = cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
    (
        out,
        Timing {
            wall_s,
            cpu_s,
            threads: rayon::current_num_threads(),
        },
    )
}

impl std::fmt::Display for Timing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:.3} s wall", self.wall_s)?;
        if let Some(cpu) = self.cpu_s {
            write!(f, ", {cpu:.2} s CPU")?;
        }
        write!(f, " on {} threads", self.threads)
    }
}
