"""Spike datasets: the dict form, pymuvr's lists, files, simulated texture sets."""

import numpy as np
import pytest

import neurotac

RAGGED = [
    [[0.3, 0.1], [], [0.2, 0.25, 0.9]],
    [[], [], []],
    [[0.05], [0.4, 0.4], []],
]


def test_pymuvr_lists_round_trip_through_the_flat_form():
    data = neurotac.from_pymuvr(RAGGED, labels=[1, 0, 1], class_names=["a", "b"], meta={"k": [1, 2]})
    assert data["times"].dtype == np.float64 and data["units"].dtype == np.uint32
    assert data["offsets"].dtype == np.int64 and data["labels"].dtype == np.int64
    assert list(data["offsets"]) == [0, 5, 5, 8]
    assert data["n_units"] == 3
    assert list(data["units"][:5]) == [0, 0, 2, 2, 2]
    assert list(data["times"][:2]) == [0.1, 0.3]  # each train sorted
    assert data["class_names"] == ["a", "b"] and data["meta"] == {"k": [1, 2]}
    back = neurotac.to_pymuvr(data)
    assert back == [[sorted(u) for u in o] for o in RAGGED]


def test_files_round_trip_in_json_and_binary(tmp_path):
    data = neurotac.from_pymuvr(RAGGED, labels=[0, 1, 0], class_names=["x", "y"], meta={"duration_s": 1.0})
    for name in ("d.json", "d.bin"):
        neurotac.save_dataset(tmp_path / name, data)
        back = neurotac.load_dataset(tmp_path / name)
        for key in ("times", "units", "offsets", "labels"):
            assert np.array_equal(back[key], data[key]), (name, key)
        assert back["class_names"] == data["class_names"] and back["meta"] == data["meta"]
        assert back["n_units"] == 3
    assert (tmp_path / "d.json").read_text().startswith("{")


def test_invalid_datasets_are_value_errors():
    with pytest.raises(neurotac.NeurotacValueError, match="3 labels for 2 observations"):
        neurotac.from_pymuvr(RAGGED[:2], labels=[0, 1, 2])
    with pytest.raises(neurotac.NeurotacValueError, match="label 1 is -1"):
        neurotac.from_pymuvr(RAGGED[:2], labels=[0, -1])
    with pytest.raises(neurotac.NeurotacValueError, match="observation 1: label 3 but only 2 class names"):
        neurotac.from_pymuvr(RAGGED[:2], labels=[0, 3], class_names=["a", "b"])
    data = neurotac.from_pymuvr(RAGGED)
    with pytest.raises(neurotac.NeurotacValueError, match="offsets must start at 0"):
        neurotac.to_pymuvr({**data, "offsets": np.array([0, 5, 4, 8])})
    with pytest.raises(neurotac.NeurotacValueError, match="spike on channel 2, but there are only 2 channels"):
        neurotac.to_pymuvr({**data, "n_units": 2})
    with pytest.raises(neurotac.NeurotacValueError, match="the dataset has no 'times'"):
        neurotac.to_pymuvr({"units": [], "offsets": [0]})


def test_a_missing_dataset_file_names_it(tmp_path):
    with pytest.raises(neurotac.NeurotacOSError, match="nope.bin"):
        neurotac.load_dataset(tmp_path / "nope.bin")


def test_simulated_set_is_seeded_and_cached(tmp_path):
    data = neurotac.simulate("artificial", trials=1, seed=7, threads=2)
    assert data["n_units"] == 49
    assert list(data["labels"]) == list(range(11)) and len(data["class_names"]) == 11
    assert len(data["offsets"]) == 12 and len(data["times"]) > 0
    assert data["meta"]["seed"] == 7 and data["meta"]["duration_s"] > 0
    cached = neurotac.simulate("artificial", trials=1, seed=7, cache_dir=tmp_path)
    again = neurotac.simulate("artificial", trials=1, seed=7, cache_dir=tmp_path, threads=1)
    assert len(list(tmp_path.iterdir())) == 1
    for d in (cached, again):
        assert np.array_equal(d["times"], data["times"]) and np.array_equal(d["units"], data["units"])
    with pytest.raises(neurotac.NeurotacValueError, match="set = 'rough': expected 'artificial' or 'natural'"):
        neurotac.simulate("rough")
    with pytest.raises(neurotac.NeurotacError):
        neurotac.simulate("natural", trials=0)


def test_simulate_keeps_its_datasets_in_the_clis_cache_by_default(tmp_path, monkeypatch):
    monkeypatch.setenv("NEUROTAC_CACHE", str(tmp_path / "cache"))
    first = neurotac.simulate("artificial", trials=1, seed=4)
    cached = list((tmp_path / "cache").iterdir())
    assert len(cached) == 1, cached  # the file neurotac simulate --cache would write
    again = neurotac.simulate("artificial", trials=1, seed=4)
    assert np.array_equal(first["times"], again["times"])
    # cache=False neither reads nor writes one.
    monkeypatch.setenv("NEUROTAC_CACHE", str(tmp_path / "other"))
    neurotac.simulate("artificial", trials=1, seed=4, cache=False)
    assert not (tmp_path / "other").exists()
    with pytest.raises(neurotac.NeurotacValueError, match="cache=False with a cache_dir"):
        neurotac.simulate("artificial", trials=1, cache=False, cache_dir=str(tmp_path))
