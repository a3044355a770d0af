use super::*;
use crate::export::OutputFormat;
use crate::threads::with_threads;
use neurotac_core::OneProcess;
use neurotac_core::io::{AtomicFileSet, Replace};
use neurotac_sensor::sim::{SimulationError, Simulator, Texture};

fn short_params() -> SimParams {
    let mut p = SimParams::default();
    p.kinematics.distance_mm = 6.0;
    p.kinematics.dwell_s = 0.02;
    p
}

#[test]
fn same_seed_is_bit_identical_at_any_thread_count_and_another_seed_differs() {
    let p = short_params();
    let run = |threads, seed| {
        with_threads(threads, || {
            simulate_set(
                TextureSet::Artificial,
                2,
                seed,
                &p,
                &|_, _| Ok(()),
                &|| {},
                &OneProcess,
            )
        })
        .unwrap()
        .unwrap()
        .dataset
    };
    let one = run(1, 5);
    let two = run(2, 5);
    assert_eq!(one.to_binary(), two.to_binary());
    assert_eq!(one.len(), 22);
    assert_eq!(one.labels()[21], 10);
    assert_ne!(run(2, 6).to_binary(), one.to_binary());
}

#[test]
fn zero_trials_or_more_than_the_trial_budget_is_an_error_before_simulating() {
    let p = short_params();
    let dir = tempfile::tempdir().unwrap();
    let load = |trials| {
        load_or_simulate(
            TextureSet::Natural,
            trials,
            1,
            &p,
            dir.path(),
            &|| {},
            &OneProcess,
        )
    };
    assert!(matches!(
        load(0),
        Err(DatasetsError::Simulation(SimulationError::ZeroTrials))
    ));
    assert!(matches!(
        load(usize::MAX),
        Err(DatasetsError::Simulation(SimulationError::TooManyTrials {
            trials: usize::MAX,
            textures: 20,
            ..
        }))
    ));
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
}

#[test]
fn cache_is_reused_and_keyed_by_the_parameters() {
    let p = short_params();
    let dir = tempfile::tempdir().unwrap();
    let first = load_or_simulate(
        TextureSet::Artificial,
        1,
        3,
        &p,
        dir.path(),
        &|| {},
        &OneProcess,
    )
    .unwrap();
    let path = cache_path(TextureSet::Artificial, 1, 3, &p, dir.path());
    assert!(path.exists());
    // A cached file is what is returned: replace it by a one-trial dataset with the same
    // metadata and read that back.
    let fake = SpikeDataset::new(
        first.observations()[..1].to_vec(),
        vec![0],
        first.class_names().to_vec(),
        first.meta().clone(),
    )
    .unwrap();
    store(&fake, dir.path(), &path).unwrap();
    let again = load_or_simulate(
        TextureSet::Artificial,
        1,
        3,
        &p,
        dir.path(),
        &|| {},
        &OneProcess,
    )
    .unwrap();
    assert_eq!(again, fake);
    let mut spoiled = first.clone();
    spoiled.meta_mut().insert("seed".into(), 999.into());
    let mut other = p;
    other.pixel.threshold_on = 0.21;
    assert_ne!(
        cache_path(TextureSet::Artificial, 1, 3, &other, dir.path()),
        path
    );
    // A file whose metadata does not match (hash collision, edits) is not trusted.
    store(&spoiled, dir.path(), &path).unwrap();
    let regenerated = load_or_simulate(
        TextureSet::Artificial,
        1,
        3,
        &p,
        dir.path(),
        &|| {},
        &OneProcess,
    )
    .unwrap();
    assert_eq!(regenerated, first);
}

#[test]
fn events_csv_has_a_header_and_labels() {
    let p = short_params();
    let camera = Camera::new(&p, 1);
    let mut sim = Simulator::new(p, &camera).unwrap();
    let tex = sim.prepare(Texture::grid(5.0).unwrap());
    let trial = sim.simulate(&tex, 9);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("e.csv");
    write_events_csv(&path, &trial.events, Some(&trial.labels)).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,x,y,on,pin"));
    assert_eq!(lines.count(), trial.events.len());
    assert!(text.contains(",-1\n"));
}

/// Simulated sets state their sample duration, and every spike lies inside it.
#[test]
fn simulated_sets_state_their_duration() {
    let p = short_params();
    let data = simulate_set(
        TextureSet::Artificial,
        1,
        2,
        &p,
        &|_, _| Ok(()),
        &|| {},
        &OneProcess,
    )
    .unwrap()
    .dataset;
    let duration_s = data.duration_s().unwrap();
    assert_eq!(duration_s, sample_duration_s(&p));
    assert!(duration_s >= p.duration_s() && duration_s < p.duration_s() + 1e-3);
    let latest = data
        .observations()
        .iter()
        .filter_map(|o| o.time_range())
        .map(|r| r.1);
    assert!(latest.fold(0.0, f64::max) < duration_s);
    // The default recording lasts the paper's 4.528 s at 15 mm/s give or take the loop's
    // latencies; every sample fits in the longest one, rounded up to the ms.
    assert_eq!(sample_duration_s(&SimParams::default()), 4.593);
}
/// `neurotac simulate`'s generation is a library call.
#[test]
fn generate_writes_the_dataset_then_reads_it_from_the_cache() {
    use crate::progress::NoProgress;
    let dir = tempfile::tempdir().unwrap();
    let config = GenerateConfig {
        set: TextureSet::Artificial,
        trials: 1,
        seed: 4,
        params: short_params(),
        out: dir.path().join("out"),
        cache: dir.path().join("cache"),
        also: vec![OutputFormat::Json, OutputFormat::Npz],
        pixel_events: None,
    };
    let run = |config: &GenerateConfig, replace: Replace| {
        let mut outputs = AtomicFileSet::new(replace);
        let made = generate(config, &mut outputs, &NoProgress, &OneProcess)?;
        outputs.commit().map_err(|source| DatasetsError::Io {
            path: config.out.clone(),
            source,
        })?;
        Ok::<_, DatasetsError>(made)
    };
    let first = run(&config, Replace::No).unwrap();
    assert!(!first.from_cache);
    assert_eq!(first.binary, dir.path().join("out/artificial.bin"));
    assert_eq!(SpikeDataset::load(&first.binary).unwrap(), first.dataset);
    assert_eq!(first.also.len(), 2);
    assert!(first.also.iter().all(|p| p.is_file()));
    let npz = std::fs::read(&first.also[1]).unwrap();
    assert_eq!(
        npz,
        crate::export::dataset_npz_bytes(&first.dataset).unwrap()
    );
    assert_eq!(first.class_means.len(), 11);
    let again = run(&config, Replace::Yes).unwrap();
    assert!(again.from_cache);
    assert_eq!(again.dataset, first.dataset);
    let with_events = GenerateConfig {
        pixel_events: Some(PixelEventFiles::LabelledCsv),
        ..config.clone()
    };
    // Interrupted before its commit (an error, or the process killed): no events folder.
    let mut dropped = AtomicFileSet::new(Replace::Yes);
    generate(&with_events, &mut dropped, &NoProgress, &OneProcess).unwrap();
    assert!(!dir.path().join("out/events").exists());
    drop(dropped);
    assert_eq!(
        neurotac_core::testing::folder_names(&dir.path().join("out")),
        ["artificial.bin", "artificial.json", "artificial.npz"]
    );
    let made = run(&with_events, Replace::Yes).unwrap();
    assert!(!made.from_cache);
    assert!(
        dir.path()
            .join("out/events/00-grid_0.0_mm/000.csv")
            .is_file()
    );
    assert_eq!(made.dataset.observations(), first.dataset.observations());
    let zero = GenerateConfig {
        trials: 0,
        ..config
    };
    assert!(matches!(
        run(&zero, Replace::No),
        Err(DatasetsError::Simulation(SimulationError::ZeroTrials))
    ));
}
