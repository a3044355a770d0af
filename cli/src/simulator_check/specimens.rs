//! Statistics of the recording protocol and of the specimens' mechanics, per texture of both
//! sets, each next to what its source expects (the simulator's module docs name the sources):
//! the duration law, the press under position control, the leading/trailing asymmetry of a
//! sliding contact on a compliant layer, the rim pins while sliding, the onset's rise time, the
//! first burst's timing spread, the pile and the fabric drag; and the spread over mountings of
//! the 5 mm / 4.5 mm count ratio. Computed from simulated slides alone, before any accuracy.

use super::statistic::Statistic;
use super::statistics::{mean, sd, spearman};
use neurotac_experiments::datasets::{
    DatasetsError, TextureSet, camera_seed, jobs_for, map_trials, prepare_textures,
};
use neurotac_sensor::geometry::PinGeometry;
use neurotac_sensor::sim::kinematics::{
    LOOP_STEPS, PAPER_DURATIONS, STEPS_BEFORE_PRESS, nominal_duration_at,
};
use neurotac_sensor::sim::{Camera, SimParams, SimulatedTrial, taxel_spikes};
use serde::Serialize;

/// Bin of the first-burst timing (s).
const BURST_BIN_S: f64 = 0.002;
/// Signal events in one bin that make a burst.
const BURST_EVENTS: usize = 10;
/// Window after the slide's start holding its onset (s).
const ONSET_WINDOW_S: f64 = 0.6;
/// Sliding-phase signal events (pins in contact, per slide) a texture needs for its
/// ahead/behind ratio to count.
const MIN_SLIDING_EVENTS: f64 = 200.0;
/// A DVS pixel's smallest resolvable pin motion (mm): about 0.2 px at 4.5 px/mm (spec §1.2:
/// 0.2–0.4 px), for the pile's single-hair release.
const DVS_RESOLUTION_MM: f64 = 0.2 / 4.5;
/// Shear modulus of the gel (MPa): RTV27905 E ≈ 0.03 MPa, G = E/3 (spec §1.1).
const GEL_SHEAR_MPA: f64 = 0.01;

/// What one slide shows of the protocol and its specimen.
#[derive(Debug, Clone)]
pub(super) struct SpecimenSlide {
    class: usize,
    spikes_per_taxel: f64,
    normal_force_n: f64,
    contact_radius_mm: f64,
    overlap_mm: f64,
    pins_in_contact: usize,
    /// Taxel spikes per outer-ring pin over taxel spikes per pin of the centre and first ring.
    rim_centre: Option<f64>,
    /// Sliding-phase signal events on in-contact pins ahead (x > 0) over behind (x < 0), with
    /// the events counted on both sides.
    lead_trail: Option<(f64, f64)>,
    /// Sliding-phase signal events per second on a pin outside the contact, and inside it.
    rim_rate_hz: f64,
    contact_rate_hz: f64,
    /// 10 → 90 % of the onset window's signal events (s).
    rise_s: Option<f64>,
    /// Slide start to the first full slip (s).
    onset_s: Option<f64>,
    /// The first burst of signal events after the recording's zero (s).
    first_burst_s: Option<f64>,
    /// When the press started (s).
    press_start_s: f64,
    forward_shift: f64,
    pile: Option<(f64, f64)>,
    drag_mm: Option<f64>,
    wrinkle_after_start_s: Option<f64>,
}

/// Analyses one slide (see [`SpecimenSlide`]).
pub(super) fn analyse_specimen(
    trial: &SimulatedTrial,
    class: usize,
) -> Result<SpecimenSlide, DatasetsError> {
    let info = &trial.info;
    let geometry = PinGeometry::default();
    let pins = geometry.pin_positions_mm();
    let taxels = taxel_spikes(trial)?;
    let counts = taxels.spikes.counts();
    let (inner, outer) = (
        geometry.rings[..2].iter().sum::<usize>(),
        *geometry.rings.last().expect("rings"),
    );
    let per_pin = |range: std::ops::Range<usize>| {
        range.clone().map(|c| counts[c] as f64).sum::<f64>() / range.len() as f64
    };
    let (centre, rim) = (per_pin(0..inner), per_pin(pins.len() - outer..pins.len()));
    let sliding = (info.motion_start_s + 0.4, info.motion_end_s - 0.1);
    let sliding_s = (sliding.1 - sliding.0).max(1e-9);
    let onset = info.motion_start_s;
    let mut per_pin_sliding = vec![0usize; pins.len()];
    let mut onset_times = Vec::new();
    let bins = (info.press_end_s / BURST_BIN_S).ceil() as usize + 1;
    let mut burst = vec![0usize; bins];
    for (e, l) in trial.events.iter().zip(&trial.labels) {
        let Some(pin) = l.pin() else { continue };
        let t = e.t.0 as f64 / 1e6;
        if (sliding.0..sliding.1).contains(&t) {
            per_pin_sliding[pin] += 1;
        }
        if (onset..onset + ONSET_WINDOW_S).contains(&t) {
            onset_times.push(t - onset);
        }
        if t < info.press_end_s {
            burst[(t / BURST_BIN_S) as usize] += 1;
        }
    }
    let inside = |p: usize| info.in_contact[p];
    let sum_where = |keep: &dyn Fn(usize) -> bool| {
        (0..pins.len())
            .filter(|&p| keep(p))
            .map(|p| per_pin_sliding[p] as f64)
            .sum::<f64>()
    };
    let ahead = sum_where(&|p| inside(p) && pins[p].0 > 0.5);
    let behind = sum_where(&|p| inside(p) && pins[p].0 < -0.5);
    let n_inside = info.in_contact.iter().filter(|&&c| c).count();
    let n_outside = pins.len() - n_inside;
    onset_times.sort_unstable_by(f64::total_cmp);
    let quantile = |q: f64| onset_times[((onset_times.len() - 1) as f64 * q).round() as usize];
    Ok(SpecimenSlide {
        class,
        spikes_per_taxel: counts.iter().sum::<usize>() as f64 / pins.len() as f64,
        normal_force_n: info.press.normal_force_n,
        contact_radius_mm: info.press.contact_radius_mm,
        overlap_mm: info.press.overlap_mm,
        pins_in_contact: n_inside,
        rim_centre: (centre > 0.0).then(|| rim / centre),
        lead_trail: (behind > 0.0).then_some((ahead / behind, ahead + behind)),
        rim_rate_hz: if n_outside > 0 {
            sum_where(&|p| !inside(p)) / n_outside as f64 / sliding_s
        } else {
            f64::NAN
        },
        contact_rate_hz: if n_inside > 0 {
            sum_where(&inside) / n_inside as f64 / sliding_s
        } else {
            f64::NAN
        },
        rise_s: (onset_times.len() >= 20).then(|| quantile(0.9) - quantile(0.1)),
        onset_s: info.onset.full_slip_s.map(|t| t - onset),
        first_burst_s: burst
            .iter()
            .position(|&n| n >= BURST_EVENTS)
            .map(|i| i as f64 * BURST_BIN_S),
        press_start_s: info.press_start_s,
        forward_shift: info.contact.forward_shift,
        pile: info.contact.pile,
        drag_mm: info.contact.fabric_drag_mm,
        wrinkle_after_start_s: info.contact.wrinkle_s.map(|t| t - onset),
    })
}

/// One texture's row of the specimen table: means over its slides.
#[derive(Debug, Clone, Serialize)]
pub struct SpecimenRow {
    /// Texture name.
    pub texture: String,
    /// Spikes per taxel.
    pub spikes_per_taxel: f64,
    /// Overlap of the dome with the specimen's surface (mm).
    pub overlap_mm: f64,
    /// Normal force (N).
    pub normal_force_n: f64,
    /// Contact radius (mm).
    pub contact_radius_mm: f64,
    /// Pins in contact.
    pub pins_in_contact: f64,
    /// Outer-ring over centre taxel spikes per pin.
    pub rim_centre: f64,
    /// Forward shift ε of the sliding pressure.
    pub forward_shift: f64,
    /// Sliding-phase signal events ahead over behind (pins in contact).
    pub lead_trail: f64,
    /// Sliding-phase signal events on the pins in contact per slide (ahead and behind).
    pub lead_trail_events: f64,
    /// Sliding-phase signal events per second per pin outside / inside the contact.
    pub rim_rate_hz: f64,
    /// The same inside the contact.
    pub contact_rate_hz: f64,
    /// 10–90 % rise of the onset's events (ms).
    pub rise_ms: f64,
    /// Slide start to the first full slip (ms).
    pub onset_ms: f64,
    /// Share of the load carried by pile hairs beyond the contact.
    pub pile_share: Option<f64>,
    /// The fabric's drag at the skin's first slip (mm).
    pub drag_mm: Option<f64>,
    /// Share of the slides in which the fabric ahead wrinkled.
    pub wrinkled: Option<f64>,
}

/// The protocol and specimen statistics, the per-texture table and the mountings' spread.
#[derive(Debug, Clone, Serialize)]
pub struct SpecimenReport {
    /// Statistics 12–18.
    pub statistics: Vec<Statistic>,
    /// One row per texture of both sets.
    pub textures: Vec<SpecimenRow>,
    /// The 5 mm / 4.5 mm intensive ratio, one per mounting.
    pub mounting_ratios: Vec<f64>,
    /// Slides simulated.
    pub trials_simulated: usize,
}

/// Runs `trials` slides of every texture of both sets and `mountings` mountings of the 4.5 and
/// 5 mm grids, and computes the statistics (see the module docs).
pub(super) fn specimen_check(
    params: &SimParams,
    seed: u64,
    trials: usize,
    mountings: usize,
    progress: &(dyn Fn() + Sync),
) -> Result<SpecimenReport, DatasetsError> {
    let camera = Camera::new(params, camera_seed(seed));
    let mut rows = Vec::new();
    let mut slides = Vec::new();
    for set in [TextureSet::Artificial, TextureSet::Natural] {
        let textures = prepare_textures(params, set);
        let classes: Vec<usize> = (0..textures.len()).collect();
        let jobs = jobs_for(set, seed, &classes, 0, trials);
        let runs = map_trials(
            params,
            &camera,
            &textures,
            &jobs,
            &|job, trial| analyse_specimen(trial, job.class),
            progress,
        )?;
        for (class, texture) in textures.iter().enumerate() {
            let of: Vec<&SpecimenSlide> = runs.iter().filter(|s| s.class == class).collect();
            rows.push(row(&texture.texture.name(), &of));
        }
        slides.push(runs);
    }
    let natural: Vec<&SpecimenRow> = rows[11..].iter().collect();
    let statistics = vec![
        duration_law(params),
        press_statistic(&rows),
        lead_trail_statistic(&rows),
        rim_statistic(&rows),
        rise_statistic(&rows),
        first_burst_statistic(params, &slides),
        pile_statistic(params, &natural),
    ];
    let ratios = mounting_ratios(params, seed, mountings, progress)?;
    Ok(SpecimenReport {
        statistics,
        textures: rows,
        trials_simulated: slides.iter().map(Vec::len).sum::<usize>() + 2 * mountings,
        mounting_ratios: ratios,
    })
}

fn row(texture: &str, slides: &[&SpecimenSlide]) -> SpecimenRow {
    let m = |f: &dyn Fn(&SpecimenSlide) -> Option<f64>| mean(slides.iter().filter_map(|s| f(s)));
    let with_fabric: Vec<&&SpecimenSlide> = slides.iter().filter(|s| s.drag_mm.is_some()).collect();
    SpecimenRow {
        texture: texture.to_owned(),
        spikes_per_taxel: m(&|s| Some(s.spikes_per_taxel)),
        overlap_mm: m(&|s| Some(s.overlap_mm)),
        normal_force_n: m(&|s| Some(s.normal_force_n)),
        contact_radius_mm: m(&|s| Some(s.contact_radius_mm)),
        pins_in_contact: m(&|s| Some(s.pins_in_contact as f64)),
        rim_centre: m(&|s| s.rim_centre),
        forward_shift: m(&|s| Some(s.forward_shift)),
        lead_trail: m(&|s| s.lead_trail.map(|l| l.0)),
        lead_trail_events: m(&|s| Some(s.lead_trail.map_or(0.0, |l| l.1))),
        rim_rate_hz: m(&|s| Some(s.rim_rate_hz).filter(|r| r.is_finite())),
        contact_rate_hz: m(&|s| Some(s.contact_rate_hz).filter(|r| r.is_finite())),
        rise_ms: 1e3 * m(&|s| s.rise_s),
        onset_ms: 1e3 * m(&|s| s.onset_s),
        pile_share: slides[0].pile.map(|_| m(&|s| s.pile.map(|p| p.1))),
        drag_mm: (!with_fabric.is_empty())
            .then(|| mean(with_fabric.iter().filter_map(|s| s.drag_mm))),
        wrinkled: (!with_fabric.is_empty()).then(|| {
            with_fabric
                .iter()
                .filter(|s| s.wrinkle_after_start_s.is_some())
                .count() as f64
                / with_fabric.len() as f64
        }),
    }
}

/// 12. The duration law against the paper's five durations.
fn duration_law(params: &SimParams) -> Statistic {
    let simulated: Vec<(f64, f64, f64)> = PAPER_DURATIONS
        .iter()
        .map(|&(v, paper)| (v, paper, nominal_duration_at(params, v)))
        .collect();
    // Least squares of T = D/v + c over the simulated durations.
    let (x, y): (Vec<f64>, Vec<f64>) = simulated.iter().map(|&(v, _, t)| (1.0 / v, t)).unzip();
    let (mx, my) = (mean(x.iter().copied()), mean(y.iter().copied()));
    let slope = x
        .iter()
        .zip(&y)
        .map(|(a, b)| (a - mx) * (b - my))
        .sum::<f64>()
        / x.iter().map(|a| (a - mx).powi(2)).sum::<f64>();
    let jitter = params.kinematics.loop_jitter_s;
    let worst = simulated
        .iter()
        .map(|&(_, paper, sim)| (sim - paper).abs())
        .fold(0.0, f64::max);
    Statistic {
        number: 12,
        name: "duration law",
        measured: format!(
            "{}; law T = {slope:.2} mm / v + {:.3} s (paper: 64.93 mm / v + 0.193 s); largest gap {:.1} ms",
            simulated
                .iter()
                .map(|(v, paper, sim)| format!("{v} mm/s {sim:.3}/{paper:.3} s"))
                .collect::<Vec<_>>()
                .join(", "),
            my - slope * mx,
            1e3 * worst
        ),
        bound: format!(
            "every nominal recording within 3 × the durations' scatter ({:.1} ms) of the paper's; the moves inside a recording total 65 mm (press 5 + slide 60)",
            3e3 * jitter
        ),
        pass: worst <= 3.0 * jitter && (slope - 65.0).abs() < 0.5,
    }
}

/// 13. The press under position control, per texture.
fn press_statistic(rows: &[SpecimenRow]) -> Statistic {
    let plausible = rows
        .iter()
        .all(|r| (0.05..=15.0).contains(&r.normal_force_n) && r.pins_in_contact >= 1.0);
    let rigid_rim = rows[..11].iter().all(|r| r.rim_centre < 1.0);
    Statistic {
        number: 13,
        name: "press per texture",
        measured: format!(
            "N {:.2}–{:.2} N, contact radius {:.1}–{:.1} mm, {:.0}–{:.0} pins in contact over both sets (per texture in check.md); grids' outer ring/centre spikes ≤ {:.2}",
            range(rows, |r| r.normal_force_n).0,
            range(rows, |r| r.normal_force_n).1,
            range(rows, |r| r.contact_radius_mm).0,
            range(rows, |r| r.contact_radius_mm).1,
            range(rows, |r| r.pins_in_contact).0,
            range(rows, |r| r.pins_in_contact).1,
            range(&rows[..11], |r| r.rim_centre).1,
        ),
        bound: "every texture pressed with 0.05–15 N over ≥ 1 pin (position control: δ = min(δ₀ + h, travel)); on the rigid grids the outer ring fires less than the centre (the gel spreads the load, Cerruti)".into(),
        pass: plausible && rigid_rim,
    }
}

/// 14. Leading over trailing pins while sliding, against the forward shift.
fn lead_trail_statistic(rows: &[SpecimenRow]) -> Statistic {
    // Textures that fire enough while sliding for a ratio to mean something.
    let usable: Vec<&SpecimenRow> = rows
        .iter()
        .filter(|r| r.lead_trail.is_finite() && r.lead_trail_events >= MIN_SLIDING_EVENTS)
        .collect();
    let rigid: Vec<f64> = usable
        .iter()
        .filter(|r| r.forward_shift == 0.0)
        .map(|r| r.lead_trail)
        .collect();
    let compliant: Vec<&&SpecimenRow> = usable.iter().filter(|r| r.forward_shift > 0.0).collect();
    let rho = spearman(
        &compliant
            .iter()
            .map(|r| r.forward_shift)
            .collect::<Vec<_>>(),
        &compliant.iter().map(|r| r.lead_trail).collect::<Vec<_>>(),
    );
    let rigid_mean = mean(rigid.iter().copied());
    let compliant_mean = mean(compliant.iter().map(|r| r.lead_trail));
    Statistic {
        number: 14,
        name: "leading / trailing pins",
        measured: format!(
            "ahead/behind events while sliding (textures with ≥ {MIN_SLIDING_EVENTS} such events per slide): rigid textures {rigid_mean:.2} (mean of {}), compliant {compliant_mean:.2} (mean of {}); Spearman ρ(ε, ratio) over compliant textures {rho:.2}; {}",
            rigid.len(),
            compliant.len(),
            compliant
                .iter()
                .map(|r| format!("{} ε {:.3} → {:.2}", r.texture, r.forward_shift, r.lead_trail))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        bound: "compliant layers (ε = 2·tan δ·δ_t/δ > 0) shift the sliding pressure forward (Hunter 1961): their leading pins fire more than on rigid textures, on average".into(),
        pass: compliant_mean > rigid_mean,
    }
}

/// 15. Rim pins while sliding.
fn rim_statistic(rows: &[SpecimenRow]) -> Statistic {
    let grids = &rows[..11];
    let coarse: Vec<f64> = grids[7..]
        .iter()
        .map(|r| r.contact_rate_hz / r.rim_rate_hz)
        .collect();
    Statistic {
        number: 15,
        name: "rim pins while sliding",
        measured: format!(
            "in-contact over outside pins' event rates while sliding: coarse grids ×{:.1}–×{:.1}; natural textures ×{:.1}–×{:.1} (per texture in check.md)",
            coarse.iter().copied().fold(f64::INFINITY, f64::min),
            coarse.iter().copied().fold(0.0, f64::max),
            range(&rows[11..], |r| r.contact_rate_hz / r.rim_rate_hz).0,
            range(&rows[11..], |r| r.contact_rate_hz / r.rim_rate_hz).1,
        ),
        bound: "signal events per pin and second outside/inside the contact; on coarse grids (3.5–5 mm) pins in contact fire ≥ 3× more than those outside it (spec §5.8)".into(),
        pass: coarse.iter().all(|&x| x >= 3.0),
    }
}

/// 16. The onset's rise time against its mechanics.
fn rise_statistic(rows: &[SpecimenRow]) -> Statistic {
    let usable: Vec<&SpecimenRow> = rows
        .iter()
        .filter(|r| r.rise_ms.is_finite() && r.onset_ms.is_finite())
        .collect();
    let rho = spearman(
        &usable.iter().map(|r| r.onset_ms).collect::<Vec<_>>(),
        &usable.iter().map(|r| r.rise_ms).collect::<Vec<_>>(),
    );
    Statistic {
        number: 16,
        name: "onset rise time",
        measured: format!(
            "Spearman ρ(time to full slip, 10–90 % rise of the onset's events) over {} textures {rho:.2}; {}",
            usable.len(),
            usable
                .iter()
                .map(|r| format!("{} {:.0}/{:.0} ms", r.texture, r.rise_ms, r.onset_ms))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        bound: "the onset's events follow its mechanics: textures that take longer to slip (more force, a softer layer or a dragged fabric) rise more slowly, ρ ≥ 0.5".into(),
        pass: rho >= 0.5,
    }
}

/// 17. The first burst's timing spread within a texture, against the loop's prediction.
fn first_burst_statistic(params: &SimParams, slides: &[Vec<SpecimenSlide>]) -> Statistic {
    // Pooled within-texture standard deviations of the burst, of the press's start, and of the
    // burst after the press's start (what the pixels and the press add).
    let pooled = |f: &dyn Fn(&SpecimenSlide) -> Option<f64>| {
        let (mut ss, mut dof) = (0.0, 0usize);
        for runs in slides {
            let classes = runs.iter().map(|s| s.class).max().map_or(0, |c| c + 1);
            for class in 0..classes {
                let t: Vec<f64> = runs
                    .iter()
                    .filter(|s| s.class == class)
                    .filter_map(f)
                    .collect();
                if t.len() >= 2 {
                    let m = mean(t.iter().copied());
                    ss += t.iter().map(|x| (x - m).powi(2)).sum::<f64>();
                    dof += t.len() - 1;
                }
            }
        }
        ((ss / dof.max(1) as f64).sqrt(), dof)
    };
    let (burst, dof) = pooled(&|s| s.first_burst_s);
    let (press, _) = pooled(&|s| s.first_burst_s.map(|_| s.press_start_s));
    let (after, _) = pooled(&|s| s.first_burst_s.map(|b| b - s.press_start_s));
    let loop_prediction =
        params.kinematics.loop_jitter_s * (STEPS_BEFORE_PRESS as f64 / LOOP_STEPS as f64).sqrt();
    let combined = press.hypot(after);
    Statistic {
        number: 17,
        name: "first-burst timing",
        measured: format!(
            "the press's first burst spreads by {:.1} ms within a texture ({dof} degrees of freedom): the press's start {:.1} ms (the loop predicts {:.1} ms: its {STEPS_BEFORE_PRESS} steps before the press, of the durations' {:.1} ms scatter over {LOOP_STEPS}), the pixels' and the press's own {:.1} ms after it",
            1e3 * burst,
            1e3 * press,
            1e3 * loop_prediction,
            1e3 * params.kinematics.loop_jitter_s,
            1e3 * after,
        ),
        bound: "the press's start within 25 % of the loop's prediction; the burst's spread within 25 % of the two parts combined (independent)".into(),
        pass: dof > 0
            && (press / loop_prediction - 1.0).abs() <= 0.25
            && (burst / combined - 1.0).abs() <= 0.25,
    }
}

/// 18. Pile hairs: their share of the load, and a single release against the DVS resolution.
fn pile_statistic(params: &SimParams, natural: &[&SpecimenRow]) -> Statistic {
    let releases: Vec<(String, f64)> = neurotac_sensor::sim::NATURAL_TEXTURES
        .iter()
        .filter_map(|t| {
            t.material.pile.map(|p| {
                (
                    t.name.to_owned(),
                    p.release_displacement_mm(
                        (t.mu_static, t.mu_kinetic),
                        GEL_SHEAR_MPA,
                        params.contact.skin_depth_mm,
                    ),
                )
            })
        })
        .collect();
    let largest = releases.iter().map(|r| r.1).fold(0.0, f64::max);
    Statistic {
        number: 18,
        name: "pile and fabric drag",
        measured: format!(
            "load share of hairs beyond the contact: {}; one hair's release moves the skin ≤ {largest:.1e} mm; fabric drag at the first slip: {}",
            natural
                .iter()
                .filter_map(|r| r
                    .pile_share
                    .map(|s| format!("{} {:.1} %", r.texture, 100.0 * s)))
                .collect::<Vec<_>>()
                .join(", "),
            natural
                .iter()
                .filter_map(|r| r.drag_mm.map(|d| format!(
                    "{} {d:.2} mm (wrinkled in {:.0} %)",
                    r.texture,
                    100.0 * r.wrinkled.unwrap_or(0.0)
                )))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        bound: format!(
            "a single hair's release stays below a DVS pixel's resolution ({DVS_RESOLUTION_MM:.3} mm, ≈ 0.2 px), so releases are not simulated"
        ),
        pass: largest < DVS_RESOLUTION_MM,
    }
}

/// The smallest and largest finite value of `f` over `rows`.
fn range(rows: &[SpecimenRow], f: impl Fn(&SpecimenRow) -> f64) -> (f64, f64) {
    rows.iter()
        .map(f)
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// The 5 mm / 4.5 mm spikes-per-taxel ratio on `mountings` rigs (one slide each).
fn mounting_ratios(
    params: &SimParams,
    seed: u64,
    mountings: usize,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<f64>, DatasetsError> {
    let set = TextureSet::Artificial;
    let textures = prepare_textures(params, set);
    let camera = Camera::new(params, camera_seed(seed));
    (0..mountings)
        .map(|m| {
            let mut remounted = *params;
            remounted.kinematics.mounting = m as u64 + 1;
            let counts = map_trials(
                &remounted,
                &camera,
                &textures,
                &jobs_for(set, seed, &[9, 10], 0, 1),
                &|_, trial| Ok(taxel_spikes(trial)?.spikes.total_spikes() as f64),
                progress,
            )?;
            Ok(counts[1] / counts[0])
        })
        .collect()
}

/// The spread of the mountings' ratios as a line.
pub fn mounting_summary(ratios: &[f64]) -> String {
    if ratios.is_empty() {
        return "no mountings".into();
    }
    let mut sorted = ratios.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    let q = |f: f64| sorted[((sorted.len() - 1) as f64 * f).round() as usize];
    format!(
        "5 mm / 4.5 mm spikes per taxel over {} mountings: mean {:.3} ± {:.3} (sd), median {:.3}, 5–95 % {:.3}–{:.3}, below 1 in {:.0} %",
        ratios.len(),
        mean(ratios.iter().copied()),
        sd(ratios),
        q(0.5),
        q(0.05),
        q(0.95),
        100.0 * ratios.iter().filter(|&&r| r < 1.0).count() as f64 / ratios.len() as f64
    )
}
