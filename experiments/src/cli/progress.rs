//! Progress bars on stderr (hidden when stderr is not a terminal): the one bar constructor
//! ([`bar`]) and [`Bars`], the CLI's [`Progress`].

use indicatif::{ProgressBar, ProgressStyle};
use neurotac_experiments::progress::Progress;
use std::sync::Mutex;

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

/// One bar per stage of a library run.
pub struct Bars(Mutex<Option<ProgressBar>>);

impl Bars {
    pub fn new() -> Self {
        Self(Mutex::new(None))
    }

    fn current(&self) -> Option<ProgressBar> {
        self.0.lock().expect("progress lock").clone()
    }
}

impl Progress for Bars {
    fn stage(&self, name: &str, total: u64) {
        let new = bar(name, total, "");
        if let Some(old) = self.0.lock().expect("progress lock").replace(new) {
            old.finish_and_clear();
        }
    }

    fn advance(&self, n: u64) {
        if let Some(b) = self.current() {
            b.inc(n);
        }
    }

    fn finish(&self) {
        if let Some(b) = self.0.lock().expect("progress lock").take() {
            b.finish_and_clear();
        }
    }

    fn note(&self, line: &str) {
        match self.current() {
            Some(b) => b.suspend(|| eprintln!("{line}")),
            None => eprintln!("{line}"),
        }
    }
}
