"""Networks to NIR graphs and back (neurotac.nir): the mapping on descriptions, graphs built
with the nir package's own constructors, and what either side refuses."""

import copy
import json

import numpy as np
import pytest

nir = pytest.importorskip("nir")

import neurotac
from neurotac.nir import (
    NirError,
    from_nir,
    graph_to_description,
    to_nir,
)

from descriptions import DT_S, lif, network, projection, sparse


def two_layers():
    """Input (3) → hidden (4, CubaLIF) → out (2, two projections with different τ_syn, so LIF +
    LI synapses); every connectivity; delays 0, 3 and 1; f32 and interpolated spike times on
    one population; sparse synapses by presynaptic neuron, as the import lists them."""
    return network(
        nodes=[
            {
                "kind": "source",
                "name": "in",
                "source": {"spike_array": {"trains": [[0.001], [0.002, 0.0031], []]}},
            },
            {"kind": "population", "name": "hidden", "model": lif(4, tau_m_s=0.02, v_reset=-0.1)},
            {
                "kind": "population",
                "name": "out",
                "model": lif(2, precision="f32", interpolate=True),
            },
            {
                "kind": "source",
                "name": "noise",
                "source": {"poisson": {"size": 2, "rate_hz": 50.0, "seed": 7}},
            },
        ],
        projections=[
            projection("in", "hidden", {"all_to_all": {"weight": 0.7}}, delay_steps=0),
            projection(
                "hidden", "out", sparse([0, 1, 3], [1, 0, 1], [0.5, -0.2, 1.1]), delay_steps=3
            ),
            projection("in", "out", sparse([0, 2], [0, 1], [0.3, 0.4]), tau_s=0.002),
            projection(
                "noise", "out", {"one_to_one": {"weight": 0.25}}, tau_s=0.002, delay_steps=0
            ),
        ],
    )


def test_description_round_trips_through_nir_unchanged():
    description = two_layers()
    graph = to_nir(description)
    assert graph_to_description(graph) == description
    # A JSON string is accepted as well as a dict.
    assert graph_to_description(to_nir(json.dumps(description))) == description


def test_description_round_trips_through_a_nir_file(tmp_path):
    description = two_layers()
    path = tmp_path / "net.nir"
    nir.write(path, to_nir(description))
    # nir.read lists nodes in HDF5's (alphabetical) order; the metadata restores neurotac's.
    assert graph_to_description(nir.read(path)) == description


def test_a_population_without_inputs_round_trips(tmp_path):
    description = two_layers()
    description["nodes"].append(
        {"kind": "population", "name": "lonely", "model": lif(2, initial={"constant": 1.5})}
    )
    graph = to_nir(description)
    # nir's type check gives it an Input of its own, which is not part of the network.
    assert ("input_lonely", "lonely") in graph.edges
    assert graph_to_description(graph) == description
    nir.write(tmp_path / "net.nir", graph)
    net = from_nir(nir.read(tmp_path / "net.nir"))
    net.run(0.01)
    assert net.spikes("lonely")[1].tolist() == [0, 1]  # started above threshold


def test_exported_graph_holds_the_weights_parameters_and_delays():
    graph = to_nir(two_layers())
    nodes = graph.nodes
    assert isinstance(nodes["in"], nir.Input) and isinstance(nodes["noise"], nir.Input)
    hidden = nodes["hidden"]
    assert isinstance(hidden, nir.CubaLIF)
    np.testing.assert_array_equal(hidden.tau_mem, [0.02] * 4)
    np.testing.assert_array_equal(hidden.tau_syn, [0.005] * 4)
    np.testing.assert_array_equal(hidden.v_threshold, [1.0] * 4)
    np.testing.assert_array_equal(hidden.v_reset, [-0.1] * 4)
    np.testing.assert_array_equal(hidden.v_leak, [0.0] * 4)
    # r·w_in/τ_syn = 1: a Linear weight is the jump of neurotac's current per spike.
    np.testing.assert_array_equal(hidden.r * hidden.w_in / hidden.tau_syn, [1.0] * 4)
    np.testing.assert_array_equal(nodes["in_to_hidden_linear"].weight, np.full((4, 3), 0.7))
    # Projections onto `out` have τ_syn 5 ms and 2 ms: a LIF with one LI synapse each.
    assert isinstance(nodes["out"], nir.LIF)
    assert isinstance(nodes["hidden_to_out_synapse"], nir.LI)
    np.testing.assert_array_equal(nodes["hidden_to_out_synapse"].tau, [0.005] * 2)
    np.testing.assert_array_equal(nodes["in_to_out_synapse"].tau, [0.002] * 2)
    expected = np.zeros((2, 4))
    expected[1, 0], expected[0, 1], expected[1, 3] = 0.5, -0.2, 1.1
    np.testing.assert_array_equal(nodes["hidden_to_out_linear"].weight, expected)
    np.testing.assert_array_equal(nodes["noise_to_out_linear"].weight, np.eye(2) * 0.25)
    # Delays in seconds, before the Linear; none for delay 0.
    np.testing.assert_array_equal(nodes["hidden_to_out_delay"].delay, [3 * DT_S] * 4)
    assert "in_to_hidden_delay" not in nodes
    assert ("hidden_to_out_delay", "hidden_to_out_linear") in graph.edges
    # Populations that feed no other are the graph's outputs.
    assert ("out", "output_out") in graph.edges and "output_hidden" not in nodes


def built_with_nir(weight, r=1.0, w_in=1.0, tau_syn=0.005, metadata=None):
    """Input (1) → Linear → CubaLIF (1) → Output, made with the nir package's constructors."""
    one = np.ones(1)
    return nir.NIRGraph(
        nodes={
            "input": nir.Input(input_type=np.array([1])),
            "linear": nir.Linear(weight=np.array([[weight]])),
            "lif": nir.CubaLIF(
                tau_syn=one * tau_syn,
                tau_mem=one * 0.01,
                r=one * r,
                v_leak=one * 0.0,
                v_threshold=one * 1.0,
                w_in=one * w_in,
            ),
            "output": nir.Output(output_type=np.array([1])),
        },
        edges=[("input", "linear"), ("linear", "lif"), ("lif", "output")],
        metadata=metadata or {},
    )


def test_graph_built_with_nir_maps_with_neurotac_defaults():
    description = graph_to_description(built_with_nir(3.0, r=2.0, w_in=0.5), dt_s=DT_S)
    (source, population) = description["nodes"]
    assert source == {
        "kind": "source",
        "name": "input",
        "source": {"spike_array": {"trains": [[]]}},
    }
    assert population["name"] == "lif"
    settings = population["model"]["settings"]
    assert (settings["integrator"], settings["precision"], settings["interpolate"]) == (
        "exact",
        "f64",
        False,
    )
    assert settings["params"] == {
        "tau_m_s": 0.01,
        "v_rest": 0.0,
        "v_th": 1.0,
        "v_reset": 0.0,
        "t_ref_s": 0.0,
        "v_min": None,
    }
    (p,) = description["projections"]
    # A spike moves NIR's current by w_in·W/τ_syn and v sees r·I: neurotac's weight is
    # W·r·w_in/τ_syn = 3·2·0.5/0.005 = 600.
    assert p["wiring"] == {"all_to_all": {"weight": pytest.approx(600.0)}}
    assert (p["pre"], p["post"], p["tau_s"], p["delay_steps"]) == ("input", "lif", 0.005, 0)
    assert description["dt_s"] == DT_S


def test_population_to_population_spikes_arrive_one_step_later_at_the_earliest():
    description = two_layers()
    description["projections"][1]["delay_steps"] = 1
    graph = to_nir(description)
    del graph.nodes["hidden_to_out_delay"]
    graph.edges.remove(("hidden", "hidden_to_out_delay"))
    graph.edges.remove(("hidden_to_out_delay", "hidden_to_out_linear"))
    graph.edges.append(("hidden", "hidden_to_out_linear"))
    assert graph_to_description(graph)["projections"][1]["delay_steps"] == 1


def test_foreign_graph_needs_a_time_step():
    with pytest.raises(NirError, match=r"pass from_nir\(graph, dt_s=\.\.\.\)"):
        graph_to_description(built_with_nir(1.0))


def refused_on_import(graph, dt_s=DT_S):
    with pytest.raises(NirError) as e:
        graph_to_description(graph, dt_s=dt_s)
    assert isinstance(e.value, neurotac.NeurotacValueError) and isinstance(e.value, ValueError)
    return str(e.value)


def test_nir_nodes_neurotac_cannot_run_are_refused_by_name():
    conv = nir.NIRGraph(
        nodes={
            "input": nir.Input(input_type=np.array([1, 4, 4])),
            "conv": nir.Conv2d(
                input_shape=(4, 4),
                weight=np.ones((2, 1, 3, 3)),
                stride=1,
                padding=0,
                dilation=1,
                groups=1,
                bias=np.zeros(2),
            ),
            "output": nir.Output(output_type=np.array([2, 2, 2])),
        },
        edges=[("input", "conv"), ("conv", "output")],
    )
    assert refused_on_import(conv) == "NIR node 'conv' (Conv2d): neurotac cannot run this node type"

    graph = built_with_nir(1.0)
    graph.nodes["lif"] = nir.I(r=np.ones(1))
    assert refused_on_import(graph) == "NIR node 'lif' (I): neurotac cannot run this node type"


def test_what_a_neurotac_population_cannot_hold_is_refused_by_name():
    graph = built_with_nir(1.0)
    graph.nodes["lif"].tau_mem = np.array([0.01, 0.02])
    graph.nodes["lif"].v_threshold = np.array([1.0, 1.0])
    message = refused_on_import(graph)
    assert message.startswith("NIR node 'lif' (CubaLIF): tau_mem differs between neurons")

    graph = built_with_nir(1.0)
    graph.nodes["linear"] = nir.Affine(weight=np.ones((1, 1)), bias=np.ones(1))
    assert refused_on_import(graph).startswith("NIR node 'linear' (Affine): a bias")
    # A zero bias is a Linear.
    graph.nodes["linear"] = nir.Affine(weight=np.ones((1, 1)), bias=np.zeros(1))
    assert graph_to_description(graph, dt_s=DT_S)["projections"][0]["wiring"] == {
        "all_to_all": {"weight": 200.0}
    }

    graph = built_with_nir(1.0)
    graph.nodes["linear"] = nir.Linear(weight=np.ones((1, 2)))
    assert "weight has shape (1, 2), expected (1, 1)" in refused_on_import(graph)


def test_a_readout_leaky_integrator_is_refused():
    # snnTorch-style readout: spikes → Linear → LI → Output.
    graph = built_with_nir(1.0)
    graph.nodes["readout"] = nir.Linear(weight=np.ones((1, 1)))
    graph.nodes["li"] = nir.LI(tau=np.ones(1) * 0.01, r=np.ones(1), v_leak=np.zeros(1))
    graph.edges[-1] = ("lif", "readout")
    graph.edges += [("readout", "li"), ("li", "output")]
    assert refused_on_import(graph).startswith("NIR node 'li' (LI): feeds Output 'output'")


def test_a_delay_must_be_whole_steps():
    graph = built_with_nir(1.0)
    graph.nodes["delay"] = nir.Delay(delay=np.array([2.5 * DT_S]))
    graph.edges[0] = ("input", "delay")
    graph.edges.insert(1, ("delay", "linear"))
    assert "is not a whole number of steps" in refused_on_import(graph)
    graph.nodes["delay"] = nir.Delay(delay=np.array([3 * DT_S]))
    assert graph_to_description(graph, dt_s=DT_S)["projections"][0]["delay_steps"] == 3


def refused_on_export(description):
    with pytest.raises(NirError) as e:
        to_nir(description)
    return str(e.value)


def test_what_nir_cannot_express_is_refused_on_export_by_name():
    description = two_layers()
    description["nodes"][1]["model"]["model"] = "izhikevich"
    assert refused_on_export(description) == (
        "population 'hidden': izhikevich neurons have no NIR equivalent (LIF and IF do)"
    )

    description = two_layers()
    description["projections"][1]["plasticity"] = {"tau_plus_s": 0.02}
    assert refused_on_export(description) == (
        "projection 'hidden' → 'out': is plastic (STDP); NIR has no plasticity rules"
    )

    description = two_layers()
    description["nodes"][2]["model"]["settings"]["params"]["t_ref_s"] = 0.002
    assert refused_on_export(description).startswith(
        "population 'out': refractory period t_ref_s = 0.002 s"
    )

    description = two_layers()
    description["nodes"][2]["model"]["settings"]["params"]["v_min"] = -1.0
    assert refused_on_export(description).startswith("population 'out': potential floor v_min")

    description = two_layers()
    description["nodes"].append(
        {"kind": "current", "name": "bias", "current": {"constant": 0.5}, "into": ["out"]}
    )
    assert refused_on_export(description) == (
        "current source 'bias': has no NIR equivalent (NIR inputs are spikes)"
    )


def test_metadata_never_overrides_the_graph():
    graph = to_nir(two_layers())
    graph.nodes["hidden"].v_threshold = np.full(4, 2.0)
    graph.nodes["in_to_hidden_linear"].weight = np.full((4, 3), 0.9)
    description = graph_to_description(graph)
    expected = copy.deepcopy(two_layers())
    expected["nodes"][1]["model"]["settings"]["params"]["v_th"] = 2.0
    expected["projections"][0]["wiring"] = {"all_to_all": {"weight": 0.9}}
    assert description == expected


# --- Running what crosses: neurotac.Network ------------------------------------------------


def recorded_spikes(net, duration_s=0.2):
    net.run(duration_s)
    return {name: [a.tolist() for a in net.spikes(name)] for name in ("hidden", "out")}


def test_network_to_nir_and_back_runs_identical_spikes(tmp_path):
    description = two_layers()
    description["projections"][0]["wiring"] = {"all_to_all": {"weight": 3.0}}
    description["nodes"][0]["source"]["spike_array"]["trains"] = [
        list(np.arange(0.001, 0.2, 0.007 * (c + 1))) for c in range(3)
    ]
    net = neurotac.Network.from_description(json.dumps(description))
    graph = to_nir(net)
    expected = recorded_spikes(net)
    assert sum(len(t) for t, _ in expected.values()) > 20
    assert recorded_spikes(from_nir(graph)) == expected
    path = tmp_path / "net.nir"
    nir.write(path, graph)
    assert recorded_spikes(from_nir(nir.read(path))) == expected


def test_graph_built_with_nir_runs_one_spike_above_the_computed_peak_and_none_below():
    # τ_mem = 10 ms, τ_syn = 5 ms, r = w_in = 1: a spike through W moves the current by W/τ_syn,
    # so v(t) = (W/τ_syn)·(e^(−t/10ms) − e^(−t/5ms)), peak 0.25·W/τ_syn. W = 0.03 (peak 1.5):
    # v crosses 1 at 2.4 ms and the current left peaks at 0.93 after the reset: one spike.
    # W = 0.01 (peak 0.5): none.
    for weight, count in ((0.03, 1), (0.01, 0)):
        net = from_nir(built_with_nir(weight), dt_s=DT_S)
        net.run(0.05, inputs={"input": [np.array([0.001])]})
        times, neurons = net.spikes("lif")
        assert len(times) == count
        if count:
            assert neurons.tolist() == [0] and 0.003 < times[0] < 0.004


def test_malformed_edges_are_refused_naming_the_edge():
    cases = [
        (lambda g: g.edges.append(("input", "nowhere")), "names node 'nowhere'"),
        (lambda g: g.edges.append(("ghost", "lif")), "names node 'ghost'"),
        (lambda g: g.edges.append(("input",)), "is not a (source, target) pair"),
        (lambda g: g.edges.append("ab"), "is not a (source, target) pair"),
        (lambda g: g.edges.append((1, "lif")), "endpoint 1 is not a node name"),
        (lambda g: g.edges.append(("input", "linear")), "is listed twice"),
        (lambda g: g.edges.append(("lif", "input")), "leads into Input 'input'"),
    ]
    for edit, expected in cases:
        graph = built_with_nir(1.0)
        edit(graph)
        message = refused_on_import(graph)
        assert message.startswith("edge ") and expected in message, message


def test_an_output_mid_path_is_refused():
    graph = built_with_nir(1.0)
    graph.nodes["lif2"] = graph.nodes["lif"]
    graph.edges += [("output", "lif2")]
    assert "leaves Output 'output'" in refused_on_import(graph)


def test_metadata_of_the_wrong_types_is_refused_naming_the_field():
    description = two_layers()
    for field, value in [
        ("dt_s", "0.1ms"),
        ("dt_s", True),
        ("order", 5),
        ("order", [1, 2]),
        ("unfed", "out"),
        ("nodes", []),
        ("stepping", 3),
    ]:
        graph = to_nir(description)
        meta = json.loads(graph.metadata["neurotac"])
        meta[field] = value
        graph.metadata["neurotac"] = json.dumps(meta)
        message = refused_on_import(graph)
        assert message.startswith(f"graph metadata: '{field}' is"), message
    graph = to_nir(description)
    meta = json.loads(graph.metadata["neurotac"])
    meta["nodes"]["in"]["source"] = "spikes"
    graph.metadata["neurotac"] = json.dumps(meta)
    assert refused_on_import(graph).startswith("graph metadata: 'nodes.in.source' is")
    # A metadata source with another channel count than its Input.
    graph = to_nir(description)
    meta = json.loads(graph.metadata["neurotac"])
    meta["nodes"]["in"]["source"] = {"poisson": {"size": 10**12, "rate_hz": 1.0, "seed": 1}}
    graph.metadata["neurotac"] = json.dumps(meta)
    assert "has 1000000000000 channels, the Input 3" in refused_on_import(graph)


def test_sizes_and_delays_beyond_the_limits_are_refused_before_anything_is_made():
    # A Delay of 3·10⁹ steps (it would size a spike history of 3·10⁹ slots).
    graph = built_with_nir(1.0)
    graph.nodes["delay"] = nir.Delay(delay=np.array([3e9 * DT_S]))
    graph.edges[0] = ("input", "delay")
    graph.edges.insert(1, ("delay", "linear"))
    message = refused_on_import(graph)
    assert message.startswith("NIR node 'delay' (Delay)") and "3000000000 steps" in message
    # An Input of 10⁹ channels (a spike train each).
    graph = built_with_nir(1.0)
    graph.nodes["input"].input_type = {"input": np.array([1000, 1000, 1000])}
    message = refused_on_import(graph)
    assert message.startswith("NIR node 'input' (Input): size 1000000000"), message
    graph.nodes["input"].input_type = {"input": np.array([-1])}
    assert "is not a list of sizes" in refused_on_import(graph)
    graph.nodes["input"].input_type = {}
    assert "no 'input' shape" in refused_on_import(graph)


def test_a_zero_time_constant_is_refused_naming_it():
    message = refused_on_import(built_with_nir(1.0, tau_syn=0.0))
    assert message.startswith("NIR node 'lif' (CubaLIF): tau_syn = 0.0, expected > 0"), message
    graph = built_with_nir(1.0)
    graph.nodes["lif"].tau_mem = np.array([-0.01])
    assert "tau_mem = -0.01, expected > 0" in refused_on_import(graph)
    # Weights that overflow once scaled by r·w_in/τ_syn.
    message = refused_on_import(built_with_nir(1e308, w_in=1e10))
    assert "are not finite" in message


def test_a_malformed_node_is_refused_naming_it():
    graph = built_with_nir(1.0)
    del graph.nodes["lif"].v_threshold
    message = refused_on_import(graph)
    assert "'lif'" in message and "malformed" in message, message
    graph = built_with_nir(1.0)
    graph.nodes["linear"].weight = "heavy"
    message = refused_on_import(graph)
    assert "('linear', 'lif')" in message or "'linear'" in message, message


def test_what_the_library_refuses_is_a_nir_error_too():
    graph = built_with_nir(1.0)
    meta = {
        "format": "neurotac-nir",
        "version": 1,
        "dt_s": DT_S,
        "stepping": "sideways",
        "order": [],
        "unfed": [],
        "nodes": {},
    }
    graph.metadata = {"neurotac": json.dumps(meta)}
    with pytest.raises(NirError, match="does not build"):
        from_nir(graph)
