"""Numbers are never silently changed on their way in: a value that does not fit the integer
type it is read as (a fraction, NaN, out of range) is refused, and a dataset is written in the
format its file name says or refused."""

import numpy as np
import pytest

import neurotac


def test_a_unit_out_of_range_is_refused_not_wrapped():
    times = [0.1, 0.2]
    with pytest.raises(neurotac.NeurotacValueError, match="expected integers that fit"):
        neurotac.van_rossum.square_distance_matrix_flat(times, [0, 2**32], [0, 1, 2], 2, 0.5, 0.01)


def test_a_fractional_label_is_refused_not_truncated():
    with pytest.raises(neurotac.NeurotacValueError, match="expected integers that fit"):
        neurotac.Knn(1).fit([0.9, 1])
    # Whole numbers given as floats are fine.
    neurotac.Knn(1).fit(np.array([0.0, 1.0]))


def test_a_nan_event_time_is_refused_not_written_as_int64_min(tmp_path):
    events = {"t": np.array([0.0, np.nan]), "x": [1, 2], "y": [3, 4], "p": [1, 0]}
    path = tmp_path / "e.csv"
    with pytest.raises(neurotac.NeurotacValueError, match="expected integers that fit"):
        neurotac.write_events(path, events)
    assert not path.exists()


def test_a_dataset_is_written_as_its_extension_says_or_refused(tmp_path):
    data = neurotac.from_pymuvr([[[0.1], [0.2, 0.3]]], labels=[0], class_names=["a"])
    neurotac.save_dataset(tmp_path / "d.npz", data)
    with np.load(tmp_path / "d.npz") as npz:
        assert list(npz["times"]) == [0.1, 0.2, 0.3]
        assert list(npz["units"]) == [0, 1, 1]
    with pytest.raises(neurotac.NeurotacValueError, match="dat"):
        neurotac.save_dataset(tmp_path / "d.dat", data)
    assert not (tmp_path / "d.dat").exists()
