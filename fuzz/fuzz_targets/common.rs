//! What every reader target checks: reading to the end (or to a typed error) terminates, every
//! event lies inside the sensor (the one the input states, else the 240 × 180 the reader
//! assumes), and the counters agree with the events delivered.

use neurotac_core::EventBuffer;
use neurotac_sensor::format::{DAVIS240_SIZE, EventReader};

/// Reads `reader` to its end or first error and checks the events against its sensor.
pub fn drain(mut reader: impl EventReader) {
    let size = reader.sensor_size().unwrap_or(DAVIS240_SIZE);
    let mut out = EventBuffer::new();
    let _ = reader.read_to_end(&mut out);
    assert!(out.x.iter().all(|&x| x < size.0) && out.y.iter().all(|&y| y < size.1));
    assert_eq!(reader.stats().events, out.len() as u64);
}
