//! The simulator's parameters: one `Copy` record ([`SimParams`]) of documented groups, every
//! default taken from `shared/specs/simulator.md` (section named on each field), validated once
//! by [`SimParams::validate`] with errors naming the field as spelled in a parameter file.
//!
//! A parameter file is the JSON form of [`SimParams`] (`serde_json::to_string_pretty(&SimParams::default())`
//! writes a complete one). Every field must be present: a missing or unknown field is an error
//! naming it, so a file never silently falls back to a default.

pub use super::parameter_sources::PARAMETER_SOURCES;
use serde::{Deserialize, Serialize};

mod file;
mod validate;

/// The recording loop and the robot's kinematics ([`super::kinematics`]), and the variability
/// a robot arm has (spec §2.1; hierarchical, §8).
///
/// A recording is the lab's loop: logging starts, the arm presses `press_travel_mm` down at the
/// linear speed, dwells, slides `distance_mm`, and logging stops. The press ends at a fixed
/// height, `press_depth_mm` below the set's base surface (position control): a specimen whose
/// surface stands higher is pressed deeper ([`super::texture::Surface::press`]).
///
/// Variability is hierarchical, as in a real recording: the texture's **mounting** (lateral
/// offset y₀ and start phase) is drawn once per texture and rig (dataset) and is the same for
/// all its slides; each **slide** adds only what the arm does not repeat — positioning jitter at
/// the arm's stated repeatability, a press-depth jitter of the same order and the loop's timing
/// ([`super::kinematics::Recording::draw`]). [`per_slide_offsets`](Self::per_slide_offsets)
/// restores independent per-slide offsets (the first implementation's behaviour) to study that
/// confound.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KinematicsParams {
    /// Cruise speed of the press and the slide (mm/s). Default 15 (paper).
    pub speed_mm_s: f64,
    /// Slide distance (mm). Default 60 (paper).
    pub distance_mm: f64,
    /// Acceleration and deceleration of the trapezoidal speed profiles (mm/s²). Default 28 000
    /// (ABB IRB 120: maximum TCP acceleration 28 m/s²; the paper's durations show no ramp,
    /// ≥ 1.7 m/s²).
    pub acceleration_mm_s2: f64,
    /// How far the press moves down, at the linear speed (mm). Default 5 (the lab's slide
    /// script; the paper's durations hold 65 mm of moves).
    pub press_travel_mm: f64,
    /// Depth of the press's end below the set's base surface (mm): the flat plate (and the
    /// grids' floor) of the artificial set, the rigid specimens' surface of the natural set.
    /// Default 2 (spec: 1.5–3). The dome starts `press_travel_mm − press_depth_mm` above that
    /// surface.
    pub press_depth_mm: f64,
    /// The dome's normal force at `press_depth_mm` on a rigid plate (N); it scales as δ^{3/2}
    /// (Hertz). Default 2 (spec: 1–3).
    pub normal_force_n: f64,
    /// The pause between the press and the slide (s). Default 0.1 (the lab's script,
    /// `time.sleep(0.1)`).
    pub dwell_s: f64,
    /// The loop's blocking-step latencies summed over one recording (s): eight steps
    /// ([`super::kinematics::LOOP_STEPS`]). Default 0.0855 (the paper's five durations, less
    /// the moves and the dwell).
    pub loop_overhead_s: f64,
    /// Standard deviation of a recording's duration about the duration law (s), spread over the
    /// eight steps. Default 0.0064 (the paper's five durations about their law).
    pub loop_jitter_s: f64,
    /// Width of the uniform lateral offset y₀ of a texture's mounting (mm), centred on 0.
    /// Default 10.
    pub lateral_offset_range_mm: f64,
    /// Width of the uniform start phase of a texture's mounting (texture offset along the
    /// slide, mm). Default 10 (one period of the coarsest grid).
    pub start_phase_range_mm: f64,
    /// Draw offset and phase independently for every slide instead of once per mounting.
    /// Default `false` (a robot repeats its path, spec §8).
    pub per_slide_offsets: bool,
    /// Per-slide positioning jitter (standard deviation, mm) of the offset and the phase: the
    /// arm's position repeatability. Default 0.01 (ABB IRB120 product specification: position
    /// repeatability RP = 0.01 mm).
    pub position_repeatability_mm: f64,
    /// Per-slide standard deviation of the press depth (mm): of the order of the arm's
    /// repeatability. Default 0.01 (ABB IRB120 product specification, RP = 0.01 mm).
    pub press_depth_sd_mm: f64,
    /// Which mounting of the textures a recording uses: 0 is the rig's own (drawn from the
    /// camera's seed), k > 0 mounts every texture afresh from another draw, with the same
    /// camera ([`super::Mounting`]). Default 0. Running several mountings shows the spread a
    /// single mounting hides (`neurotac reproduce --mountings K`).
    pub mounting: u64,
}

impl Default for KinematicsParams {
    fn default() -> Self {
        Self {
            speed_mm_s: 15.0,
            distance_mm: 60.0,
            acceleration_mm_s2: 28_000.0,
            press_travel_mm: 5.0,
            press_depth_mm: 2.0,
            normal_force_n: 2.0,
            dwell_s: 0.1,
            loop_overhead_s: 0.0855,
            loop_jitter_s: 0.0064,
            lateral_offset_range_mm: 10.0,
            start_phase_range_mm: 10.0,
            per_slide_offsets: false,
            position_repeatability_mm: 0.01,
            press_depth_sd_mm: 0.01,
            mounting: 0,
        }
    }
}

/// Which length a grid's "size" d sets (spec §2.1, §7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PeriodRule {
    /// Diameter d and edge-to-edge gap d: period p = 2d (default).
    Gap,
    /// Centre-to-centre spacing d: period p = d, diameter d/2 and gap d/2.
    CentreToCentre,
}

/// Contact mechanics: skin-on-texture contact, skin → pin transfer, friction and stick-slip
/// shear (spec §2.2, §8). Three fields are calibrated ([`SimParams::calibrated_parameters`]);
/// every other default is a prior with its source.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactParams {
    /// Depth z of the elastic-layer low-pass T(k) = (1 + kz)·e^(−kz) (mm). Default 1.25 (§6).
    pub skin_depth_mm: f64,
    /// **Calibrated** (2.5 mm grid → 9.84): the sag/conformity law. Default 7.9023, from
    /// `neurotac simulate calibrate` (20 re-mounted slides per step, seed 1: 9.85 spikes per
    /// taxel). The gap g₀ (mm) over which
    /// the free skin, as a membrane under the nominal contact pressure q, sags by 1 mm; it sets
    /// the skin tension T = q·g₀²/(8 · 1 mm) of the contact solve ([`super::contact`]).
    pub gap_conformity_mm: f64,
    /// Winkler stiffness of the gel behind the skin (N/mm³): E_gel / gel thickness. Default
    /// 0.002 (RTV27905 gel E ≈ 0.03 MPa \[K\], spec §1.1; ≈ 15 mm of gel under the skin).
    pub foundation_stiffness_n_mm3: f64,
    /// Width of the contact edge in χ(r) = 1/(1 + e^((r − a)/w)) (mm). Default 0.8.
    pub contact_edge_mm: f64,
    /// **Calibrated** (5 mm grid → 34.73): effective lever G_lever turning skin slope into
    /// pin-tip displacement (mm; spec range 0.4–0.6). Default 0.5916, from `neurotac simulate
    /// calibrate` (20 re-mounted slides per step, seed 1: 34.75 spikes per taxel).
    pub lever_mm: f64,
    /// **Calibrated** (flat plate → 4.63): the fraction g_pin of the skin's shear that reaches
    /// the pin tips, so the onset's size on the pins (spec §2.2: g_pin ≈ 0.5 \[A\]). Default from
    /// `neurotac simulate calibrate`: 0.3125 (20 re-mounted slides per step, seed 1: 4.66 spikes
    /// per taxel).
    pub pin_shear_gain: f64,
    /// Radial bulge β: pin displacement β·w·r̂ per mm of skin deflection. Default 0.1 (0–0.3).
    pub bulge: f64,
    /// Distance from the contact's edge to where a fabric specimen is taped to the base plate
    /// (mm): the span its drag stretches, shears and wrinkles ([`super::fabric`]). Default 30.
    pub fabric_mount_span_mm: f64,
    /// Friction of a fabric specimen on the base plate, μ_fb: it holds the fabric under the
    /// dome until the onset's load exceeds μ_fb·N ([`super::fabric`]). Default 0.3.
    pub fabric_base_friction: f64,
    /// Shear stiffness per area of the skin layer under a pin, κ = G_skin / t_skin (N/mm³): turns
    /// the local traction into local shear. Default 0.35 (Shore A 28 print → E ≈ 1.05 MPa by
    /// Gent's relation, G = E/3; t = 1 mm, spec §1.1).
    pub skin_shear_stiffness_n_mm3: f64,
    /// Height of the grid cylinders (mm). Default 1 (paper).
    pub bump_height_mm: f64,
    /// What a grid's size d means. Default [`PeriodRule::Gap`].
    pub period_rule: PeriodRule,
    /// Tangential stiffness k_t of the skin (N/mm). Default 2 (spec: 1–3).
    pub tangential_stiffness_n_mm: f64,
    /// Slip time constant τ = c_d/k_t (s). Default 0.01 (spec: 5–20 ms).
    pub slip_time_s: f64,
    /// Lag of the slip velocity behind its quasi-static value (s): the patch's inertia; it
    /// lets velocity weakening produce periodic stick-slip. Default 0.001 \[A\].
    pub slip_inertia_s: f64,
    /// Kinetic adhesive friction μ_k of the skin on a flat printed plate. Default 0.7
    /// (spec §6 prototype; rubber on smooth polymer 0.5–1, Persson 2001).
    pub adhesion_mu_kinetic: f64,
    /// The onset snap: static adhesive friction exceeds the kinetic by this fraction,
    /// μ_s,adh = μ_k,adh·(1 + excess). Default 0.3: μ_s/μ_k = 1.3 for a smooth adhesive solid,
    /// the prior the natural catalogue gives acrylic and foil (a printed plate is one). It was
    /// the flat plate's calibrated value until the press and the gel's traction profile were
    /// in: since then even no snap at all leaves the flat plate above the paper's 4.63 (5.6–6.3
    /// spikes per taxel), so the flat plate calibrates the shear gain instead.
    pub static_excess: f64,
    /// Loss tangent tan δ of the skin rubber: hysteresis friction μ_hys = tan δ·⟨|∂z_s/∂X|⟩
    /// over the conformed skin (Greenwood & Tabor 1958). Default 0.25 (photopolymer rubbers
    /// Tango/Agilus at room temperature and Hz frequencies: 0.2–0.4 \[K\]).
    pub loss_tangent: f64,
    /// RMS slope h'_rms of the printed surface's micro-roughness, for the real contact area
    /// A/A₀ = erf(√2·p/(E*·h'_rms)) (Persson 2001). Default 0.2 (3D-printed polymer
    /// surfaces, R_a ≈ 2–10 µm over ≈ 20–50 µm \[A\]).
    pub micro_slope_rms: f64,
    /// Plane-strain modulus E* of the skin (MPa) for the real contact area. Default 1.4
    /// (E ≈ 1.05 MPa, ν = 0.5: E* = E/(1 − ν²)).
    pub skin_modulus_mpa: f64,
    /// Smallest micro-slip amplitude δ_ms (mm). Default 0.01: the slip one Schallamach wave or
    /// slip pulse carries in a soft elastomer contact, 10–100 µm \[K\] (the waves carry a fixed
    /// slip each: Viswanathan, Mahato & Chandrasekar 2014; Viswanathan et al. 2016).
    pub microslip_min_mm: f64,
    /// Largest micro-slip amplitude δ_ms (mm). Default 0.1 (same source).
    pub microslip_max_mm: f64,
    /// Reload time constant τ_ms of a micro-slip (s). Default 0.003 (spec: 2–5 ms).
    pub microslip_time_s: f64,
    /// Edge catches per grid period: while the skin slides over a bump grid it catches on the
    /// bump edges and lets go in a micro-slip (amplitudes `microslip_min/max_mm`), at this
    /// many per period p of travel, i.e. at v/p per catch. Default 1 \[A\]: one catch per row of
    /// bumps passing the contact's leading edge; stick-slip of rubber on edged surfaces
    /// (Schallamach waves, Viswanathan et al. 2016) gives no rate for a bump grid.
    pub edge_catches_per_period: f64,
    /// Radius of the skin footprint that drives one pin (mm): the partial-slip front moves a
    /// pin as it crosses this disc ([`super::slip_front`]). Default 0.75: half the pin-tip
    /// diameter of 1.2–1.5 mm (spec §1.1, from TacTip blob areas).
    pub pin_footprint_radius_mm: f64,
    /// Whether the onset slips as a front over the contact (Cattaneo–Mindlin, brush
    /// approximation, [`super::slip_front`]) rather than all at once when the lumped shear
    /// reaches its stick limit. Default true; `false` is the single-snap onset of earlier
    /// versions, kept to measure what the front changes.
    pub partial_slip: bool,
    /// Exponent β of the stick zone's shrinking area, A_stick/A = (1 − Q/Q_s)^β
    /// ([`super::slip_front`]). Default 2/3: Cattaneo–Mindlin for an elastic sphere (Johnson,
    /// Contact Mechanics 1985, §7.2); a fingertip pad's stuck area falls linearly, β = 1
    /// (André, Lefèvre & Thonnard, J. R. Soc. Interface 2011).
    pub stick_area_exponent: f64,
    /// Standard deviation of the friction factor shared by every texture of one recording
    /// (rig and day: humidity, skin wear). Default 0.05 \[A\] (elastomer friction changes by
    /// 5–20 % with humidity and surface state).
    pub friction_day_sd: f64,
    /// Standard deviation of the slow friction drift over the slides of one texture: a smooth
    /// random function of the slide index with periods of 50–400 slides. Default 0.03 \[A\].
    pub friction_drift_sd: f64,
}

impl Default for ContactParams {
    fn default() -> Self {
        Self {
            skin_depth_mm: 1.25,
            gap_conformity_mm: 7.9023,
            foundation_stiffness_n_mm3: 0.002,
            contact_edge_mm: 0.8,
            lever_mm: 0.5916,
            pin_shear_gain: 0.3125,
            bulge: 0.1,
            fabric_mount_span_mm: 30.0,
            fabric_base_friction: 0.3,
            skin_shear_stiffness_n_mm3: 0.35,
            bump_height_mm: 1.0,
            period_rule: PeriodRule::Gap,
            tangential_stiffness_n_mm: 2.0,
            slip_time_s: 0.01,
            slip_inertia_s: 0.001,
            adhesion_mu_kinetic: 0.7,
            static_excess: 0.3,
            loss_tangent: 0.25,
            micro_slope_rms: 0.2,
            skin_modulus_mpa: 1.4,
            microslip_min_mm: 0.01,
            microslip_max_mm: 0.1,
            microslip_time_s: 0.003,
            edge_catches_per_period: 1.0,
            pin_footprint_radius_mm: 0.75,
            partial_slip: true,
            stick_area_exponent: 2.0 / 3.0,
            friction_day_sd: 0.05,
            friction_drift_sd: 0.03,
        }
    }
}

/// How the camera sees the pins (spec §1.2, §3.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpticsParams {
    /// Radius r_d of a pin's bright disc (px). Default 3 (spec: 2.5–3.5).
    pub pin_radius_px: f64,
    /// Edge blur w of the disc (px). Default 0.7 (spec: 0.5–1).
    pub edge_blur_px: f64,
    /// Background intensity I_bg (DN). Default 25.
    pub background_dn: f64,
    /// Pin intensity I_pin (DN); contrast K = I_pin/I_bg = 10 by default (spec: 5–20).
    pub pin_dn: f64,
    /// Intensity I_lin below which the log conversion is linear (DN). Default 20 (v2e).
    pub linear_below_dn: f64,
    /// Intensity I_max at which the photoreceptor reaches f_max (DN). Default 255 (v2e).
    pub full_scale_dn: f64,
    /// Radius of the pixel patch simulated around each pin's rest position (px); pixels farther
    /// from every pin only produce noise. Default 10 (spec: ±10 px).
    pub patch_radius_px: f64,
}

impl Default for OpticsParams {
    fn default() -> Self {
        Self {
            pin_radius_px: 3.0,
            edge_blur_px: 0.7,
            background_dn: 25.0,
            pin_dn: 250.0,
            linear_below_dn: 20.0,
            full_scale_dn: 255.0,
            patch_radius_px: 10.0,
        }
    }
}

/// The DVS pixel (spec §3.2–3.3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PixelParams {
    /// Mean ON threshold C⁺ (log intensity). Default 0.20 (v2e; ≈ 22 % contrast). The
    /// DAVIS240's published minimum contrast, ≈ 11 % (Brandli et al., JSSC 2014), makes the flat
    /// plate exceed the paper's 4.63 spikes per taxel with no onset snap at all, so the
    /// recordings' default-bias thresholds were higher (see `pixel.threshold_on` in
    /// [`PARAMETER_SOURCES`]).
    pub threshold_on: f64,
    /// Mean OFF threshold C⁻ (log intensity). Default 0.25 (spec §3.3: default DAVIS biases make
    /// OFF slightly higher \[A\]; no published DAVIS240 ON/OFF asymmetry was found).
    pub threshold_off: f64,
    /// Pixel-to-pixel standard deviation σ_C of both thresholds (fixed-pattern noise).
    /// Default 0.03.
    pub threshold_sd: f64,
    /// Refractory period t_ref (s). Default 0.0005.
    pub refractory_s: f64,
    /// Photoreceptor bandwidth f_max at full-scale intensity (Hz). Default 300 (v2e).
    pub bandwidth_hz: f64,
    /// Fixed output latency (s). Default 15 µs.
    pub latency_s: f64,
    /// Mean of the exponential latency jitter (s). Default 30 µs (spec: 10–50 µs).
    pub latency_jitter_s: f64,
    /// Whether a slide starts with every pixel's memorised reference level anywhere between its
    /// thresholds (`L̃ − L_ref ~ U(−C⁻_p, C⁺_p)`, drawn per slide and pixel) rather than exactly
    /// at its current level. Default true: a DVS pixel stores the log intensity of its last
    /// event (Lichtsteiner et al., JSSC 2008), and before a slide that was somewhere in the
    /// previous slide, the arm's return and the rest, so how close each pixel starts to its next
    /// event is a per-slide draw. `false` starts every pixel freshly reset (as v2e and ESIM do
    /// at their first frame).
    pub random_initial_reference: bool,
}

impl Default for PixelParams {
    fn default() -> Self {
        Self {
            threshold_on: 0.20,
            threshold_off: 0.25,
            threshold_sd: 0.03,
            refractory_s: 0.0005,
            bandwidth_hz: 300.0,
            latency_s: 15e-6,
            latency_jitter_s: 30e-6,
            random_initial_reference: true,
        }
    }
}

/// Pixel noise (spec §3.2–3.3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseParams {
    /// Median leak (background-activity) ON rate r₀ (Hz per pixel). Default 0.1.
    pub leak_rate_hz: f64,
    /// Pixel-to-pixel spread of the leak rate: r = r₀·10^(spread·N(0,1)). Default 0.1.
    pub leak_spread_decades: f64,
    /// Shot-noise rate (Hz per pixel), half ON and half OFF. Default 0.1.
    pub shot_rate_hz: f64,
}

/// The noise budget (Hz per pixel): leak plus shot noise averaged over the pixels. The simulator's
/// work grows with the noise events it draws, so a larger rate is refused before simulating.
pub const MAX_NOISE_RATE_HZ: f64 = 1000.0;

/// The noise events a trial may draw (mean rate × pixels × duration): each is held in memory
/// (16 bytes) until the trial's events are sorted, so this bounds that memory to 3.2 GB.
pub const MAX_NOISE_EVENTS: f64 = 2e8;

impl NoiseParams {
    /// The leak rate averaged over the pixels (Hz): with r = r₀·10^(s·N(0,1)),
    /// the mean of r is r₀·exp((s·ln 10)²/2) (the mean of a log-normal).
    pub fn mean_leak_rate_hz(&self) -> f64 {
        let s = self.leak_spread_decades * std::f64::consts::LN_10;
        self.leak_rate_hz * (s * s / 2.0).exp()
    }
}

impl Default for NoiseParams {
    fn default() -> Self {
        Self {
            leak_rate_hz: 0.1,
            leak_spread_decades: 0.1,
            shot_rate_hz: 0.1,
        }
    }
}

/// Numerical settings: the speed ↔ accuracy knobs (spec §3.2, "Sampling").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverParams {
    /// Largest change of (filtered) log intensity allowed in one pixel step: steps shrink
    /// while pins move fast and grow while they rest. Default 0.067 (≈ C⁺/3, ESIM).
    pub step_tolerance: f64,
    /// Longest pixel step (s): how often a patch whose pins rest and whose filter has settled
    /// is visited (its noise events are handled exactly inside the step). Default 0.25.
    pub max_step_s: f64,
    /// Sampling interval of the mechanics (pin positions are interpolated linearly between
    /// samples) (s). Default 0.0005.
    pub mechanics_dt_s: f64,
    /// Integration step of the shear ODE (s). Default 0.00005.
    pub shear_dt_s: f64,
}

impl Default for SolverParams {
    fn default() -> Self {
        Self {
            step_tolerance: 0.067,
            max_step_s: 0.25,
            mechanics_dt_s: 0.0005,
            shear_dt_s: 0.00005,
        }
    }
}

/// Every parameter of the simulator (see the module docs). `Copy`: pass it by value.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimParams {
    /// Robot kinematics and trial variability.
    pub kinematics: KinematicsParams,
    /// Contact mechanics.
    pub contact: ContactParams,
    /// Pin appearance in the image.
    pub optics: OpticsParams,
    /// DVS pixels.
    pub pixel: PixelParams,
    /// Noise.
    pub noise: NoiseParams,
    /// Numerical settings.
    pub solver: SolverParams,
}

/// The paper's intensive-code means (spikes per taxel) of the 0, 2.5 and 5 mm grids: the only
/// numbers the simulator is calibrated on (spec §5).
pub const PAPER_INTENSIVE_MEANS: [(f64, f64); 3] = [(0.0, 4.63), (2.5, 9.84), (5.0, 34.73)];

/// One calibrated parameter: what was fitted, to which anchor (spec §5 calibration rule).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CalibratedParameter {
    /// The parameter as spelled in the parameter file (`group.field`).
    pub name: &'static str,
    /// Its value.
    pub value: f64,
    /// The grid whose intensive mean it is fitted to (mm).
    pub anchor_grid_mm: f64,
    /// The paper's intensive mean of that grid (spikes per taxel).
    pub target_spikes_per_taxel: f64,
}

impl SimParams {
    /// The (at most three) calibrated parameters, each with the one intensive mean it is
    /// fitted to (spec §5): `contact.pin_shear_gain` (the onset's size on the pins) ← flat
    /// plate 4.63, `contact.gap_conformity_mm` ← 2.5 mm grid 9.84, `contact.lever_mm` ← 5 mm
    /// grid 34.73.
    /// Everything else is a prior; every accuracy is a held-out prediction.
    pub fn calibrated_parameters(&self) -> [CalibratedParameter; 3] {
        let c = &self.contact;
        let [flat, mid, coarse] = PAPER_INTENSIVE_MEANS;
        [
            CalibratedParameter {
                name: "contact.pin_shear_gain",
                value: c.pin_shear_gain,
                anchor_grid_mm: flat.0,
                target_spikes_per_taxel: flat.1,
            },
            CalibratedParameter {
                name: "contact.gap_conformity_mm",
                value: c.gap_conformity_mm,
                anchor_grid_mm: mid.0,
                target_spikes_per_taxel: mid.1,
            },
            CalibratedParameter {
                name: "contact.lever_mm",
                value: c.lever_mm,
                anchor_grid_mm: coarse.0,
                target_spikes_per_taxel: coarse.1,
            },
        ]
    }

    /// The overlap of the dome with a specimen whose surface stands `height_mm` above the
    /// set's base when the press ends `depth_mm` below the base, at most the press's travel
    /// (position control, [`super::layer`]): `min(δ₀ + h, travel)`, never negative.
    pub fn overlap_mm(&self, height_mm: f64, depth_mm: f64) -> f64 {
        (depth_mm + height_mm).clamp(0.0, self.kinematics.press_travel_mm)
    }

    /// Time from the slide's start until the skin's shear reaches its stick limit
    /// s_s = μ_s·N/k_t (s), on the actual trapezoidal ramp: while sticking the shear follows the
    /// base's travel times `shear_share` (the part of it that shears the skin rather than a
    /// compliant texture, [`super::layer::Press`]), so this is when `share·x_b(t) = s_s` —
    /// `√(2·x/a)` with `x = s_s/share` if the stick ends during the acceleration,
    /// `v/(2a) + x/v` after it (≈ x/v, i.e. ∝ 1/v, only in the second case).
    pub fn stick_time_s(&self, mu_static: f64, normal_force_n: f64, shear_share: f64) -> f64 {
        let k = &self.kinematics;
        let x = mu_static * normal_force_n
            / self.contact.tangential_stiffness_n_mm
            / shear_share.max(1e-12);
        let (v, a) = (k.speed_mm_s, k.acceleration_mm_s2);
        if x <= v * v / (2.0 * a) {
            (2.0 * x / a).sqrt()
        } else {
            v / (2.0 * a) + x / v
        }
    }
}

#[cfg(test)]
mod tests;
