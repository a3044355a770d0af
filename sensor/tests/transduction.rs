//! Receptive fields, pooling, re-centring, layouts and the whole transducer.

mod common;

use neurotac_core::{Event, EventBuffer, Timestamp};
use neurotac_sensor::error::{FormatError, ReaderTransductionError, TransductionError};
use neurotac_sensor::filter::{BackgroundActivityFilter, MapStart, RefractoryFilter};
use neurotac_sensor::format::{DAVIS240_SIZE, Format, reader_from_bytes, to_bytes};
use neurotac_sensor::stage::{Filtered, Stage};
use neurotac_sensor::taxel::{
    PositionUpdate, ReceptiveFieldMask, ReceptiveFields, TaxelEvent, TaxelLayout, TaxelPixelEvent,
    TaxelPooling, Transducer, TransductionConfig,
};
use std::path::Path;

fn ev(t: i64, x: u16, y: u16) -> Event {
    Event {
        t: Timestamp(t),
        x,
        y,
        polarity: true,
    }
}

fn buffer(events: &[(i64, u16, u16)]) -> EventBuffer {
    events.iter().map(|&(t, x, y)| ev(t, x, y)).collect()
}

/// A deterministic pseudo-random stream of pin-like activity around the default layout plus
/// uniform background noise.
fn synthetic_stream(n: usize, seed: u64) -> EventBuffer {
    let centres = TaxelLayout::neurotac_default().centres().to_vec();
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as u32
    };
    let mut t = 1_000_000i64;
    (0..n)
        .map(|_| {
            t += (next() % 200) as i64;
            if next() % 10 < 8 {
                let (cx, cy) = centres[(next() % 49) as usize];
                let dx = (next() % 9) as f64 - 4.0;
                let dy = (next() % 9) as f64 - 4.0;
                ev(t, (cx + dx).round() as u16, (cy + dy).round() as u16)
            } else {
                ev(t, (next() % 240) as u16, (next() % 180) as u16)
            }
        })
        .collect()
}

#[test]
fn nearest_centre_wins_and_events_outside_every_field_are_dropped() {
    let layout = TaxelLayout::new(vec![(50.0, 50.0), (63.0, 50.0)]);
    let fields = ReceptiveFields::new(&layout, 6.0, 0.0, 240, 180).unwrap();
    assert_eq!(fields.assign(50, 50), Some(0));
    assert_eq!(fields.assign(56, 50), Some(0)); // 6 from taxel 0, 7 from taxel 1
    assert_eq!(fields.assign(57, 50), Some(1)); // 7 vs 6
    assert_eq!(fields.assign(50, 57), None); // 7 px away from both
    assert_eq!(fields.assign(0, 0), None);
    let mut mask = ReceptiveFieldMask::new(fields);
    let mut out = Vec::new();
    mask.push(
        &buffer(&[(0, 50, 50), (1, 100, 100), (2, 60, 52)]),
        &mut out,
    )
    .unwrap();
    assert_eq!(
        out.iter()
            .map(|e| (e.event.t.0, e.taxel))
            .collect::<Vec<_>>(),
        vec![(0, 0), (2, 1)]
    );
    let e = mask.push(&buffer(&[(3, 240, 0)]), &mut out).unwrap_err();
    assert!(
        matches!(
            e,
            TransductionError::OutOfRange {
                index: 3,
                x: 240,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn pooling_emits_one_taxel_event_per_active_window_with_means() {
    let mut pooling = TaxelPooling::new(3, 20_000, 2, Some(0)).unwrap();
    let labelled = |t, x, y, taxel| TaxelPixelEvent {
        event: ev(t, x, y),
        taxel,
    };
    let input = vec![
        labelled(1_000, 10, 20, 2),
        labelled(3_000, 12, 22, 2),
        labelled(5_000, 50, 50, 0), // alone in its window: below min_events = 2
        labelled(25_000, 10, 20, 1),
        labelled(26_001, 11, 20, 1),
    ];
    let mut out = Vec::new();
    pooling.push(&input, &mut out).unwrap();
    assert_eq!(out.len(), 1, "window 0 closed when window 1 began");
    let e = out[0];
    assert_eq!(
        (e.taxel, e.window, e.count, e.x, e.y, e.t_us),
        (2, 0, 2, 11.0, 21.0, 2_000.0)
    );
    // Live use: time passing the window end closes it without a new event.
    pooling.advance_to(39_999, &mut out);
    assert_eq!(out.len(), 1);
    pooling.advance_to(40_000, &mut out);
    assert_eq!(out.len(), 2);
    assert_eq!((out[1].taxel, out[1].window, out[1].t_us), (1, 1, 25_500.5));
    assert!(matches!(
        TaxelPooling::new(1, 0, 1, None),
        Err(TransductionError::InvalidParameter { .. })
    ));
    let mut early = TaxelPooling::new(1, 10, 1, Some(100)).unwrap();
    assert!(matches!(
        early.add(&labelled(50, 0, 0, 0), &mut out),
        Err(TransductionError::BeforeOrigin { .. })
    ));
}

#[test]
fn recentring_follows_the_pin_but_is_bounded() {
    let layout = TaxelLayout::new(vec![(50.0, 50.0), (70.0, 50.0)]);
    let mut fields = ReceptiveFields::new(&layout, 6.0, 5.0, 240, 180).unwrap();
    let update = PositionUpdate { gain: 0.5 };
    let at = |taxel, x, y| neurotac_sensor::taxel::TaxelEvent {
        taxel,
        window: 0,
        count: 3,
        x,
        y,
        t_us: 0.0,
    };
    update.apply(&[at(0, 54.0, 50.0)], &mut fields);
    assert_eq!(fields.centres()[0], (52.0, 50.0));
    // A pull of 20 px stops at max_shift = 5 px from home.
    update.apply(&[at(0, 92.0, 50.0)], &mut fields);
    assert_eq!(fields.centres()[0], (55.0, 50.0));
    // Taxel 1 may not come within 2·r = 12 px of taxel 0 (at 55): a move to 66 is refused.
    update.apply(&[at(1, 62.0, 50.0)], &mut fields);
    assert_eq!(fields.centres()[1], (70.0, 50.0));
    // The lookup follows the moved centre: pixel 60 is now taxel 0's (5 px from 55).
    assert_eq!(fields.assign(60, 50), Some(0));
}

#[test]
fn layouts_are_validated_and_round_trip_through_json() {
    let default = TaxelLayout::neurotac_default();
    default.validate(6.0, Some(49), 240, 180).unwrap();
    let e = default.validate(8.0, Some(49), 240, 180).unwrap_err();
    assert!(matches!(e, TransductionError::LayoutOverlap { .. }), "{e}");
    let e = TaxelLayout::new(vec![(10.0, 10.0)])
        .validate(6.0, Some(49), 240, 180)
        .unwrap_err();
    assert!(matches!(
        e,
        TransductionError::LayoutCount {
            expected: 49,
            got: 1
        }
    ));
    let e = TaxelLayout::new(vec![(10.0, 10.0), (250.0, 10.0)])
        .validate(6.0, None, 240, 180)
        .unwrap_err();
    assert!(
        matches!(e, TransductionError::LayoutOutOfImage { taxel: 1, .. }),
        "{e}"
    );
    let e = TaxelLayout::new(vec![(f64::NAN, 10.0)])
        .validate(6.0, None, 240, 180)
        .unwrap_err();
    assert!(matches!(
        e,
        TransductionError::LayoutOutOfImage { taxel: 0, .. }
    ));

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("layout.json");
    std::fs::write(&path, default.to_json()).unwrap();
    assert_eq!(TaxelLayout::from_json_file(&path).unwrap(), default);
    std::fs::write(&path, r#"{"centres": 3}"#).unwrap();
    let e = TaxelLayout::from_json_file(&path).unwrap_err();
    assert!(
        e.to_string().contains("layout.json: not a taxel layout"),
        "{e}"
    );
    let e = TaxelLayout::from_json_file(&dir.path().join("missing.json")).unwrap_err();
    assert!(matches!(e, TransductionError::LayoutIo { .. }));
}

#[test]
fn layout_detection_finds_the_pins_of_a_calibration_recording() {
    let events = synthetic_stream(60_000, 7);
    let d = TaxelLayout::detect(&events, 49, 6.0);
    assert_eq!((d.found, d.expected), (49, 49));
    assert!(d.confidence > 0.5, "confidence {}", d.confidence);
    assert!(d.captured_fraction > 0.75, "{}", d.captured_fraction);
    // Ordered like the default layout, each within a pixel of its pin.
    for (found, truth) in d
        .layout
        .centres()
        .iter()
        .zip(TaxelLayout::neurotac_default().centres())
    {
        assert!(dist(*found, *truth) < 1.0, "{found:?} vs {truth:?}");
    }
    d.layout.validate(6.0, Some(49), 240, 180).unwrap();
    assert!(d.is_reliable() && d.active == 49, "{d:?}");
    // Only the pins left of x = 110 active: they fix the ring lattice, so every pin is still
    // placed within a pixel, with less confidence.
    let few: EventBuffer = events.iter().filter(|e| e.x < 110).collect();
    let partial = TaxelLayout::detect(&few, 49, 6.0);
    assert!(partial.active < 30, "{} active", partial.active);
    assert!(partial.confidence < d.confidence, "{}", partial.confidence);
    for (found, truth) in partial
        .layout
        .centres()
        .iter()
        .zip(TaxelLayout::neurotac_default().centres())
    {
        assert!(dist(*found, *truth) < 1.0, "{found:?} vs {truth:?}");
    }
    // Nothing recorded: nothing found, no confidence.
    let none = TaxelLayout::detect(&EventBuffer::new(), 49, 6.0);
    assert_eq!((none.found, none.confidence), (0, 0.0));
    // A scene without pins (uniform noise) is never reliable.
    let noise: EventBuffer = events
        .iter()
        .enumerate()
        .map(|(i, mut e)| {
            e.x = ((i * 7919) % 240) as u16;
            e.y = ((i * 104_729 / 240) % 180) as u16;
            e
        })
        .collect();
    let d = TaxelLayout::detect(&noise, 49, 6.0);
    assert!(!d.is_reliable(), "confidence {}", d.confidence);
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

fn transduce(events: &EventBuffer, chunk: usize, config: TransductionConfig) -> Transducer {
    let mut t = Transducer::new(&TaxelLayout::neurotac_default(), config).unwrap();
    let mut start = 0;
    while start < events.len() {
        let end = (start + chunk).min(events.len());
        let part: EventBuffer = (start..end).map(|i| events.get(i).unwrap()).collect();
        t.push(&part).unwrap();
        start = end;
    }
    t.finish();
    t
}

#[test]
fn transduction_does_not_depend_on_how_the_stream_is_chunked() {
    let events = synthetic_stream(50_000, 3);
    // Fields wide enough for the synthetic stream's spread (the default is the paper's 3 px).
    let config = TransductionConfig {
        rf_radius_px: 6.0,
        ..TransductionConfig::default()
    };
    let whole = transduce(&events, usize::MAX, config);
    assert!(whole.counts().taxel_events > 1000);
    for chunk in [1, 13, 4096] {
        let t = transduce(&events, chunk, config);
        assert_eq!(t.taxel_events(), whole.taxel_events(), "chunk {chunk}");
        assert_eq!(t.fields().centres(), whole.fields().centres());
    }
    let trains = whole.spike_trains();
    assert_eq!(trains.n_channels(), 49);
    assert_eq!(trains.total_spikes() as u64, whole.counts().taxel_events);
    // At most one spike per taxel per 20 ms window.
    for c in trains.channels() {
        assert!(
            c.windows(2)
                .all(|w| (w[1] / 0.02).floor() > (w[0] / 0.02).floor())
        );
    }
}

#[test]
fn bad_streams_are_typed_errors_and_empty_ones_give_no_spikes() {
    let layout = TaxelLayout::neurotac_default();
    let mut t = Transducer::new(&layout, TransductionConfig::default()).unwrap();
    let e = t.push(&buffer(&[(10, 1, 1), (9, 1, 1)])).unwrap_err();
    assert!(
        matches!(
            e,
            TransductionError::Backwards {
                index: 1,
                previous_us: 10,
                got_us: 9
            }
        ),
        "{e}"
    );
    let mut t = Transducer::new(&layout, TransductionConfig::default()).unwrap();
    let e = t.push(&buffer(&[(10, 1, 1), (11, 239, 180)])).unwrap_err();
    assert!(
        matches!(
            e,
            TransductionError::OutOfRange {
                index: 1,
                y: 180,
                ..
            }
        ),
        "{e}"
    );
    let mut empty = Transducer::new(&layout, TransductionConfig::default()).unwrap();
    empty.push(&EventBuffer::new()).unwrap();
    empty.finish();
    assert_eq!(empty.spike_trains().total_spikes(), 0);
    assert_eq!(empty.spike_trains().n_channels(), 49);
    let bad = TransductionConfig {
        recentre_gain: 1.5,
        ..TransductionConfig::default()
    };
    assert!(Transducer::new(&layout, bad).is_err());
    let bad = TransductionConfig {
        ba_window_us: Some(0),
        ..TransductionConfig::default()
    };
    assert!(Transducer::new(&layout, bad).is_err());
    let bad = TransductionConfig {
        rf_radius_px: 12.0,
        ..TransductionConfig::default()
    };
    assert!(matches!(
        Transducer::new(&layout, bad),
        Err(TransductionError::LayoutOverlap { .. })
    ));
}

#[test]
fn the_real_recording_transduces_with_consistent_counts() {
    let Some(dir) = common::shared_data() else {
        return;
    };
    let events = common::pick_events(&dir);
    let config = TransductionConfig {
        ba_start: MapStart::Zero,
        ..TransductionConfig::default()
    };
    let t = transduce(&events, 10_000, config);
    let c = t.counts();
    assert_eq!(c.events_in, 118_558);
    assert_eq!(
        c.after_filters, 81_980,
        "the BA stage is the dv-processing filter at 5 ms"
    );
    assert!(c.in_fields <= c.after_filters && c.taxel_events <= c.in_fields);
    // 1.39 s in 20 ms windows: at most 70 spikes per taxel.
    assert!(t.spike_trains().counts().iter().all(|&n| n <= 70));
}

/// `stage` run over `events` in chunks of `chunk`, then finished.
fn run_chain<S>(mut stage: S, events: &EventBuffer, chunk: usize) -> Vec<TaxelEvent>
where
    S: Stage<Input = EventBuffer, Output = Vec<TaxelEvent>>,
{
    let mut out = Vec::new();
    let mut start = 0;
    while start < events.len() {
        let end = (start + chunk).min(events.len());
        let part: EventBuffer = (start..end).map(|i| events.get(i).unwrap()).collect();
        stage.push(&part, &mut out).unwrap();
        start = end;
    }
    stage.finish(&mut out).unwrap();
    out
}

/// The stages of `config` (without re-centring) chained: BA filter → refractory filter (when
/// configured) → receptive-field mask → pooling, windows aligned to the first event as the
/// transducer aligns them.
fn chain_taxel_events(
    events: &EventBuffer,
    chunk: usize,
    config: TransductionConfig,
) -> Vec<TaxelEvent> {
    let layout = TaxelLayout::neurotac_default();
    let (w, h) = (config.width, config.height);
    let ba = BackgroundActivityFilter::new(w, h, config.ba_window_us.unwrap(), config.ba_start);
    let fields =
        ReceptiveFields::new(&layout, config.rf_radius_px, config.max_shift_px, w, h).unwrap();
    let origin = config.origin_us.or(events.t.first().copied());
    let pooling = TaxelPooling::new(
        layout.len(),
        config.pool_window_us,
        config.min_events,
        origin,
    )
    .unwrap();
    let mask_and_pool = ReceptiveFieldMask::new(fields).then(pooling);
    let ba = Filtered::new(ba.unwrap());
    match config.refractory_us {
        None => run_chain(ba.then(mask_and_pool), events, chunk),
        Some(p) => {
            let refractory = Filtered::new(RefractoryFilter::new(w, h, p).unwrap());
            run_chain(ba.then(refractory).then(mask_and_pool), events, chunk)
        }
    }
}

/// One transduction pipeline: the transducer is the stage chain fused; without
/// re-centring (which only the fused loop feeds back) both give the same taxel events, with
/// and without the refractory filter, however either input is chunked.
#[test]
fn stage_chain_and_transducer_give_the_same_taxel_events() {
    let events = synthetic_stream(50_000, 11);
    for refractory_us in [None, Some(300)] {
        for ba_start in [MapStart::Zero, MapStart::Empty] {
            let config = TransductionConfig {
                recentre_gain: 0.0,
                refractory_us,
                ba_start,
                // The synthetic stream's pins move by a few pixels: 6 px fields hold them.
                rf_radius_px: 6.0,
                ..TransductionConfig::default()
            };
            let fused = transduce(&events, 4096, config);
            assert!(fused.counts().taxel_events > 1000);
            assert!(fused.counts().after_filters < fused.counts().events_in);
            for chunk in [1000, usize::MAX] {
                assert_eq!(
                    chain_taxel_events(&events, chunk, config),
                    fused.taxel_events(),
                    "refractory {refractory_us:?}, {ba_start:?}, chunk {chunk}"
                );
            }
        }
    }
    // Re-centring is what the chain lacks: with it the fields move and the events differ.
    let recentred = transduce(&events, 4096, TransductionConfig::default());
    let fixed = TransductionConfig {
        recentre_gain: 0.0,
        ..TransductionConfig::default()
    };
    assert_ne!(
        recentred.taxel_events(),
        chain_taxel_events(&events, 4096, fixed)
    );
}

/// The same on the shared DAVIS240C recording (skipped when absent).
#[test]
fn stage_chain_equals_the_transducer_on_the_real_recording() {
    let Some(dir) = common::shared_data() else {
        return;
    };
    let events = common::pick_events(&dir);
    let config = TransductionConfig {
        recentre_gain: 0.0,
        ..TransductionConfig::default()
    };
    let fused = transduce(&events, 10_000, config);
    assert!(fused.counts().taxel_events > 100);
    assert_eq!(
        chain_taxel_events(&events, 10_000, config),
        fused.taxel_events()
    );
}

#[test]
fn transducing_a_reader_equals_pushing_its_events() {
    let events = synthetic_stream(30_000, 5);
    let pushed = transduce(&events, usize::MAX, TransductionConfig::default());
    for format in [Format::Aedat2, Format::Csv] {
        let bytes = to_bytes(&events, format, DAVIS240_SIZE).unwrap();
        let mut reader = reader_from_bytes(&bytes).unwrap();
        let mut t = Transducer::new(
            &TaxelLayout::neurotac_default(),
            TransductionConfig::default(),
        )
        .unwrap();
        let done = t
            .transduce_reader(&mut reader, Path::new("<memory>"))
            .unwrap();
        assert_eq!(t.taxel_events(), pushed.taxel_events(), "{format:?}");
        assert_eq!(done.counts, pushed.counts());
        assert_eq!(done.spike_trains, pushed.spike_trains());
        assert_eq!(done.read.events, events.len() as u64);
        assert_eq!(
            done.first_last_us,
            Some((events.t[0], events.t[events.len() - 1]))
        );
    }
    // An empty input: no events, no spikes, 49 empty trains.
    let mut reader = reader_from_bytes(b"t,x,y,on\n").unwrap();
    let mut t = Transducer::new(
        &TaxelLayout::neurotac_default(),
        TransductionConfig::default(),
    )
    .unwrap();
    let done = t
        .transduce_reader(&mut reader, Path::new("empty.csv"))
        .unwrap();
    assert_eq!((done.read.events, done.first_last_us), (0, None));
    assert_eq!(done.spike_trains.n_channels(), 49);
    assert_eq!(done.spike_trains.total_spikes(), 0);
}

#[test]
fn transducing_a_bad_reader_names_the_input_and_where() {
    let layout = TaxelLayout::neurotac_default();
    let mut t = Transducer::new(&layout, TransductionConfig::default()).unwrap();
    // Readers keep a time going back in file order; the transducer refuses it.
    let mut reader = reader_from_bytes(b"t,x,y,on\n10,5,5,1\n9,5,5,0\n").unwrap();
    let e = t
        .transduce_reader(&mut reader, Path::new("recording.csv"))
        .unwrap_err();
    assert!(
        matches!(
            &e,
            ReaderTransductionError::Transduction {
                path,
                source: TransductionError::Backwards { index: 1, .. },
            } if path == Path::new("recording.csv")
        ),
        "{e:?}"
    );
    assert!(e.to_string().starts_with("recording.csv: "), "{e}");
    // A line that does not parse: the reader's error, naming line and byte offset.
    let mut t = Transducer::new(&layout, TransductionConfig::default()).unwrap();
    let mut reader = reader_from_bytes(b"t,x,y,on\n10,5,5,1\n11,x,5,0\n").unwrap();
    let e = t
        .transduce_reader(&mut reader, Path::new("recording.csv"))
        .unwrap_err();
    assert!(
        matches!(
            e,
            ReaderTransductionError::Read(FormatError::Text {
                line: 3,
                offset: 18,
                ..
            })
        ),
        "{e:?}"
    );
}
