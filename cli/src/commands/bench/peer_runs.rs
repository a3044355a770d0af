//! Running a benchmark beside its peer: both sides interleaved and the fastest run of each kept
//! ([`fastest_interleaved`]), the peer's numbers and the ratio added to the report
//! ([`add_peer`]), and the report printed ([`print`]); shared by every `bench` case.

use neurotac_cli::peers::{PeerResult, run_brian2};
use serde::de::DeserializeOwned;
use serde_json::{Value, json};
use std::path::Path;

/// What the peer runs: the script's arguments, and the precision and method (Brian2's
/// precision name, neurotac's method name) that both sides must have run for a ratio.
pub(super) struct PeerCase<'a> {
    pub(super) python: &'a Path,
    pub(super) args: Vec<String>,
    pub(super) precision: &'static str,
    pub(super) method: &'static str,
}

/// Runs `ours` and, with a peer, the peer `repeats` times each, interleaved (ours, peer, ours,
/// …) so that both sides see the same machine, and keeps the fastest run of each (`wall` of
/// ours, `run_s` of the peer's, read as `P`): a shared machine's noise only ever adds time.
pub(super) fn fastest_interleaved<T, P: DeserializeOwned + AsRef<PeerResult>>(
    repeats: usize,
    mut ours: impl FnMut() -> anyhow::Result<T>,
    wall: impl Fn(&T) -> f64,
    peer: Option<&PeerCase<'_>>,
) -> anyhow::Result<(T, Option<P>)> {
    let mut best: Option<T> = None;
    let mut best_peer: Option<P> = None;
    for _ in 0..repeats.max(1) {
        let run = ours()?;
        if best.as_ref().is_none_or(|b| wall(&run) < wall(b)) {
            best = Some(run);
        }
        if let Some(case) = peer {
            let run: P = run_brian2(case.python, &case.args)?;
            let fastest = |p: &P| p.as_ref().run_s;
            if best_peer
                .as_ref()
                .is_none_or(|b| fastest(&run) < fastest(b))
            {
                best_peer = Some(run);
            }
        }
    }
    Ok((best.expect("at least one run"), best_peer))
}

/// Adds the peer's numbers to `report`, and `speedup = peer time / our time` when the peer ran
/// what `case` asked (else `no_ratio`, the line that says what differs).
pub(super) fn add_peer(
    report: &mut Value,
    peer: &PeerResult,
    case: &PeerCase<'_>,
    our_wall_s: f64,
    work: f64,
) {
    report["peer"] = json!(peer.peer);
    report["peer_precision"] = json!(peer.precision);
    report["peer_method"] = json!(peer.method);
    report["peer_wall_s"] = json!(peer.run_s);
    report["peer_spikes"] = json!(peer.spikes);
    report["peer_per_s"] = json!(work / peer.run_s);
    match peer.matches(case.precision, case.method) {
        Ok(()) => report["speedup"] = json!(peer.run_s / our_wall_s),
        Err(why) => report["no_ratio"] = json!(why),
    }
}

pub(super) fn print(report: &Value, json: bool, line: String) {
    if json {
        println!("{report}");
        return;
    }
    println!("{line}");
    let Some(peer) = report["peer"].as_str() else {
        return;
    };
    let said = |key: &str| report[key].as_str().unwrap_or("unstated").to_owned();
    print!(
        "{peer} ({}, {}): {:.4} s wall, {} spikes",
        said("peer_precision"),
        said("peer_method"),
        report["peer_wall_s"].as_f64().unwrap_or(f64::NAN),
        report["peer_spikes"],
    );
    match report["speedup"].as_f64() {
        Some(speedup) => println!(" → neurotac is {speedup:.2}× faster"),
        None => println!("\n{}", said("no_ratio")),
    }
}
