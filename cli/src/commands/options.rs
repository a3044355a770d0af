//! The option groups several commands share.

use clap::ValueEnum;
use neurotac_experiments::datasets::simulated::TextureSet;

/// The values of `--set`: which simulated texture set(s).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SetArg {
    /// The 11 bump grids (paper: 100 slides each; Table 1).
    Artificial,
    /// The 20 natural textures (paper: 50 slides each; Table 2).
    Natural,
    /// Both, artificial first.
    Both,
}

impl SetArg {
    /// The sets, in run order.
    pub fn sets(self) -> Vec<TextureSet> {
        match self {
            SetArg::Artificial => vec![TextureSet::Artificial],
            SetArg::Natural => vec![TextureSet::Natural],
            SetArg::Both => vec![TextureSet::Artificial, TextureSet::Natural],
        }
    }
}
