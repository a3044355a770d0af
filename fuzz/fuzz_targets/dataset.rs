//! The spike-dataset reader (`SpikeDataset::from_bytes`: the binary form, versions 1 and 2, or
//! JSON) on arbitrary bytes: a typed error, or a dataset that keeps its promises and converts to
//! both forms and back (`neurotac_core::testing::fuzz::check_dataset_bytes`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_core::testing::fuzz::check_dataset_bytes;

fuzz_target!(|data: &[u8]| {
    let _ = check_dataset_bytes(data);
});
