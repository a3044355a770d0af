//! The NeuroTac simulator (`shared/specs/simulator.md`): a TacTip-style dome with 49 pins
//! pressed into and slid over a texture, filmed by a simulated DAVIS240, producing pixel events
//! in the same form as the real camera — so the very same transduction
//! ([`crate::taxel::Transducer`]) runs on them.
//!
//! | stage (spec §) | module | main types |
//! |---|---|---|
//! | parameters and their sources (§1–3, §7) | [`params`], [`parameter_sources`] | [`SimParams`] |
//! | the recording loop: press, dwell, slide, the loop's latencies (§2.1) | [`kinematics`] | [`kinematics::Recording`] |
//! | the press under position control, compliant layers | [`layer`] | [`layer::Layer`], [`layer::Press`] |
//! | skin-on-texture contact (§2.2, §8) | [`contact`] | [`SkinContact`] |
//! | textures, friction (§2.1, §2.4) | [`texture`] | [`Texture`], [`TextureField`], [`Surface`] |
//! | natural textures as materials (§2.4) | [`natural`] | [`NATURAL_TEXTURES`], [`NaturalTexture`] |
//! | fabric drag and wrinkling, pile hairs | [`fabric`] | [`fabric::FabricMechanics`], [`fabric::Pile`] |
//! | stick-slip, the press, pins (§2.2) | [`mechanics`] | [`PinTrajectories`] |
//! | variability: mountings and per-slide draws (§2.1, §8) | [`mounting`] | [`Mounting`], [`TrialDraw`] |
//! | partial-slip front of the onset (§9) | [`slip_front`] | [`slip_front::SlipFront`], [`slip_front::PinShear`] |
//! | how the load reaches the pins through the gel | [`shear_spread`] | [`shear_spread::ShearSpread`] |
//! | camera fixed-pattern noise (§3.2) | [`camera`] | [`Camera`] |
//! | rendering, DVS pixels, noise (§3.1–3.2) | [`pixel`] | [`PixelModel`], [`EventLabel`] |
//! | pixel-level diagnostics (§5.7) | [`diagnostics`] | [`edge_pass`], [`pixel_sanity`] |
//! | one trial, transduction | here | [`Simulator`], [`SimulatedTrial`], [`taxel_spikes`] |
//!
//! **What a recording is** (a decision from the lab's slide script and the paper's durations,
//! [`kinematics`]): logging starts (t = 0 is the host's clock then), the arm presses 5 mm down
//! at the slide's speed, dwells 0.1 s, slides 60 mm, and logging stops; between them the loop's
//! blocking calls take their latencies. The press ends at a fixed height below the set's base
//! ([`layer`]), so a grid's 1 mm bumps or a fabric's thickness deepen it: force, contact radius
//! and the pins in contact differ per texture, and the press itself splays the pins it covers.
//! Sliding, the skin's load reaches the pins through the gel ([`shear_spread`]) with a pressure
//! shifted forward on compliant layers; a fabric is dragged on its mounting and wrinkles at the
//! onset, pile hairs drag beyond the contact ([`fabric`]).
//!
//! Seeds: a [`Camera`] (fixed-pattern noise) is drawn once from a camera seed and records every
//! trial; the same seed names the rig, which fixes each texture's [`Mounting`] (offset, phase,
//! friction drift). Each slide is a pure function of (parameters, camera, texture, slide
//! index, trial seed).
//!
//! ```
//! use neurotac_sensor::sim::{Camera, SimParams, Simulator, Texture, taxel_spikes};
//! let mut params = SimParams::default();
//! params.kinematics.distance_mm = 5.0; // a short slide keeps the example fast
//! let camera = Camera::new(&params, 7);
//! let mut sim = Simulator::new(params, &camera)?;
//! let grid = sim.prepare(Texture::from_name("grid 5 mm")?);
//! let trial = sim.simulate(&grid, 42);
//! assert_eq!(trial.events.len(), trial.labels.len());
//! let spikes = taxel_spikes(&trial)?;
//! assert_eq!(spikes.spikes.n_channels(), 49);
//! # Ok::<(), neurotac_sensor::sim::SimulationError>(())
//! ```

pub mod camera;
pub mod contact;
pub mod diagnostics;
pub mod error;
pub mod fabric;
mod fft;
pub mod kinematics;
pub mod layer;
pub mod mechanics;
pub mod mounting;
pub mod natural;
pub mod parameter_sources;
pub mod params;
pub mod pixel;
mod random;
pub mod shear_spread;
pub mod slip_front;
pub mod texture;

pub use camera::Camera;
pub use contact::SkinContact;
pub use diagnostics::{EdgePass, PixelSanity, edge_pass, pixel_sanity};
pub use error::SimulationError;

/// The most trials (slides × textures) one run may simulate: 100 paper datasets, hours of
/// simulation, about a gigabyte of taxel spikes and pixel-event statistics held at once.
pub const MAX_TRIALS: usize = 100_000;

/// Checks `trials` slides of each of `textures` textures against the budget before anything is
/// allocated: at least one slide and at most [`MAX_TRIALS`] trials in all.
pub fn check_trials(trials: usize, textures: usize) -> Result<(), SimulationError> {
    if trials == 0 {
        return Err(SimulationError::ZeroTrials);
    }
    match trials.checked_mul(textures) {
        Some(n) if n <= MAX_TRIALS => Ok(()),
        _ => Err(SimulationError::TooManyTrials {
            trials,
            textures,
            limit: MAX_TRIALS,
        }),
    }
}
pub use mechanics::{ContactFacts, PinTrajectories};
pub use mounting::{Mounting, TrialDraw};
pub use natural::{NATURAL_TEXTURES, NaturalTexture};
pub use params::{CalibratedParameter, PAPER_INTENSIVE_MEANS, PeriodRule, SimParams};
pub use pixel::{EventLabel, PixelModel, PixelRunStats};
pub use slip_front::{PinShear, SlipFront};
pub use texture::{GRID_SIZES_MM, Surface, Texture, TextureField};

use crate::filter::MapStart;
use crate::geometry::PinGeometry;
use crate::taxel::{TaxelLayout, Transducer, TransductionConfig, TransductionCounts};
use mechanics::Mechanics;
use neurotac_core::seed_hash::splitmix64;
use neurotac_core::{EventBuffer, MultiSpikeTrain};
use pixel::RawEvent;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A texture with its solved contact, skin-filtered field and surface, built once and shared
/// by its trials (the expensive part of a texture: [`contact::solve`]).
#[derive(Debug, Clone)]
pub struct PreparedTexture {
    /// The texture.
    pub texture: Texture,
    /// Its skin-filtered field.
    pub field: TextureField,
    /// Its friction, micro-slips and contact facts.
    pub surface: Surface,
    /// Its mounting key ([`Mounting::texture_key`] of its name).
    pub mounting_key: u64,
}

impl PreparedTexture {
    /// Prepares `texture` for a sensor of the default geometry ([`PinGeometry::default`]).
    pub fn new(texture: Texture, params: &SimParams) -> Self {
        Self::for_dome(texture, params, PinGeometry::default().dome_radius_mm)
    }

    /// Prepares `texture` for a dome of radius `dome_radius_mm` (sets the nominal pressure).
    pub fn for_dome(texture: Texture, params: &SimParams, dome_radius_mm: f64) -> Self {
        let (field, surface) = texture.prepare(params, dome_radius_mm);
        Self {
            mounting_key: Mounting::texture_key(&texture.name()),
            texture,
            field,
            surface,
        }
    }
}

/// What happened in one trial besides the events.
#[derive(Debug, Clone, PartialEq)]
pub struct TrialInfo {
    /// Texture name.
    pub texture: String,
    /// The trial seed.
    pub seed: u64,
    /// Index of the slide among its texture's slides (drives the friction drift).
    pub slide: usize,
    /// The per-trial draws.
    pub draw: TrialDraw,
    /// Recording length (s); events lie in `[0, duration)`.
    pub duration_s: f64,
    /// When the press starts moving down (s).
    pub press_start_s: f64,
    /// When the press reaches its depth (s).
    pub press_end_s: f64,
    /// When the slide starts (s).
    pub motion_start_s: f64,
    /// When the slide stops (s).
    pub motion_end_s: f64,
    /// The press: overlap, force, contact radius, shear share ([`layer::Press`]).
    pub press: layer::Press,
    /// How the load reached the pins; the fabric's drag and wrinkling.
    pub contact: mechanics::ContactFacts,
    /// Pixel-model effort.
    pub pixel_stats: PixelRunStats,
    /// Largest pin displacement from rest (px).
    pub max_displacement_px: f64,
    /// Pins in contact (χ > 0.5).
    pub in_contact: Vec<bool>,
    /// How the onset let go.
    pub onset: OnsetFacts,
}

/// The onset of one slide as the mechanics produced it: when the contact slipped as a whole,
/// where the partial-slip front reached each pin, and when each pin was released
/// ([`slip_front`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct OnsetFacts {
    /// Stick limit s_s = μ_s·N/k_t (mm).
    pub stick_limit_mm: f64,
    /// First full slip (s from the recording start), if any.
    pub full_slip_s: Option<f64>,
    /// Per pin: the load fraction θ at which the front reached it (`None`: no contact under
    /// it, or the single-snap onset).
    pub front: Vec<Option<f64>>,
    /// Per pin: its predicted release time (s), when the lumped shear reached θ·s_s.
    pub predicted_release_s: Vec<Option<f64>>,
    /// Per pin: when it was actually released (s): when it first moved at less than half its
    /// stuck rate before the full slip ([`PinTrajectories::release_times`]).
    pub release_s: Vec<f64>,
}

/// One simulated slide: pixel events, time-ordered, with their ground truth.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedTrial {
    /// Pixel events (µs from the recording start, 240 × 180 addresses, polarity).
    pub events: EventBuffer,
    /// One label per event: source pin or noise.
    pub labels: Vec<EventLabel>,
    /// Trial facts.
    pub info: TrialInfo,
}

impl SimulatedTrial {
    /// The signal events alone (noise removed), for counterfactual diagnostics.
    pub fn signal_events(&self) -> EventBuffer {
        self.events
            .iter()
            .zip(&self.labels)
            .filter(|(_, l)| !l.is_noise())
            .map(|(e, _)| e)
            .collect()
    }

    /// Number of noise-labelled events.
    pub fn noise_count(&self) -> usize {
        self.labels.iter().filter(|l| l.is_noise()).count()
    }
}

/// The simulator: validated parameters, the camera, prepared patches and reusable buffers.
/// One per thread; [`simulate`](Self::simulate) allocates only to grow its buffers and for
/// the returned trial.
#[derive(Debug, Clone)]
pub struct Simulator {
    params: SimParams,
    camera: Camera,
    pins_px: Vec<(f64, f64)>,
    mechanics: Mechanics,
    pixels: PixelModel,
    trajectories: PinTrajectories,
    raw: Vec<RawEvent>,
    dome_radius_mm: f64,
}

impl Simulator {
    /// A simulator of the default NeuroTac geometry ([`PinGeometry::default`]).
    pub fn new(params: SimParams, camera: &Camera) -> Result<Self, SimulationError> {
        Self::with_geometry(params, camera, &PinGeometry::default())
    }

    /// A simulator of `geometry` (validates `params`).
    pub fn with_geometry(
        params: SimParams,
        camera: &Camera,
        geometry: &PinGeometry,
    ) -> Result<Self, SimulationError> {
        params.validate()?;
        let n = geometry.n_pins();
        if n == 0 || n >= pixel::NOISE_LABEL as usize {
            return Err(SimulationError::Geometry { pins: n });
        }
        let pins_px = geometry.pin_positions_px();
        Ok(Self {
            pixels: PixelModel::new(&params, &pins_px, camera)?,
            mechanics: Mechanics::new(
                geometry.pin_positions_mm(),
                geometry.dome_radius_mm,
                geometry.scale_px_per_mm,
            ),
            params,
            camera: camera.clone(),
            pins_px,
            trajectories: PinTrajectories::default(),
            raw: Vec::new(),
            dome_radius_mm: geometry.dome_radius_mm,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// Rest positions of the pins in the image (px).
    pub fn pins_px(&self) -> &[(f64, f64)] {
        &self.pins_px
    }

    /// Solves `texture`'s contact and builds its field and surface for these parameters.
    pub fn prepare(&self, texture: Texture) -> PreparedTexture {
        PreparedTexture::for_dome(texture, &self.params, self.dome_radius_mm)
    }

    /// The pin trajectories of the last simulated trial.
    pub fn trajectories(&self) -> &PinTrajectories {
        &self.trajectories
    }

    /// Simulates the first slide over `texture` ([`simulate_slide`](Self::simulate_slide)
    /// with slide index 0).
    pub fn simulate(&mut self, texture: &PreparedTexture, seed: u64) -> SimulatedTrial {
        self.simulate_slide(texture, 0, seed)
    }

    /// Simulates slide `slide` (its index among the texture's slides, which places it on the
    /// friction drift) over `texture`; the result is a pure function of the parameters, the
    /// camera (and rig), the texture, `slide` and `seed`.
    pub fn simulate_slide(
        &mut self,
        texture: &PreparedTexture,
        slide: usize,
        seed: u64,
    ) -> SimulatedTrial {
        self.simulate_with(texture, slide, seed, true)
    }

    /// [`simulate_slide`](Self::simulate_slide), optionally without noise (signal only).
    pub fn simulate_with(
        &mut self,
        texture: &PreparedTexture,
        slide: usize,
        seed: u64,
        with_noise: bool,
    ) -> SimulatedTrial {
        let params = self.params;
        let mut rng = ChaCha8Rng::seed_from_u64(splitmix64(seed ^ 0x6d65_6368));
        let mounting = Mounting::of_specimen(
            &params,
            self.camera.rig_seed,
            texture.mounting_key,
            texture.surface.friction_spread,
        );
        let draw = TrialDraw::draw(&params, &texture.surface, &mounting, slide, &mut rng);
        self.mechanics.run(
            &params,
            &texture.field,
            &texture.surface,
            &draw,
            &mut rng,
            &mut self.trajectories,
        );
        let rec = draw.recording;
        let duration_s = rec.end_s;
        self.raw.clear();
        let pixel_stats = self.pixels.run(
            &self.camera,
            &self.trajectories,
            duration_s,
            splitmix64(seed ^ 0x7069_7865_6c73),
            with_noise,
            &mut self.raw,
        );
        // Time order, ties by row and column: a total order, since a pixel never emits twice in
        // one microsecond, so the unstable (in-place) sort is deterministic.
        self.raw.sort_unstable_by_key(|e| (e.t_us, e.y, e.x));
        let end_us = neurotac_core::time::s_to_us(duration_s);
        let mut events = EventBuffer::with_capacity(self.raw.len());
        let mut labels = Vec::with_capacity(self.raw.len());
        for e in self.raw.iter().filter(|e| e.t_us < end_us) {
            events.t.push(e.t_us);
            events.x.push(e.x);
            events.y.push(e.y);
            events.polarity.push(e.on);
            labels.push(EventLabel(e.label));
        }
        let motion_start_s = rec.slide_start_s;
        let onset = self.onset_facts(motion_start_s);
        SimulatedTrial {
            events,
            labels,
            info: TrialInfo {
                texture: texture.texture.name(),
                seed,
                slide,
                draw,
                duration_s,
                press_start_s: rec.press_start_s,
                press_end_s: rec.press_end_s(),
                motion_start_s,
                motion_end_s: rec.slide_end_s(),
                press: self
                    .trajectories
                    .press
                    .expect("the mechanics set the press"),
                contact: self.trajectories.contact,
                pixel_stats,
                max_displacement_px: self.trajectories.max_displacement_px(),
                in_contact: self.trajectories.in_contact.clone(),
                onset,
            },
        }
    }

    /// The onset facts of the last trajectories (slide motion from `motion_start_s`).
    fn onset_facts(&self, motion_start_s: f64) -> OnsetFacts {
        let tr = &self.trajectories;
        let full = tr.full_slip_s;
        let end = full.unwrap_or(motion_start_s);
        let s_s = tr.stick_limit_mm;
        // The lumped shear from the motion start to the full slip, sampled with the trajectories.
        let last = full.map_or(tr.n_samples, |f| {
            ((f / tr.dt_s) as usize + 1).min(tr.n_samples)
        });
        let first = (0..last)
            .find(|&k| k as f64 * tr.dt_s >= motion_start_s)
            .unwrap_or(last);
        let crossing = |theta: f64| -> Option<f64> {
            let target = (theta * s_s) as f32;
            (first..last)
                .find(|&k| tr.shear_mm[k] >= target)
                .map(|k| k as f64 * tr.dt_s)
        };
        OnsetFacts {
            stick_limit_mm: s_s,
            full_slip_s: full,
            predicted_release_s: tr.slip_front.iter().map(|t| t.and_then(crossing)).collect(),
            front: tr.slip_front.clone(),
            release_s: tr.release_times(motion_start_s, end),
        }
    }
}

/// Taxel spikes of a trial and what the transduction saw.
#[derive(Debug, Clone, PartialEq)]
pub struct TaxelSpikes {
    /// One spike train per taxel (s from the recording start).
    pub spikes: MultiSpikeTrain,
    /// Stage counts.
    pub counts: TransductionCounts,
    /// Largest distance of a receptive-field centre from its home, checked every pooling
    /// window (px).
    pub max_centre_drift_px: f64,
}

/// The transduction with the paper's settings (BA filter 5 ms, receptive fields of 6 px
/// diameter — radius 3 px — on the default layout, 20 ms pooling, re-centring), windows aligned
/// to the recording start.
///
/// Simulated recordings start at t = 0 µs, so the BA time surface starts empty
/// ([`MapStart::Empty`]): that is how dv-processing's zero-initialised map behaves on a real
/// camera's absolute timestamps, whereas a zero map with t starting at 0 would pass every event
/// of the first 5 ms.
pub fn paper_transduction() -> TransductionConfig {
    TransductionConfig {
        origin_us: Some(0),
        ba_start: MapStart::Empty,
        ..TransductionConfig::default()
    }
}

/// Runs `trial`'s events through [`Transducer`] with [`paper_transduction`].
pub fn taxel_spikes(trial: &SimulatedTrial) -> Result<TaxelSpikes, SimulationError> {
    transduce(&trial.events)
}

/// Runs pixel events (from t = 0 µs) through [`Transducer`] with [`paper_transduction`], one
/// pooling window at a time, tracking the receptive-field drift.
pub fn transduce(events: &EventBuffer) -> Result<TaxelSpikes, SimulationError> {
    transduce_with(events, paper_transduction())
}

/// [`transduce`] with other transduction settings (e.g. another pooling or BA window).
pub fn transduce_with(
    events: &EventBuffer,
    config: TransductionConfig,
) -> Result<TaxelSpikes, SimulationError> {
    let layout = TaxelLayout::neurotac_default();
    let mut transducer = Transducer::new(&layout, config)?;
    let window = config.pool_window_us;
    let mut chunk = EventBuffer::new();
    let mut max_drift = 0.0f64;
    let mut i = 0;
    while i < events.len() {
        let end_t = (events.t[i] / window + 1) * window;
        chunk.clear();
        while i < events.len() && events.t[i] < end_t {
            chunk.push(events.get(i).expect("in range"));
            i += 1;
        }
        transducer.push(&chunk)?;
        let fields = transducer.fields();
        for (c, h) in fields.centres().iter().zip(fields.home()) {
            max_drift = max_drift.max(((c.0 - h.0).powi(2) + (c.1 - h.1).powi(2)).sqrt());
        }
    }
    transducer.finish();
    Ok(TaxelSpikes {
        spikes: transducer.spike_trains(),
        counts: transducer.counts(),
        max_centre_drift_px: max_drift,
    })
}
