//! The spread of every coding's accuracy over mountings (`neurotac reproduce --mountings K`): a
//! simulated set run on K mountings of its textures — where the rig put each texture (its
//! lateral offset, phase and specimen friction) — shows how much of a single run's accuracy is
//! that one draw.

use super::tables::pct;
use neurotac_experiments::reproduce::SetReport;
use std::fmt::Write as _;

/// Mean and sample standard deviation of `v` (the standard deviation is 0 for one value).
fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}

/// Each coding's leave-one-out accuracy over the set's mountings as Markdown (mean ± sd, range,
/// every mounting's value and chosen parameters); empty for a set run on one mounting.
pub fn mounting_table(set: &SetReport) -> String {
    let runs = &set.mountings;
    let Some(first) = runs.first() else {
        return String::new();
    };
    let mut s = format!(
        "Leave-one-out accuracy (%) over {} mountings of the textures (mounting 0 is the set \
         above; the others re-mount every texture, nothing else changes):\n\n\
         | coding | mean ± sd | range |",
        runs.len()
    );
    for run in runs {
        let _ = write!(s, " mounting {} |", run.mounting);
    }
    s.push_str("\n|---|---|---|");
    s.push_str(&"---|".repeat(runs.len()));
    s.push('\n');
    for (i, (coding, _, _)) in first.codings.iter().enumerate() {
        let values: Vec<f64> = runs.iter().map(|r| r.codings[i].1).collect();
        let (mean, sd) = mean_sd(&values);
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let _ = write!(
            s,
            "| {} | {} ± {} | {}–{} |",
            coding.label(),
            pct(mean),
            pct(sd),
            pct(lo),
            pct(hi)
        );
        for run in runs {
            let (_, accuracy, parameters) = &run.codings[i];
            match parameters.is_empty() {
                true => {
                    let _ = write!(s, " {} |", pct(*accuracy));
                }
                false => {
                    let _ = write!(s, " {} ({parameters}) |", pct(*accuracy));
                }
            }
        }
        s.push('\n');
    }
    let spikes: Vec<f64> = runs.iter().map(|r| r.mean_spikes_per_taxel).collect();
    let (mean, sd) = mean_sd(&spikes);
    let _ = writeln!(
        s,
        "\nSpikes per taxel over the mountings: {mean:.2} ± {sd:.2}.\n"
    );
    s
}
