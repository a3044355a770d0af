//! The committed corpus of the fuzz target `sim_params` (`fuzz/corpus/sim_params/`), replayed on
//! stable through the same checks as the fuzzer (`neurotac_sensor::testing::check_params_text`):
//! every file reads as simulator parameters or fails with a typed error — never a panic — and
//! parameters that read validate and read back equal from the file they write.
//!
//! The corpus holds the named seeds of `fuzz/make_seeds.sh` (the default parameter file and its
//! variants: cut at several offsets, NaN, Infinity and 1e999 values, wrong types, missing,
//! unknown and duplicate fields, deep nesting) and what the fuzzer found, minimised
//! (`fuzz/README.md`).

use neurotac_core::testing::fuzz::corpus;
use neurotac_sensor::sim::{SimParams, SimulationError};
use neurotac_sensor::testing::check_params_text;

#[test]
fn every_parameter_corpus_file_reads_or_fails_typed() {
    let Some(files) = corpus("sim_params") else {
        return;
    };
    assert!(!files.is_empty(), "empty corpus");
    let mut total_bytes = 0;
    let mut outcomes = std::collections::BTreeMap::new();
    for (name, bytes) in &files {
        total_bytes += bytes.len();
        // A file that is not UTF-8 is refused when it is read (`SimParams::from_json_file`).
        let Ok(text) = std::str::from_utf8(bytes) else {
            continue;
        };
        let read = std::panic::catch_unwind(|| check_params_text(text))
            .unwrap_or_else(|_| panic!("sim_params/{name}: a check failed (message above)"));
        outcomes.insert(name.as_str(), read);
    }
    assert!(total_bytes <= 1_000_000, "corpus of {total_bytes} bytes");
    // The named seeds: the defaults as `neurotac simulate params` writes them read back, and
    // the broken variants fail, each with the error of its kind.
    let outcome = |name: &str| {
        outcomes
            .get(name)
            .unwrap_or_else(|| panic!("sim_params/{name} is missing"))
    };
    assert_eq!(
        outcome("default.json").as_ref().ok(),
        Some(&SimParams::default())
    );
    // A field or a group given twice is refused, not silently the last one taken.
    for name in [
        "nan.json",
        "overflow.json",
        "string_for_number.json",
        "cut_1000.json",
        "duplicate_field.json",
        "duplicate_group.json",
    ] {
        assert!(
            matches!(outcome(name), Err(SimulationError::ParamsJson { .. })),
            "{name}: {:?}",
            outcome(name)
        );
    }
    for name in ["negative.json", "microslip_max_below_min.json"] {
        assert!(
            matches!(outcome(name), Err(SimulationError::InvalidParameter { .. })),
            "{name}: {:?}",
            outcome(name)
        );
    }
    eprintln!(
        "replayed {} parameter corpus files ({total_bytes} bytes)",
        files.len()
    );
}
