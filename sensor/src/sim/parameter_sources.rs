//! Where every simulator parameter comes from: the `sources` section of a parameter file
//! ([`PARAMETER_SOURCES`], written by [`SimParams::to_json_string`](super::params::SimParams::to_json_string)
//! and printed by `neurotac simulate params`).

/// Where each prior comes from, as written into a parameter file's `sources` section: one
/// entry per field (`group.field`) or per group where one source covers the whole group.
/// Tags: CALIBRATED (one of the three fitted values, with its anchor); \[R\] a value read in
/// the named source; \[K\] a literature value as remembered, not re-read; \[A\] an assumption
/// with its basis and the range a user should explore; "no source" where none was found (the
/// value is kept and never tuned).
pub const PARAMETER_SOURCES: &[(&str, &str)] = &[
    ("kinematics.speed_mm_s", "[R] paper: 15 mm/s"),
    ("kinematics.distance_mm", "[R] paper: 60 mm per sample"),
    (
        "kinematics.acceleration_mm_s2",
        "[A] spec 2.1: 100-500 mm/s^2 (an ABB IRB120 linear move; explore 100-500)",
    ),
    (
        "kinematics.rest_before_s",
        "no source: the paper does not say how long the recording runs before the motion; [A] spec 2.1 0.2-0.5 s (only the rest's noise depends on it)",
    ),
    (
        "kinematics.rest_after_s",
        "no source: as rest_before_s; [A] spec 2.1 0.2-0.5 s",
    ),
    ("kinematics.press_depth_mm", "[A] spec 2.1: 1.5-3 mm"),
    (
        "kinematics.normal_force_n",
        "[A] spec 2.1: 1-3 N; Hertz with R = 20 mm gives E* ~ 0.12 MPa for the skin+gel dome, consistent with a TacTip (no measured force-depth curve found)",
    ),
    (
        "kinematics.lateral_offset_range_mm",
        "[A] mounting of a texture under the arm, drawn once per texture",
    ),
    (
        "kinematics.start_phase_range_mm",
        "[A] one period of the coarsest grid, drawn once per texture",
    ),
    (
        "kinematics.per_slide_offsets",
        "[A] off: a robot arm repeats its path to 0.01 mm (ABB IRB120 RP), so offsets belong to the mounting; on restores independent per-slide offsets to study that confound",
    ),
    (
        "kinematics.position_repeatability_mm",
        "[R] ABB IRB120 product specification: position repeatability RP = 0.01 mm",
    ),
    (
        "kinematics.press_depth_sd_mm",
        "[A] same order as the arm's repeatability (ABB IRB120, RP = 0.01 mm)",
    ),
    (
        "kinematics.onset_jitter_s",
        "[A] assumption: a host-commanded motion start jitters by a few controller cycles: ABB EGM streams at 250 Hz (4 ms) [R, abb-motion-program-exec docs], IRC5 I/O timing is not deterministic (12 ms RAPID base rate) [R, weak]; explore 0.004-0.025 s",
    ),
    (
        "contact.skin_depth_mm",
        "INFORMED BY THE INTENSIVE MEANS: spec 6 chose 1.25 mm inside the 1-1.5 mm bracket because the prototype's 2.5/5 mm count ratio matched the paper's (34.7/9.8); the bracket itself is the 1 mm skin over the pin bases (spec 1.1)",
    ),
    (
        "contact.gap_conformity_mm",
        "CALIBRATED on the 2.5 mm grid (9.84 spikes/taxel)",
    ),
    (
        "contact.foundation_stiffness_n_mm3",
        "[K] RTV27905 gel E ~ 0.03 MPa (5-50 kPa; no datasheet value found) over ~15 mm of gel",
    ),
    (
        "contact.contact_edge_mm",
        "[A] assumption: the width of the contact edge in chi(r) of the 1 mm skin over the gel, about the skin thickness; explore 0.5-1.5 mm (no source)",
    ),
    (
        "contact.lever_mm",
        "CALIBRATED on the 5 mm grid (34.73 spikes/taxel)",
    ),
    ("contact.pin_shear_gain", "[A] spec 2.2: g_pin ~ 0.5"),
    (
        "contact.bulge",
        "[A] assumption: spec 2.2's radial bulge beta in its range 0-0.3 (no source measures a TacTip's radial pin splay per mm of skin deflection); explore 0-0.3",
    ),
    (
        "contact.shear_spread",
        "[A] assumption: spec 2.2, phi(r) = exp(-(r/1.5a)^2): the gel carries the patch's shear to pins outside contact; no source measures a TacTip's shear spread; explore 1-2",
    ),
    (
        "contact.skin_shear_stiffness_n_mm3",
        "[K] Gent (1958) Shore A 28 -> E ~ 1.05 MPa, G = E/3, 1 mm skin (lab manufacturing note)",
    ),
    ("contact.bump_height_mm", "[R] paper: cylinders 1 mm high"),
    (
        "contact.period_rule",
        "no source: the paper says 'spacing' without saying edge-to-edge or centre-to-centre; [A] gap (p = 2d), spec 2.1 and 7; centre_to_centre is the alternative to explore",
    ),
    (
        "contact.tangential_stiffness_n_mm",
        "[A] spec 2.2: 1-3 N/mm; Cattaneo-Mindlin's initial stiffness 8Ga/(2-nu) with the Hertz-consistent G ~ 0.03 MPa gives 1.0-2.5 N/mm (Johnson 1985 ch. 7)",
    ),
    ("contact.slip_time_s", "[A] spec 2.2: 5-20 ms"),
    (
        "contact.slip_inertia_s",
        "[A] assumption: the contact patch's inertia, 1 ms, well below the slip time; it only lets velocity weakening produce stick-slip (acrylic); no source; explore 0.5-5 ms",
    ),
    (
        "contact.adhesion_mu_kinetic",
        "[K] spec 6 prototype; rubber on smooth polymer 0.5-1 (Persson 2001)",
    ),
    (
        "contact.static_excess",
        "CALIBRATED on the flat plate (4.63 spikes/taxel)",
    ),
    (
        "contact.loss_tangent",
        "[K] photopolymer rubbers (Tango/Agilus) tan delta 0.2-0.4; hysteresis friction after Greenwood & Tabor 1958",
    ),
    (
        "contact.micro_slope_rms",
        "[A] 3D-printed polymer micro-roughness; real contact area after Persson 2001",
    ),
    (
        "contact.skin_modulus_mpa",
        "[K] Gent (1958) Shore A 28, nu = 0.5",
    ),
    (
        "contact.microslip_min_mm",
        "[K] slip carried by one Schallamach wave or slip pulse in a soft elastomer contact, 10-100 um (Viswanathan, Mahato & Chandrasekar 2014; Viswanathan et al. 2016 describe the waves, the amplitude is remembered)",
    ),
    ("contact.microslip_max_mm", "[K] as microslip_min_mm"),
    (
        "contact.microslip_time_s",
        "[A] spec 2.2: 2-5 ms reload after a micro-slip; no source",
    ),
    (
        "contact.edge_catches_per_period",
        "[A] assumption: one catch of the skin per row of bumps passing the contact's edge (Schallamach-type stick-slip on an edged surface); no source gives a rate; explore 0-4",
    ),
    (
        "contact.pin_footprint_radius_mm",
        "[R] spec 1.1: pin tip 1.2-1.5 mm diameter (TacTip blob areas); half of 1.5 mm",
    ),
    (
        "contact.partial_slip",
        "[R] a tangentially loaded contact slips from its weakest part inward (Cattaneo-Mindlin, Johnson 1985 7.2; Delhaye, Lefevre & Thonnard 2014 for fingertips); stick zone from the Ciavarella-Jager principle (Ciavarella 1998; Jager 1998)",
    ),
    (
        "contact.stick_area_exponent",
        "[K] Cattaneo-Mindlin (c/a)^2 = (1 - Q/muP)^(2/3) (Johnson 1985 7.2); a fingertip loses its stuck area linearly, exponent 1 [R] (Andre et al., J R Soc Interface 2011)",
    ),
    (
        "contact.friction_day_sd",
        "[A] assumption: elastomer friction varies 5-20 % with humidity and surface state; temperature alone gives 0.2-0.7 %/K (activation energy 25 kJ/mol, Vorvolakos & Chaudhury 2003 [R]); explore 0.02-0.1",
    ),
    (
        "contact.friction_drift_sd",
        "[A] assumption: slow drift over a texture's session, periods of 50-400 slides; the within-session repeatability of skin-textile friction (ICC 0.91-0.94, Temel et al. 2021/2022 [R]) implies 5-6 %; explore 0.01-0.06",
    ),
    (
        "optics",
        "[A] spec 1.2 and 3.1 (disc radius, blur, contrast), v2e lin-log",
    ),
    (
        "pixel.threshold_on",
        "[R] v2e default 0.20 (~22 % contrast). The DAVIS240's published minimum contrast ~11 % (Brandli et al., IEEE JSSC 49(10) 2014 [K]; commercial DVS >= 10 % [R] Graca et al. 2024) is the chip's best with tuned biases: with C = 0.104/0.117 the flat plate makes 6.9 spikes/taxel with no onset snap at all, above the paper's 4.63, so the recording's default-bias thresholds were higher; explore 0.10-0.35",
    ),
    (
        "pixel.threshold_off",
        "[A] spec 3.3: default DAVIS biases make OFF slightly higher (0.25); no published DAVIS240 ON/OFF asymmetry found",
    ),
    (
        "pixel",
        "spec 3.3: v2e defaults (sigma 0.03 [R v2e; DVS128 2.1 %, Lichtsteiner 2008], refractory 0.5 ms, 300 Hz, latency)",
    ),
    (
        "pixel.random_initial_reference",
        "Lichtsteiner et al. (JSSC 2008): a pixel memorises the log intensity of its last event; [A] uniform between the thresholds at a slide's start",
    ),
    (
        "noise",
        "spec 3.3: total background activity 0.1-0.3 Hz per pixel",
    ),
    (
        "solver",
        "numerical settings (neurotac tradeoff simulator); step tolerance C+/3 (ESIM)",
    ),
    (
        "natural.friction",
        "20 natural textures (sensor::sim::NATURAL_TEXTURES): mu_k = adhesion (1.0 [K]) x fraction of area in contact [A] + the material class's ploughing friction measured with a rigid tool (Penn Haptic Texture Toolkit, Culbertson et al. 2014 [R]); mu_s/mu_k 1.2 for fabrics and foam (Temel et al. 2022: 1.14-1.24 [R]), 1.3 for smooth adhesive solids [K]; each specimen drawn with a 20 % spread (Temel 2022: 0.90 +- 0.19 [R])",
    ),
    (
        "natural.roughness",
        "[A] spec 2.4: weave periods and amplitudes from yarn and loop sizes (0.25-6 mm); self-affine roughness with Hurst 0.5-0.8 (Persson 2001 surface spectra); fabric relief measured by profile (Mooneghi et al. 2014 review of fabric surface roughness, KES-FB4 SMD)",
    ),
    (
        "natural.compliance",
        "relief transmitted kappa = E_t/(E_t + E_eff), E_eff = 0.3 MPa: rigid wood, acrylic, metal 1; woven fabrics 0.5-0.8 and knits, felt 0.3-0.5; pile fabrics and PU foam 0.05-0.1 [A] (spec 2.4)",
    ),
    (
        "natural.layer",
        "series compliance: fabrics from Kawabata compression KES-FB3, thickness T0 and compressibility EMC (middle of each fabric class's typical range [K]; E_t = 4.9 kPa / EMC, densifying at EMC); PU foam E ~ 50 kPa from Gibson & Ashby, Cellular Solids 1997 (E*/Es = (rho*/rho_s)^2 [R], 13-110 kPa), 10 mm thick [A]; wood, MDF, acrylic, metal mesh and foil rigid (GPa [K]); layer shear G = E/3 [A]",
    ),
    (
        "natural.microslip_rate",
        "[A] spec 2.4 lambda_ms per texture; no source",
    ),
];
