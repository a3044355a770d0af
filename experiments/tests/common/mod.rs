//! Runs the `neurotac` binary of this build.
#![allow(dead_code)] // each test file uses what it needs

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
