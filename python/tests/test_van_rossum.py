"""neurotac.van_rossum against the NumPy reference of the definition (and pymuvr, if installed)."""

import math

import numpy as np
import pytest

import neurotac
from neurotac import van_rossum
from reference import assert_close, squared_distance


def random_observations(rng, samples, units, mean_spikes, duration_s=1.0, quantum_s=None):
    """Random observations in pymuvr's form; some units and samples come out empty."""
    out = []
    for _ in range(samples):
        obs = []
        for _ in range(units):
            times = rng.uniform(0.0, duration_s, rng.poisson(mean_spikes))
            if quantum_s is not None:
                times = np.round(times / quantum_s) * quantum_s
            obs.append(sorted(times.tolist()))
        out.append(obs)
    return out


@pytest.mark.parametrize("cos", [0.0, 0.4, 1.0])
@pytest.mark.parametrize("tau", [0.005, 0.076, 1.0])
def test_square_matrix_matches_the_definition(cos, tau):
    rng = np.random.default_rng(11)
    obs = random_observations(rng, 8, 5, 3.0)
    obs.append([[] for _ in range(5)])  # an empty sample
    d = van_rossum.square_distance_matrix(obs, cos, tau)
    assert d.dtype == np.float64 and d.shape == (9, 9)
    assert np.all(np.diag(d) == 0.0)
    assert np.array_equal(d, d.T)
    assert_close(d, obs, obs, cos, tau)


@pytest.mark.parametrize("cos", [0.0, 0.7, 1.0])
def test_rectangular_matrix_matches_the_definition(cos):
    rng = np.random.default_rng(12)
    rows = random_observations(rng, 4, 6, 4.0)
    columns = random_observations(rng, 7, 6, 4.0)
    d = van_rossum.distance_matrix(rows, columns, cos, 0.02)
    assert d.shape == (4, 7)
    assert_close(d, rows, columns, cos, 0.02)


def test_realistic_49_taxel_samples():
    rng = np.random.default_rng(13)
    obs = random_observations(rng, 7, 49, 8.0, duration_s=4.5, quantum_s=1e-6)
    for cos in (0.0, 0.4, 1.0):
        assert_close(van_rossum.square_distance_matrix(obs, cos, 0.076), obs, obs, cos, 0.076)


def test_identical_spike_times_count_every_pair():
    # Within-train repeats and cross-unit coincidences (the pooled train repeats times):
    # pymuvr gets these wrong (van-rossum.md §4); the definition counts every pair once.
    obs = [
        [[0.1, 0.1, 0.3], [0.1], [0.3, 0.3]],
        [[0.1], [0.1, 0.1], [0.3]],
        [[0.1, 0.1, 0.3], [0.1], [0.3, 0.3]],
        [[0.3], [], [0.1, 0.3]],
    ]
    for cos in (0.0, 0.5, 1.0):
        d = van_rossum.square_distance_matrix(obs, cos, 0.05)
        assert d[0, 2] == 0.0  # identical observations
        assert_close(d, obs, obs, cos, 0.05)
    # Single unit: ⟨[0.1], [0.1, 0.1]⟩ = 2, so D² = 1 + 4 − 4 = 1.
    d = van_rossum.square_distance_matrix([[[0.1]], [[0.1, 0.1]]], 0.0, 0.01)
    assert d[0, 1] == pytest.approx(1.0, rel=1e-12)


def test_one_spike_against_none_is_one_at_any_cos():
    for cos in (0.0, 0.3, 1.0):
        d = van_rossum.square_distance_matrix([[[0.5], []], [[], []]], cos, 0.076)
        assert d[0, 1] == pytest.approx(1.0, rel=1e-12)


def test_empty_units_samples_and_inputs():
    assert van_rossum.square_distance_matrix([], 0.5, 0.1).shape == (0, 0)
    assert van_rossum.distance_matrix([], [[[0.1]]], 0.5, 0.1).shape == (0, 1)
    assert van_rossum.distance_matrix([[[0.1]]], [], 0.5, 0.1).shape == (1, 0)
    empty = [[[], [], []], [[], [], []]]
    assert np.all(van_rossum.square_distance_matrix(empty, 0.5, 0.1) == 0.0)
    # Zero units per sample.
    assert np.all(van_rossum.square_distance_matrix([[], []], 0.5, 0.1) == 0.0)


def test_tiny_tau_on_microsecond_stamps():
    # τ = 1 µs on 4.5-s data with 1-µs stamps: pymuvr overflows, the definition is finite.
    rng = np.random.default_rng(14)
    obs = random_observations(rng, 5, 4, 20.0, duration_s=4.5, quantum_s=1e-6)
    obs[1][0] = sorted(obs[1][0] + [obs[0][0][0], obs[0][0][0] + 1e-6])  # neighbours 1 µs apart
    for cos in (0.0, 1.0):
        d = van_rossum.square_distance_matrix(obs, cos, 1e-6)
        assert np.all(np.isfinite(d))
        assert_close(d, obs, obs, cos, 1e-6)


def test_huge_tau_is_the_spike_count_limit():
    rng = np.random.default_rng(15)
    obs = random_observations(rng, 6, 5, 5.0)
    for cos in (0.0, 0.6, 1.0):
        d = van_rossum.square_distance_matrix(obs, cos, 1e4)
        assert_close(d, obs, obs, cos, 1e4)
        counts = np.array([[len(u) for u in o] for o in obs], dtype=float)
        delta = counts[:, None, :] - counts[None, :, :]
        limit = (1 - cos) * np.sum(delta**2, axis=2) + cos * np.sum(delta, axis=2) ** 2
        assert np.allclose(d**2, limit, rtol=1e-3, atol=1e-2)


def test_translation_invariance_far_from_zero():
    rng = np.random.default_rng(16)
    obs = random_observations(rng, 5, 3, 6.0)
    shifted = [[[t + 1e5 for t in u] for u in o] for o in obs]
    d = van_rossum.square_distance_matrix(obs, 0.4, 0.076)
    d_shifted = van_rossum.square_distance_matrix(shifted, 0.4, 0.076)
    assert np.allclose(d_shifted**2, d**2, rtol=1e-8, atol=1e-8)


def test_unsorted_ragged_numpy_and_tuple_trains():
    sorted_obs = [[[0.1, 0.2, 0.3], [0.15]], [[0.05], []], [[0.25, 0.4], [0.1, 0.2, 0.3, 0.35]]]
    mixed = [
        [np.array([0.3, 0.1, 0.2]), (0.15,)],
        [[0.05], np.array([])],
        [(0.4, 0.25), [0.35, 0.1, 0.3, 0.2]],
    ]
    expected = van_rossum.square_distance_matrix(sorted_obs, 0.3, 0.05)
    assert np.array_equal(van_rossum.square_distance_matrix(mixed, 0.3, 0.05), expected)
    # Integer times are numbers too.
    assert van_rossum.square_distance_matrix([[[1]], [[2]]], 0.0, 1.0)[0, 1] == pytest.approx(
        math.sqrt(2 - 2 * math.exp(-1)), rel=1e-12
    )


def test_the_flat_entry_point_equals_the_lists():
    rng = np.random.default_rng(17)
    obs = random_observations(rng, 7, 4, 3.0)
    data = neurotac.from_pymuvr(obs)
    flat = van_rossum.square_distance_matrix_flat(
        data["times"], data["units"], data["offsets"], data["n_units"], 0.4, 0.03
    )
    assert np.array_equal(flat, van_rossum.square_distance_matrix(obs, 0.4, 0.03))
    # Spikes of a sample may come in any order.
    offsets = data["offsets"]
    units = np.concatenate([data["units"][a:b][::-1] for a, b in zip(offsets[:-1], offsets[1:])])
    times = np.concatenate([data["times"][a:b][::-1] for a, b in zip(offsets[:-1], offsets[1:])])
    again = van_rossum.square_distance_matrix_flat(times, units, offsets, 4, 0.4, 0.03)
    assert np.array_equal(again, flat)


def test_thread_count_does_not_change_the_matrix():
    rng = np.random.default_rng(18)
    obs = random_observations(rng, 20, 6, 5.0)
    one = van_rossum.square_distance_matrix(obs, 0.4, 0.05, threads=1)
    assert np.array_equal(van_rossum.square_distance_matrix(obs, 0.4, 0.05, threads=2), one)
    assert np.array_equal(van_rossum.square_distance_matrix(obs, 0.4, 0.05), one)


@pytest.mark.parametrize(
    "cos, tau, message",
    [
        (1.5, 0.1, "cos = 1.5: in [0, 1]"),
        (-0.1, 0.1, "cos = -0.1: in [0, 1]"),
        (0.5, 0.0, "tau_s = 0: finite and > 0 (seconds)"),
        (0.5, -1.0, "tau_s = -1: finite and > 0 (seconds)"),
        (0.5, float("nan"), "tau_s = NaN: finite and > 0 (seconds)"),
    ],
)
def test_bad_parameters_are_value_errors_with_the_library_message(cos, tau, message):
    with pytest.raises(ValueError) as e:
        van_rossum.square_distance_matrix([[[0.1]], [[0.2]]], cos, tau)
    assert isinstance(e.value, neurotac.NeurotacError)
    assert str(e.value) == message


def test_bad_spike_trains_name_the_sample():
    with pytest.raises(neurotac.NeurotacValueError, match=r"^sample 1: channel 0, spike 1: time NaN is not finite$"):
        van_rossum.square_distance_matrix([[[0.1]], [[0.2, float("nan")]]], 0.5, 0.1)
    with pytest.raises(neurotac.NeurotacValueError, match=r"^sample 1 has 1 channels, sample 0 has 2$"):
        van_rossum.square_distance_matrix([[[0.1], []], [[0.2]]], 0.5, 0.1)
    with pytest.raises(neurotac.NeurotacValueError, match="sample 0, unit 1: expected a sequence"):
        van_rossum.square_distance_matrix([[[0.1], 0.3]], 0.5, 0.1)
    with pytest.raises(neurotac.NeurotacValueError, match="observations: expected a sequence"):
        van_rossum.square_distance_matrix(3.0, 0.5, 0.1)


def test_the_reference_itself_on_a_hand_computed_pair():
    # One unit, u = [0], v = [1], τ = 1: D² = 1 + 1 − 2e⁻¹.
    d2, _ = squared_distance([[0.0]], [[1.0]], 0.0, 1.0)
    assert d2 == pytest.approx(2 - 2 * math.exp(-1), rel=1e-15)


def test_agrees_with_pymuvr_where_pymuvr_is_exact():
    pymuvr = pytest.importorskip("pymuvr", reason="pymuvr is not installed (optional oracle)")
    rng = np.random.default_rng(19)
    obs = random_observations(rng, 12, 49, 10.0, duration_s=4.5, quantum_s=1e-6)
    obs = [[sorted(set(u)) for u in o] for o in obs]  # pymuvr needs no repeats within a train
    for cos in (0.0, 0.4, 1.0):
        for tau in (0.01, 0.076, 1.0):
            theirs = np.asarray(pymuvr.square_distance_matrix(obs, cos, tau))
            ours = van_rossum.square_distance_matrix(obs, cos, tau)
            assert np.allclose(ours**2, theirs**2, rtol=1e-9, atol=1e-9), (cos, tau)
            rect = van_rossum.distance_matrix(obs[:5], obs[5:], cos, tau)
            theirs_rect = np.asarray(pymuvr.distance_matrix(obs[:5], obs[5:], cos, tau))
            assert np.allclose(rect**2, theirs_rect**2, rtol=1e-9, atol=1e-9), (cos, tau)
