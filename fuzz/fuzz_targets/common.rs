//! What every reader target checks: reading to the end (or to a typed error) terminates, every
//! event lies inside the sensor, and the counters agree with the events delivered.

use neurotac_core::EventBuffer;
use neurotac_sensor::format::EventReader;

/// Reads `reader` to its end or first error and checks the events against `size`.
pub fn drain(mut reader: impl EventReader, size: (u16, u16)) {
    let mut out = EventBuffer::new();
    let _ = reader.read_to_end(&mut out);
    assert!(out.x.iter().all(|&x| x < size.0) && out.y.iter().all(|&y| y < size.1));
    assert_eq!(reader.stats().events, out.len() as u64);
}
