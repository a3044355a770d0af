//! Projections: connectivity plus exponential current synapses.
//!
//! Each projection keeps one synaptic current per target neuron,
//!
//! ```text
//! τ_syn · dI/dt = −I        between spikes (advanced exactly: I ← I·e^(−dt/τ_syn))
//! I ← I + w                 when a presynaptic spike arrives (delay d steps after emission)
//! ```
//!
//! and the target population receives the sum of its projections' currents at the start of the
//! step, held constant over the step. Currents below 10⁻³⁰ in magnitude are flushed to zero so a long silence never
//! leaves subnormal numbers in the loop (they are 10–100× slower on x86).

mod connectivity;
mod exp;
mod projection;
mod stdp;
mod weights;

pub(crate) use connectivity::Wiring;
pub use connectivity::{Connectivity, Synapse};
pub use exp::ExpSynapse;
pub(crate) use projection::RunningProjection;
pub(crate) use stdp::Plasticity;
pub use stdp::{Stdp, TraceInteraction, WeightDependence};
pub use weights::Weights;
