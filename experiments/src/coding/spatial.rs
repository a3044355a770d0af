//! The spatial coding: the spike count of each taxel over the sample, one number per taxel,
//! compared by Euclidean distance ([`SpatialCoding`]; the paper's "Spatial coding").

use crate::coding::counts::CountCoding;
use neurotac_core::coding::SpatialCoding;

/// The spatial coding (module docs). Its readout: one count per channel per sample.
pub const SPATIAL: CountCoding<SpatialCoding> = CountCoding {
    key: "spatial",
    label: "Spatial",
    new: SpatialCoding::new,
    per_channel: true,
};
