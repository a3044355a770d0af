//! The one-page summary of every speed ↔ accuracy trade (`neurotac tradeoff` without a
//! subcommand): per trade, what is traded, the Pareto front, links to the trade's own files and
//! how to choose.

use super::neurons::{self, NeuronTradeoffRow};
use super::simulator::{self, SimulatorTradeoffConfig, SimulatorTradeoffRow};
use super::vr::{self, VrTradeoff};
use std::fmt::Write;

/// Sub-folder (relative to the summary) holding the neuron trade's `neurons.{csv,md,svg}`.
pub const NEURONS_DIR: &str = "neurons";
/// Sub-folder holding the Van Rossum trade's `vr.{csv,md,svg}`.
pub const VR_DIR: &str = "vr";
/// Sub-folder holding the simulator trade's `simulator.{csv,md,svg}`.
pub const SIMULATOR_DIR: &str = "simulator";

fn links(dir: &str, stem: &str) -> String {
    format!(
        "Data: [{stem}.csv]({dir}/{stem}.csv) · plot: [{stem}.svg]({dir}/{stem}.svg) · full table: [{stem}.md]({dir}/{stem}.md)\n\n"
    )
}

/// The summary page. `header` is a line placed under the title (how and when it was made).
pub fn summary_markdown(
    header: &str,
    neurons: &[NeuronTradeoffRow],
    vr: &VrTradeoff,
    simulator: &[SimulatorTradeoffRow],
    simulator_config: &SimulatorTradeoffConfig,
) -> String {
    let mut s = String::from("# Speed ↔ accuracy trade-offs\n\n");
    let _ = writeln!(s, "{header}\n");
    s.push_str("Each table is a Pareto front: the settings no other measured setting beats on both speed and accuracy. Anything off the front is a setting to avoid; along the front, buying accuracy costs speed.\n\n");

    s.push_str("## Neuron simulation\n\n");
    s.push_str("Traded: model × integrator × time step dt × precision (f32/f64) × spike-time stamping (grid or interpolated), for neuron updates per second (one thread) against the mean spike-time error to a known truth (LIF closed form; Izhikevich by RK4 at 1 µs). Only points with the right spike count compete.\n\n");
    s.push_str(&neurons::pareto_table(neurons));
    s.push('\n');
    s.push_str(&links(NEURONS_DIR, "neurons"));
    s.push_str("How to choose: read the front of your model from the top and stop at the first row whose mean error is below your timing budget (e.g. well under the 1 ms bins of the codings); interpolated stamping is nearly free and usually buys more accuracy than a smaller dt.\n\n");

    s.push_str("## Van Rossum distance: exact vs synaptic traces\n\n");
    let _ = write!(
        s,
        "Traded: the step at which a network samples its synaptic traces (and their precision, f64/f32), for the time of the {n} × {n} distance matrix against leave-one-out KNN accuracy (k = {k}, τ = {tau} s, cos θ = {cos}); the exact (Markage) distance competes too.\n\n",
        n = vr.samples,
        k = vr.k,
        tau = vr.tau_s,
        cos = vr.cos
    );
    s.push_str(&vr::pareto_table(vr));
    s.push('\n');
    s.push_str(&links(VR_DIR, "vr"));
    s.push_str("How to choose: to classify offline, take the fastest row on the front; the trace distance is what an on-line network computes (`reproduce --vr-from traces`), and its accuracy at your trace step is in the table.\n\n");

    s.push_str("## Simulator step tolerance\n\n");
    let _ = write!(
        s,
        "Traded: the pixel model's step tolerance (largest change of log intensity per step), for simulated trials per second (one thread) against the timing error of pin events relative to a fine-step run (tolerance {}; flat plate and 5 mm grid, {} slides each).\n\n",
        simulator_config.reference_tolerance, simulator_config.trials
    );
    s.push_str(&simulator::pareto_table(simulator));
    s.push('\n');
    s.push_str(&links(SIMULATOR_DIR, "simulator"));
    s.push_str("How to choose: taxel spikes pool events over 20 ms windows, so a mean timing error of a few hundred µs is invisible downstream: take the fastest tolerance on the front whose mean error stays well below the pooling window and whose count error is small.\n");
    s
}
