"""NIR graphs built the way snnTorch, Norse and Sinabs export their layers (their node
conventions: ``r``, ``v_leak``, ``w_in``, no or zero ``v_reset``, zero-bias ``Affine``), imported
and run next to the same neurons computed by hand with the mapping's equations
(``neurotac.nir``'s docstring); what cannot match exactly refused in one line."""

import math
import warnings

import numpy as np
import pytest

nir = pytest.importorskip("nir")

from neurotac.nir import NirError, from_nir, graph_to_description, to_nir


def chain(neuron, weight, bias=None, n_in=None):
    """Input → Affine (or Linear) → ``neuron`` → Output."""
    weight = np.atleast_2d(np.asarray(weight, dtype=float))
    n_out, n_in = weight.shape
    linear = nir.Linear(weight=weight) if bias is None else nir.Affine(weight=weight, bias=np.asarray(bias, dtype=float))
    return nir.NIRGraph(
        nodes={
            "input": nir.Input(input_type=np.array([n_in])),
            "fc": linear,
            "neuron": neuron,
            "output": nir.Output(output_type=np.array([n_out])),
        },
        edges=[("input", "fc"), ("fc", "neuron"), ("neuron", "output")],
    )


def spike_steps(net, name, dt_s):
    times, neurons = net.spikes(name)
    return list(zip(np.rint(times / dt_s).astype(int).tolist(), neurons.tolist()))


def run_steps(net, steps_per_channel, dt_s, duration_steps):
    net.run(duration_steps * dt_s, inputs={"input": [np.array(s, dtype=float) * dt_s for s in steps_per_channel]})


def test_snntorch_leaky_runs_as_snntorch_computes_it_with_step_spikes_and_euler():
    # snnTorch's export of Leaky(beta): tau = dt/(1 − β), r = tau/dt, v_leak = 0; dt = 1e-4.
    dt, beta, w = 1e-4, 0.8, np.array([[0.35, 0.5]])
    tau = dt / (1 - beta)
    neuron = nir.LIF(tau=np.full(1, tau), r=np.full(1, tau / dt), v_leak=np.zeros(1), v_threshold=np.ones(1))
    inputs = [[3, 4, 5, 9, 10, 30], [4, 12, 13, 14, 31, 32]]
    net = from_nir(chain(neuron, w, bias=np.zeros(1)), dt_s=dt, input_spikes="step", integrator="euler")
    run_steps(net, inputs, dt, 60)
    mem, expected = 0.0, []
    for k in range(60):
        mem = beta * mem + sum(w[0, c] * (k in inputs[c]) for c in range(2))
        if mem >= 1.0:
            expected.append((k + 1, 0))
            mem = 0.0
    assert len(expected) >= 3
    assert spike_steps(net, "neuron", dt) == expected


def test_a_lif_fed_without_a_synapse_jumps_by_r_w_over_tau_and_decays_exactly():
    # Norse's LIFBoxCell export: r = 1, v_leak and v_reset as set; dirac spikes, exact step:
    # v_{k+1} = v_leak + (v_k − v_leak)·e^(−dt/τ) + W·r/τ.
    dt, tau, w = 1e-4, 0.02, 0.009
    neuron = nir.LIF(tau=np.full(2, tau), r=np.ones(2), v_leak=np.full(2, 0.1), v_threshold=np.ones(2),
                     v_reset=np.full(2, -0.2))
    inputs = [[1, 2, 3, 4, 40, 41, 42], [10, 11, 12, 13, 14, 15]]
    net = from_nir(chain(neuron, np.diag([w, 1.5 * w])), dt_s=dt)
    run_steps(net, inputs, dt, 80)
    decay = math.exp(-dt / tau)
    v, expected = [0.1, 0.1], []
    for k in range(80):
        for i in range(2):
            jump = (w if i == 0 else 1.5 * w) / tau * (k in inputs[i])
            v[i] = 0.1 + (v[i] - 0.1) * decay + jump
            if v[i] >= 1.0:
                expected.append((k + 1, i))
                v[i] = -0.2
    assert len(expected) >= 2
    assert spike_steps(net, "neuron", dt) == expected
    # The mapping's parameters: a one-step synapse and the weight over the step's gain.
    d = graph_to_description(chain(neuron, np.diag([w, 1.5 * w])), dt_s=dt)
    (p,) = d["projections"]
    assert math.exp(-dt / p["tau_s"]) == 0.0
    assert p["wiring"]["sparse"]["weight"][0] == pytest.approx(w / tau / -math.expm1(-dt / tau))


def test_sinabs_iaf_adds_each_weight_to_the_membrane_and_resets_to_zero():
    # Sinabs' export of IAF: IF with r = 1 and v_threshold, no v_reset (NIR's default 0), a
    # zero-bias Affine; a spike through W moves v by W.
    dt = 1e-3
    neuron = nir.IF(r=np.ones(2), v_threshold=np.array([1.0, 2.0]))
    w = np.array([[0.3, 0.5], [0.7, 0.2]])
    inputs = [[2, 5, 9, 14, 15, 18], [3, 9, 11, 12, 17, 18]]
    graph = chain(neuron, w, bias=np.zeros(2))
    net = from_nir(graph, dt_s=dt)
    run_steps(net, inputs, dt, 25)
    v, expected = [0.0, 0.0], []
    for k in range(25):
        for i in range(2):
            v[i] += sum(w[i, c] * (k in inputs[c]) for c in range(2))
            if v[i] >= [1.0, 2.0][i]:
                expected.append((k + 1, i))
                v[i] = 0.0
    assert len(expected) >= 4
    assert spike_steps(net, "neuron", dt) == expected
    # Per-neuron thresholds with v_reset = 0: each neuron's potential in units of its threshold.
    (population,) = [n for n in graph_to_description(graph, dt_s=dt)["nodes"] if n["kind"] == "population"]
    assert population["model"]["model"] == "if"
    assert population["model"]["settings"]["params"]["v_th"] == 1.0


def test_an_affine_bias_into_a_neuron_without_synapse_is_a_constant_current():
    # τ·v̇ = (0 − v) + R·b: from 0, v reaches 1 at t = τ·ln(R·b/(R·b − 1)); exact steps on the grid.
    dt, tau, b = 1e-4, 0.01, 1.5
    neuron = nir.LIF(tau=np.full(1, tau), r=np.ones(1), v_leak=np.zeros(1), v_threshold=np.ones(1))
    net = from_nir(chain(neuron, [[0.0]], bias=[b]), dt_s=dt)
    net.run(0.05)
    times, _ = net.spikes("neuron")
    period = tau * math.log(b / (b - 1))
    assert len(times) == int(0.05 / period)
    assert abs(times[0] - period) <= dt


def test_scale_nodes_multiply_the_weights_and_a_cubalif_reads_w_in_and_r():
    # Norse's CubaLIF export (r = w_in = 1) behind a Scale: w = W·s·R·w_in/τ_syn.
    graph = chain(nir.CubaLIF(tau_syn=np.full(2, 0.005), tau_mem=np.full(2, 0.01), r=np.ones(2),
                              v_leak=np.zeros(2), v_threshold=np.ones(2), w_in=np.array([1.0, 2.0])),
                  np.eye(2))
    graph.nodes["scale"] = nir.Scale(scale=np.array([3.0, 0.5]))
    graph.edges = [("input", "scale"), ("scale", "fc"), ("fc", "neuron"), ("neuron", "output")]
    (p,) = graph_to_description(graph, dt_s=1e-4)["projections"]
    assert p["wiring"]["sparse"]["weight"] == pytest.approx([3.0 / 0.005, 0.5 * 2.0 / 0.005])
    # The same scales after the Linear scale its rows (post), not its columns (pre).
    graph.edges = [("input", "fc"), ("fc", "scale"), ("scale", "neuron"), ("neuron", "output")]
    (p,) = graph_to_description(graph, dt_s=1e-4)["projections"]
    assert p["wiring"]["sparse"]["weight"] == pytest.approx([3.0 / 0.005, 0.5 * 2.0 / 0.005])


def test_what_cannot_match_exactly_is_refused_in_one_line_naming_the_node():
    lif = dict(tau=np.array([0.01, 0.02]), r=np.ones(2), v_leak=np.zeros(2), v_threshold=np.ones(2))
    cases = [
        (chain(nir.LIF(**lif), np.eye(2)), "NIR node 'neuron' (LIF): tau differs between neurons"),
        (chain(nir.LIF(**{**lif, "tau": np.full(2, 0.01), "v_threshold": np.array([1.0, 2.0]),
                          "v_reset": np.array([0.5, 0.5])}), np.eye(2)),
         "NIR node 'neuron' (LIF): v_threshold differs between neurons (1.0 to 2.0) and v_reset and v_leak do not scale"),
        (chain(nir.CubaLIF(tau_syn=np.full(2, 0.005), tau_mem=np.full(2, 0.01), r=np.ones(2),
                           v_leak=np.zeros(2), v_threshold=np.ones(2)), np.eye(2), bias=[1.0, 0.0]),
         "NIR node 'fc' (Affine): a bias into a synapse"),
    ]
    for graph, expected in cases:
        with pytest.raises(NirError) as e:
            graph_to_description(graph, dt_s=1e-4)
        assert str(e.value).startswith(expected), str(e.value)
        assert "\n" not in str(e.value) and isinstance(e.value, ValueError)


def test_a_time_step_far_above_the_time_constants_is_refused_and_a_coarse_one_warned_about():
    graph = chain(nir.CubaLIF(tau_syn=np.full(1, 0.005), tau_mem=np.full(1, 0.01), r=np.ones(1),
                              v_leak=np.zeros(1), v_threshold=np.ones(1)), [[1.0]])
    with pytest.raises(NirError, match=r"dt_s = 10.0 s is longer than its shortest time constant, tau_syn = 0.005 s of node 'neuron'"):
        from_nir(graph, dt_s=10.0)
    with pytest.warns(UserWarning, match="more than a tenth"):
        from_nir(graph, dt_s=0.001)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        from_nir(graph, dt_s=1e-4)


def test_if_populations_and_one_step_projections_export_and_come_back_with_the_same_spikes():
    dt = 1e-4
    graph = chain(nir.IF(r=np.ones(2), v_threshold=np.ones(2)), [[0.6, 0.0], [0.3, 0.8]])
    first = from_nir(graph, dt_s=dt)
    first.run(0.01, inputs={"input": [np.array([0.001, 0.0012, 0.0014, 0.004]), np.array([0.002, 0.0021])]})
    first_spikes = [a.tolist() for a in first.spikes("neuron")]
    assert first_spikes[0]
    exported = to_nir(first)
    assert isinstance(exported.nodes["neuron"], nir.IF)
    again = from_nir(exported)
    again.run(0.01)
    assert [a.tolist() for a in again.spikes("neuron")] == first_spikes
