//! The numbers the NeuroTac paper reports (Ward-Cherrier, Pestell & Lepora, ICRA 2020), to
//! print next to a reproduction.

/// One of the paper's tables: leave-one-out accuracy (%) of the four codings, in the order of
/// [`crate::coding::CodingName::ALL`].
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
