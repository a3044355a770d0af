use super::*;
use crate::error::{SpikeError, SpikeLocation};

#[test]
fn duration_is_typed_metadata_that_old_files_may_lack() {
    let mut d = sample();
    assert_eq!(d.duration_s(), None);
    d.set_duration_s(4.5).unwrap();
    assert_eq!(d.duration_s(), Some(4.5));
    let back = SpikeDataset::from_binary(&d.to_binary(), Path::new("x.bin")).unwrap();
    assert_eq!(back.duration_s(), Some(4.5));
    assert!(matches!(
        d.set_duration_s(f64::NAN),
        Err(DatasetError::Meta {
            field: "duration_s",
            ..
        })
    ));
    let bad = r#"{"observations":[[[0.1]]],"meta":{"duration_s":"long"}}"#;
    let e = SpikeDataset::from_json_str(bad, Path::new("bad.json")).unwrap_err();
    assert_eq!(
        e.to_string(),
        r#"meta.duration_s = "long": a finite number of seconds > 0"#
    );
}

fn sample() -> SpikeDataset {
    let obs = vec![
        MultiSpikeTrain::from_channels(vec![vec![0.001, 0.5], vec![]]).unwrap(),
        MultiSpikeTrain::from_channels(vec![vec![], vec![0.25, 0.25, 4.5]]).unwrap(),
    ];
    let mut meta = serde_json::Map::new();
    meta.insert("sensor".into(), "neurotac-sim".into());
    SpikeDataset::new(obs, vec![1, 0], vec!["smooth".into(), "5 mm".into()], meta).unwrap()
}

#[test]
fn json_has_the_documented_shape_and_round_trips() {
    let d = sample();
    let text = d.to_json_string();
    assert_eq!(
        text,
        r#"{"labels":[1,0],"class_names":["smooth","5 mm"],"observations":[[[0.001,0.5],[]],[[],[0.25,0.25,4.5]]],"meta":{"sensor":"neurotac-sim"}}"#
    );
    let back = SpikeDataset::from_json_str(&text, Path::new("x.json")).unwrap();
    assert_eq!(back, d);
}

#[test]
fn json_round_trips_full_precision_times_bit_for_bit() {
    // Times with all 17 significant digits (serde_json's exact float parsing is required).
    let channels: Vec<Vec<f64>> = (0..49)
        .map(|c| {
            (1..30)
                .map(|k| (k as f64 * 0.1 + c as f64 * 1e-3).sqrt() / 3.0)
                .collect()
        })
        .collect();
    let d =
        SpikeDataset::unlabelled(vec![MultiSpikeTrain::from_channels(&channels).unwrap()]).unwrap();
    let back = SpikeDataset::from_json_str(&d.to_json_string(), Path::new("x")).unwrap();
    let bits = |d: &SpikeDataset| {
        d.observations()[0]
            .flat_times()
            .iter()
            .map(|t| t.to_bits())
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&back), bits(&d));
}

#[test]
fn json_with_only_observations_is_accepted() {
    let d = SpikeDataset::from_json_str(
        r#"{"observations": [[[0.1], [0.2, 0.3]]]}"#,
        Path::new("o.json"),
    )
    .unwrap();
    assert_eq!(d.len(), 1);
    assert!(d.labels().is_empty());
    assert_eq!(d.n_channels(), 2);
}

#[test]
fn json_errors_name_the_observation_and_the_problem() {
    let e = SpikeDataset::from_json_str(
        r#"{"observations": [[[0.1]], [[0.3, 0.2]]]}"#,
        Path::new("d.json"),
    )
    .unwrap_err();
    assert!(
        matches!(e, DatasetError::Spikes { observation: 1, .. }),
        "{e}"
    );
    let e = SpikeDataset::from_json_str(
        r#"{"observations": [[[0.1]], [[0.2], []]]}"#,
        Path::new("d.json"),
    )
    .unwrap_err();
    assert!(matches!(
        e,
        DatasetError::ChannelCount {
            observation: 1,
            expected: 1,
            got: 2
        }
    ));
    let e = SpikeDataset::from_json_str(
        r#"{"labels": [0], "observations": []}"#,
        Path::new("d.json"),
    )
    .unwrap_err();
    assert!(matches!(
        e,
        DatasetError::LabelCount {
            labels: 1,
            observations: 0
        }
    ));
    let e = SpikeDataset::from_json_str(
        r#"{"labels": [2], "class_names": ["a"], "observations": [[[]]]}"#,
        Path::new("d.json"),
    )
    .unwrap_err();
    assert!(matches!(
        e,
        DatasetError::LabelOutOfRange {
            observation: 0,
            label: 2,
            n_classes: 1
        }
    ));
    let e = SpikeDataset::from_json_str(r#"{"labels": []}"#, Path::new("d.json")).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("d.json: invalid spike-dataset JSON"),
        "{e}"
    );
}

/// The JSON form of `sample()` with observation 1's channel 1 written as `channel`.
fn json_with_channel(channel: &str) -> String {
    format!(
        r#"{{"labels":[1,0],"class_names":["smooth","5 mm"],"observations":[[[0.001,0.5],[]],[[],{channel}]]}}"#
    )
}

#[test]
fn a_broken_json_dataset_error_names_observation_channel_spike_and_position() {
    // Each broken channel, the column serde_json stops at (the byte after an out-of-order
    // time, the last byte of a number beyond f64, the first letter of a word JSON does not
    // have), and the whole message.
    let prefix = json_with_channel("@").find('@').unwrap();
    let cases = [
        (
            "[0.25,0.5,0.3]",
            prefix + 14,
            "channel 1, spike 2: times not sorted (0.3 s after 0.5 s)",
        ),
        (
            "[0.25,NaN]",
            prefix + 7,
            "channel 1, spike 1: time NaN is not finite",
        ),
        (
            "[0.25,Infinity]",
            prefix + 7,
            "channel 1, spike 1: time inf is not finite",
        ),
        (
            "[-Infinity]",
            prefix + 3,
            "channel 1, spike 0: time -inf is not finite",
        ),
        (
            "[0.25, 1e999]",
            prefix + 12,
            "channel 1, spike 1: time inf is not finite",
        ),
        (
            "[0.25,-1e999]",
            prefix + 12,
            "channel 1, spike 1: time -inf is not finite",
        ),
    ];
    for (channel, column, says) in cases {
        let text = json_with_channel(channel);
        let e = SpikeDataset::from_json_str(&text, Path::new("d.json")).unwrap_err();
        assert!(
            matches!(
                e,
                DatasetError::Spikes {
                    observation: 1,
                    position: Some(FilePosition::Text { line: 1, column: c }),
                    source: SpikeError::NonFinite { channel: 1, .. }
                        | SpikeError::Unsorted { channel: 1, .. },
                } if c == column
            ),
            "{channel}: {e:?}"
        );
        assert_eq!(
            crate::error_chain(&e),
            format!("observation 1 (line 1, column {column}): {says}"),
            "{channel}"
        );
        assert_eq!(e.path(), None);
    }
    // What is not a number at all keeps serde_json's message, with the place.
    for (channel, found, column) in [
        (r#"[0.25,"NaN"]"#, r#"string "NaN""#, prefix + 11),
        ("[0.25,null]", "null", prefix + 10),
    ] {
        let e = SpikeDataset::from_json_str(&json_with_channel(channel), Path::new("d.json"))
            .unwrap_err();
        let at = SpikeLocation {
            observation: 1,
            channel: Some(1),
            spike: Some(1),
        };
        assert!(
            matches!(e, DatasetError::Json { at: Some(a), .. } if a == at),
            "{e:?}"
        );
        assert_eq!(
            crate::error_chain(&e),
            format!(
                "d.json: invalid spike-dataset JSON in observation 1, channel 1, spike 1: \
                 invalid type: {found}, expected a spike time (a number of seconds) at line 1 \
                 column {column}"
            )
        );
    }
}

#[test]
fn json_errors_keep_line_and_column_and_the_place_in_observations() {
    // Pretty-printed: the NaN is on line 5.
    let text = "{\n  \"observations\": [\n    [[0.1]],\n    [\n      [0.2, NaN]\n    ]\n  ]\n}";
    let e = SpikeDataset::from_json_str(text, Path::new("p.json")).unwrap_err();
    assert_eq!(
        crate::error_chain(&e),
        "observation 1 (line 5, column 13): channel 0, spike 1: time NaN is not finite"
    );
    // An observation or a channel that is not a list is placed as far as it goes.
    let e = SpikeDataset::from_json_str(r#"{"observations":[[[0.1]],5]}"#, Path::new("o.json"))
        .unwrap_err();
    assert_eq!(
        crate::error_chain(&e),
        "o.json: invalid spike-dataset JSON in observation 1: invalid type: integer `5`, \
         expected an observation (a list of channels) at line 1 column 26"
    );
    let e = SpikeDataset::from_json_str(r#"{"observations":[[[0.1],{}]]}"#, Path::new("o.json"))
        .unwrap_err();
    assert!(
        crate::error_chain(&e).starts_with(
            "o.json: invalid spike-dataset JSON in observation 0, channel 1: invalid type: map"
        ),
        "{e}"
    );
    // Outside `observations` there is no place in them, but still a line and column.
    let e = SpikeDataset::from_json_str(
        r#"{"observations":[[[0.1]]],"labels":["a"]}"#,
        Path::new("l.json"),
    )
    .unwrap_err();
    assert!(matches!(e, DatasetError::Json { at: None, .. }), "{e:?}");
    assert_eq!(
        crate::error_chain(&e),
        r#"l.json: invalid spike-dataset JSON: invalid type: string "a", expected usize at line 1 column 39"#
    );
    // Truncated inside a channel: a syntax error at the spike, not a time.
    let e = SpikeDataset::from_json_str(r#"{"observations":[[[0.1,0.2"#, Path::new("t.json"))
        .unwrap_err();
    assert_eq!(
        crate::error_chain(&e),
        "t.json: invalid spike-dataset JSON in observation 0, channel 0, spike 2: EOF while \
         parsing a list at line 1 column 26"
    );
    assert_eq!(e.path(), Some(Path::new("t.json")));
}

/// `bytes` (a binary dataset) with the time `old` (which must occur once) replaced by `new`
/// and the checksum recomputed; also the byte offset of that time.
fn binary_with_time(mut bytes: Vec<u8>, old: f64, new: f64) -> (Vec<u8>, usize) {
    let at = bytes
        .windows(8)
        .position(|w| w == old.to_le_bytes())
        .unwrap();
    assert_eq!(
        bytes[at + 8..]
            .windows(8)
            .position(|w| w == old.to_le_bytes()),
        None
    );
    bytes[at..at + 8].copy_from_slice(&new.to_le_bytes());
    let body = bytes.len() - CHECKSUM_BYTES;
    let crc = crc32fast::hash(&bytes[..body]);
    bytes[body..].copy_from_slice(&crc.to_le_bytes());
    (bytes, at)
}

#[test]
fn a_broken_binary_dataset_error_names_observation_channel_spike_and_byte() {
    // sample(): observation 0 is [[0.001, 0.5], []], observation 1 is [[], [0.25, 0.25, 4.5]].
    let cases = [
        (
            4.5,
            0.1,
            "observation 1",
            "channel 1, spike 2: times not sorted (0.1 s after 0.25 s)",
        ),
        (
            4.5,
            f64::NAN,
            "observation 1",
            "channel 1, spike 2: time NaN is not finite",
        ),
        (
            0.5,
            f64::INFINITY,
            "observation 0",
            "channel 0, spike 1: time inf is not finite",
        ),
        (
            0.001,
            f64::NEG_INFINITY,
            "observation 0",
            "channel 0, spike 0: time -inf is not finite",
        ),
    ];
    for (old, new, observation, says) in cases {
        let (bytes, at) = binary_with_time(sample().to_binary(), old, new);
        let e = SpikeDataset::from_binary(&bytes, Path::new("d.bin")).unwrap_err();
        assert!(
            matches!(
                e,
                DatasetError::Spikes {
                    position: Some(FilePosition::Byte { offset }),
                    ..
                } if offset == at
            ),
            "{e:?}"
        );
        assert_eq!(
            crate::error_chain(&e),
            format!("{observation} (byte {at}): {says}")
        );
        assert_eq!(e.path(), None);
        // Version 1 (no checksum) is placed the same way.
        let mut old_form = bytes.clone();
        old_form.truncate(bytes.len() - CHECKSUM_BYTES);
        old_form[8..12].copy_from_slice(&VERSION_WITHOUT_CHECKSUM.to_le_bytes());
        let e = SpikeDataset::from_binary(&old_form, Path::new("d.bin")).unwrap_err();
        assert_eq!(
            crate::error_chain(&e),
            format!("{observation} (byte {at}): {says}")
        );
    }
}

#[test]
fn binary_round_trips_and_files_load_by_magic() {
    let d = sample();
    let dir = tempfile::tempdir().unwrap();
    let (bin, json) = (dir.path().join("d.ntspk"), dir.path().join("d.json"));
    d.save_binary(&bin).unwrap();
    d.save_json(&json).unwrap();
    assert_eq!(SpikeDataset::load(&bin).unwrap(), d);
    assert_eq!(SpikeDataset::load(&json).unwrap(), d);
    // On realistic data (49 taxels, full-precision times) the binary form is the compact one.
    let slide = MultiSpikeTrain::from_channels((0..49).map(|c| {
        (0..40)
            .map(|i| (c * 40 + i) as f64 * 1.234_567e-3)
            .collect::<Vec<_>>()
    }))
    .unwrap();
    let big = SpikeDataset::unlabelled(vec![slide]).unwrap();
    assert!(big.to_binary().len() < big.to_json_string().len());
}

/// The version-1 form of a dataset (no checksum), as files written before the format had a
/// checksum hold it.
fn version_1(d: &SpikeDataset) -> Vec<u8> {
    let mut bytes = d.to_binary();
    bytes.truncate(bytes.len() - CHECKSUM_BYTES);
    bytes[8..12].copy_from_slice(&VERSION_WITHOUT_CHECKSUM.to_le_bytes());
    bytes
}

#[test]
fn every_one_bit_flip_is_a_checksum_error_naming_the_file() {
    let bytes = sample().to_binary();
    assert_eq!(&bytes[8..12], &VERSION.to_le_bytes());
    // Past magic and version, every flipped bit is caught by the checksum.
    for byte in 12..bytes.len() {
        for bit in 0..8 {
            let mut flipped = bytes.clone();
            flipped[byte] ^= 1 << bit;
            match SpikeDataset::from_binary(&flipped, Path::new("cache/a.bin")) {
                Err(e @ DatasetError::Checksum { .. }) => {
                    assert!(e.to_string().starts_with("cache/a.bin: checksum mismatch"))
                }
                other => panic!("byte {byte} bit {bit}: {other:?}"),
            }
        }
    }
    for cut in 0..bytes.len() {
        assert!(
            SpikeDataset::from_binary(&bytes[..cut], Path::new("t")).is_err(),
            "cut {cut}"
        );
    }
    // In the magic or the version it is a typed error too.
    for byte in 0..12 {
        let mut flipped = bytes.clone();
        flipped[byte] ^= 1;
        assert!(SpikeDataset::from_binary(&flipped, Path::new("a")).is_err());
    }
}

#[test]
fn version_1_files_without_a_checksum_still_load() {
    let d = sample();
    let old = version_1(&d);
    assert_eq!(SpikeDataset::from_binary(&old, Path::new("v1")).unwrap(), d);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("v1.bin");
    std::fs::write(&path, &old).unwrap();
    assert_eq!(SpikeDataset::load(&path).unwrap(), d);
}

#[test]
fn corrupt_binary_is_a_typed_error_never_a_huge_allocation() {
    // Version 1 has no checksum: its structural checks are what guards it.
    let bytes = version_1(&sample());
    // Every truncation fails cleanly.
    for cut in 0..bytes.len() {
        assert!(
            SpikeDataset::from_binary(&bytes[..cut], Path::new("t")).is_err(),
            "cut {cut}"
        );
    }
    // An observation count of 2⁶³ is rejected before allocating.
    let mut huge = bytes.clone();
    huge[12..20].copy_from_slice(&(1u64 << 63).to_le_bytes());
    match SpikeDataset::from_binary(&huge, Path::new("h")) {
        Err(DatasetError::Binary {
            offset: 12, what, ..
        }) => assert!(what.contains("observation count")),
        other => panic!("{other:?}"),
    }
    // A spike count beyond the file is rejected.
    let mut counts = bytes.clone();
    let n = counts.len();
    counts[n - 8 * 3 - 8..n - 8 * 3].copy_from_slice(&(u64::MAX / 2).to_le_bytes());
    assert!(SpikeDataset::from_binary(&counts, Path::new("c")).is_err());
    let mut trailing = bytes;
    trailing.push(0);
    assert!(SpikeDataset::from_binary(&trailing, Path::new("t")).is_err());
}

#[test]
fn labels_and_class_names_beyond_the_class_limit_are_refused_in_both_forms() {
    let obs = || vec![MultiSpikeTrain::from_channels([[0.1]]).unwrap(); 2];
    let largest = MAX_CLASSES - 1;
    let ok = SpikeDataset::new(obs(), vec![0, largest], vec![], Default::default()).unwrap();
    assert_eq!(ok.n_classes(), MAX_CLASSES);
    // A label the binary form once refused (≥ 2³²) and one it read (4·10⁹): refused in JSON, in
    // binary version 1 and 2 alike, naming the observation, so a JSON file converts to binary
    // and back and no per-class table is sized by a corrupt label.
    for label in [MAX_CLASSES, 4_000_000_000, 1 << 32] {
        let json = format!(r#"{{"labels":[0,{label}],"observations":[[[0.1]],[[0.1]]]}}"#);
        let mut binary = ok.to_binary();
        let at = binary.len() - 4 - 2 * (8 + 8 + 8) - 8;
        binary[at..at + 8].copy_from_slice(&(label as u64).to_le_bytes());
        let n = binary.len() - CHECKSUM_BYTES;
        let crc = crc32fast::hash(&binary[..n]);
        binary[n..].copy_from_slice(&crc.to_le_bytes());
        let v1 = {
            let mut b = binary[..n].to_vec();
            b[8..12].copy_from_slice(&VERSION_WITHOUT_CHECKSUM.to_le_bytes());
            b
        };
        for (form, read) in [
            (
                "JSON",
                SpikeDataset::from_json_str(&json, Path::new("d.json")),
            ),
            (
                "binary",
                SpikeDataset::from_binary(&binary, Path::new("d.bin")),
            ),
            (
                "version 1",
                SpikeDataset::from_binary(&v1, Path::new("d.bin")),
            ),
        ] {
            match read {
                Err(
                    e @ DatasetError::LabelBeyondLimit {
                        observation: 1,
                        max: MAX_CLASSES,
                        ..
                    },
                ) => assert_eq!(
                    e.to_string(),
                    format!(
                        "observation 1: label {label}, but a dataset has at most 1024 classes (labels 0 to 1023)"
                    )
                ),
                other => panic!("{form}, label {label}: {other:?}"),
            }
        }
    }
    let names = vec![String::new(); MAX_CLASSES + 1];
    let json = serde_json::json!({"class_names": names, "observations": []}).to_string();
    match SpikeDataset::from_json_str(&json, Path::new("d.json")) {
        Err(e @ DatasetError::TooManyClassNames { names: 1025, .. }) => assert_eq!(
            e.to_string(),
            "1025 class names, but a dataset has at most 1024 classes"
        ),
        other => panic!("{other:?}"),
    }
}
