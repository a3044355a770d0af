//! The accuracy ↔ cost study (`neurotac tradeoff`): for every setting of a swept family, the
//! leave-one-out accuracy of the four codings on a labelled texture set, with its Wilson 95 %
//! interval and McNemar's exact test against the family's reference setting on the same
//! samples, next to what the setting costs (wall and CPU time, the work the code counts) and
//! the numerical error the setting makes.
//!
//! The reference setting of a family (its first, the exact or finest one) runs the paper's
//! whole pipeline ([`run_encoded`]: the Δt sweep and the (τ, cos θ) optimisation), so its
//! accuracy is `reproduce`'s for the same set, seed and trials. Every other setting is scored
//! at the reference's chosen Δt, τ and cos θ, so the setting is the only thing that changes.
//!
//! | family | settings | reference | numerical error |
//! |---|---|---|---|
//! | [`Family::VanRossum`] | exact, or synaptic traces at a trace step × f64/f32 | exact | relative error of the spatiotemporal distance |
//! | [`Family::Afferents`] | integrator × dt × precision, automatic or clock-driven stepping | the model's integrator, 0.1 ms, f64, automatic stepping (`reproduce --afferents`) | afferent spike-time error |
//! | [`Family::Transduction`] | pooling window, BA window (one at a time) | the paper's: 20 ms, 5 ms | taxel spike-time error |
//! | [`Family::Simulator`] | pixel step tolerance, mechanics sampling step, shear ODE step (one at a time, and the defaults) | the finest of each: 0.02, 0.25 ms, 25 µs | taxel spike-time error |
//!
//! The transduction family re-simulates the set once ([`resimulate`]: the simulator is
//! seeded, so the paper's setting gives the cached set again) and transduces every trial's
//! pixel events under every setting; its cost adds the transduction time (summed over trials)
//! and leaves the shared simulation out. The simulator family simulates the set once per
//! setting (not from the cache, so that the simulation is timed); its cost adds that pass.
//! [`recommend`] picks a family's operating point; [`report`] writes the files.

pub mod report;
mod resimulate;
mod settings;

pub use resimulate::{SimulatedSource, resimulate};
pub use settings::{Family, Setting};

use super::TradeoffError;
use super::pareto::pareto_front;
use neurotac_core::ndarray::Array2;
use neurotac_core::{Knn, SpikeDataset};
use neurotac_experiments::coding::{CodingName, CodingParameters};
use neurotac_experiments::menu::Menu;
use neurotac_experiments::progress::Progress;
use neurotac_experiments::protocols::{Accuracy, McNemar, Protocol, evaluate};
use neurotac_experiments::readouts::EncodedSet;
use neurotac_experiments::reproduce::{PipelineConfig, SetResult, run_encoded};
use neurotac_experiments::timing::timed;
use neurotac_sensor::sim::{SimParams, paper_transduction};
use serde::Serialize;

/// The significance level of the recommendation: a setting whose McNemar p-value is below it
/// (and whose accuracy is below the reference's) is significantly worse.
pub const ALPHA: f64 = 0.05;

/// One coding at one setting.
#[derive(Debug, Clone, Serialize)]
pub struct CodingOutcome {
    /// The coding.
    pub coding: CodingName,
    /// Leave-one-out accuracy with its Wilson 95 % interval.
    pub loo: Accuracy,
    /// McNemar's exact test against the reference setting on the same samples.
    pub mcnemar: McNemar,
}

/// The numerical error a setting makes against the reference (what the error columns show).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct NumericalError {
    /// Mean over the compared items (pairs of samples, or spikes).
    pub mean: f64,
    /// Largest.
    pub max: f64,
}

/// One setting measured.
#[derive(Debug, Clone, Serialize)]
pub struct SettingResult {
    /// [`Setting::label`].
    pub label: String,
    /// The reference setting (its accuracy is the full pipeline's).
    pub reference: bool,
    /// Wall time of the encoding and the four codings' distances and leave-one-out (s); plus,
    /// for the simulator family, its simulation pass, and for the transduction family, the
    /// transduction of every trial (summed over trials, over the worker threads).
    pub wall_s: f64,
    /// Process CPU time of the same (s), when known.
    pub cpu_s: Option<f64>,
    /// Neuron updates of the afferent layer (event-driven steps update only afferents with input); `None`
    /// without one.
    pub neuron_updates: Option<u64>,
    /// Synaptic events delivered to the afferents (one per taxel spike, one-to-one); `None`
    /// without an afferent layer.
    pub synaptic_events: Option<u64>,
    /// Spikes the codings read (taxel or afferent spikes) over every sample.
    pub output_spikes: u64,
    /// The four codings, in the menu's order.
    pub codings: Vec<CodingOutcome>,
    /// Numerical error against the reference ([`Family::error_name`]).
    pub error: NumericalError,
    /// On the Pareto front of (wall time, mean accuracy of the codings).
    pub front: bool,
    /// The family's recommended operating point ([`recommend`]).
    pub recommended: bool,
}

impl SettingResult {
    /// Mean leave-one-out accuracy of the four codings.
    pub fn mean_accuracy(&self) -> f64 {
        let n = self.codings.len().max(1) as f64;
        self.codings.iter().map(|c| c.loo.mean).sum::<f64>() / n
    }
}

/// One family on one set.
#[derive(Debug, Clone, Serialize)]
pub struct FamilyStudy {
    /// [`Family::stem`].
    pub family: String,
    /// [`Family::title`].
    pub title: String,
    /// [`Family::error_name`].
    pub error_name: &'static str,
    /// The reference's chosen parameters, used by every setting (`Δt = 159 ms; τ = 76 ms,
    /// cos θ = 0.40`).
    pub parameters: String,
    /// Wall time of the reference's whole pipeline, searches included (s).
    pub reference_pipeline_s: f64,
    /// The settings, the reference first.
    pub settings: Vec<SettingResult>,
    /// Index of the recommended setting.
    pub recommended: usize,
}

/// One set studied.
#[derive(Debug, Clone, Serialize)]
pub struct SetStudy {
    /// Set name (`artificial`, `natural`, a recorded folder's name).
    pub name: String,
    /// Samples.
    pub samples: usize,
    /// Classes.
    pub classes: usize,
    /// The families in the order asked.
    pub families: Vec<FamilyStudy>,
}

/// What a study runs on each set.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyConfig {
    /// The pipeline of the reference settings (`reproduce`'s, paper or quick).
    pub pipeline: PipelineConfig,
    /// The families, in order.
    pub families: Vec<Family>,
    /// Fewer settings per family.
    pub quick: bool,
}

/// The Δt, τ and cos θ the full pipeline chose.
fn chosen_parameters(result: &SetResult) -> CodingParameters {
    let bayes = result.bayes_search().map(|b| &b.result);
    CodingParameters {
        window_ms: result.dt_search().map(|s| s.sweep.best_window_ms),
        duration_ms: None,
        tau_s: bayes.map(|b| b.best_tau_s),
        cos: bayes.map(|b| b.best_cos),
    }
}

/// What making a setting's set cost: wall and CPU seconds.
type Cost = (f64, Option<f64>);

/// A coding's distance matrix and its leave-one-out predictions.
type Scored = (CodingName, Array2<f64>, Vec<usize>);

/// Every coding's distance matrix at `parameters`, and its leave-one-out predictions.
fn score(
    set: &EncodedSet,
    parameters: &CodingParameters,
    knn: Knn,
) -> Result<Vec<Scored>, TradeoffError> {
    CodingName::ALL
        .iter()
        .map(|&c| {
            let d = c
                .scheme()
                .distances(set, parameters, &neurotac_core::OneProcess)?;
            let e = evaluate(
                d.view(),
                &set.labels,
                set.n_classes(),
                knn,
                Protocol::LeaveOneOut,
            )?;
            Ok((c, d, e.predicted))
        })
        .collect()
}

/// `|D_h − D| / D` over the pairs of distinct samples with `D > 0`.
fn relative_error(reference: &Array2<f64>, other: &Array2<f64>) -> NumericalError {
    let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0usize);
    for ((i, j), &d) in reference.indexed_iter() {
        if i < j && d > 0.0 {
            let e = (other[(i, j)] - d).abs() / d;
            sum += e;
            max = max.max(e);
            n += 1;
        }
    }
    NumericalError {
        mean: if n == 0 { 0.0 } else { sum / n as f64 },
        max,
    }
}

/// For every spike of `other`, the distance to the nearest spike of the same channel and
/// sample of `reference` (ms); a channel with no reference spike is skipped.
fn spike_time_error(reference: &EncodedSet, other: &EncodedSet) -> NumericalError {
    let (mut sum, mut max, mut n) = (0.0, 0.0f64, 0usize);
    for (r, o) in reference.trains.iter().zip(&other.trains) {
        for ch in 0..r.n_channels().min(o.n_channels()) {
            let truth = r.channel(ch);
            if truth.is_empty() {
                continue;
            }
            for &t in o.channel(ch) {
                let k = truth.partition_point(|&x| x < t);
                let near = [k.checked_sub(1), Some(k)]
                    .into_iter()
                    .flatten()
                    .filter_map(|i| truth.get(i))
                    .map(|&x| (x - t).abs())
                    .fold(f64::INFINITY, f64::min);
                sum += near * 1e3;
                max = max.max(near * 1e3);
                n += 1;
            }
        }
    }
    NumericalError {
        mean: if n == 0 { 0.0 } else { sum / n as f64 },
        max,
    }
}

/// Studies `family` on `data` (labelled): the reference through the whole pipeline, every
/// setting at its parameters (module docs). `progress` gets one stage per setting.
pub fn study_family(
    name: &str,
    data: &SpikeDataset,
    source: Option<&SimulatedSource>,
    family: Family,
    config: &StudyConfig,
    progress: &dyn Progress,
) -> Result<FamilyStudy, TradeoffError> {
    let settings = family.settings(config.quick);
    let needs_source = || {
        source.ok_or_else(|| TradeoffError::NeedsSimulation {
            family: family.stem(),
        })
    };
    // Each setting's own set when the family makes one, with its cost (wall s, CPU s).
    let made: Option<Vec<(SpikeDataset, Cost)>> = match family {
        // One simulation, every transduction of it, each costing its transduction time: the
        // per-trial times summed (CPU), and that over the worker threads (wall).
        Family::Transduction => {
            let source = needs_source()?;
            let configs: Vec<_> = settings.iter().filter_map(|s| s.transduction).collect();
            let threads = rayon::current_num_threads().max(1) as f64;
            let (sets, _) = resimulate(source, &source.params, &configs, progress)?;
            Some(
                (sets.into_iter())
                    .map(|(set, s)| (set, (s / threads, Some(s))))
                    .collect(),
            )
        }
        // One simulation per setting, each costing the whole pass.
        Family::Simulator => {
            let source = needs_source()?;
            let mut sets = Vec::with_capacity(settings.len());
            for solver in settings.iter().filter_map(|s| s.solver) {
                let params = SimParams {
                    solver,
                    ..source.params
                };
                let (mut set, pass) =
                    resimulate(source, &params, &[paper_transduction()], progress)?;
                sets.push((set.remove(0).0, (pass.wall_s, pass.cpu_s)));
            }
            Some(sets)
        }
        _ => None,
    };
    let input = |i: usize| made.as_ref().map_or(data, |t| &t[i].0);
    let making = |i: usize| made.as_ref().map_or((0.0, Some(0.0)), |t| t[i].1);
    let data = input(0);
    let knn =
        Knn::new(config.pipeline.k).map_err(neurotac_experiments::error::ExperimentError::from)?;
    let labels = data.labels();
    let taxel_spikes: u64 = data
        .observations()
        .iter()
        .map(|o| o.total_spikes() as u64)
        .sum();
    let reference_set = settings[0].encode(data)?;
    let full = run_encoded(
        name,
        &reference_set,
        &config.pipeline,
        progress,
        &neurotac_core::OneProcess,
    )?;
    let parameters = chosen_parameters(&full);
    let described = (full.codings.iter())
        .map(|c| c.parameters.as_str())
        .filter(|p| !p.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    let reference_predictions: Vec<Vec<usize>> = full
        .codings
        .iter()
        .map(|c| c.loo.predicted.clone())
        .collect();
    let mut reference_matrices: Vec<Array2<f64>> = Vec::new();
    let mut rows = Vec::with_capacity(settings.len());
    for (i, setting) in settings.iter().enumerate() {
        progress.stage(
            &format!("{name}: {} — {}", family.stem(), setting.label()),
            0,
        );
        let (measured, timing) = timed(|| -> Result<_, TradeoffError> {
            let set = setting.encode(input(i))?;
            let scored = score(&set, &parameters, knn)?;
            Ok((set, scored))
        });
        let (set, scored) = measured?;
        progress.finish();
        // Every row, the reference's too, is its own leave-one-out at the chosen parameters
        // (the reference's equals the full pipeline's: same distances, same parameters).
        let codings = (scored.iter().zip(&reference_predictions))
            .map(
                |((coding, _, predicted), reference_predicted)| CodingOutcome {
                    coding: *coding,
                    loo: Accuracy::of(predicted, labels),
                    mcnemar: McNemar::of(reference_predicted, predicted, labels)
                        .expect("every setting predicts every sample of the same set"),
                },
            )
            .collect();
        let error = match family {
            Family::VanRossum => {
                let st = CodingName::ALL.len() - 1;
                if i == 0 {
                    reference_matrices = scored.into_iter().map(|(_, d, _)| d).collect();
                    NumericalError::default()
                } else {
                    relative_error(&reference_matrices[st], &scored[st].1)
                }
            }
            Family::Afferents(_) | Family::Transduction | Family::Simulator => match i {
                0 => NumericalError::default(),
                _ => spike_time_error(&reference_set, &set),
            },
        };
        rows.push(SettingResult {
            label: setting.label(),
            reference: i == 0,
            wall_s: timing.wall_s + making(i).0,
            cpu_s: timing.cpu_s.zip(making(i).1).map(|(a, b)| a + b),
            neuron_updates: setting.afferents.map(|_| set.neuron_updates),
            synaptic_events: setting.afferents.map(|_| taxel_spikes),
            output_spikes: set.trains.iter().map(|t| t.total_spikes() as u64).sum(),
            codings,
            error,
            front: false,
            recommended: false,
        });
    }
    let points: Vec<_> = (rows.iter())
        .map(|r| Some((1.0 / r.wall_s.max(1e-9), 1.0 - r.mean_accuracy())))
        .collect();
    for (row, front) in rows.iter_mut().zip(pareto_front(&points)) {
        row.front = front;
    }
    let recommended = recommend(&rows);
    rows[recommended].recommended = true;
    Ok(FamilyStudy {
        family: family.stem(),
        title: family.title(),
        error_name: family.error_name(),
        parameters: described,
        reference_pipeline_s: full.time.wall_s,
        settings: rows,
        recommended,
    })
}

/// `true` when every coding of `row` is acceptable against `reference`: not significantly
/// below it (McNemar p ≥ [`ALPHA`], or accuracy at least the reference's) and its Wilson
/// interval not entirely below the reference's.
pub fn acceptable(row: &SettingResult, reference: &SettingResult) -> bool {
    row.codings.iter().zip(&reference.codings).all(|(c, r)| {
        let not_worse = c.mcnemar.p >= ALPHA || c.loo.mean >= r.loo.mean;
        let overlaps = c.loo.wilson_high >= r.loo.wilson_low;
        not_worse && overlaps
    })
}

/// The recommended operating point of a family's `rows` (the reference first): the cheapest
/// (least wall time) acceptable setting ([`acceptable`]); the reference when no other is.
pub fn recommend(rows: &[SettingResult]) -> usize {
    let Some(reference) = rows.first() else {
        return 0;
    };
    (0..rows.len())
        .filter(|&i| i == 0 || acceptable(&rows[i], reference))
        .min_by(|&a, &b| rows[a].wall_s.total_cmp(&rows[b].wall_s))
        .unwrap_or(0)
}

/// Studies every family of `config` on one labelled set (`source`: how it was simulated, for
/// the transduction family; `None` for a recorded set).
pub fn study_set(
    name: &str,
    data: &SpikeDataset,
    source: Option<&SimulatedSource>,
    config: &StudyConfig,
    progress: &dyn Progress,
) -> Result<SetStudy, TradeoffError> {
    let families = (config.families.iter())
        .map(|&f| study_family(name, data, source, f, config, progress))
        .collect::<Result<_, _>>()?;
    Ok(SetStudy {
        name: name.to_owned(),
        samples: data.len(),
        classes: data.n_classes(),
        families,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_experiments::datasets::simulated::{TextureSet, load_or_simulate};
    use neurotac_experiments::progress::NoProgress;
    use neurotac_experiments::reproduce::{ReproduceConfig, run_set};
    use neurotac_sensor::taxel::TransductionConfig;

    fn small_pipeline() -> PipelineConfig {
        let mut p = ReproduceConfig::quick(1, "unused".into()).pipeline;
        p.bayes.epochs = 12;
        p.bayes.tau_step_s = 0.02;
        p
    }

    #[test]
    fn the_exact_reference_scores_what_reproduce_scores_on_the_same_set() {
        let cache = tempfile::tempdir().unwrap();
        let data = load_or_simulate(
            TextureSet::Artificial,
            3,
            1,
            &SimParams::default(),
            cache.path(),
            &|| {},
            &neurotac_core::OneProcess,
        )
        .unwrap();
        let pipeline = small_pipeline();
        let config = StudyConfig {
            pipeline,
            families: vec![Family::VanRossum],
            quick: true,
        };
        let study = study_set("artificial", &data, None, &config, &NoProgress).unwrap();
        let reproduce = run_set("artificial", &data, &pipeline, &NoProgress).unwrap();
        let vr = &study.families[0];
        let reference = &vr.settings[0];
        assert!(reference.reference && reference.label == "exact");
        assert_eq!(reference.codings.len(), reproduce.codings.len());
        for (s, r) in reference.codings.iter().zip(&reproduce.codings) {
            assert_eq!(s.coding, r.coding);
            assert_eq!(s.loo, r.loo.accuracy, "{:?}", s.coding);
            assert_eq!((s.mcnemar.b, s.mcnemar.c, s.mcnemar.p), (0, 0, 1.0));
        }
        // Every other setting is scored at the reference's parameters on the same samples: the
        // codings the setting does not touch predict exactly as the reference does.
        for row in &vr.settings[1..] {
            for c in &row.codings[..3] {
                assert_eq!(
                    (c.mcnemar.b, c.mcnemar.c),
                    (0, 0),
                    "{} {:?}",
                    row.label,
                    c.coding
                );
            }
            assert!(row.error.mean > 0.0, "{}", row.label);
        }
        let parameters = chosen_parameters(&reproduce);
        assert!(parameters.window_ms.is_some() && parameters.tau_s.is_some());
        assert!(vr.parameters.contains("Δt =") && vr.parameters.contains("cos θ ="));
    }

    #[test]
    fn the_papers_transduction_of_a_re_simulated_set_is_the_cached_set() {
        let cache = tempfile::tempdir().unwrap();
        let params = SimParams::default();
        let set = TextureSet::Artificial;
        let cached = load_or_simulate(
            set,
            2,
            1,
            &params,
            cache.path(),
            &|| {},
            &neurotac_core::OneProcess,
        )
        .unwrap();
        let source = SimulatedSource {
            set,
            trials: 2,
            seed: 1,
            params,
        };
        let wider = TransductionConfig {
            pool_window_us: 40_000,
            ..paper_transduction()
        };
        let (sets, _) = resimulate(
            &source,
            &source.params,
            &[paper_transduction(), wider],
            &NoProgress,
        )
        .unwrap();
        let (paper, _) = &sets[0];
        assert_eq!(paper.observations(), cached.observations());
        assert_eq!(paper.labels(), cached.labels());
        assert_eq!(paper.duration_s(), cached.duration_s());
        // Another window is another set of the same samples.
        assert_ne!(sets[1].0.observations(), cached.observations());
        assert_eq!(sets[1].0.labels(), cached.labels());
    }

    fn row(wall_s: f64, accuracy: &[(usize, usize, usize)]) -> SettingResult {
        // (hits, b, c) out of 100 samples, per coding.
        let codings = (accuracy.iter().zip(CodingName::ALL))
            .map(|(&(hits, b, c), &coding)| {
                let predicted: Vec<usize> = (0..100).map(|i| usize::from(i >= hits)).collect();
                let truth = vec![0; 100];
                CodingOutcome {
                    coding,
                    loo: Accuracy::of(&predicted, &truth),
                    mcnemar: McNemar {
                        b,
                        c,
                        p: neurotac_experiments::protocols::mcnemar_exact_p(b, c),
                    },
                }
            })
            .collect();
        SettingResult {
            label: format!("{wall_s} s"),
            reference: false,
            wall_s,
            cpu_s: None,
            neuron_updates: None,
            synaptic_events: None,
            output_spikes: 0,
            codings,
            error: NumericalError::default(),
            front: false,
            recommended: false,
        }
    }

    #[test]
    fn the_recommended_point_is_the_cheapest_never_significantly_or_wholly_below_the_reference() {
        let reference = row(10.0, &[(95, 0, 0); 4]);
        // Cheapest, but 10 discordant pairs all against it on one coding: p = 0.002.
        let significantly_worse = row(1.0, &[(95, 0, 0), (95, 0, 0), (85, 10, 0), (95, 0, 0)]);
        // Not significant by the (here made-up) test, but its interval lies wholly below.
        let interval_below = row(2.0, &[(95, 0, 0), (70, 1, 0), (95, 0, 0), (95, 0, 0)]);
        // Slightly lower, not significantly, interval overlapping: acceptable.
        let fine = row(3.0, &[(94, 2, 1), (95, 0, 0), (93, 3, 1), (96, 0, 1)]);
        let slower_fine = row(4.0, &[(95, 0, 0); 4]);
        let rows = vec![
            reference,
            significantly_worse,
            interval_below,
            slower_fine,
            fine,
        ];
        assert!(rows[2].codings[1].loo.wilson_high < rows[0].codings[1].loo.wilson_low);
        assert_eq!(recommend(&rows), 4);
        for (i, r) in rows.iter().enumerate() {
            assert_eq!(acceptable(r, &rows[0]), ![1, 2].contains(&i), "{i}");
        }
        // Nothing cheaper acceptable: the reference itself.
        assert_eq!(recommend(&rows[..3]), 0);
        let mut cheaper_reference = rows.clone();
        cheaper_reference[0].wall_s = 0.5;
        assert_eq!(recommend(&cheaper_reference), 0);
    }
}
