//! The numbers the NeuroTac paper reports (Ward-Cherrier, Pestell & Lepora, ICRA 2020), to
//! print next to a reproduction: its accuracy tables, chosen parameters and intensive means, and
//! the confusions its discussion names.

use crate::coding::CodingName;
use serde::Serialize;

/// The paper's four codings, in the order of its tables (every `[_; 4]` below is in this order).
pub const CODINGS: [CodingName; 4] = [
    CodingName::Intensive,
    CodingName::Spatial,
    CodingName::Temporal,
    CodingName::Spatiotemporal,
];

/// One of the paper's tables: leave-one-out accuracy (%) of the four codings, in the order of
/// [`CODINGS`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperTable {
    /// `Table 1` or `Table 2`.
    pub table: &'static str,
    /// Which texture set.
    pub set: &'static str,
    /// Accuracy (%) per coding.
    pub accuracy_percent: [f64; 4],
    /// The ± the table gives (%), if any.
    pub std_percent: Option<[f64; 4]>,
}

/// Table 1: the 11 artificial textures (bump grids 0–5 mm), 100 slides each.
pub const ARTIFICIAL: PaperTable = PaperTable {
    table: "Table 1",
    set: "artificial",
    accuracy_percent: [78.5, 95.5, 98.1, 98.3],
    std_percent: Some([41.1, 20.6, 13.7, 13.0]),
};

/// Table 2: the 20 natural textures, 50 slides each.
pub const NATURAL: PaperTable = PaperTable {
    table: "Table 2",
    set: "natural",
    accuracy_percent: [69.8, 85.5, 93.0, 92.8],
    std_percent: None,
};

/// The temporal coding's window chosen by the paper's Δt sweep (artificial set), ms.
pub const DT_MS: f64 = 159.0;
/// The Van Rossum τ the paper's optimisation converged to (artificial set), ms.
pub const TAU_MS: f64 = 76.0;
/// The cos θ the paper's optimisation converged to (artificial set).
pub const COS_THETA: f64 = 0.4;

/// Mean spikes per taxel of the intensive coding for the 0, 2.5 and 5 mm grids (the paper's
/// spike-train figure): `(grid size mm, mean)`.
pub const INTENSIVE_MEANS: [(f64, f64); 3] = [(0.0, 4.63), (2.5, 9.84), (5.0, 34.73)];

/// The paper's table for a set name (`artificial` or `natural`).
pub fn table_for(set: &str) -> Option<&'static PaperTable> {
    match set {
        "artificial" => Some(&ARTIFICIAL),
        "natural" => Some(&NATURAL),
        _ => None,
    }
}

/// The class name of the simulated bump grid of `mm` (`grid 2.5 mm`), as the intensive means
/// above are looked up.
pub fn grid_name(mm: f64) -> String {
    format!("grid {mm:.1} mm")
}

/// The grid size (mm) a class name of [`grid_name`]'s form names (`grid 2.5 mm` → 2.5);
/// `None` for any other name.
pub fn grid_size_mm(class_name: &str) -> Option<f64> {
    class_name
        .strip_prefix("grid ")?
        .strip_suffix(" mm")?
        .parse()
        .ok()
}

/// A confusion between natural textures that the paper names (its natural-texture
/// discussion, Fig. 6), by the simulator's texture names.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NamedConfusion {
    /// The true texture.
    pub truth: &'static str,
    /// The texture it is predicted as.
    pub predicted: &'static str,
    /// The two textures' numbers in the paper's table of natural textures (`(6, 17)`).
    pub paper_numbers: (u32, u32),
    /// `true` when the paper says the two are confused with each other (`↔`), `false` for one
    /// way only (`→`).
    pub mutual: bool,
    /// Per coding ([`CODINGS`] order): whether the paper sees the
    /// confusion (`false`: it says the coding tells them apart).
    pub confused_under: [bool; 4],
    /// The paper's sentence.
    pub quote: &'static str,
}

impl NamedConfusion {
    /// `fake fur ↔ felt (6 ↔ 17)`, `liquid satin → foam (7 → 1)`.
    pub fn label(&self) -> String {
        let arrow = if self.mutual { "↔" } else { "→" };
        let (a, b) = self.paper_numbers;
        format!(
            "{} {arrow} {} ({a} {arrow} {b})",
            self.truth, self.predicted
        )
    }
}

/// The confusions the paper names on the natural set.
pub const NAMED_CONFUSIONS: [NamedConfusion; 2] = [
    NamedConfusion {
        truth: "fake fur",
        predicted: "felt",
        paper_numbers: (6, 17),
        mutual: true,
        confused_under: [true, true, false, false],
        quote: "for Intensive and Spatial coding, fake fur and felt (textures 6 and 17) are \
                confused, whereas Temporal and Spatiotemporal coding can distinguish them",
    },
    NamedConfusion {
        truth: "liquid satin",
        predicted: "foam",
        paper_numbers: (7, 1),
        mutual: false,
        confused_under: [false, false, false, true],
        quote: "liquid satin (texture 7) is misclassified as foam (texture 1) only when \
                Spatiotemporal coding is applied",
    },
];

/// Where the paper sees one coding's errors on the artificial set (its Fig. 5 discussion).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GridErrors {
    /// The grid sizes (mm, inclusive) the paper says the coding's errors concentrate on;
    /// `None` when it calls the coding near-perfect.
    pub concentrated_on_mm: Option<(f64, f64)>,
    /// The paper's words.
    pub quote: &'static str,
}

/// The paper on each coding's errors on the artificial set, in
/// [`CODINGS`] order.
pub const GRID_ERRORS: [GridErrors; 4] = [
    GridErrors {
        concentrated_on_mm: Some((0.0, 2.0)),
        quote: "the least effective, particularly for the smoother textures (0–2 mm)",
    },
    GridErrors {
        concentrated_on_mm: Some((0.0, 1.5)),
        quote: "more accurate, though still some slight inaccuracy for smoother textures \
                (0–1.5 mm)",
    },
    GridErrors {
        concentrated_on_mm: None,
        quote: "near-perfect",
    },
    GridErrors {
        concentrated_on_mm: None,
        quote: "near-perfect",
    },
];

/// The paper on where the artificial set's errors fall, for every coding.
pub const NEIGHBOURING_ERRORS_QUOTE: &str =
    "classification errors occur most often between neighbouring classes";
