//! How well `TaxelLayout::detect` finds the NeuroTac's pins, measured against the simulator's
//! ground truth, and the calibration of `LayoutDetection::RELIABLE_CONFIDENCE`.
//!
//! Print the accuracy table with
//! `cargo test --release -p neurotac-sensor --test layout_accuracy -- --nocapture`.

mod common;

use neurotac_core::EventBuffer;
use neurotac_sensor::geometry::PinGeometry;
use neurotac_sensor::sim::{Camera, NATURAL_TEXTURES, SimParams, Simulator, Texture};
use neurotac_sensor::taxel::{LayoutDetection, TaxelLayout};

/// Radius (px) within which a found centre counts as on its pin.
const HIT_PX: f64 = 3.0;
/// Fraction of centres within [`HIT_PX`] for a layout to count as right.
const RIGHT_FRACTION: f64 = 0.9;

/// One-to-one matching of found centres to true pins (closest pairs first): how many matched
/// pairs lie within [`HIT_PX`], and the mean distance over the matched pairs (px).
fn accuracy(found: &[(f64, f64)], truth: &[(f64, f64)]) -> (usize, f64) {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, f) in found.iter().enumerate() {
        for (j, t) in truth.iter().enumerate() {
            pairs.push(((f.0 - t.0).hypot(f.1 - t.1), i, j));
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let (mut used_f, mut used_t) = (vec![false; found.len()], vec![false; truth.len()]);
    let (mut hits, mut sum, mut n) = (0, 0.0, 0);
    for (d, i, j) in pairs {
        if !used_f[i] && !used_t[j] {
            used_f[i] = true;
            used_t[j] = true;
            hits += usize::from(d <= HIT_PX);
            sum += d;
            n += 1;
        }
    }
    (hits, if n == 0 { f64::NAN } else { sum / n as f64 })
}

/// One detection scored against the truth.
struct Scored {
    case: &'static str,
    confidence: f64,
    reliable: bool,
    hits: usize,
    mean_px: f64,
}

impl Scored {
    fn new(case: &'static str, d: &LayoutDetection, truth: &[(f64, f64)]) -> Self {
        let (hits, mean_px) = accuracy(d.layout.centres(), truth);
        Self {
            case,
            confidence: d.confidence,
            reliable: d.is_reliable(),
            hits,
            mean_px,
        }
    }

    fn right(&self) -> bool {
        self.hits as f64 >= RIGHT_FRACTION * 49.0
    }
}

/// The events of `events` before `end_us`.
fn head(events: &EventBuffer, end_us: i64) -> EventBuffer {
    events.iter().take_while(|e| e.t.0 < end_us).collect()
}

/// `events` and `truth` magnified by `factor` about the image centre: pins too far apart for
/// the NeuroTac's rings (outside the finder's ±20 % scale range).
fn magnified(
    events: &EventBuffer,
    truth: &[(f64, f64)],
    factor: f64,
) -> (EventBuffer, Vec<(f64, f64)>) {
    let map = |x: f64, y: f64| (120.0 + factor * (x - 120.0), 90.0 + factor * (y - 90.0));
    let out = events
        .iter()
        .filter_map(|mut e| {
            let (x, y) = map(f64::from(e.x), f64::from(e.y));
            let inside = (0.0..239.5).contains(&x) && (0.0..179.5).contains(&y);
            inside.then(|| {
                e.x = x.round() as u16;
                e.y = y.round() as u16;
                e
            })
        })
        .collect();
    (out, truth.iter().map(|&(x, y)| map(x, y)).collect())
}

/// 50 slides per seed: 10 grids × 3 slides and 5 natural textures × 4 slides; each seed is a
/// camera (its fixed-pattern noise) and a sensor whose pins sit off the nominal position and
/// scale. The slides are shortened to 8 mm: their first second (the loop's latencies, the press,
/// the dwell, the slide's onset) is a full recording's.
fn simulated_detections() -> Vec<Scored> {
    let mut params = SimParams::default();
    params.kinematics.distance_mm = 8.0;
    let sim0 = Simulator::new(params, &Camera::new(&params, 0)).unwrap();
    let grids = (1..=10).map(|k| (Texture::grid(0.5 * f64::from(k)).unwrap(), 3));
    let naturals = NATURAL_TEXTURES
        .iter()
        .step_by(4)
        .map(|t| (Texture::from_name(t.name).unwrap(), 4));
    let textures: Vec<_> = grids
        .chain(naturals)
        .map(|(t, slides)| (sim0.prepare(t), slides))
        .collect();
    let mut scored = Vec::new();
    for seed in 0..3u64 {
        let camera = Camera::new(&params, 100 + seed);
        let geometry = PinGeometry {
            centre_px: (117.0 + 3.7 * seed as f64, 92.5 - 2.3 * seed as f64),
            scale_px_per_mm: 4.35 + 0.15 * seed as f64,
            ..PinGeometry::default()
        };
        let mut sim = Simulator::with_geometry(params, &camera, &geometry).unwrap();
        let truth = sim.pins_px().to_vec();
        let mut slide_seed = seed * 1000;
        for (texture, slides) in &textures {
            for slide in 0..*slides {
                slide_seed += 1;
                let trial = sim.simulate_slide(texture, slide, slide_seed);
                let events = &trial.events;
                // The CLI's default calibration window (the press and the slide's onset, when
                // every pin moves), and a window before the dome touches (noise only: nothing
                // to find).
                let calibration = head(events, 1_000_000);
                let d = TaxelLayout::detect(&calibration, 49, 3.0);
                scored.push(Scored::new("1000 ms (default)", &d, &truth));
                let d = TaxelLayout::detect(&head(events, 100_000), 49, 3.0);
                scored.push(Scored::new("100 ms (before the press)", &d, &truth));
                // Pins spaced unlike the NeuroTac's rings.
                let (wide, wide_truth) = magnified(&calibration, &truth, 1.4);
                let d = TaxelLayout::detect(&wide, 49, 3.0);
                scored.push(Scored::new("1000 ms, pins 1.4× apart", &d, &wide_truth));
            }
        }
    }
    scored
}

#[test]
fn the_layout_finder_finds_the_pins_of_sliding_slides_and_its_confidence_is_calibrated() {
    let scored = simulated_detections();
    println!(
        "{:<24} {:>5} {:>8} {:>14} {:>13} {:>11} {:>13}",
        "case", "n", "right", "within 3 px", "mean error", "reliable", "confidence"
    );
    let mut cases: Vec<&str> = scored.iter().map(|s| s.case).collect();
    cases.dedup();
    cases.sort_unstable();
    cases.dedup();
    for case in &cases {
        let rows: Vec<&Scored> = scored.iter().filter(|s| s.case == *case).collect();
        let n = rows.len() as f64;
        let within = rows.iter().map(|s| s.hits as f64).sum::<f64>() / (49.0 * n);
        // Over the slides where the finder placed centres at all (none: "–").
        let placed: Vec<f64> = rows
            .iter()
            .map(|s| s.mean_px)
            .filter(|m| m.is_finite())
            .collect();
        let mean_px = match placed.is_empty() {
            true => "–".to_owned(),
            false => format!("{:.1}", placed.iter().sum::<f64>() / placed.len() as f64),
        };
        let (lo, hi) = rows.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), s| {
            (lo.min(s.confidence), hi.max(s.confidence))
        });
        println!(
            "{:<24} {:>5} {:>8} {:>13.1}% {:>10} px {:>11} {:>6.2}–{:.2}",
            case,
            rows.len(),
            rows.iter().filter(|s| s.right()).count(),
            100.0 * within,
            mean_px,
            rows.iter().filter(|s| s.reliable).count(),
            lo,
            hi
        );
    }
    let right_conf = scored.iter().filter(|s| s.right()).map(|s| s.confidence);
    let wrong_conf = scored.iter().filter(|s| !s.right()).map(|s| s.confidence);
    let lowest_right = right_conf.fold(f64::INFINITY, f64::min);
    let highest_wrong = wrong_conf.fold(0.0, f64::max);
    println!(
        "threshold {}: right layouts' confidence from {lowest_right:.3}, wrong ones' up to {highest_wrong:.3}",
        LayoutDetection::RELIABLE_CONFIDENCE
    );

    // The calibration: a reliable detection is a right one, with a margin above every wrong
    // one.
    for s in scored.iter().filter(|s| s.reliable) {
        assert!(
            s.right(),
            "{}: confidence {:.3} but only {} of 49 within 3 px",
            s.case,
            s.confidence,
            s.hits
        );
    }
    assert!(
        highest_wrong < 0.5 * LayoutDetection::RELIABLE_CONFIDENCE,
        "a wrong layout reached confidence {highest_wrong:.3}"
    );
    // The accuracy floor on the default window: every slide right and reliable, centres
    // within a pixel and a half on average (the pins move while the window is recorded).
    let default: Vec<&Scored> = scored
        .iter()
        .filter(|s| s.case.starts_with("1000 ms ("))
        .collect();
    assert_eq!(default.len(), 150);
    for s in &default {
        assert!(
            s.right() && s.reliable,
            "{} of 49 at confidence {:.3}",
            s.hits,
            s.confidence
        );
        assert!(s.mean_px < 1.5, "mean error {:.2} px", s.mean_px);
    }
    // Nothing to find is never reliable.
    assert!(
        scored
            .iter()
            .filter(|s| !s.case.starts_with("1000 ms ("))
            .all(|s| !s.reliable)
    );
}

#[test]
fn the_real_non_tactile_recording_is_not_taken_for_a_pin_layout() {
    // `shared/data/davis240/pick`: a hand picking parts, not a NeuroTac. Whatever the finder
    // places, it must not call it reliable.
    let Some(dir) = common::shared_data() else {
        return;
    };
    let events = common::pick_events(&dir);
    for window_us in [500_000, 1_390_420] {
        let d = TaxelLayout::detect(&head(&events, window_us), 49, 3.0);
        println!(
            "pick, first {} ms: confidence {:.3}, {} of 49 pins active",
            window_us / 1000,
            d.confidence,
            d.active
        );
        assert!(!d.is_reliable(), "confidence {:.3}", d.confidence);
    }
}
