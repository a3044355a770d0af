//! Re-simulating a simulated set ([`resimulate`]) for the families that change how its
//! spikes are made (transduction, simulator).

use super::TradeoffError;
use neurotac_core::{MultiSpikeTrain, SpikeDataset};
use neurotac_experiments::datasets::metadata::write_metadata;
use neurotac_experiments::datasets::simulated::{
    TextureSet, camera_seed, jobs_for, map_trials, prepare_textures, sample_duration_s,
};
use neurotac_experiments::progress::Progress;
use neurotac_experiments::timing::{Timing, timed};
use neurotac_sensor::sim::{Camera, SimParams, SimulationError, check_trials, transduce_with};
use neurotac_sensor::taxel::TransductionConfig;

/// Where a simulated set comes from (what the transduction family re-simulates).
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedSource {
    /// The texture set.
    pub set: TextureSet,
    /// Slides per texture.
    pub trials: usize,
    /// Seed of the simulation.
    pub seed: u64,
    /// Simulator parameters.
    pub params: SimParams,
}

/// Simulates `source` once with `params` and transduces every trial under each of
/// `configs`: one labelled dataset per configuration (in the cached set's order and with its
/// duration) with the transduction time of each summed over the trials (s), and the time of
/// the whole pass (simulation and every transduction).
pub fn resimulate(
    source: &SimulatedSource,
    params: &SimParams,
    configs: &[TransductionConfig],
    progress: &dyn Progress,
) -> Result<(Vec<(SpikeDataset, f64)>, Timing), TradeoffError> {
    let SimulatedSource {
        set, trials, seed, ..
    } = source;
    let simulation = |e: SimulationError| TradeoffError::Simulation(e.into());
    check_trials(*trials, set.textures().len()).map_err(simulation)?;
    params.validate().map_err(simulation)?;
    let (per_trial, pass) = timed(|| {
        let textures = prepare_textures(params, *set);
        let camera = Camera::new(params, camera_seed(*seed));
        let classes: Vec<usize> = (0..textures.len()).collect();
        let jobs = jobs_for(*set, *seed, &classes, 0, *trials);
        progress.stage(&format!("{}: simulating", set.name()), jobs.len() as u64);
        let per_trial: Result<Vec<Vec<(MultiSpikeTrain, f64)>>, _> = map_trials(
            params,
            &camera,
            &textures,
            &jobs,
            &|_, trial| {
                (configs.iter())
                    .map(|&c| {
                        let (spikes, time) = timed(|| transduce_with(&trial.events, c));
                        Ok((spikes?.spikes, time.wall_s))
                    })
                    .collect()
            },
            &|| progress.advance(1),
        );
        progress.finish();
        per_trial.map(|p| (p, jobs))
    });
    let (per_trial, jobs) = per_trial?;
    let labels: Vec<usize> = jobs.iter().map(|j| j.class).collect();
    let duration_s = sample_duration_s(params);
    let sets = (0..configs.len())
        .map(|k| {
            let observations = per_trial.iter().map(|t| t[k].0.clone()).collect();
            let seconds = per_trial.iter().map(|t| t[k].1).sum();
            let mut meta = serde_json::Map::new();
            write_metadata(&mut meta, &configs[k], Some(duration_s));
            let data = SpikeDataset::new(observations, labels.clone(), set.class_names(), meta)
                .map_err(|e| TradeoffError::Simulation(e.into()))?;
            Ok((data, seconds))
        })
        .collect::<Result<_, TradeoffError>>()?;
    Ok((sets, pass))
}
