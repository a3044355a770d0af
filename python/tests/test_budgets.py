"""Sizes, durations, counts and threads are checked against a stated budget before anything is
allocated or simulated: one number can't kill or hang the interpreter, it raises an error that
names it and its limit."""

import pytest

import neurotac


def test_a_unit_count_over_the_budget_is_refused():
    with pytest.raises(neurotac.NeurotacValueError, match=r"n_units = 1099511627776 .* limit"):
        neurotac.van_rossum.square_distance_matrix_flat([0.1], [0], [0, 1], 2**40, 0.5, 0.01)
    data = neurotac.from_pymuvr([[[0.1], [0.2]]], labels=[0], class_names=["a"])
    data["n_units"] = 2**40
    with pytest.raises(neurotac.NeurotacValueError, match="n_units = 1099511627776"):
        neurotac.coding.spatial(data)


def test_a_temporal_duration_over_the_budget_is_refused():
    data = neurotac.from_pymuvr([[[0.1], [0.2]]], labels=[0], class_names=["a"])
    with pytest.raises(neurotac.NeurotacValueError, match="at most 3 600 000 ms"):
        neurotac.coding.temporal(data, 0.01, duration=4e6)


def test_a_trial_count_over_the_budget_is_refused_before_simulating():
    with pytest.raises(neurotac.NeurotacValueError, match="limit of 100000 simulated trials"):
        neurotac.simulate("artificial", trials=10**15)


def test_a_thread_count_over_the_budget_is_refused_before_any_thread_starts():
    data = neurotac.from_pymuvr([[[0.1], [0.2]]], labels=[0], class_names=["a"])
    with pytest.raises(neurotac.NeurotacError, match="limit of 1024 threads"):
        neurotac.coding.spatiotemporal(data, 0.01, 0.5, threads=10**6)
