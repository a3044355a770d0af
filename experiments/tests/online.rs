//! The online recogniser's decision at the end of each replayed slide equals the
//! offline classifier's prediction for that sample, for all four codings.

use neurotac_core::coding::{IntensiveCoding, SpatialCoding, feature_matrix};
use neurotac_core::distance::{VanRossum, euclidean_distance_matrix};
use neurotac_core::ndarray::Array2;
use neurotac_core::{EventBuffer, Knn, OneProcess, SpikeDataset};
use neurotac_experiments::coding::{Coding, CodingName};
use neurotac_experiments::datasets::simulated::{TextureSet, simulate_set};
use neurotac_experiments::online::eval::subset;
use neurotac_experiments::online::{OnlineClassifier, OnlineTraining, Recogniser};
use neurotac_experiments::readouts::{VrFrom, encode_offline};
use neurotac_sensor::sim::{SimParams, paper_transduction};
use std::collections::BTreeMap;
use std::sync::Mutex;

const TRIALS: usize = 3;

/// Short slides of the artificial set, 3 per texture: the dataset (class-major) and each
/// slide's pixel events.
fn slides() -> (SpikeDataset, BTreeMap<(usize, usize), EventBuffer>) {
    let mut params = SimParams::default();
    params.kinematics.distance_mm = 6.0;
    let events = Mutex::new(BTreeMap::new());
    let set = simulate_set(
        TextureSet::Artificial,
        TRIALS,
        5,
        &params,
        &|job, trial| {
            events
                .lock()
                .unwrap()
                .insert((job.class, job.trial), trial.events.clone());
            Ok(())
        },
        &|| {},
        &OneProcess,
    )
    .unwrap();
    (set.dataset, events.into_inner().unwrap())
}

#[test]
fn final_online_decisions_equal_the_offline_predictions() {
    let (data, events) = slides();
    // Trial 2 of each class is held out; the training set keeps the others in order.
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for i in 0..data.len() {
        if i % TRIALS == TRIALS - 1 {
            test.push(i);
        } else {
            train.push(i);
        }
    }
    let order: Vec<usize> = train.iter().chain(&test).copied().collect();
    let pick = |idx: &[usize]| subset(&data, idx).unwrap();
    let (all, training) = (pick(&order), pick(&train));
    let (train_idx, test_idx): (Vec<usize>, Vec<usize>) = (
        (0..train.len()).collect(),
        (train.len()..order.len()).collect(),
    );
    let training = OnlineTraining::new(&training, None).unwrap();

    // Offline: the square matrices of the whole set, KNN from the training rows.
    let encoded = encode_offline(&all, VrFrom::Exact).unwrap();
    let window_ms = 50;
    let (tau_s, cos) = (0.07, 0.5);
    let temporal = {
        let width = (encoded.duration_ms - window_ms + 1) as usize;
        let mut m = Array2::zeros((all.len(), width));
        for (o, mut row) in all.observations().iter().zip(m.rows_mut()) {
            let bins = neurotac_core::coding::pooled_bin_counts(o, encoded.duration_ms);
            neurotac_core::coding::write_window_features(
                &bins,
                window_ms,
                all.n_channels(),
                row.as_slice_mut().unwrap(),
            );
        }
        m
    };
    let codings = [
        (
            Coding::of(CodingName::Intensive),
            euclidean_distance_matrix(
                feature_matrix(&IntensiveCoding::new(), all.observations())
                    .unwrap()
                    .view(),
                &neurotac_core::OneProcess,
            )
            .unwrap(),
        ),
        (
            Coding::of(CodingName::Spatial),
            euclidean_distance_matrix(
                feature_matrix(&SpatialCoding::new(), all.observations())
                    .unwrap()
                    .view(),
                &neurotac_core::OneProcess,
            )
            .unwrap(),
        ),
        (
            Coding::temporal(window_ms),
            euclidean_distance_matrix(temporal.view(), &neurotac_core::OneProcess).unwrap(),
        ),
        (
            Coding::spatiotemporal(tau_s, cos),
            VanRossum::new(tau_s)
                .unwrap()
                .matrices(&encoded.trains, &neurotac_core::OneProcess)
                .unwrap()
                .distances(cos)
                .unwrap(),
        ),
    ];
    let knn = Knn::new(4).unwrap();
    for (coding, distances) in codings {
        let offline = knn
            .predict(distances.view(), all.labels(), &train_idx, &test_idx)
            .unwrap();
        let classifier = OnlineClassifier::new(&training, coding, 4).unwrap();
        for (&i, &expected) in test.iter().zip(&offline) {
            let pixels = &events[&(data.labels()[i], TRIALS - 1)];
            let mut r = Recogniser::new(&classifier, paper_transduction(), 3).unwrap();
            // Replayed in chunks of 997 events, as a reader delivers them.
            let mut chunk = EventBuffer::new();
            for start in (0..pixels.len()).step_by(997) {
                chunk.clear();
                for j in start..(start + 997).min(pixels.len()) {
                    chunk.push(pixels.get(j).unwrap());
                }
                r.push(&chunk).unwrap();
            }
            let last = r.finish().unwrap();
            assert_eq!(last.class, expected, "{} coding, sample {i}", coding.name);
            // A decision after every 20 ms window up to the recording's end (a recording stops
            // when the lab's loop stops logging, within the samples' duration).
            let windows = r.decisions().len() as u32;
            let last_us = *pixels.t.last().expect("events") as u32;
            assert_eq!(windows, last_us / 20_000 + 1, "{}", coding.name);
            assert!(
                windows <= training.duration_ms().div_ceil(20),
                "{}",
                coding.name
            );
            assert!(
                r.decisions()
                    .iter()
                    .all(|d| d.vote_share > 0.0 && d.vote_share <= 1.0)
            );
        }
    }
}

/// A small training set: 2 short slides of each artificial texture.
fn small_training() -> OnlineTraining {
    let mut params = SimParams::default();
    params.kinematics.distance_mm = 6.0;
    let set = simulate_set(
        TextureSet::Artificial,
        2,
        3,
        &params,
        &|_, _| Ok(()),
        &|| {},
        &OneProcess,
    )
    .unwrap();
    OnlineTraining::new(&set.dataset, None).unwrap()
}

/// The live camera path (`--device`): the DAVIS driver over the recorded USB stream of the
/// shared DAVIS240C recording gives the decisions of replaying the same events from its file;
/// unplugged mid-slide, it fails with the disconnection and keeps what it decided.
#[test]
fn the_camera_path_decides_as_the_file_replay_and_keeps_its_decisions_when_unplugged() {
    use neurotac_experiments::online::{ReplaySpeed, recognise_stream, replay};
    use neurotac_sensor::davis::{Davis, DeviceInfo, ReplayEnd, ReplayTransport, StartOptions};
    let Some(dir) = neurotac_core::testing::shared_data("davis240") else {
        return;
    };
    let training = small_training();
    let coding = Coding::of(CodingName::Spatial);
    let live = neurotac_sensor::taxel::TransductionConfig {
        origin_us: None,
        ..paper_transduction()
    };
    let strip = |d: &[neurotac_experiments::online::Decision]| -> Vec<(f64, usize, f64)> {
        d.iter().map(|d| (d.t_s, d.class, d.vote_share)).collect()
    };
    // The file.
    let classifier = OnlineClassifier::new(&training, coding, 4).unwrap();
    let mut from_file = Recogniser::new(&classifier, live, 3).unwrap();
    let mut reader = neurotac_sensor::format::open_reader(&dir.join("pick_events.csv")).unwrap();
    let file_final = replay(&mut from_file, &mut *reader, ReplaySpeed::Max, &mut |_| {}).unwrap();
    // The camera, whole and cut at 30 % of its bytes.
    let bytes = std::fs::read(dir.join("pick_usb_words.bin")).unwrap();
    let usb = DeviceInfo {
        product_id: neurotac_sensor::davis::protocol::PRODUCT_ID_FX2,
        firmware: neurotac_sensor::davis::protocol::FIRMWARE_FX2,
        bus: 1,
        address: 2,
        serial: None,
    };
    for cut in [bytes.len(), bytes.len() * 3 / 10 / 4 * 4] {
        let transport = ReplayTransport::new(bytes[..cut].to_vec(), 8192, ReplayEnd::Unplug);
        let davis = Davis::open(transport, usb.clone()).unwrap();
        davis.send_default_config().unwrap();
        let mut stream = davis.start(StartOptions::default()).unwrap();
        let mut r = Recogniser::new(&classifier, live, 3).unwrap();
        let mut seen = 0;
        let result = recognise_stream(&mut r, &mut stream, &mut |_| seen += 1);
        assert_eq!(seen, r.decisions().len());
        let n = r.decisions().len();
        assert!(n > 0);
        assert_eq!(strip(r.decisions()), strip(&from_file.decisions()[..n]));
        match result {
            Ok(last) => {
                assert_eq!(cut, bytes.len());
                assert_eq!(last.class, file_final.class);
            }
            Err(e) => {
                assert!(e.to_string().contains("disconnected"), "{e}");
                assert!(n < from_file.decisions().len(), "unplugged mid-slide");
            }
        }
    }
}

#[test]
fn bad_streams_are_refused_with_what_was_decided_kept() {
    let training = small_training();
    let classifier = OnlineClassifier::new(&training, Coding::of(CodingName::Spatial), 4).unwrap();
    let mut r = Recogniser::new(&classifier, paper_transduction(), 3).unwrap();
    // An empty stream.
    assert!(r.finish().unwrap_err().to_string().contains("empty"));
    let mut r = Recogniser::new(&classifier, paper_transduction(), 3).unwrap();
    let mut events = EventBuffer::new();
    for k in 0..200i64 {
        events.push(neurotac_core::Event {
            t: neurotac_core::Timestamp(k * 500),
            x: 120,
            y: 90,
            polarity: true,
        });
    }
    r.push(&events).unwrap();
    let decided = r.decisions().len();
    assert!(decided >= 4);
    // Out of order: a typed error naming the event; the decisions stay.
    let mut back = EventBuffer::new();
    back.push(neurotac_core::Event {
        t: neurotac_core::Timestamp(10),
        x: 1,
        y: 1,
        polarity: false,
    });
    let e = r.push(&back).unwrap_err();
    assert!(e.to_string().contains("10"), "{e}");
    assert_eq!(r.decisions().len(), decided);
    // Off the sensor.
    let mut off = EventBuffer::new();
    off.push(neurotac_core::Event {
        t: neurotac_core::Timestamp(200_000),
        x: 500,
        y: 1,
        polarity: false,
    });
    assert!(r.push(&off).is_err());
    assert_eq!(r.decisions().len(), decided);
}
