//! The USB word decoder on arbitrary bytes, cut at an arbitrary point: no panic, addresses in
//! range, and the same events and counters as decoding in one piece.
#![no_main]

use libfuzzer_sys::fuzz_target;
use neurotac_core::EventBuffer;
use neurotac_sensor::davis::UsbDecoder;

fuzz_target!(|data: &[u8]| {
    let Some((&cut, bytes)) = data.split_first() else {
        return;
    };
    let split = usize::from(cut).min(bytes.len());
    let mut whole = EventBuffer::new();
    let mut one = UsbDecoder::davis240();
    one.decode(bytes, &mut whole);
    let mut parts = EventBuffer::new();
    let mut specials = Vec::new();
    let mut two = UsbDecoder::davis240();
    two.decode_with_specials(&bytes[..split], &mut parts, &mut specials);
    two.decode_with_specials(&bytes[split..], &mut parts, &mut specials);
    assert_eq!(whole, parts);
    assert_eq!(one.stats(), two.stats());
    assert!(whole.x.iter().all(|&x| x < 240) && whole.y.iter().all(|&y| y < 180));
    assert!(whole.len() as u64 <= one.stats().words);
});
