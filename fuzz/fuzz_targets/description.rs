//! The network-description reader (`NetworkBuilder::from_description` of JSON, what
//! `neurotac.Network.from_description` and `neurotac.nir.from_nir` run) on arbitrary bytes: a
//! typed error, or a network that builds (or is refused typed) and runs
//! (`neurotac_neurons::testing::check_description_text`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_neurons::testing::check_description_text;

fuzz_target!(|data: &[u8]| {
    check_description_text(data);
});
