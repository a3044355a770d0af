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
        "[K] ABB IRB 120 product specification: maximum TCP acceleration 28 m/s^2; [R] the paper's five durations show no ramp: fitting T = 65/v + c + k.v gives k = 0.0003 +- 0.0004 s^2/mm, and two moves add k = 2/a, so a >= 1.7 m/s^2 (2 sd); the earlier 300 mm/s^2 [A] is excluded",
    ),
    (
        "kinematics.press_travel_mm",
        "[R] the lab's slide script (neuromorphic-data-gathering, ABB_slides.py: tap_move z = 5 mm at the linear speed, inside the recording); [R] the paper's durations fit T = 64.93 mm/v + 0.193 s: the 60 mm slide and one 5 mm move",
    ),
    (
        "kinematics.press_depth_mm",
        "[A] spec 2.1: 1.5-3 mm; now the depth of the press's end below the set's base surface (position control), so the dome starts press_travel - press_depth = 3 mm above it; explore 1-4 mm",
    ),
    (
        "kinematics.normal_force_n",
        "[A] spec 2.1: 1-3 N at press_depth_mm on a rigid plate; Hertz with R = 20 mm gives E* ~ 0.12 MPa for the skin+gel dome, consistent with a TacTip (no measured force-depth curve found)",
    ),
    (
        "kinematics.dwell_s",
        "[R] the lab's slide script: time.sleep(0.1) between the press and the slide; the paper's durations leave 0.193 s beside the moves (one dwell and the loop's latencies)",
    ),
    (
        "kinematics.loop_overhead_s",
        "[R] derived: the paper's five sample durations (source text, Results) less the 65 mm of moves at v with their ramps (2v/a) and the 0.1 s dwell: 0.0855 s, split equally over the loop's 8 blocking steps [A] (counted in ABB_slides.py: 2 frame commands and a pose query, 2 MoveL starts, 2 fine points with their replies, the logging thread's last batch)",
    ),
    (
        "kinematics.loop_jitter_s",
        "[R] derived: standard deviation of the paper's five durations about that law (4 degrees of freedom, so uncertain by about 2x): 6.4 ms; independent steps [A], so the slide onset (6 of 8 steps after the recording's zero) spreads by 5.5 ms",
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
        "kinematics.mounting",
        "a selector, not a physical value: 0 = the rig's own mounting of every texture, k > 0 = another draw of the mountings (lateral offset, phase, specimen friction, friction day and drift) with the same camera",
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
    (
        "contact.pin_shear_gain",
        "CALIBRATED on the flat plate (4.63 spikes/taxel): the onset's size on the pins; spec 2.2 g_pin ~ 0.5 [A]",
    ),
    (
        "contact.bulge",
        "[A] assumption: spec 2.2's radial bulge beta in its range 0-0.3 (no source measures a TacTip's radial pin splay per mm of skin deflection); explore 0-0.3",
    ),
    (
        "contact.fabric_mount_span_mm",
        "[A] assumption: a fabric specimen taped along its edges to the base plate, its tape 30 mm beyond the contact's edge (a 70-80 mm coupon); nothing says how the lab mounted its fabrics; explore 10-60 mm (the drag stiffness scales as 1/span)",
    ),
    (
        "contact.fabric_base_friction",
        "[K] fabric on a smooth polymer plate, mu ~ 0.2-0.4 (textile-on-plastic friction, Das, Kothari & Vandana, AUTEX Res. J. 2005: fabric-to-metal 0.2-0.35 [R abstract]); explore 0.2-0.6",
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
        "[K] mu_s/mu_k = 1.3 for a smooth adhesive solid, the prior the natural catalogue gives acrylic and foil (a printed plate is one); calibrated on the flat plate before the press and the gel's traction profile were simulated, but even 0 then leaves the flat plate at 5.6-6.3 spikes/taxel, above the paper's 4.63, so the flat plate now calibrates contact.pin_shear_gain",
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
        "[A] assumption: one catch of the skin per row of bumps passing the contact's edge (Schallamach-type stick-slip on an edged surface); no source gives a rate; explore 0-4. Each catch's slip scales with how deep the skin sinks into the gaps (its deepest sag over the bump height): a ridge engages the skin only when the skin reaches below its top (ridge-height threshold for skin friction on ridged surfaces: Darden & Schwartz, Wear 2013 [K], not re-read)",
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
        "[R] v2e defaults (spec 3.3): threshold mismatch sigma 0.03 (DVS128: 2.1 %, Lichtsteiner 2008 [K]), refractory 0.5 ms, photoreceptor bandwidth 300 Hz; [A] latency 15 us + exponential jitter of mean 30 us (spec 3.2: 10-50 us)",
    ),
    (
        "pixel.random_initial_reference",
        "Lichtsteiner et al. (JSSC 2008): a pixel memorises the log intensity of its last event; [A] uniform between the thresholds at a slide's start",
    ),
    (
        "noise",
        "[A] spec 3.3: total background activity 0.1-0.3 Hz per pixel (v2e's leak and shot noise model [R]; DVS128 background activity ~0.1 Hz at room temperature [K])",
    ),
    (
        "solver",
        "numerical settings, not physical values (the speed/accuracy knobs `neurotac tradeoff` studies); step tolerance C+/3 [R] (ESIM's adaptive sampling)",
    ),
    (
        "natural.friction",
        "20 natural textures (sensor::sim::NATURAL_TEXTURES): mu_k = adhesion (1.0 [K]) x fraction of area in contact [A] + the material class's ploughing friction measured with a rigid tool (Penn Haptic Texture Toolkit, Culbertson et al. 2014 [R]); mu_s/mu_k 1.2 for fabrics and foam (Temel et al. 2022: 1.14-1.24 [R]), 1.3 for smooth adhesive solids [K]; each specimen drawn with its class's spread (natural.friction_spread)",
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
        "series compliance: fabrics from Kawabata compression KES-FB3, thickness T0, compressibility EMC and resilience RC (middle of each fabric class's typical range [K]; E_t = 4.9 kPa / EMC, densifying at EMC, loss tangent (1 - RC)/(2 pi)); PU foam E ~ 50 kPa from Gibson & Ashby, Cellular Solids 1997 (E*/Es = (rho*/rho_s)^2 [R], 13-110 kPa), 10 mm thick [A], loss tangent 0.15 (flexible PU foam 0.1-0.2 at 1-10 Hz [K]); wood, MDF, acrylic, metal mesh and foil rigid (GPa [K]); layer shear G = E/3 [A]; a specimen's surface stands T0 above the base plate (position control)",
    ),
    (
        "natural.fabric",
        "KES-FB1 tensile strain EMT at 500 gf/cm and shear rigidity G, KES-FB2 bending rigidity B per fabric class (middle of the typical ranges of Kawabata's hand-evaluation data [K], not re-read): wovens EMT 3-5 %, G 0.4-3 gf/(cm.deg), B 0.03-0.4 gf.cm2/cm; knits and nets EMT 15-30 %, G 0.2-0.5; felt G 4, B 1; pile fabrics B 0.2-1; no source separates fabrics of one class",
    ),
    (
        "natural.pile",
        "hairs standing proud of pile and hairy fabrics: length beyond the fabric's surface (wool knit 1.5 mm, tweed 1 mm, felt 0.5 mm, needlecord 0.3 mm, fleece 1 mm, fake fur guard hairs 3 mm) [A]; fibre diameters wool 25 um, acrylic fur 40 um, fleece PET 15 um, cotton 15 um [K]; moduli wool and acrylic 3 GPa, PET 4 GPa, cotton 8 GPa [K]; densities 2-30 hairs/mm^2 [A] (no source measures hairiness per area for these fabrics); Euler buckling of a clamped-free hair",
    ),
    (
        "natural.friction_spread",
        "relative spread of each specimen's friction: cotton fabrics 21 % [R] (Temel, Johnson & Lloyd, Tribol. Lett. 70, 2022: cotton on skin 0.90 +- 0.19, between body sites, used as a proxy); smooth adhesive solids (acrylic, foil, metal mesh) 25 % [K] (adhesion friction of elastomers on smooth surfaces varies widely with surface state: Derler & Gerhardt, Tribol. Lett. 2012 review, not re-read); wood and MDF 15 % [A]; every other class 20 % [A] (Temel's cotton as a proxy); Kim et al. (Wear 2013), named for per-fabric spreads, could not be read here",
    ),
    (
        "natural.microslip_rate",
        "[A] spec 2.4 lambda_ms per texture; no source",
    ),
];
