"""neurotac.Network from Python: made from a description, run with input trains, spikes and
weights read and written, saved and loaded."""

import json

import neurotac
import numpy as np
import pytest

from descriptions import DT_S, lif, network


def one_neuron(weight, trains=((0.001,),)):
    """One input channel → one LIF neuron (τ_m 10 ms) through a 5 ms synapse of `weight`."""
    return network(
        nodes=[
            {
                "kind": "source",
                "name": "in",
                "source": {"spike_array": {"trains": [list(t) for t in trains]}},
            },
            {"kind": "population", "name": "lif", "model": lif(1)},
        ],
        projections=[
            {
                "pre": "in",
                "post": "lif",
                "tau_s": 0.005,
                "delay_steps": 0,
                "wiring": {"all_to_all": {"weight": weight}},
                "plasticity": None,
            }
        ],
    )


def recurrent():
    """Poisson (20) → A (30) ⇄ B (10): random sparse weights, an all-to-all inhibitory
    projection back, delays 2 and 3 steps."""
    rng = np.random.default_rng(3)
    pre, post = np.nonzero(rng.random((30, 10)) < 0.3)
    in_pre, in_post = np.nonzero(rng.random((20, 30)) < 0.5)
    return network(
        nodes=[
            {
                "kind": "source",
                "name": "noise",
                "source": {"poisson": {"size": 20, "rate_hz": 80.0, "seed": 11}},
            },
            {"kind": "population", "name": "a", "model": lif(30)},
            {"kind": "population", "name": "b", "model": lif(10, tau_m_s=0.02)},
        ],
        projections=[
            {
                "pre": "noise",
                "post": "a",
                "tau_s": 0.005,
                "delay_steps": 0,
                "wiring": {
                    "sparse": {
                        "pre": in_pre.tolist(),
                        "post": in_post.tolist(),
                        "weight": rng.uniform(0.1, 0.5, len(in_pre)).tolist(),
                    }
                },
                "plasticity": None,
            },
            {
                "pre": "a",
                "post": "b",
                "tau_s": 0.005,
                "delay_steps": 2,
                "wiring": {
                    "sparse": {
                        "pre": pre.tolist(),
                        "post": post.tolist(),
                        "weight": rng.uniform(0.5, 1.5, len(pre)).tolist(),
                    }
                },
                "plasticity": None,
            },
            {
                "pre": "b",
                "post": "a",
                "tau_s": 0.003,
                "delay_steps": 3,
                "wiring": {"all_to_all": {"weight": -0.05}},
                "plasticity": None,
            },
        ],
    )


def spikes_of(net, duration_s=0.2):
    net.run(duration_s)
    return {name: [a.tolist() for a in net.spikes(name)] for name in ("a", "b")}


def test_one_input_spike_fires_once_above_and_never_below_the_computed_peak():
    # τ_m = 10 ms, τ_syn = 5 ms: one spike of weight w gives v(t) = w·(e^(−t/10ms) − e^(−t/5ms)),
    # peak 0.25·w at t = 6.9 ms. w = 6: v crosses 1 at 2.4 ms, the current left (3.7) peaks at
    # 0.93 after the reset: one spike. w = 2: peak 0.5, none.
    net = neurotac.Network.from_description(json.dumps(one_neuron(6.0)))
    net.run(0.05)
    times, neurons = net.spikes("lif")
    assert neurons.tolist() == [0]
    assert 0.001 + 0.002 < times[0] < 0.001 + 0.003
    net = neurotac.Network.from_description(json.dumps(one_neuron(2.0)))
    net.run(0.05)
    assert len(net.spikes("lif")[0]) == 0
    # 49 ms after the spike v has decayed from its peak 0.5: 2·(e^(−4.9) − e^(−9.8)) ≈ 0.0149.
    (v,) = net.state("lif", "v")
    assert v == pytest.approx(2.0 * (np.exp(-4.9) - np.exp(-9.8)), rel=0.05)
    assert (net.inputs, net.populations, net.n_projections) == (["in"], ["lif"], 1)


def test_description_round_trips_and_runs_the_same_spikes():
    net = neurotac.Network.from_description(json.dumps(recurrent()))
    again = neurotac.Network.from_description(net.description())
    first = spikes_of(net)
    assert sum(len(t) for t, _ in first.values()) > 50
    assert spikes_of(again) == first


def test_run_replaces_inputs_relative_to_the_run_start_and_continues():
    net = neurotac.Network.from_description(json.dumps(one_neuron(6.0, trains=((),))))
    net.run(0.01)
    assert len(net.spikes("lif")[0]) == 0
    # A spike 1 ms into the second run: emitted at 11 ms of network time.
    net.run(0.02, inputs={"in": [np.array([0.001])]})
    times, _ = net.spikes("lif")
    assert len(times) == 1 and 0.011 + 0.002 < times[0] < 0.011 + 0.003
    in_times, _ = net.spikes("in")
    assert in_times.tolist() == [pytest.approx(0.011)]
    # reset: time 0; the input replays its trains at the network times they were given for,
    # so the same spike comes again, and the recorded spikes start anew with the run.
    net.reset()
    assert net.time_s == 0.0
    net.run(0.03)
    assert net.spikes("lif")[0].tolist() == times.tolist()


def test_save_then_load_continues_with_the_same_spikes(tmp_path):
    net = neurotac.Network.from_description(json.dumps(recurrent()))
    net.run(0.1)
    path = tmp_path / "net.ntnet"
    net.save(str(path))
    loaded = neurotac.Network.load(str(path))
    assert loaded.time_s == net.time_s
    net.run(0.1)
    loaded.run(0.1)
    # A loaded network records from where it was saved.
    for name in ("noise", "a", "b"):
        t, i = net.spikes(name)
        late = t > 0.1 + DT_S / 2
        assert 0 < late.sum() < len(t)
        lt, li = loaded.spikes(name)
        assert (lt.tolist(), li.tolist()) == (t[late].tolist(), i[late].tolist())


def test_weights_read_and_written_dense_and_per_synapse():
    net = neurotac.Network.from_description(json.dumps(recurrent()))
    assert np.all(net.weights(2) == -0.05) and net.weights(2).shape == (10, 30)
    pre, post, weight = net.weights(1, dense=False)
    dense = net.weights(1)
    assert dense.shape == (30, 10)
    assert np.array_equal(dense[pre, post], weight)
    net.set_weights(1, dense * 2)
    assert np.array_equal(net.weights(1, dense=False)[2], weight * 2)
    net.set_weights(1, weight)
    assert np.array_equal(net.weights(1), dense)
    missing = np.argwhere(dense == 0)[0]
    bad = dense.copy()
    bad[tuple(missing)] = 1.0
    with pytest.raises(neurotac.NeurotacValueError, match=r"has no synapse"):
        net.set_weights(1, bad)
    with pytest.raises(neurotac.NeurotacValueError, match=r"projection 3: the network has 3"):
        net.weights(3)


def test_errors_name_what_is_wrong():
    net = neurotac.Network.from_description(json.dumps(one_neuron(1.0)))
    with pytest.raises(neurotac.NeurotacValueError, match="'x' is not a spike input"):
        net.run(0.01, inputs={"x": [[0.001]]})
    with pytest.raises(
        neurotac.NeurotacValueError,
        match=r"'out' is not a population or spike input of the network \(its population or spike inputs: in, lif\)",
    ):
        net.spikes("out")
    with pytest.raises(neurotac.NeurotacValueError, match="not finite"):
        net.run(0.01, inputs={"in": [[float("nan")]]})
    with pytest.raises(neurotac.NeurotacValueError, match="missing field `format`"):
        neurotac.Network.from_description("{}")
    with pytest.raises(neurotac.NeurotacOSError, match="cannot read the network file"):
        neurotac.Network.load("/nonexistent/net.ntnet")
    with pytest.raises(neurotac.NeurotacValueError, match="plastic"):
        net.set_learning(0, False)


STDP = {
    "tau_plus_s": 0.02,
    "tau_minus_s": 0.02,
    "a_plus": 0.01,
    "a_minus": 0.012,
    "w_min": 0.0,
    "w_max": 1.0,
    "dependence": "additive",
    "interaction": "all_to_all",
}


def test_plastic_projection_learns_until_frozen():
    description = recurrent()
    sparse = description["projections"][1]["wiring"]["sparse"]
    sparse["weight"] = [min(w, 1.0) for w in sparse["weight"]]
    description["projections"][1]["plasticity"] = STDP
    net = neurotac.Network.from_description(json.dumps(description))
    before = net.weights(1, dense=False)[2]
    net.run(0.1)
    learned = net.weights(1, dense=False)[2]
    assert not np.array_equal(learned, before)
    assert np.all((learned >= 0.0) & (learned <= 1.0))
    net.set_learning(1, False)
    net.run(0.1)
    assert np.array_equal(net.weights(1, dense=False)[2], learned)
    # The description carries the learned weights and the rule.
    described = json.loads(net.description())["projections"][1]
    assert described["plasticity"] == STDP
    assert described["wiring"]["sparse"]["weight"] == learned.tolist()
    # A weight outside the rule's bounds is refused, and nothing changes.
    with pytest.raises(neurotac.NeurotacValueError, match="STDP bounds"):
        net.set_weights(1, learned + 2.0)
    assert np.array_equal(net.weights(1, dense=False)[2], learned)


def test_a_run_of_absurdly_many_steps_is_refused_at_once():
    description = recurrent()
    description["dt_s"] = 1e-300
    net = neurotac.Network.from_description(json.dumps(description))
    with pytest.raises(neurotac.NeurotacValueError, match="2⁴⁰ steps"):
        net.run(0.01)
    assert net.time_s == 0.0


def test_a_long_run_stops_on_ctrl_c_keeping_the_steps_done():
    import _thread
    import threading
    import time

    net = neurotac.Network.from_description(json.dumps(recurrent()))
    timer = threading.Timer(0.5, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            net.run(1e6)  # 10¹⁰ steps: hours, unless interrupted
    finally:
        timer.cancel()
    assert time.monotonic() - start < 30
    assert 0 < net.time_s < 1e6
    # It goes on from there.
    before = net.time_s
    net.run(0.01)
    assert net.time_s == pytest.approx(before + 0.01)


def test_a_crafted_saved_network_is_an_error_not_an_abort(tmp_path):
    net = neurotac.Network.from_description(json.dumps(recurrent()))
    net.run(0.01)
    good = tmp_path / "net.ntnet"
    net.save(good)
    data = good.read_bytes()
    # The saved step (a CBOR u64) set near 2⁶⁴, length and checksum made right.
    import zlib

    body = data[20:-4]
    at = body.find(b"\x64step") + 5  # the key "step", then its CBOR unsigned integer
    width = {0x18: 2, 0x19: 3, 0x1A: 5, 0x1B: 9}.get(body[at], 1)
    body = body[:at] + b"\x1b" + (2**64 - 6).to_bytes(8, "big") + body[at + width :]
    crafted = data[:12] + len(body).to_bytes(8, "little") + body
    crafted += zlib.crc32(crafted).to_bytes(4, "little")
    bad = tmp_path / "bad.ntnet"
    bad.write_bytes(crafted)
    with pytest.raises(neurotac.NeurotacError) as e:
        neurotac.Network.load(bad)
    assert "bad.ntnet" in str(e.value)


def test_descriptions_of_what_cannot_be_held_are_refused_not_aborted():
    cases = [
        (lambda d: d["projections"][1].update(delay_steps=2**32 - 1), "delay_steps"),
        (
            lambda d: d["nodes"][0]["source"]["poisson"].update(size=2**40),
            "at most 2³² − 1",
        ),
        (lambda d: d["nodes"][1]["model"].update(size=2**32 - 1), "more than can be allocated"),
    ]
    for edit, expected in cases:
        description = recurrent()
        edit(description)
        with pytest.raises(neurotac.NeurotacValueError, match=expected):
            neurotac.Network.from_description(json.dumps(description))
    # A plastic 200 000 × 200 000 all-to-all projection: 4·10¹⁰ synapses.
    description = recurrent()
    description["nodes"][0]["source"]["poisson"]["size"] = 200_000
    description["nodes"][1]["model"]["size"] = 200_000
    description["projections"][0]["wiring"] = {"all_to_all": {"weight": 0.2}}
    description["projections"][0]["plasticity"] = STDP
    with pytest.raises(neurotac.NeurotacValueError, match="more than can be allocated"):
        neurotac.Network.from_description(json.dumps(description))
