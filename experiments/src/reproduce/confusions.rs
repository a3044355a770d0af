//! What a set's leave-one-out predictions say class by class ([`loo_analysis`]): the recall of
//! every class under every coding, and the confusions the paper names measured on the same
//! predictions — the natural-texture pairs of [`paper::NAMED_CONFUSIONS`] (when the set has
//! both textures) and, for a set of bump grids, how many errors fall between neighbouring grid
//! sizes and on the sizes where the paper sees them ([`paper::GRID_ERRORS`]).

use super::SetResult;
use super::paper::{self, GridErrors, NamedConfusion};
use crate::coding::CodingName;
use crate::protocols::ConfusionMatrix;
use serde::Serialize;

/// The leave-one-out recall of every class under one coding.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CodingRecall {
    /// The coding.
    pub coding: CodingName,
    /// Recall (fraction) per class (index = label); `None` for a class without samples.
    pub per_class: Vec<Option<f64>>,
}

/// A confusion the paper names, measured on this run's leave-one-out predictions.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NamedConfusionRates {
    /// The paper's statement.
    pub paper: NamedConfusion,
    /// Per coding ([`paper::CODINGS`] order): the fraction of `truth` samples predicted as
    /// `predicted`.
    pub truth_as_predicted: [Option<f64>; 4],
    /// Per coding: the fraction of `predicted` samples predicted as `truth` (the other way).
    pub predicted_as_truth: [Option<f64>; 4],
}

/// One coding's leave-one-out errors on a set of bump grids, next to where the paper sees them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridErrorRates {
    /// The coding.
    pub coding: CodingName,
    /// The paper on this coding's errors.
    pub paper: GridErrors,
    /// Misclassified samples.
    pub errors: usize,
    /// The fraction of errors between neighbouring grid sizes (adjacent in size order);
    /// `None` without errors.
    pub between_neighbours: Option<f64>,
    /// The fraction of errors whose true grid lies in the paper's range
    /// ([`GridErrors::concentrated_on_mm`]); `None` without errors or without a range.
    pub in_paper_range: Option<f64>,
}

/// A set's leave-one-out predictions class by class (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LooAnalysis {
    /// Per coding, in the paper's order.
    pub recall: Vec<CodingRecall>,
    /// The paper's named confusions whose two textures are classes of the set.
    pub named_confusions: Vec<NamedConfusionRates>,
    /// Per coding, for a set whose classes are all bump grids (`grid D mm`); else empty.
    pub grid_errors: Vec<GridErrorRates>,
}

/// The leave-one-out confusion matrices of `set`'s codings, in [`paper::CODINGS`] order.
pub fn loo_matrices(set: &SetResult) -> [&ConfusionMatrix; 4] {
    paper::CODINGS.map(|c| &set.coding(c).loo.confusion)
}

/// The analysis of `set`'s leave-one-out predictions (see the module docs).
pub fn loo_analysis(set: &SetResult) -> LooAnalysis {
    let loo = loo_matrices(set);
    LooAnalysis {
        recall: paper::CODINGS
            .iter()
            .zip(loo)
            .map(|(&coding, m)| CodingRecall {
                coding,
                per_class: m.recall(),
            })
            .collect(),
        named_confusions: named_confusion_rates(&set.class_names, loo),
        grid_errors: grid_error_rates(&set.class_names, loo),
    }
}

/// Every confusion of [`paper::NAMED_CONFUSIONS`] whose two textures are among `class_names`,
/// measured on `loo` (one matrix per coding, [`paper::CODINGS`] order).
pub fn named_confusion_rates(
    class_names: &[String],
    loo: [&ConfusionMatrix; 4],
) -> Vec<NamedConfusionRates> {
    let index = |name: &str| class_names.iter().position(|n| n == name);
    paper::NAMED_CONFUSIONS
        .iter()
        .filter_map(|&named| {
            let (truth, predicted) = (index(named.truth)?, index(named.predicted)?);
            Some(NamedConfusionRates {
                paper: named,
                truth_as_predicted: loo.map(|m| m.rate(truth, predicted)),
                predicted_as_truth: loo.map(|m| m.rate(predicted, truth)),
            })
        })
        .collect()
}

/// For classes that are all bump grids (`grid D mm`, [`paper::grid_size_mm`]), each coding's
/// errors in `loo` against [`paper::GRID_ERRORS`]; empty for any other set.
pub fn grid_error_rates(class_names: &[String], loo: [&ConfusionMatrix; 4]) -> Vec<GridErrorRates> {
    let Some(sizes_mm) = class_names
        .iter()
        .map(|n| paper::grid_size_mm(n))
        .collect::<Option<Vec<f64>>>()
    else {
        return Vec::new();
    };
    // Each class's rank in size order: neighbours differ by one.
    let mut by_size: Vec<usize> = (0..sizes_mm.len()).collect();
    by_size.sort_by(|&a, &b| sizes_mm[a].total_cmp(&sizes_mm[b]));
    let mut rank = vec![0; sizes_mm.len()];
    for (r, &class) in by_size.iter().enumerate() {
        rank[class] = r;
    }
    paper::CODINGS
        .iter()
        .zip(paper::GRID_ERRORS)
        .zip(loo)
        .map(|((&coding, paper), m)| {
            let (mut errors, mut neighbours, mut in_range) = (0, 0, 0);
            for (truth, predicted, count) in m.errors() {
                errors += count;
                if rank.get(truth)?.abs_diff(*rank.get(predicted)?) == 1 {
                    neighbours += count;
                }
                if let Some((lo, hi)) = paper.concentrated_on_mm {
                    let d = sizes_mm[truth];
                    if d >= lo - 1e-9 && d <= hi + 1e-9 {
                        in_range += count;
                    }
                }
            }
            let fraction = |k: usize| (errors > 0).then(|| k as f64 / errors as f64);
            Some(GridErrorRates {
                coding,
                paper,
                errors,
                between_neighbours: fraction(neighbours),
                in_paper_range: paper.concentrated_on_mm.and(fraction(in_range)),
            })
        })
        .collect::<Option<Vec<_>>>()
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(names: &[&str]) -> Vec<String> {
        names.iter().map(|&n| n.to_owned()).collect()
    }

    /// Hand-made predictions of four codings over the same truth.
    fn matrices(truth: &[usize], predicted: [&[usize]; 4], n: usize) -> [ConfusionMatrix; 4] {
        predicted.map(|p| ConfusionMatrix::of(p, truth, n))
    }

    #[test]
    fn hand_made_predictions_give_the_expected_named_confusion_rates() {
        // Classes: foam, fake fur, liquid satin, felt; two samples each.
        let classes = names(&["foam", "fake fur", "liquid satin", "felt"]);
        let truth = [0, 0, 1, 1, 2, 2, 3, 3];
        let m = matrices(
            &truth,
            [
                &[0, 0, 3, 3, 2, 2, 1, 3], // fur → felt 2/2, felt → fur 1/2
                &[0, 0, 3, 1, 2, 2, 3, 3], // fur → felt 1/2
                &[0, 0, 1, 1, 2, 2, 3, 3], // perfect
                &[0, 0, 1, 1, 0, 2, 3, 3], // satin → foam 1/2
            ],
            4,
        );
        let rates = named_confusion_rates(&classes, [&m[0], &m[1], &m[2], &m[3]]);
        assert_eq!(rates.len(), 2);
        let fur = &rates[0];
        assert_eq!((fur.paper.truth, fur.paper.predicted), ("fake fur", "felt"));
        assert_eq!(
            fur.truth_as_predicted,
            [Some(1.0), Some(0.5), Some(0.0), Some(0.0)]
        );
        assert_eq!(
            fur.predicted_as_truth,
            [Some(0.5), Some(0.0), Some(0.0), Some(0.0)]
        );
        let satin = &rates[1];
        assert_eq!(satin.paper.predicted, "foam");
        assert_eq!(
            satin.truth_as_predicted,
            [Some(0.0), Some(0.0), Some(0.0), Some(0.5)]
        );
        // A set without the paper's textures has none of its named confusions.
        assert!(
            named_confusion_rates(&names(&["a", "b"]), [&m[0], &m[1], &m[2], &m[3]]).is_empty()
        );
    }

    #[test]
    fn grid_errors_are_split_into_neighbours_and_the_papers_range() {
        // Grids listed out of size order: neighbours are judged by size, not by label.
        let classes = names(&["grid 0.0 mm", "grid 3.0 mm", "grid 0.5 mm", "grid 2.5 mm"]);
        let truth = [0, 0, 1, 1, 2, 2, 3, 3];
        let m = matrices(
            &truth,
            [
                // 0 → 0.5 (neighbour, in 0–2), 0.5 → 3.0 (not a neighbour, in 0–2), 2.5 → 3.0
                // (neighbour, not in 0–2).
                &[0, 2, 1, 1, 2, 1, 1, 3],
                // 0.5 → 0 (neighbour, in 0–1.5).
                &[0, 0, 1, 1, 0, 2, 3, 3],
                &[0, 0, 1, 1, 2, 2, 3, 3],
                // 3.0 → 0 (not a neighbour).
                &[0, 0, 0, 1, 2, 2, 3, 3],
            ],
            4,
        );
        let rates = grid_error_rates(&classes, [&m[0], &m[1], &m[2], &m[3]]);
        let got: Vec<(usize, Option<f64>, Option<f64>)> = rates
            .iter()
            .map(|r| (r.errors, r.between_neighbours, r.in_paper_range))
            .collect();
        assert_eq!(
            got,
            [
                (3, Some(2.0 / 3.0), Some(2.0 / 3.0)),
                (1, Some(1.0), Some(1.0)),
                (0, None, None),
                (1, Some(0.0), None),
            ]
        );
        assert_eq!(rates[0].paper.concentrated_on_mm, Some((0.0, 2.0)));
        // Not bump grids: nothing to say.
        assert!(
            grid_error_rates(
                &names(&["felt", "grid 1.0 mm"]),
                [&m[0], &m[1], &m[2], &m[3]]
            )
            .is_empty()
        );
    }
}
