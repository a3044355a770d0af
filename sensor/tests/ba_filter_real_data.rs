//! The background-activity filter against dv-processing 2.0.4's keep masks on the real
//! DAVIS240C recording (`shared/data/davis240`).

mod common;

use neurotac_core::{EventBuffer, Timestamp};
use neurotac_sensor::filter::{BackgroundActivityFilter, MapStart};
use neurotac_sensor::stage::{EventFilter, Filtered, Stage};

fn keep_mask(events: &EventBuffer, window_us: i64, start: MapStart) -> Vec<bool> {
    let mut f = BackgroundActivityFilter::new(240, 180, window_us, start).unwrap();
    events.iter().map(|e| f.retain(e).unwrap()).collect()
}

#[test]
fn keep_masks_equal_dv_processing_event_for_event() {
    let Some(dir) = common::shared_data() else {
        return;
    };
    let events = common::pick_events(&dir);
    assert_eq!(events.len(), 118_558);
    for (window, file, kept) in [
        (2000, "pick_ba_keep_2000us.npy", 70_563),
        (5000, "pick_ba_keep_5000us.npy", 81_980),
    ] {
        let oracle = common::npy_bool(&dir.join(file));
        let ours = keep_mask(&events, window, MapStart::Zero);
        assert_eq!(ours.len(), oracle.len());
        if let Some(i) = (0..ours.len()).find(|&i| ours[i] != oracle[i]) {
            panic!(
                "{window} µs: event {i} {:?}: ours {} vs dv-processing {}",
                events.get(i),
                ours[i],
                oracle[i]
            );
        }
        assert_eq!(ours.iter().filter(|&&k| k).count(), kept);
    }
}

#[test]
fn start_up_variants_match_the_documented_counts() {
    let Some(dir) = common::shared_data() else {
        return;
    };
    let events = common::pick_events(&dir);
    // With timestamps far from 0, the zero map supports nothing (davis240.md §3.1).
    let mut shifted = events.clone();
    shifted
        .t
        .iter_mut()
        .for_each(|t| *t += 1_700_000_000_000_000);
    for (window, kept) in [
        (1000, 55_165),
        (2000, 70_481),
        (5000, 81_856),
        (10_000, 95_476),
    ] {
        let count = |m: Vec<bool>| m.iter().filter(|&&k| k).count();
        assert_eq!(
            count(keep_mask(&shifted, window, MapStart::Zero)),
            kept,
            "{window} µs, shifted"
        );
        // An empty start gives the same on the original timestamps.
        assert_eq!(
            count(keep_mask(&events, window, MapStart::Empty)),
            kept,
            "{window} µs, empty map"
        );
    }
}

#[test]
fn the_batch_stage_equals_the_per_event_filter_for_any_chunking() {
    let Some(dir) = common::shared_data() else {
        return;
    };
    let events = common::pick_events(&dir);
    let reference = keep_mask(&events, 5000, MapStart::Zero);
    for chunk in [1, 7, 4096, 200_000] {
        let mut stage =
            Filtered::new(BackgroundActivityFilter::new(240, 180, 5000, MapStart::Zero).unwrap());
        let mut out = EventBuffer::new();
        let mut start = 0;
        while start < events.len() {
            let end = (start + chunk).min(events.len());
            let part: EventBuffer = (start..end).map(|i| events.get(i).unwrap()).collect();
            stage.push(&part, &mut out).unwrap();
            start = end;
        }
        let expected: Vec<Timestamp> = events
            .iter()
            .zip(&reference)
            .filter(|(_, k)| **k)
            .map(|(e, _)| e.t)
            .collect();
        assert_eq!(
            out.t.iter().map(|&t| Timestamp(t)).collect::<Vec<_>>(),
            expected,
            "chunk {chunk}"
        );
        assert_eq!(stage.kept, 81_980);
        assert!((stage.reduction_factor() - (1.0 - 81_980.0 / 118_558.0)).abs() < 1e-12);
    }
}
