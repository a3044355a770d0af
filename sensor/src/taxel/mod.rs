//! Taxels: the 49 receptive fields of the NeuroTac's pins, and turning pixel events into taxel
//! spikes ([`Transducer`], a whole input with [`Transducer::transduce_reader`]; stages
//! [`ReceptiveFieldMask`] and [`TaxelPooling`]; re-centring [`PositionUpdate`]; layouts
//! [`TaxelLayout`]).

mod fields;
mod lattice;
mod layout;
mod pooling;
mod transducer;

pub use fields::{ReceptiveFieldMask, ReceptiveFields, TaxelPixelEvent};
pub use layout::{LayoutDetection, TaxelLayout};
pub use pooling::{PositionUpdate, TaxelEvent, TaxelPooling};
pub use transducer::{ReaderTransduction, Transducer, TransductionConfig, TransductionCounts};
