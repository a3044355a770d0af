//! The two bundled texture sets ([`TextureSet`]): the artificial bump grids and the natural
//! textures of the paper.

use neurotac_sensor::sim::{GRID_SIZES_MM, NATURAL_TEXTURES, Texture};
use serde::{Deserialize, Serialize};

/// Which texture set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TextureSet {
    /// 11 bump grids, d = 0 … 5 mm in 0.5 mm steps (paper: 100 slides each).
    Artificial,
    /// The 20 natural textures of the paper's Table II (paper: 50 slides each).
    Natural,
}

impl TextureSet {
    /// The textures, in class order.
    pub fn textures(self) -> Vec<Texture> {
        match self {
            TextureSet::Artificial => GRID_SIZES_MM
                .iter()
                .map(|&d| Texture::Grid { size_mm: d })
                .collect(),
            TextureSet::Natural => NATURAL_TEXTURES.iter().map(Texture::Natural).collect(),
        }
    }

    /// Class names (index = label).
    pub fn class_names(self) -> Vec<String> {
        self.textures().iter().map(Texture::name).collect()
    }

    /// Slides per texture in the paper.
    pub fn paper_trials(self) -> usize {
        match self {
            TextureSet::Artificial => 100,
            TextureSet::Natural => 50,
        }
    }

    /// `artificial` or `natural`.
    pub fn name(self) -> &'static str {
        match self {
            TextureSet::Artificial => "artificial",
            TextureSet::Natural => "natural",
        }
    }

    pub(crate) fn id(self) -> u64 {
        match self {
            TextureSet::Artificial => 1,
            TextureSet::Natural => 2,
        }
    }
}
