//! The intensive coding: the mean spike count per taxel over the sample, one number, compared
//! by Euclidean distance ([`IntensiveCoding`]; the paper's "Intensive coding").

use crate::coding::counts::CountCoding;
use neurotac_core::coding::IntensiveCoding;

/// The intensive coding (module docs). Its readout: one number per sample.
pub const INTENSIVE: CountCoding<IntensiveCoding> = CountCoding {
    key: "intensive",
    label: "Intensive",
    new: IntensiveCoding::new,
    per_channel: false,
};
