//! [`ExpSynapse`]: the parameters of a projection's exponential current synapses (time
//! constant and delay; the equations are in the [synapse module docs](super)).

/// Exponential current synapse parameters shared by all synapses of a projection: each
/// presynaptic spike adds its weight `w` to the synaptic current, which decays as
/// `I(t) = w·e^{−t/τ_syn}` and enters the target model's input (weights are in the model's input
/// units; [`one_spike_weight`](crate::graph::one_spike_weight) finds the weight at which one spike makes
/// a neuron fire).
///
/// **Delay rule:** `delay_steps ≥ 1` from a population, `≥ 0` from a spike input.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExpSynapse {
    /// Decay time constant τ_syn in seconds (> 0).
    pub tau_s: f64,
    /// Transmission delay in whole steps. 0 is allowed from input nodes only; from a
    /// population it must be ≥ 1, since a population's spikes of step k exist only after its
    /// own integration in step k (the delay rule, checked by
    /// [`NetworkBuilder::connect`](crate::graph::NetworkBuilder::connect)).
    pub delay_steps: u32,
}

impl ExpSynapse {
    /// A synapse with time constant `tau_s` and a one-step delay.
    pub fn new(tau_s: f64) -> Self {
        Self {
            tau_s,
            delay_steps: 1,
        }
    }

    /// The same synapse with another delay.
    pub fn with_delay(self, delay_steps: u32) -> Self {
        Self {
            delay_steps,
            ..self
        }
    }
}
