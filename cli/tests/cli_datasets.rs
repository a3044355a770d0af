//! Broken spike datasets: `classify` says on one line which file, observation, channel and
//! spike is broken, where in the file, and what is wrong with it.

mod common;

use common::neurotac;
use neurotac_core::{MultiSpikeTrain, SpikeDataset};
use std::path::Path;

/// Two labelled observations of three channels; observation 1, channel 2 is
/// `[0.125, 0.375, 0.625]` (times that occur nowhere else).
fn dataset() -> SpikeDataset {
    let observations = vec![
        MultiSpikeTrain::from_channels(vec![vec![0.1], vec![0.2, 0.3], vec![]]).unwrap(),
        MultiSpikeTrain::from_channels(vec![vec![0.4], vec![], vec![0.125, 0.375, 0.625]]).unwrap(),
    ];
    let names = vec!["smooth".to_owned(), "rough".to_owned()];
    SpikeDataset::new(observations, vec![0, 1], names, serde_json::Map::new()).unwrap()
}

/// The one-line stderr of a failed `classify` on `input`.
fn classify_error(input: &Path) -> String {
    let (ok, stdout, stderr) = neurotac(&[
        "classify",
        "--input",
        input.to_str().unwrap(),
        "--coding",
        "spatial",
    ]);
    assert!(!ok, "{stdout}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    stderr.trim_end().to_owned()
}

#[test]
fn classify_names_where_a_broken_json_dataset_is_broken_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let text = dataset().to_json_string();
    for (broken, says) in [
        (
            "0.125,0.375,0.2",
            "spike 2: times not sorted (0.2 s after 0.375 s)",
        ),
        ("0.125,NaN,0.625", "spike 1: time NaN is not finite"),
        ("0.125,1e999,0.625", "spike 1: time inf is not finite"),
    ] {
        let broken_text = text.replace("0.125,0.375,0.625", broken);
        assert_ne!(broken_text, text);
        let path = dir.path().join("broken.json");
        std::fs::write(&path, &broken_text).unwrap();
        // serde_json stops on the word it cannot read, after a number it cannot hold, or on the
        // byte after an out-of-order time.
        let at = broken_text.find(broken).unwrap();
        let column = match broken {
            "0.125,NaN,0.625" => at + 7,
            "0.125,1e999,0.625" => at + 11,
            _ => at + broken.len() + 1,
        };
        assert_eq!(
            classify_error(&path),
            format!(
                "error: reading the spike dataset {}: observation 1 (line 1, column {column}): \
                 channel 2, {says}",
                path.display()
            )
        );
    }
    // A time that is not a number keeps serde_json's message, line and column.
    let path = dir.path().join("string.json");
    let broken_text = text.replace("0.375", "\"NaN\"");
    std::fs::write(&path, &broken_text).unwrap();
    let column = broken_text.find("\"NaN\"").unwrap() + 5;
    assert_eq!(
        classify_error(&path),
        format!(
            "error: reading the spike dataset: {}: invalid spike-dataset JSON in observation 1, \
             channel 2, spike 1: invalid type: string \"NaN\", expected a spike time (a number of \
             seconds) at line 1 column {column}",
            path.display()
        )
    );
}

#[test]
fn classify_names_where_a_broken_binary_dataset_is_broken_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = dataset().to_binary();
    for (new, says) in [
        (f64::NAN, "spike 1: time NaN is not finite"),
        (0.0625, "spike 1: times not sorted (0.0625 s after 0.125 s)"),
        (f64::NEG_INFINITY, "spike 1: time -inf is not finite"),
    ] {
        // 0.375, spike 1 of observation 1's channel 2, replaced; the checksum recomputed so that
        // the file is intact and only the time is wrong.
        let mut broken = bytes.clone();
        let at = broken
            .windows(8)
            .position(|w| w == 0.375f64.to_le_bytes())
            .unwrap();
        broken[at..at + 8].copy_from_slice(&new.to_le_bytes());
        let body = broken.len() - 4;
        let crc = crc32fast::hash(&broken[..body]);
        broken[body..].copy_from_slice(&crc.to_le_bytes());
        let path = dir.path().join("broken.bin");
        std::fs::write(&path, &broken).unwrap();
        assert_eq!(
            classify_error(&path),
            format!(
                "error: reading the spike dataset {}: observation 1 (byte {at}): channel 2, {says}",
                path.display()
            )
        );
    }
}

#[test]
fn a_missing_dataset_error_keeps_the_system_cause() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("absent.json");
    let message = classify_error(&path);
    assert!(
        message.starts_with(&format!(
            "error: reading the spike dataset: cannot read {}: ",
            path.display()
        )),
        "{message}"
    );
    assert!(message.contains("os error"), "{message}");
}

#[test]
fn classify_names_the_sample_and_channel_of_a_spike_before_time_0() {
    // A negative time reads (times need only be finite and sorted); the coding refuses it.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("early.json");
    let text = dataset().to_json_string();
    std::fs::write(&path, text.replace("0.125,0.375", "-0.5,0.375")).unwrap();
    assert_eq!(
        classify_error(&path),
        "error: sample 1, channel 2: spike at -0.5 s, before the sample start (0 s)"
    );
}
