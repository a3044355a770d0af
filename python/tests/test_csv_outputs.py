"""Every CSV the `neurotac` command writes loads with Python's `csv` module as written: each
command that writes CSV runs on a small input, and every `.csv` it wrote is read with
`csv.reader` (a header of distinct names, every row as long as it). Class names holding a comma,
quotes and a `|` come back as they were. Uses the binary of this repository's build
(`target/release/neurotac`, or `$NEUROTAC_BIN`); skipped with the reason when it has not been
built."""

import csv
import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = pathlib.Path(os.environ.get("NEUROTAC_BIN", ROOT / "target" / "release" / "neurotac"))

pytestmark = pytest.mark.skipif(
    not BIN.is_file(),
    reason=f"the neurotac command is not built at {BIN} (cargo build --release -p neurotac-cli)",
)

CLASSES = ['fine, "soft"|ribbed', "plain"]


def cli(*args):
    done = subprocess.run([str(BIN), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, f"neurotac {' '.join(map(str, args))}: {done.stderr}"


def read(path):
    """The header and rows of a CSV file, as Python's csv module reads it."""
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    assert len(set(header)) == len(header) and all(header), f"{path}: {header}"
    for i, row in enumerate(body, start=2):
        assert len(row) == len(header), f"{path}, record {i}: {len(row)} fields, header {len(header)}"
    return header, body


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    """Runs every command that writes CSV once; returns {command: its output folder}."""
    root = tmp_path_factory.mktemp("csv")
    cache = root / "cache"
    out = {}
    # simulate's pixel events as CSV (they are also the slides of a recorded set below), and
    # with the source pin of every event.
    out["simulate"] = root / "simulated"
    cli("simulate", "--set", "artificial", "--trials", "4", "--cache", cache, "--out", out["simulate"],
        "--pixel-events", "--event-format", "csv")
    out["simulate --labels"] = root / "labelled"
    cli("simulate", "--set", "artificial", "--trials", "1", "--cache", cache, "--out",
        out["simulate --labels"], "--pixel-events", "--labels")
    # reproduce on a recorded set of two classes with awkward names.
    data = root / "recorded"
    folders = sorted((out["simulate"] / "events").iterdir())
    for name, folder in zip(CLASSES, [folders[0], folders[-1]]):
        shutil.copytree(folder, data / name)
    out["reproduce"] = root / "report"
    cli("reproduce", "--dataset", data, "--epochs", "8", "--tau-step", "30ms", "--out", out["reproduce"])
    out["tradeoff"] = root / "tradeoff"
    cli("tradeoff", "--quick", "--trials", "3", "--epochs", "10", "--cache", cache, "--out", out["tradeoff"])
    out["tradeoff neurons, simulator"] = root / "trades"
    cli("tradeoff", "neurons", "--quick", "--out", out["tradeoff neurons, simulator"])
    cli("tradeoff", "simulator", "--quick", "--out", out["tradeoff neurons, simulator"])
    out["recognise --eval"] = root / "eval"
    cli("recognise", "--eval", "--set", "artificial", "--trials", "5", "--cache", cache, "--out",
        out["recognise --eval"])
    out["convert, filter"] = root / "events"
    out["convert, filter"].mkdir()
    slide = next((data / CLASSES[0]).iterdir())
    cli("convert", slide, out["convert, filter"] / "converted.csv")
    cli("filter", slide, out["convert, filter"] / "filtered.csv")
    return out


def test_every_csv_loads_with_as_many_fields_as_its_header(outputs):
    for command, folder in outputs.items():
        files = sorted(folder.rglob("*.csv"))
        assert files, f"{command} wrote no CSV"
        for path in files:
            read(path)


def test_names_with_commas_and_quotes_come_back_as_written(outputs):
    report = outputs["reproduce"]
    header, rows = read(report / "loo_recall.csv")
    assert header[:2] == ["set", "class"]
    assert [r[1] for r in rows] == CLASSES
    header, rows = read(next(report.glob("confusion_loo_*_temporal.csv")))
    assert header[1:] == CLASSES and [r[0] for r in rows] == CLASSES
    header, rows = read(outputs["tradeoff"] / "artificial" / "transduction" / "transduction.csv")
    assert header[0] == "setting" and header[-2:] == ["front", "recommended"]
    assert rows[0][0] == "pool 20 ms, BA 5 ms"
    header, rows = read(outputs["tradeoff"] / "artificial" / "simulator" / "simulator.csv")
    assert rows[0][0] == "tolerance 0.02, mechanics 0.25 ms, shear 25 µs"
    labelled = next((outputs["simulate --labels"] / "events").rglob("*.csv"))
    assert read(labelled)[0] == ["t", "x", "y", "on", "pin"]
