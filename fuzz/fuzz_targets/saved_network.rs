//! The saved-network reader (`NetworkBuilder::from_saved_bytes`, what `NetworkBuilder::load`
//! and `neurotac.Network.load` run) on arbitrary bytes, as a file and as the body of a file with
//! a valid header and checksum: a typed error, or a network that builds (or is refused typed)
//! and runs (`neurotac_neurons::testing::check_saved_network_bytes`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_neurons::testing::check_saved_network_bytes;

fuzz_target!(|data: &[u8]| {
    check_saved_network_bytes(data);
});
