//! [`one_spike_weight`]: the synaptic weight at which one input spike makes a neuron fire.
//!
//! **Units of a weight.** A projection's weight is the jump of its synaptic current per
//! presynaptic spike, in the target model's input units: the current then decays as
//! `w·e^{−t/τ_syn}` and is added to the model's input `I` each step. For LIF, `I` is in
//! potential units (`v∞ = v_rest + I`, threshold 1 by default); for Izhikevich, in mV/ms. How
//! large a weight must be to matter therefore depends on the model, its parameters, τ_syn and
//! dt — which is what this helper measures instead of leaving it to trial and error.

use super::{Connectivity, ExpSynapse, NetworkBuilder, NetworkConfig, SpikeArrayInput};
use crate::error::GraphError;
use crate::model::NeuronModel;
use crate::spikes::MultiSpikeTrain;

/// The smallest weight (within a relative `1e-6`) at which one lone spike through `synapse`
/// makes a resting neuron of `model()` (one neuron) fire at least once, at step `dt_s`.
///
/// Found by doubling from 1 until the neuron fires, then bisection; each trial runs a fresh
/// network for `10·τ_syn + 0.2 s` after the spike. A weight a little above the result (the
/// afferents of `neurotac_experiments::afferents` use 1.25×) gives one spike per lone input
/// spike with a margin for dt; far above it, one input spike can make several.
///
/// Errors: a model that is not one neuron, one that fires with no input, or one that does not
/// fire below a weight of 2⁴⁰ ([`GraphError::InvalidParameter`]).
pub fn one_spike_weight<M: NeuronModel + 'static>(
    model: impl Fn() -> M,
    synapse: ExpSynapse,
    dt_s: f64,
) -> Result<f64, GraphError> {
    let size = model().len();
    if size != 1 {
        return Err(GraphError::SizeMismatch {
            what: "one_spike_weight model (one neuron)".into(),
            expected: 1,
            got: size,
        });
    }
    let t_spike = 0.01;
    let duration = t_spike + f64::from(synapse.delay_steps) * dt_s + 10.0 * synapse.tau_s + 0.2;
    let spikes = |weight: f64| -> Result<usize, GraphError> {
        let mut b = NetworkBuilder::new();
        let input = b.add_spike_input(
            "spike",
            SpikeArrayInput::new(
                MultiSpikeTrain::from_channels(vec![vec![t_spike]])
                    .expect("one finite spike time is a valid train"),
            ),
        )?;
        let neuron = b.add_population("neuron", model())?;
        b.connect(input, neuron, Connectivity::OneToOne { weight }, synapse)?;
        let recorder = b.record_spikes(neuron)?;
        let mut net = b.build(NetworkConfig { dt_s })?;
        net.run(duration, &crate::OneProcess)?;
        Ok(net.readout(recorder)?.spikes().len())
    };
    if spikes(0.0)? > 0 {
        return Err(GraphError::InvalidParameter {
            what: "one_spike_weight model".into(),
            value: 0.0,
            expected: "a neuron that stays silent without input",
        });
    }
    let (mut low, mut high) = (0.0, 1.0);
    while spikes(high)? == 0 {
        low = high;
        high *= 2.0;
        if high > 2f64.powi(40) {
            return Err(GraphError::InvalidParameter {
                what: "one_spike_weight search".into(),
                value: high,
                expected: "a neuron that fires for some weight below 2⁴⁰",
            });
        }
    }
    while high - low > 1e-6 * high {
        let mid = 0.5 * (low + high);
        if spikes(mid)? > 0 {
            high = mid;
        } else {
            low = mid;
        }
    }
    Ok(high)
}
