//! The parameter file: the JSON form of [`SimParams`], read and written.

use super::{
    ContactParams, KinematicsParams, NoiseParams, OpticsParams, PARAMETER_SOURCES, PixelParams,
    SimParams, SolverParams,
};
use crate::sim::SimulationError;
use serde::Deserialize;
use std::path::Path;

/// A parameter file: the groups of [`SimParams`] and the documentary sections that
/// [`SimParams::to_json_string`] writes, skipped. Parsed straight from the text (not through a
/// `serde_json::Value`, which keeps the last of two equal keys and has no positions).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ParamFile {
    #[serde(default, rename = "sources")]
    _sources: serde::de::IgnoredAny,
    #[serde(default, rename = "calibrated")]
    _calibrated: serde::de::IgnoredAny,
    kinematics: KinematicsParams,
    contact: ContactParams,
    optics: OpticsParams,
    pixel: PixelParams,
    noise: NoiseParams,
    solver: SolverParams,
}

impl SimParams {
    /// Reads and validates a JSON parameter file (every field required).
    pub fn from_json_file(path: &Path) -> Result<Self, SimulationError> {
        let text = std::fs::read_to_string(path).map_err(|source| SimulationError::ParamsIo {
            path: path.to_owned(),
            source,
        })?;
        Self::from_json_str(&text, path)
    }

    /// Parses and validates the JSON form; `path` only names the source in errors. The
    /// documentary sections `sources` and `calibrated` written by
    /// [`to_json_string`](Self::to_json_string) are skipped. A field or group given twice is an
    /// error, like a missing or unknown one, with its line and column.
    pub fn from_json_str(text: &str, path: &Path) -> Result<Self, SimulationError> {
        let file: ParamFile =
            serde_json::from_str(text).map_err(|source| SimulationError::ParamsJson {
                path: path.to_owned(),
                source,
            })?;
        let params = SimParams {
            kinematics: file.kinematics,
            contact: file.contact,
            optics: file.optics,
            pixel: file.pixel,
            noise: file.noise,
            solver: file.solver,
        };
        params.validate()?;
        Ok(params)
    }

    /// The JSON form: a `sources` section naming where each prior comes from
    /// ([`PARAMETER_SOURCES`]), a `calibrated` section ([`calibrated_parameters`](Self::calibrated_parameters)),
    /// then every field.
    pub fn to_json_string(&self) -> String {
        let mut map = serde_json::Map::new();
        let sources: serde_json::Map<String, serde_json::Value> = PARAMETER_SOURCES
            .iter()
            .map(|(k, v)| ((*k).to_owned(), (*v).into()))
            .collect();
        map.insert("sources".into(), sources.into());
        map.insert(
            "calibrated".into(),
            serde_json::to_value(self.calibrated_parameters()).expect("finite values serialise"),
        );
        if let serde_json::Value::Object(fields) =
            serde_json::to_value(self).expect("finite parameters serialise")
        {
            map.extend(fields);
        }
        serde_json::to_string_pretty(&serde_json::Value::Object(map))
            .expect("finite parameters serialise")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_field_or_group_given_twice_is_an_error_with_its_line() {
        let text = SimParams::default().to_json_string();
        let twice_field = text.replacen(
            "\"speed_mm_s\": 15.0,",
            "\"speed_mm_s\": 150.0,\n    \"speed_mm_s\": 15.0,",
            1,
        );
        let pixel = &text[text.find("  \"pixel\": {").unwrap()..];
        let pixel = &pixel[..pixel.find("},").unwrap() + 2];
        let twice_group = text.replacen(pixel, &format!("{pixel}\n{pixel}"), 1);
        let missing = text.replacen("\"refractory_s\": 0.0005,", "", 1);
        for (bad, what) in [
            (twice_field, "duplicate field `speed_mm_s`"),
            (twice_group, "duplicate field `pixel`"),
            (missing, "missing field `refractory_s`"),
        ] {
            let err = SimParams::from_json_str(&bad, Path::new("p.json")).unwrap_err();
            let SimulationError::ParamsJson { source, .. } = &err else {
                panic!("{what}: {err:?}")
            };
            assert!(source.to_string().contains(what), "{source}");
            assert!(source.line() > 1, "{what}: no line in {source}");
        }
    }
}
