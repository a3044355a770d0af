//! Test support (hidden from the documentation): what the fuzz target `sim_params` checks,
//! shared with the test that replays its committed corpus on stable. A check panics when the
//! reader breaks a promise (that is the fuzzer's crash); a typed error is a pass.

use crate::sim::{SimParams, SimulationError};
use std::path::Path;

/// Reads `text` as a simulator parameter file ([`SimParams::from_json_str`], the reader behind every
/// `--params` option of `neurotac`) and checks what it gives: parameters that were read pass
/// [`SimParams::validate`], and the file written from them
/// ([`SimParams::to_json_string`]) reads back to the same parameters.
pub fn check_params_text(text: &str) -> Result<SimParams, SimulationError> {
    let path = Path::new("<fuzz>");
    let read = SimParams::from_json_str(text, path);
    if let Ok(params) = &read {
        if let Err(e) = params.validate() {
            panic!("parameters that were read do not validate: {e}");
        }
        let again = SimParams::from_json_str(&params.to_json_string(), path);
        assert_eq!(
            again.as_ref().ok(),
            Some(params),
            "written and read back: {again:?}"
        );
    }
    read
}
