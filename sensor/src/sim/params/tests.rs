use super::*;
use crate::sim::SimulationError;
use std::path::Path;

#[test]
fn every_parameter_names_its_source_or_says_it_has_none() {
    let json = serde_json::to_value(SimParams::default()).unwrap();
    let mut missing = Vec::new();
    for (group, fields) in json.as_object().unwrap() {
        for field in fields.as_object().unwrap().keys() {
            let name = format!("{group}.{field}");
            if !PARAMETER_SOURCES
                .iter()
                .any(|(k, _)| *k == name || *k == group.as_str())
            {
                missing.push(name);
            }
        }
    }
    assert!(missing.is_empty(), "no source for {missing:?}");
    // Every entry carries a tag: read, remembered, assumed, calibrated, informed by the
    // calibration targets, an explicit "no source", or not a physical value at all (a selector,
    // numerical settings).
    let tags = [
        "[R]",
        "[K]",
        "[A]",
        "CALIBRATED",
        "INFORMED",
        "no source",
        "a selector",
        "numerical settings",
    ];
    let untagged: Vec<&str> = PARAMETER_SOURCES
        .iter()
        .filter(|(_, v)| !tags.iter().any(|t| v.contains(t)))
        .map(|(k, _)| *k)
        .collect();
    assert!(untagged.is_empty(), "untagged sources: {untagged:?}");
}

#[test]
fn defaults_validate_and_a_recording_lasts_as_long_as_the_papers_at_15_mm_s() {
    let p = SimParams::default();
    p.validate().unwrap();
    // The paper's 4.528 s, and the longest recording a few ms beyond.
    let nominal = super::super::kinematics::Recording::nominal(&p).end_s;
    assert!((nominal - 4.528).abs() < 0.01, "{nominal}");
    assert!(p.duration_s() > nominal && p.duration_s() < nominal + 0.1);
}

/// The field `validate` names when it refuses `p`.
fn refused_field(p: &SimParams) -> &'static str {
    match p.validate() {
        Err(SimulationError::InvalidParameter { field, .. }) => field,
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_values_name_their_field() {
    type Spoil = fn(&mut SimParams);
    let cases: [(Spoil, &str); 6] = [
        (|p| p.pixel.threshold_on = -0.2, "pixel.threshold_on"),
        (|p| p.pixel.refractory_s = -1e-4, "pixel.refractory_s"),
        (|p| p.contact.lever_mm = f64::NAN, "contact.lever_mm"),
        (|p| p.kinematics.speed_mm_s = -15.0, "kinematics.speed_mm_s"),
        (|p| p.optics.pin_radius_px = -3.0, "optics.pin_radius_px"),
        (
            |p| p.noise.shot_rate_hz = f64::INFINITY,
            "noise.shot_rate_hz",
        ),
    ];
    for (spoil, name) in cases {
        let mut p = SimParams::default();
        spoil(&mut p);
        assert_eq!(refused_field(&p), name);
    }
}

#[test]
fn a_trial_too_long_names_the_field_that_makes_it_long() {
    type Spoil = fn(&mut SimParams);
    let cases: [(Spoil, &str); 5] = [
        (
            |p| p.kinematics.acceleration_mm_s2 = 1e-6,
            "kinematics.acceleration_mm_s2",
        ),
        (|p| p.kinematics.distance_mm = 1e6, "kinematics.distance_mm"),
        (|p| p.kinematics.speed_mm_s = 1e-3, "kinematics.speed_mm_s"),
        (|p| p.kinematics.dwell_s = 900.0, "kinematics.dwell_s"),
        (
            |p| p.kinematics.press_travel_mm = 1e5,
            "kinematics.press_travel_mm",
        ),
    ];
    for (spoil, name) in cases {
        let mut p = SimParams::default();
        spoil(&mut p);
        assert_eq!(refused_field(&p), name);
    }
}

#[test]
fn a_leak_spread_whose_mean_noise_exceeds_the_budget_is_refused() {
    let mut p = SimParams::default();
    p.noise.leak_spread_decades = 1.0;
    p.validate().unwrap();
    for spread in [2.0, 1e300] {
        p.noise.leak_spread_decades = spread;
        assert_eq!(refused_field(&p), "noise.leak_spread_decades");
    }
    // The error prints the number as a person writes it, not 301 digits.
    let e = p.validate().unwrap_err().to_string();
    assert!(
        e.starts_with("parameter `noise.leak_spread_decades` = 1e300: "),
        "{e}"
    );
    // The mean of r₀·10^(s·N(0,1)) is r₀·exp((s·ln 10)²/2).
    p.noise.leak_spread_decades = 1.0;
    let mean = p.noise.mean_leak_rate_hz() / p.noise.leak_rate_hz;
    assert!((mean - (std::f64::consts::LN_10.powi(2) / 2.0).exp()).abs() < 1e-12);
}

#[test]
fn noise_events_beyond_the_memory_budget_are_refused_naming_the_larger_rate() {
    let mut p = SimParams::default();
    p.noise.shot_rate_hz = 500.0; // 500 Hz × 43 200 pixels × 4.55 s ≈ 9.8·10⁷ events
    p.validate().unwrap();
    p.kinematics.dwell_s = 100.0; // ≈ 2.2·10⁹
    assert_eq!(refused_field(&p), "noise.shot_rate_hz");
}

#[test]
fn parameter_files_round_trip_and_missing_fields_are_named() {
    let p = SimParams::default();
    let text = p.to_json_string();
    assert_eq!(
        SimParams::from_json_str(&text, Path::new("p.json")).unwrap(),
        p
    );
    let missing = text.replace("\"refractory_s\": 0.0005,", "");
    assert!(text.contains("\"sources\"") && text.contains("ABB IRB120"));
    let err = SimParams::from_json_str(&missing, Path::new("p.json")).unwrap_err();
    let SimulationError::ParamsJson { source, .. } = &err else {
        panic!("{err:?}")
    };
    assert!(source.to_string().contains("refractory_s"), "{source}");
    let negative = text.replace("\"threshold_off\": 0.25", "\"threshold_off\": -0.25");
    let err = SimParams::from_json_str(&negative, Path::new("p.json")).unwrap_err();
    assert!(err.to_string().contains("pixel.threshold_off"), "{err}");
}
