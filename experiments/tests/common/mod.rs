//! Runs the `neurotac` binary of this build.
#![allow(dead_code)] // each test file uses what it needs

use std::path::Path;
use std::process::Command;

/// `(success, stdout, stderr)` of `neurotac ARGS`.
pub fn neurotac(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_neurotac"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A small artificial `reproduce` (3 slides per texture, 12 epochs) into `out`, caching
/// datasets in `cache`, with `extra` arguments.
pub fn small_reproduce(out: &Path, cache: &Path, extra: &[&str]) -> (bool, String, String) {
    let (out, cache) = (out.to_str().unwrap(), cache.to_str().unwrap());
    let mut args = vec![
        "reproduce",
        "--set",
        "artificial",
        "--trials",
        "3",
        "--epochs",
        "12",
        "--tau-step",
        "0.03",
        "--out",
        out,
        "--cache",
        cache,
    ];
    args.extend_from_slice(extra);
    neurotac(&args)
}
