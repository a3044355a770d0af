//! Progress on stderr: the one meter constructor ([`bar`]) and [`Bars`], the CLI's
//! [`Progress`].
//!
//! On a terminal a [`Meter`] is an indicatif bar (a spinner when the total is unknown). When
//! stderr is not a terminal (a log file, `2>log`, a batch job) bars are not drawn; instead a
//! meter writes plain lines: one when it starts (`  ▸ name (1100 steps)`), now and then one with
//! its count (`  · name: 330/1100 (30 %), 61.2 s` — at most one every [`LOG_EVERY`] and one per
//! tenth of the total) and one when it ends (`  ✓ name — 204.1 s`), so a long run's log shows
//! every stage and its time.

use indicatif::{ProgressBar, ProgressStyle};
use neurotac_experiments::progress::Progress;
use std::io::IsTerminal;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The shortest time between two count lines of one meter in a log.
pub const LOG_EVERY: Duration = Duration::from_secs(5);

/// A meter of `total` steps named `name` (`unit`: what a step is, e.g. `trials `, with its
/// trailing space), or of an unknown number when `total` is 0.
pub fn bar(name: &str, total: u64, unit: &str) -> Meter {
    let bar = if total == 0 {
        let b = ProgressBar::new_spinner();
        b.set_style(
            ProgressStyle::with_template("  {spinner} {msg} [{elapsed_precise}]")
                .expect("valid template"),
        );
        b.enable_steady_tick(std::time::Duration::from_millis(120));
        b
    } else {
        let b = ProgressBar::new(total);
        b.set_style(
            ProgressStyle::with_template(&format!(
                "  {{msg}} [{{elapsed_precise}}] {{wide_bar}} {{pos}}/{{len}} {unit}(eta {{eta}})"
            ))
            .expect("valid template"),
        );
        b
    };
    bar.set_message(name.to_owned());
    let log = !std::io::stderr().is_terminal();
    if log {
        match (total, unit.trim()) {
            (0, _) => eprintln!("  ▸ {name}"),
            (n, "") => eprintln!("  ▸ {name} ({n} steps)"),
            (n, unit) => eprintln!("  ▸ {name} ({n} {unit})"),
        }
    }
    let count = Count {
        done: 0,
        logged: 0,
        logged_at: Instant::now(),
    };
    Meter {
        bar,
        log,
        track: Arc::new(Track {
            name: name.to_owned(),
            total,
            start: Instant::now(),
            count: Mutex::new(count),
        }),
    }
}

/// One stage's progress: a bar on a terminal, plain lines in a log (see the module). Clones
/// share the count.
#[derive(Clone)]
pub struct Meter {
    bar: ProgressBar,
    /// Whether stderr is not a terminal: plain lines instead of the bar.
    log: bool,
    track: Arc<Track>,
}

struct Track {
    name: String,
    total: u64,
    start: Instant,
    count: Mutex<Count>,
}

struct Count {
    done: u64,
    /// The count of the last count line, and when it was written.
    logged: u64,
    logged_at: Instant,
}

impl Meter {
    /// `n` more steps are done.
    pub fn inc(&self, n: u64) {
        self.bar.inc(n);
        if !self.log {
            return;
        }
        let t = &*self.track;
        let mut count = t.count.lock().expect("progress lock");
        count.done += n;
        let tenth = t.total.div_ceil(10).max(1);
        if count.logged_at.elapsed() < LOG_EVERY
            || (t.total > 0 && count.done - count.logged < tenth)
        {
            return;
        }
        let seconds = t.start.elapsed().as_secs_f64();
        match t.total {
            0 => eprintln!("  · {}: {}, {seconds:.1} s", t.name, count.done),
            total => eprintln!(
                "  · {}: {}/{total} ({:.0} %), {seconds:.1} s",
                t.name,
                count.done,
                100.0 * count.done as f64 / total as f64
            ),
        }
        count.logged = count.done;
        count.logged_at = Instant::now();
    }

    /// The meter is over: the bar is cleared; in a log, its end line with the wall time.
    pub fn finish_and_clear(&self) {
        self.end(self.log);
    }

    /// Clears the bar and, when `say`, writes the end line (`  ✓ name — 12.3 s`).
    fn end(&self, say: bool) {
        self.bar.finish_and_clear();
        if say {
            let t = &*self.track;
            eprintln!("  ✓ {} — {:.1} s", t.name, t.start.elapsed().as_secs_f64());
        }
    }

    /// Prints `line` on stderr, above the bar when one is drawn.
    fn say(&self, line: &str) {
        self.bar.suspend(|| eprintln!("{line}"));
    }
}

/// One meter per stage of a library run; a finished stage leaves one line with its name and
/// wall time (`  ✓ artificial: Δt sweep 1…200 ms — 12.3 s`), so the stages of a long run stay
/// readable after their bars are gone (and a log shows them).
pub struct Bars(Mutex<Option<Meter>>);

impl Bars {
    pub fn new() -> Self {
        Self(Mutex::new(None))
    }

    fn current(&self) -> Option<Meter> {
        self.0.lock().expect("progress lock").clone()
    }
}

impl Progress for Bars {
    fn stage(&self, name: &str, total: u64) {
        // The previous stage ends (and says so) before the next one starts.
        if let Some(old) = self.0.lock().expect("progress lock").take() {
            old.end(true);
        }
        *self.0.lock().expect("progress lock") = Some(bar(name, total, ""));
    }

    fn advance(&self, n: u64) {
        if let Some(m) = self.current() {
            m.inc(n);
        }
    }

    fn finish(&self) {
        if let Some(stage) = self.0.lock().expect("progress lock").take() {
            stage.end(true);
        }
    }

    fn note(&self, line: &str) {
        match self.current() {
            Some(m) => m.say(line),
            None => eprintln!("{line}"),
        }
    }
}
