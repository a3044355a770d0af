"""The bindings against the `neurotac` command's own outputs: the same dataset, distances and
numpy files. Uses the binary of this repository's build (`target/release/neurotac`, or
`$NEUROTAC_BIN`); skipped with the reason when it has not been built."""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import neurotac

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = pathlib.Path(os.environ.get("NEUROTAC_BIN", ROOT / "target" / "release" / "neurotac"))

pytestmark = pytest.mark.skipif(
    not BIN.is_file(),
    reason=f"the neurotac command is not built at {BIN} (cargo build --release -p neurotac-cli)",
)


def cli(*args):
    done = subprocess.run([str(BIN), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    path = tmp_path_factory.mktemp("cli") / "d.bin"
    cli("synth", "--output", path, "--samples", "30", "--classes", "3", "--spikes-per-unit", "6", "--seed", "5")
    return path


def test_export_npz_holds_the_dataset_the_bindings_read(dataset, tmp_path):
    npz = tmp_path / "d.npz"
    cli("export", dataset, npz)
    archive = np.load(npz)
    data = neurotac.load_dataset(dataset)
    for key in ("times", "units", "offsets", "labels"):
        assert np.array_equal(archive[key], data[key]), key
        assert archive[key].dtype == data[key].dtype, key
    meta = json.loads(archive["meta.json"])
    assert meta["n_units"] == data["n_units"] and meta["class_names"] == data["class_names"]
    assert meta["meta"] == data["meta"]


def test_distance_matrices_equal_the_cli_npy_and_npz(dataset, tmp_path):
    data = neurotac.load_dataset(dataset)
    cli("distances", "--input", dataset, "--metric", "van-rossum", "--tau", "0.05s", "--cos", "0.4",
        "--output", tmp_path / "vr.npy")
    ours = neurotac.coding.distances(data, "spatiotemporal", tau=0.05, cos=0.4)
    assert np.array_equal(np.load(tmp_path / "vr.npy"), ours)
    cli("distances", "--input", dataset, "--metric", "euclidean", "--coding", "temporal", "--dt", "0.1s",
        "--output", tmp_path / "t.npz")
    ours = neurotac.coding.distances(data, "temporal", dt=0.1)
    assert np.array_equal(np.load(tmp_path / "t.npz")["matrix"], ours)


def test_an_unknown_output_extension_is_refused(dataset, tmp_path):
    done = subprocess.run([str(BIN), "distances", "--input", str(dataset), "--metric", "van-rossum",
                           "--tau", "50ms", "--cos", "0.4", "--output", str(tmp_path / "vr.txt")],
                          capture_output=True, text=True)
    assert done.returncode != 0
    assert "unknown output extension" in done.stderr and not (tmp_path / "vr.txt").exists()
