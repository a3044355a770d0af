//! The distance matrices, the Δt sweep, the Van Rossum search and the pipeline split over ranks
//! (threads standing in for MPI ranks) give every rank the one-process results, bit for bit,
//! for 1, 2 and 3 ranks and for more ranks than some blocks have rows.

use neurotac_core::ndarray::Array2;
use neurotac_core::ranks::ThreadRanks;
use neurotac_core::{Knn, SpikeDataset};
use neurotac_experiments::coding::spatiotemporal::van_rossum_input;
use neurotac_experiments::coding::{CodingName, CodingParameters, coding_distances};
use neurotac_experiments::datasets::synthetic::{SyntheticConfig, synthetic_dataset};
use neurotac_experiments::menu::Menu;
use neurotac_experiments::neuron_setup::Precision;
use neurotac_experiments::progress::NoProgress;
use neurotac_experiments::readouts::{VrFrom, encode_offline};
use neurotac_experiments::reproduce::{PipelineConfig, SetResult, run_encoded};
use neurotac_experiments::search::bayes::{
    BayesConfig, BayesResult, VanRossumInput, VanRossumObjective, bayes_optimise,
};
use neurotac_experiments::search::dt_sweep::dt_sweep;

/// Rank counts checked (5 leaves some ranks a single row of the smaller matrices' triangles).
const RANK_COUNTS: [usize; 4] = [1, 2, 3, 5];

/// 24 samples of 5 taxels over 0.6 s in 3 classes.
fn small() -> SpikeDataset {
    synthetic_dataset(&SyntheticConfig {
        samples: 24,
        classes: 3,
        channels: 5,
        spikes_per_unit: 6.0,
        duration_s: 0.6,
        seed: 7,
    })
}

fn bits(m: &Array2<f64>) -> Vec<u64> {
    m.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn coding_distances_on_ranks_are_the_one_process_matrices() {
    let data = small();
    let parameters = CodingParameters {
        window_ms: Some(40),
        duration_ms: Some(600),
        tau_s: Some(0.02),
        cos: Some(0.4),
    };
    for &coding in CodingName::ALL {
        let want = coding_distances(
            data.observations(),
            coding,
            &parameters,
            &neurotac_core::OneProcess,
        )
        .unwrap();
        for size in RANK_COUNTS {
            let got = ThreadRanks::run(size, |r| {
                coding_distances(data.observations(), coding, &parameters, r).unwrap()
            });
            for (rank, m) in got.iter().enumerate() {
                assert_eq!(bits(m), bits(&want), "{coding:?}, rank {rank} of {size}");
            }
        }
    }
}

#[test]
fn dt_sweep_on_ranks_is_the_one_process_sweep() {
    let data = small();
    let (obs, labels) = (data.observations(), data.labels());
    let knn = Knn::default();
    let want = dt_sweep(obs, labels, 600, 90, knn, &neurotac_core::OneProcess).unwrap();
    for size in RANK_COUNTS {
        let got = ThreadRanks::run(size, |r| dt_sweep(obs, labels, 600, 90, knn, r).unwrap());
        for (rank, sweep) in got.iter().enumerate() {
            assert_eq!(sweep, &want, "rank {rank} of {size}");
        }
    }
}

/// A short search over `input`: its result and the matrices it computed.
fn search(
    input: VanRossumInput<'_>,
    labels: &[usize],
    ranks: &dyn neurotac_core::Ranks,
) -> (BayesResult, usize) {
    let config = BayesConfig {
        epochs: 12,
        initial: 4,
        tau_step_s: 0.015,
        cos_step: 0.1,
        ..BayesConfig::default()
    };
    // A cache of 2 matrices: evictions and recomputations happen on every rank alike.
    let mut objective = VanRossumObjective::new(input, labels, Knn::default(), 2).on_ranks(ranks);
    let result = bayes_optimise(&config, |i, tau, cos| objective.accuracy(i, tau, cos)).unwrap();
    (result, objective.matrices_computed)
}

#[test]
fn van_rossum_search_on_ranks_is_the_one_process_search() {
    let data = small();
    let traces = VrFrom::Traces {
        trace_dt_s: 1e-3,
        precision: Precision::F32,
    };
    for vr_from in [VrFrom::Exact, traces] {
        let set = encode_offline(&data, vr_from).unwrap();
        let input = van_rossum_input(&set);
        let want = search(input, &set.labels, &neurotac_core::OneProcess);
        for size in RANK_COUNTS {
            let got = ThreadRanks::run(size, |r| search(input, &set.labels, r));
            for (rank, result) in got.iter().enumerate() {
                assert_eq!(result, &want, "{vr_from:?}, rank {rank} of {size}");
            }
        }
    }
}

/// What a pipeline result says, its timings left out.
fn outcome(r: &SetResult) -> serde_json::Value {
    let mut v = serde_json::to_value(r).unwrap();
    let o = v.as_object_mut().unwrap();
    o.remove("time");
    for coding in o["codings"].as_array_mut().unwrap() {
        let coding = coding.as_object_mut().unwrap();
        coding.remove("time");
        // The search's time, under its kind.
        if let Some(search) = coding.get_mut("search").and_then(|s| s.as_object_mut()) {
            for (_, kind) in search.iter_mut() {
                kind.as_object_mut().unwrap().remove("time");
            }
        }
    }
    v
}

#[test]
fn the_pipeline_on_ranks_is_the_one_process_pipeline() {
    let data = small();
    let set = encode_offline(&data, VrFrom::Exact).unwrap();
    let mut config = PipelineConfig::paper(1);
    config.max_window_ms = 60;
    config.bayes.epochs = 10;
    config.bayes.tau_step_s = 0.03;
    config.bayes.cos_step = 0.25;
    let want = outcome(
        &run_encoded(
            "small",
            &set,
            &config,
            &NoProgress,
            &neurotac_core::OneProcess,
        )
        .unwrap(),
    );
    for size in [2, 3] {
        let got = ThreadRanks::run(size, |r| {
            outcome(&run_encoded("small", &set, &config, &NoProgress, r).unwrap())
        });
        for (rank, result) in got.iter().enumerate() {
            assert_eq!(result, &want, "rank {rank} of {size}");
        }
    }
}
