//! Test helpers: the shared DAVIS240C recording (CSV) and NumPy keep masks.
#![allow(dead_code)] // each test file uses a different subset of the helpers

use neurotac_core::{Event, EventBuffer, Timestamp};
use std::path::PathBuf;

#[path = "../../../tests/common/shared_data.rs"]
mod shared_data;

/// `../shared/data/davis240/`, or `None` (with the reason printed) when it is absent.
pub fn shared_data() -> Option<PathBuf> {
    shared_data::davis240_dir()
}

/// The recording's events from `pick_events.csv` (`t,x,y,on`, t in µs).
pub fn pick_events(dir: &std::path::Path) -> EventBuffer {
    let text = std::fs::read_to_string(dir.join("pick_events.csv")).expect("readable CSV");
    text.lines()
        .skip(1)
        .map(|line| {
            let f: Vec<i64> = line
                .split(',')
                .map(|v| v.parse().expect("integer field"))
                .collect();
            Event {
                t: Timestamp(f[0]),
                x: f[1] as u16,
                y: f[2] as u16,
                polarity: f[3] == 1,
            }
        })
        .collect()
}

/// A NumPy `|b1` vector (format 1.0), as saved by `numpy.save`.
pub fn npy_bool(path: &std::path::Path) -> Vec<bool> {
    let bytes = std::fs::read(path).expect("readable .npy");
    assert_eq!(
        &bytes[..6],
        b"\x93NUMPY",
        "{}: not a .npy file",
        path.display()
    );
    let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + header_len]).expect("ASCII header");
    assert!(header.contains("'descr': '|b1'"), "{header}");
    bytes[10 + header_len..].iter().map(|&b| b != 0).collect()
}
