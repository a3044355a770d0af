//! The typed metadata of a taxel spike dataset: its sample duration
//! ([`SpikeDataset::duration_s`], in `neurotac-core`) and the transduction that made it (every
//! field of [`TransductionConfig`] under `meta.transduction`), written by [`write_metadata`] and read
//! by [`transduction_of`] — the one writer and the one reader of these fields for every
//! dataset (simulated, recorded, `neurotac transduce`).
//!
//! Older files wrote the settings flat into `meta` (`ba_window_us`, `rf_radius_px`,
//! `pool_window_us` or `pool_ms`, `recentre_gain`); [`transduction_of`] still reads them.

use neurotac_core::{DatasetError, SpikeDataset};
use neurotac_sensor::taxel::TransductionConfig;

/// The metadata key of the transduction settings.
pub const TRANSDUCTION_KEY: &str = "transduction";

/// Writes the typed metadata into `meta`: the transduction under `meta.transduction` and, when
/// known, the sample duration under `meta.duration_s` (checked as
/// [`SpikeDataset::set_duration_s`] does when the dataset is built).
pub fn write_metadata(
    meta: &mut serde_json::Map<String, serde_json::Value>,
    transduction: &TransductionConfig,
    duration_s: Option<f64>,
) {
    meta.insert(
        TRANSDUCTION_KEY.into(),
        serde_json::to_value(transduction).expect("settings serialise"),
    );
    if let Some(d) = duration_s {
        meta.insert(neurotac_core::dataset::DURATION_S_KEY.into(), d.into());
    }
}

/// The transduction that made `data`: `meta.transduction`, else the flat fields of older
/// files (defaults of [`TransductionConfig`] for what they did not record), else `None`.
pub fn transduction_of(data: &SpikeDataset) -> Result<Option<TransductionConfig>, DatasetError> {
    let meta = data.meta();
    if let Some(value) = meta.get(TRANSDUCTION_KEY) {
        return serde_json::from_value(value.clone())
            .map(Some)
            .map_err(|_| DatasetError::Meta {
                field: TRANSDUCTION_KEY,
                value: value.to_string(),
                expected: "an object of every transduction setting (see TransductionConfig)",
            });
    }
    let number = |key: &str| meta.get(key).and_then(|v| v.as_f64());
    let (Some(rf_radius_px), Some(recentre_gain)) =
        (number("rf_radius_px"), number("recentre_gain"))
    else {
        return Ok(None);
    };
    let mut settings = TransductionConfig {
        rf_radius_px,
        recentre_gain,
        // `neurotac transduce` wrote 0 for "no filter", the recorded loader null.
        ba_window_us: meta
            .get("ba_window_us")
            .and_then(|v| v.as_i64())
            .filter(|&w| w > 0),
        ..TransductionConfig::default()
    };
    if let Some(us) = meta.get("pool_window_us").and_then(|v| v.as_i64()) {
        settings.pool_window_us = us;
    } else if let Some(ms) = number("pool_ms") {
        settings.pool_window_us = neurotac_core::time::s_to_us(ms * 1e-3);
    }
    if let Some(origin) = meta.get("origin_us").and_then(|v| v.as_i64()) {
        settings.origin_us = Some(origin);
    }
    Ok(Some(settings))
}

#[cfg(test)]
mod tests {
    use super::*;
    use neurotac_core::MultiSpikeTrain;
    use neurotac_sensor::filter::MapStart;
    use std::path::Path;

    fn one_sample(meta: serde_json::Value) -> SpikeDataset {
        let serde_json::Value::Object(meta) = meta else {
            panic!("an object")
        };
        SpikeDataset::new(
            vec![MultiSpikeTrain::from_channels(vec![vec![0.01]]).unwrap()],
            vec![],
            vec![],
            meta,
        )
        .unwrap()
    }

    #[test]
    fn settings_round_trip_through_the_file() {
        let config = TransductionConfig {
            ba_start: MapStart::Empty,
            origin_us: Some(0),
            ba_window_us: None,
            ..TransductionConfig::default()
        };
        let mut data = one_sample(serde_json::json!({}));
        write_metadata(data.meta_mut(), &config, Some(4.5));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("d.bin");
        data.save_binary(&path).unwrap();
        let back = SpikeDataset::load(&path).unwrap();
        assert_eq!(back.duration_s(), Some(4.5));
        assert_eq!(transduction_of(&back).unwrap(), Some(config));
        assert_eq!(back.meta()["transduction"]["ba_start"], "empty");
    }

    /// Files written before the settings were typed still load, with their settings.
    #[test]
    fn old_flat_metadata_still_loads() {
        // `load_recorded`'s old shape.
        let text = r#"{"observations":[[[0.01]]],"meta":{"source":"textures","ba_window_us":null,
            "rf_radius_px":6.0,"pool_window_us":10000,"recentre_gain":0.5,"duration_s":1.201}}"#;
        let recorded = SpikeDataset::from_json_str(text, Path::new("old.json")).unwrap();
        assert_eq!(recorded.duration_s(), Some(1.201));
        let s = transduction_of(&recorded).unwrap().unwrap();
        assert_eq!(
            (
                s.ba_window_us,
                s.rf_radius_px,
                s.pool_window_us,
                s.recentre_gain
            ),
            (None, 6.0, 10_000, 0.5)
        );
        // `neurotac transduce`'s old shape: pool in ms, 0 for no filter.
        let cli = one_sample(
            serde_json::json!({"layout": "default", "ba_window_us": 5000,
            "rf_radius_px": 3.0, "pool_ms": 20.0, "recentre_gain": 0.0, "origin_us": 17}),
        );
        let s = transduction_of(&cli).unwrap().unwrap();
        assert_eq!(
            (
                s.ba_window_us,
                s.rf_radius_px,
                s.pool_window_us,
                s.origin_us
            ),
            (Some(5000), 3.0, 20_000, Some(17))
        );
        assert_eq!(cli.duration_s(), None);
        // Nothing recorded: nothing claimed.
        assert_eq!(
            transduction_of(&one_sample(serde_json::json!({}))).unwrap(),
            None
        );
    }
}
