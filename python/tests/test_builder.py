"""neurotac.NetworkBuilder: networks defined in Python — populations, inputs, projections,
monitors — built, run and read back by name, saved and exchanged, with bad arguments refused
naming the argument."""

import json
import math

import neurotac
import numpy as np
import pytest

from neurotac import NetworkBuilder, NeurotacValueError, Stdp

DT_S = 1e-4


def one_afferent(weight=5.0, times=(0.001,)):
    """One taxel → one LIF afferent (τ_m 10 ms) through a 5 ms synapse, delivered at once."""
    b = NetworkBuilder(dt_s=DT_S)
    b.add_spike_input("taxels", [list(times)])
    b.add_population("afferents", 1, tau_m_s=0.01)
    b.connect("taxels", "afferents", "one_to_one", weight=weight, tau_syn_s=0.005)
    return b


def test_a_lone_taxel_spike_makes_one_afferent_spike_at_the_closed_form_time():
    # v(t) = (w·τ_s/(τ_m − τ_s))·(e^(−t/τ_m) − e^(−t/τ_s)) for a current jump w at t = 0
    # (held over each step: the grid step's answer is within one step of the closed form).
    b = one_afferent()
    b.monitor_state("afferents", "v")
    net = b.build()
    net.run(0.03)
    times, neurons = net.spikes("afferents")
    assert neurons.tolist() == [0]
    w, tau_m, tau_s = 5.0, 0.01, 0.005
    t = np.arange(1, 3000) * 1e-5
    v = w * tau_s / (tau_m - tau_s) * (np.exp(-t / tau_m) - np.exp(-t / tau_s))
    crossing = 0.001 + t[np.argmax(v >= 1.0)]
    assert abs(times[0] - crossing) <= 2 * DT_S, (times[0], crossing)
    t_v, v_trace = net.state_trace("afferents", "v")
    assert v_trace.shape == (300, 1) and t_v[0] == pytest.approx(DT_S)
    assert v_trace.max() < 1.0  # the spike step resets to 0


def test_the_builder_mirrors_the_rust_example_and_reads_projections_by_name():
    trains = [np.arange(0.0, 0.95, 1.0 / (5 + c / 2)) for c in range(49)]
    b = NetworkBuilder(dt_s=DT_S)
    assert b.add_spike_input("taxels", trains) == "taxels"
    assert b.add_population("afferents", 49) == "afferents"
    name = b.connect("taxels", "afferents", "one_to_one", weight=5.0, tau_syn_s=5e-3, delay_s=0)
    assert name == "taxels->afferents"
    net = b.build()
    net.run(1.0)
    assert net.recorded == ["taxels", "afferents"]
    assert net.projections == ["taxels->afferents"]
    by_name, by_pre, by_index = (net.weights(p) for p in ("taxels->afferents", "taxels", 0))
    assert np.array_equal(by_name, by_pre) and np.array_equal(by_name, by_index)
    assert np.array_equal(by_name, 5.0 * np.eye(49))
    _, neurons = net.spikes("afferents")
    counts = np.bincount(neurons, minlength=49)
    # The same network in Rust (examples/taxel_afferents.rs, 2 s) gives 1–3 spikes per taxel
    # spike; here every afferent fires at least once per taxel spike.
    taxel_counts = np.array([len(t) for t in trains])
    assert np.all(counts >= taxel_counts)
    with pytest.raises(NeurotacValueError, match="no such projection; the network has 1 projections: taxels->afferents"):
        net.weights("afferents")
    net.set_weights("taxels", 2.0 * np.eye(49))
    assert net.weights("taxels")[3, 3] == 2.0


def test_izhikevich_presets_and_parameters_by_name():
    b = NetworkBuilder(dt_s=DT_S)
    b.add_population("rs", 2, model="izhikevich", preset="rs")
    b.add_population("fs", 2, model="izhikevich", preset="fs", d=3.0)
    b.add_current_input("drive", ["rs", "fs"], amplitude=10.0)
    net = b.build()
    fs = json.loads(net.description())["nodes"][1]["model"]["settings"]["params"]
    assert (fs["a"], fs["d"]) == (0.1, 3.0)
    net.run(0.2)
    rs_spikes = len(net.spikes("rs")[0])
    fs_spikes = len(net.spikes("fs")[0])
    assert 0 < rs_spikes < fs_spikes  # fast spiking fires faster under the same drive


def test_bad_arguments_are_refused_naming_the_argument():
    b = NetworkBuilder(dt_s=DT_S)
    b.add_population("a", 3)
    cases = [
        (lambda: b.add_population("b", 0), "size = 0"),
        (lambda: b.add_population("a", 2), "name = 'a'"),
        (lambda: b.add_population("b", 2, model="hodgkin"), "model = 'hodgkin'"),
        (lambda: b.add_population("b", 2, preset="rs"), "preset = 'rs': LIF has no presets"),
        (lambda: b.add_population("b", 2, model="izhikevich", preset="xx"), "preset = 'xx'"),
        (lambda: b.add_population("b", 2, tau=0.01), "tau: not a parameter of lif"),
        (lambda: b.add_population("b", 2, integrator="izhikevich2003"), "integrator = 'izhikevich2003'"),
        (lambda: b.add_population("b", 2, v_th=float("nan")), "v_th = nan"),
        (lambda: b.connect("a", "ghost", weight=1.0), "post = 'ghost'"),
        (lambda: b.connect("a", "a", "every", weight=1.0), "connectivity = 'every'"),
        (lambda: b.connect("a", "a", weight=1.0, delay_s=1.5e-4), "delay_s = 0.00015"),
        (lambda: b.connect("a", "a", weight=1.0, tau_syn_s=-1), "tau_syn_s = -1"),
        (lambda: b.connect("a", "a", "random", weight=1.0, probability=0.5), "seed = None"),
        (lambda: b.connect("a", "a", "random", weight=1.0, probability=2, seed=1), "probability = 2"),
        (lambda: b.connect("a", "a", "sparse", pre_indices=[0], post_indices=[3], weight=1.0), "post_indices = 3"),
        (lambda: b.connect("a", "a", weight=1.0, stdp="song"), "stdp = 'song'"),
        (lambda: b.monitor_state("a", "v", every_s=0.5e-4), "every_s = 5e-05"),
        (lambda: b.add_poisson_input("p", 3, rate_hz=-1, seed=1), "rate_hz = -1"),
        (lambda: b.add_current_input("c", "ghost", amplitude=1.0), "into = 'ghost'"),
        (lambda: NetworkBuilder(dt_s=0), "dt_s = 0"),
        (lambda: Stdp(0.02, 0.02, 0.01, 0.01, 1.0, dependence="hebbian"), "dependence = 'hebbian'"),
    ]
    for make, expected in cases:
        with pytest.raises(NeurotacValueError) as e:
            make()
        assert expected in str(e.value), (expected, str(e.value))
        assert isinstance(e.value, ValueError)
    # A variable the model does not have: Rust names it when the network is built.
    b.monitor_state("a", "u")
    with pytest.raises(NeurotacValueError, match=r"population 'a'.*lif has no state variable 'u' \(has: v\)"):
        b.build()


def test_random_connectivity_is_the_seeded_draw_and_stdp_learns():
    b = NetworkBuilder(dt_s=DT_S)
    b.add_poisson_input("noise", 100, rate_hz=15.0, seed=3)
    b.add_population("out", 10)
    w_max = 0.6
    b.connect("noise", "out", "random", probability=0.2, weight=0.3, seed=11,
              stdp=Stdp.additive(0.02, 0.02, 0.01 * w_max, 0.0105 * w_max, w_max))
    first, second = b.build(), b.build()
    pre, post, w = first.weights(0, dense=False)
    assert 100 < len(w) < 300  # ≈ 200 of the 1000 pairs
    again = second.weights(0, dense=False)
    assert all(np.array_equal(x, y) for x, y in zip((pre, post, w), again))
    first.run(2.0)
    learned = first.weights("noise", dense=False)[2]
    assert not np.array_equal(learned, w) and learned.min() >= 0 and learned.max() <= w_max
    first.set_learning("noise->out", False)
    frozen = first.weights("noise", dense=False)[2]
    first.run(0.5)
    assert np.array_equal(first.weights("noise", dense=False)[2], frozen)


def test_population_rate_counts_every_spike_per_neuron_and_second():
    b = NetworkBuilder(dt_s=DT_S)
    b.add_spike_input("clock", [np.arange(0.0, 1.0, 0.01)] * 4)  # 100 Hz on 4 channels
    net = b.build()
    net.run(1.0)
    starts, rate_hz = net.population_rate("clock", bin_s=0.1)
    assert starts.tolist() == pytest.approx([0.1 * k for k in range(10)])
    assert rate_hz.tolist() == pytest.approx([100.0] * 10)
    with pytest.raises(NeurotacValueError, match="bin_s = 0"):
        net.population_rate("clock", bin_s=0)


def test_delays_currents_and_steps_reach_the_neurons():
    b = NetworkBuilder(dt_s=DT_S)
    b.add_spike_input("in", [[0.001]])
    b.add_population("a", 1)
    b.add_population("b", 1)
    b.connect("in", "a", weight=20.0)
    b.connect("a", "b", weight=20.0, delay_s=0.002)
    b.add_current_input("late", "b", steps=[(0.05, 3.0)])
    net = b.build()
    net.run(0.1)
    (a_times, _), (b_times, _) = net.spikes("a"), net.spikes("b")
    assert len(a_times) >= 1 and b_times[0] >= a_times[0] + 0.002
    # From 50 ms the step current (v∞ = 3) fires b at the closed-form period τ·ln(3/2).
    late = b_times[b_times > 0.05]
    period = 0.01 * math.log(3 / 2)
    assert len(late) == pytest.approx(0.05 / period, abs=1.5)


def test_a_built_network_saves_loads_and_exchanges_through_nir(tmp_path):
    nir = pytest.importorskip("nir")
    from neurotac.nir import from_nir, to_nir

    b = one_afferent(times=(0.001, 0.004, 0.03))
    net = b.build()
    path = tmp_path / "afferent.ntnet"
    net.save(str(path))
    loaded = neurotac.Network.load(str(path))
    through_nir = from_nir(to_nir(net))
    for n in (net, loaded, through_nir):
        n.run(0.06)
    expected = [a.tolist() for a in net.spikes("afferents")]
    assert [a.tolist() for a in loaded.spikes("afferents")] == expected
    assert [a.tolist() for a in through_nir.spikes("afferents")] == expected


def test_the_old_unit_names_still_work_with_a_deprecation_warning():
    data = {
        "times": np.array([0.001, 0.0105, 0.02]),
        "units": np.array([0, 1, 0], dtype=np.uint32),
        "offsets": np.array([0, 3]),
        "n_units": 2,
        "labels": np.array([0]),
        "class_names": ["a"],
        "meta": {"duration_s": 0.05},
    }
    new = neurotac.coding.temporal(data, dt_s=0.01)
    with pytest.warns(DeprecationWarning, match="dt= is deprecated: use dt_s="):
        old = neurotac.coding.temporal(data, dt=0.01)
    assert np.array_equal(new, old)
    assert np.array_equal(neurotac.coding.temporal(data, 0.01), new)
    with pytest.raises(NeurotacValueError, match="dt and dt_s given"):
        neurotac.coding.temporal(data, dt_s=0.01, dt=0.01)
