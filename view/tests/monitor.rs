//! What a frame shows: the transduction's counts and spikes (as `neurotac transduce`), the
//! decaying event image, what the drawing leaves out, and bad events.

use neurotac_core::{Event, EventBuffer};
use neurotac_sensor::format::open_reader;
use neurotac_sensor::taxel::{TaxelLayout, Transducer, TransductionConfig};
use neurotac_view::{MonitorConfig, PlayState, StreamMonitor, ViewError};

fn monitor() -> StreamMonitor {
    StreamMonitor::new(&TaxelLayout::neurotac_default(), MonitorConfig::default()).unwrap()
}

fn event(t: i64, x: u16, y: u16, polarity: bool) -> Event {
    Event {
        t: neurotac_core::Timestamp(t),
        x,
        y,
        polarity,
    }
}

/// Events around every taxel centre, 60 ms apart in bursts, over 1.5 s.
fn bursts() -> EventBuffer {
    let layout = TaxelLayout::neurotac_default();
    let mut events = EventBuffer::new();
    for step in 0..25i64 {
        for (k, &(x, y)) in layout.centres().iter().enumerate() {
            for j in 0..3i64 {
                let t = step * 60_000 + (k as i64) * 200 + j * 50;
                events.push(event(
                    t,
                    x as u16 + (j as u16 % 2),
                    y as u16,
                    !(k + j as usize).is_multiple_of(3),
                ));
            }
        }
    }
    events
}

#[test]
fn counts_and_raster_equal_the_transduction_in_any_chunking() {
    let events = bursts();
    let mut transducer = Transducer::new(
        &TaxelLayout::neurotac_default(),
        TransductionConfig::default(),
    )
    .unwrap();
    transducer.push(&events).unwrap();
    transducer.finish();
    let expected: Vec<(u16, f64)> = transducer
        .taxel_events()
        .iter()
        .map(|e| (e.taxel, e.t_us * 1e-6))
        .collect();
    assert!(expected.len() > 100, "the bursts make taxel spikes");
    for chunk in [1, 7, 4096] {
        let mut m = monitor();
        let all: Vec<Event> = events.iter().collect();
        for part in all.chunks(chunk) {
            m.push(&part.iter().copied().collect()).unwrap();
        }
        m.finish();
        let frame = m.frame(1, "bursts", PlayState::Ended, Some("max"));
        let c = transducer.counts();
        assert_eq!(
            (
                frame.counts.events_in,
                frame.counts.after_filters,
                frame.counts.in_fields
            ),
            (c.events_in, c.after_filters, c.in_fields)
        );
        assert_eq!(frame.counts.taxel_spikes, expected.len() as u64);
        // The stream is 1.44 s long: the 2 s raster holds every spike, at its time.
        assert_eq!(frame.raster.spikes, expected, "chunks of {chunk}");
        assert_eq!(frame.taxel_home.len(), 49);
        assert_eq!(frame.field_centres.len(), 49);
    }
}

#[test]
fn a_recording_shows_the_counts_neurotac_transduce_prints() {
    let Some(dir) = neurotac_core::testing::shared_data("davis240") else {
        return;
    };
    let path = dir.join("pick.aedat");
    let mut transducer = Transducer::new(
        &TaxelLayout::neurotac_default(),
        TransductionConfig::default(),
    )
    .unwrap();
    let t = transducer
        .transduce_reader(&mut *open_reader(&path).unwrap(), &path)
        .unwrap();
    let mut m = monitor();
    let mut reader = open_reader(&path).unwrap();
    let mut chunk = EventBuffer::new();
    while reader.read_chunk(&mut chunk).unwrap() > 0 {
        m.push(&chunk).unwrap();
        chunk.clear();
    }
    m.finish();
    let frame = m.frame(1, "pick", PlayState::Ended, Some("max"));
    // The numbers of `neurotac transduce pick.aedat`: 118558 → 81980 → 3797 → 298.
    assert_eq!(frame.counts.events_in, t.counts.events_in);
    assert_eq!(frame.counts.after_filters, t.counts.after_filters);
    assert_eq!(frame.counts.in_fields, t.counts.in_fields);
    assert_eq!(frame.counts.taxel_spikes, t.counts.taxel_events);
    assert_eq!(
        frame.raster.spikes.len() as u64,
        t.spike_trains.total_spikes() as u64
    );
}

#[test]
fn the_event_image_decays_from_each_pixels_last_event() {
    let mut m = monitor();
    let events: EventBuffer = [event(0, 10, 20, true), event(1_000, 30, 40, false)]
        .into_iter()
        .collect();
    m.push(&events).unwrap();
    let at = |frame: &neurotac_view::Frame, x: usize, y: usize| frame.image.intensity[y * 240 + x];
    let f = m.frame(1, "", PlayState::Playing, None);
    assert_eq!(f.image.intensity.len(), 240 * 180);
    assert!(
        (at(&f, 30, 40) + 1.0).abs() < 1e-6,
        "OFF is negative, fresh is full"
    );
    let expected = (-1.0f64 / 30.0).exp() as f32; // 1 ms old at τ = 30 ms
    assert!((at(&f, 10, 20) - expected).abs() < 1e-6);
    // One τ later (a quiet stream's clock moving on).
    m.advance_to(31_000);
    let f = m.frame(2, "", PlayState::Playing, None);
    assert!((at(&f, 10, 20) - (-31.0f64 / 30.0).exp() as f32).abs() < 1e-6);
    assert!((at(&f, 30, 40) + (-1.0f32).exp()).abs() < 1e-6);
    // Past five decay times nothing is left.
    m.advance_to(200_000);
    let f = m.frame(3, "", PlayState::Playing, None);
    assert!(f.image.intensity.iter().all(|&a| a == 0.0));
}

#[test]
fn an_early_frame_draws_its_raster_from_the_stream_origin_never_before_it() {
    let mut m = monitor();
    let events = bursts();
    let early: EventBuffer = events.iter().filter(|e| e.t.0 < 500_000).collect();
    m.push(&early).unwrap();
    m.advance_to(500_000);
    let f = m.frame(1, "", PlayState::Snapshot, None);
    assert!((f.t_s - 0.5).abs() < 1e-9, "{}", f.t_s);
    assert_eq!((f.raster.from_s, f.raster.to_s), (0.0, 2.0));
    assert!(
        f.raster
            .spikes
            .iter()
            .all(|&(_, t)| (0.0..=0.5).contains(&t))
    );
    let svg = neurotac_view::draw_frame(&f);
    assert!(svg.contains("snapshot"), "the header says what it is");
    assert!(!svg.contains(">-"), "no negative time on the axis");
    // Past the window's length the window ends at the frame time.
    let late: EventBuffer = events.iter().filter(|e| e.t.0 >= 500_000).collect();
    m.push(&late).unwrap();
    m.advance_to(2_500_000);
    let f = m.frame(2, "", PlayState::Playing, None);
    assert_eq!((f.raster.from_s, f.raster.to_s), (0.5, 2.5));
}

#[test]
fn the_drawn_share_says_how_many_new_events_the_image_shows() {
    let mut m = monitor();
    // 100 events on 10 pixels since the last frame: the image shows 10 of them.
    let events: EventBuffer = (0..100)
        .map(|i| event(i as i64 * 10, (i % 10) as u16, 5, true))
        .collect();
    m.push(&events).unwrap();
    let f = m.frame(1, "", PlayState::Playing, None);
    assert_eq!(f.decimation.events_since_last_frame, 100);
    assert!((f.decimation.drawn_share - 0.1).abs() < 1e-12);
    // Nothing new: nothing left out.
    let f = m.frame(2, "", PlayState::Playing, None);
    assert_eq!(f.decimation.events_since_last_frame, 0);
    assert_eq!(f.decimation.drawn_share, 1.0);
}

#[test]
fn a_bad_event_is_a_typed_error_after_the_good_ones_are_shown() {
    let mut m = monitor();
    let events: EventBuffer = [
        event(5, 1, 1, true),
        event(9, 2, 2, true),
        event(4, 3, 3, true),
    ]
    .into_iter()
    .collect();
    let e = m.push(&events).unwrap_err();
    assert!(matches!(e, ViewError::Transduction(_)), "{e}");
    assert!(e.to_string().contains('2'), "names the event's index: {e}");
    assert_eq!(m.counts().events_in, 2);
    let off_sensor: EventBuffer = [event(10, 240, 0, true)].into_iter().collect();
    assert!(m.push(&off_sensor).is_err());
    assert_eq!(m.counts().events_in, 2);
    let bad = MonitorConfig {
        decay_ms: f64::NAN,
        ..MonitorConfig::default()
    };
    assert!(StreamMonitor::new(&TaxelLayout::neurotac_default(), bad).is_err());
}
