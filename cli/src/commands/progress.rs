//! Progress bars on stderr (hidden when stderr is not a terminal): the one bar constructor
//! ([`bar`]) and [`Bars`], the CLI's [`Progress`].

use indicatif::{ProgressBar, ProgressStyle};
use neurotac_experiments::progress::Progress;
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::Instant;

/// A bar of `total` steps named `name` (`unit`: what a step is, e.g. `trials`), or a spinner
/// when `total` is 0 (unknown).
pub fn bar(name: &str, total: u64, unit: &str) -> ProgressBar {
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
    bar
}

/// One bar per stage of a library run; when stderr is a terminal, a finished stage leaves one
/// line with its name and wall time (`  ✓ artificial: Δt sweep 1…200 ms — 12.3 s`), so the
/// stages of a long run stay readable after their bars are gone.
pub struct Bars(Mutex<Option<Stage>>);

struct Stage {
    bar: ProgressBar,
    name: String,
    start: Instant,
}

impl Stage {
    fn end(self) {
        self.bar.finish_and_clear();
        if std::io::stderr().is_terminal() {
            eprintln!(
                "  ✓ {} — {:.1} s",
                self.name,
                self.start.elapsed().as_secs_f64()
            );
        }
    }
}

impl Bars {
    pub fn new() -> Self {
        Self(Mutex::new(None))
    }

    fn current(&self) -> Option<ProgressBar> {
        let stage = self.0.lock().expect("progress lock");
        stage.as_ref().map(|s| s.bar.clone())
    }
}

impl Progress for Bars {
    fn stage(&self, name: &str, total: u64) {
        let new = Stage {
            bar: bar(name, total, ""),
            name: name.to_owned(),
            start: Instant::now(),
        };
        if let Some(old) = self.0.lock().expect("progress lock").replace(new) {
            old.end();
        }
    }

    fn advance(&self, n: u64) {
        if let Some(b) = self.current() {
            b.inc(n);
        }
    }

    fn finish(&self) {
        if let Some(stage) = self.0.lock().expect("progress lock").take() {
            stage.end();
        }
    }

    fn note(&self, line: &str) {
        match self.current() {
            Some(b) => b.suspend(|| eprintln!("{line}")),
            None => eprintln!("{line}"),
        }
    }
}
