//! The simulator parameter-file reader (`SimParams::from_json_str`) on arbitrary text: a typed
//! error, or parameters that validate and read back equal from the file they write
//! (`neurotac_sensor::testing::check_params_text`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_sensor::testing::check_params_text;

fuzz_target!(|data: &[u8]| {
    // A file that is not UTF-8 is refused before parsing (`SimParams::from_json_file`).
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = check_params_text(text);
    }
});
