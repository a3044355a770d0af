"""Event files: round trips in every format, the shared DAVIS240 recording, transduction."""

from pathlib import Path

import numpy as np
import pytest

import neurotac

FORMATS = [".aedat", ".aedat2", ".aedat3", ".aedat4", ".txt", ".csv"]
DAVIS240 = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "davis240"


def random_events(n=5000, seed=3):
    rng = np.random.default_rng(seed)
    events = np.empty(n, dtype=neurotac.EVENT_DTYPE)
    events["t"] = 1_000 + np.cumsum(rng.integers(0, 40, n))  # non-decreasing, with ties
    events["x"] = rng.integers(0, 240, n)
    events["y"] = rng.integers(0, 180, n)
    events["p"] = rng.integers(0, 2, n).astype(bool)
    return events


@pytest.mark.parametrize("extension", FORMATS)
def test_round_trip_in_every_format(tmp_path, extension):
    events = random_events()
    path = tmp_path / f"events{extension}"
    neurotac.write_events(path, events)
    back = neurotac.read_events(path)
    assert back.dtype == neurotac.EVENT_DTYPE
    assert np.array_equal(back, events)
    # str paths work too, and an empty recording stays empty.
    neurotac.write_events(str(path), events[:0])
    assert len(neurotac.read_events(str(path))) == 0


def test_write_accepts_a_dict_and_integer_polarity(tmp_path):
    events = random_events(100)
    as_dict = {k: events[k] for k in ("t", "x", "y")}
    as_dict["p"] = events["p"].astype(np.int8)
    path = tmp_path / "e.csv"
    neurotac.write_events(path, as_dict)
    assert np.array_equal(neurotac.read_events(path), events)


def test_a_missing_file_is_an_os_error_naming_it(tmp_path):
    missing = tmp_path / "no-such-recording.aedat4"
    with pytest.raises(OSError) as e:
        neurotac.read_events(missing)
    assert isinstance(e.value, neurotac.NeurotacError)
    assert str(e.value).startswith(f"cannot read {missing}: ")
    assert "No such file or directory" in str(e.value)
    with pytest.raises(neurotac.NeurotacOSError, match="no-such-recording"):
        neurotac.transduce(missing)


def test_bad_files_and_names_carry_the_cli_message(tmp_path):
    junk = tmp_path / "junk.bin"
    junk.write_bytes(b"\x00\x01 not events")
    with pytest.raises(neurotac.NeurotacError, match=r"junk\.bin: not an event file: at byte 0"):
        neurotac.read_events(junk)
    with pytest.raises(neurotac.NeurotacError, match="cannot tell the event format from the extension"):
        neurotac.write_events(tmp_path / "events.dat", random_events(3))
    with pytest.raises(neurotac.NeurotacValueError, match="x = 70000 is not a pixel coordinate"):
        neurotac.write_events(tmp_path / "e.csv", {"t": [1], "x": [70000], "y": [1], "p": [True]})
    with pytest.raises(neurotac.NeurotacValueError, match="fields t, x, y, p"):
        neurotac.write_events(tmp_path / "e.csv", np.zeros(3))


@pytest.fixture(scope="module")
def davis240():
    if not (DAVIS240 / "pick_raw_jaer_fields.npy").is_file():
        pytest.skip(f"the shared DAVIS240 recording is not at {DAVIS240} (shared/ beside the repository)")
    raw_x, raw_y, t, p = np.load(DAVIS240 / "pick_raw_jaer_fields.npy").astype(np.int64)
    # The oracle holds raw jAER fields: top-left x = 239 − rawX, y = 179 − rawY (README there).
    expected = np.empty(len(t), dtype=neurotac.EVENT_DTYPE)
    expected["t"], expected["x"], expected["y"], expected["p"] = t, 239 - raw_x, 179 - raw_y, p == 1
    return expected


def test_an_unreliable_automatic_layout_is_refused_unless_accepted(davis240):
    # The shared recording is a hand picking parts, not a NeuroTac: no pin rings to find.
    path = DAVIS240 / "pick.aedat"
    with pytest.raises(neurotac.NeurotacValueError, match="unreliable .*accept_uncertain_layout=True"):
        neurotac.transduce(path, layout="auto")
    accepted = neurotac.transduce(path, layout="auto", accept_uncertain_layout=True)
    assert accepted["meta"]["layout"] == "auto"


@pytest.mark.parametrize(
    "name",
    ["pick.aedat", "pick_none.aedat4", "pick_lz4.aedat4", "pick_zstd.aedat4", "pick_events.csv", "pick_events.txt"],
)
def test_the_shared_recording_matches_the_raw_oracle(davis240, name):
    events = neurotac.read_events(DAVIS240 / name)
    assert len(events) == 118_558
    assert np.array_equal(events, davis240)
    assert int(events["p"].sum()) == 75_525


def test_transducing_a_file_or_its_events_gives_the_same_trains(davis240, tmp_path):
    path = tmp_path / "pick.aedat4"
    neurotac.write_events(path, davis240)
    from_file = neurotac.transduce(path, label="pick")
    from_events = neurotac.transduce(davis240, label="pick")
    assert from_file["n_units"] == 49 and len(from_file["offsets"]) == 2
    assert from_file["class_names"] == ["pick"] and list(from_file["labels"]) == [0]
    for key in ("times", "units", "offsets"):
        assert np.array_equal(from_file[key], from_events[key]), key
    meta = from_file["meta"]
    assert meta["pixel_events"] == 118_558 and meta["layout"] == "default"
    assert meta["transduction"]["ba_window_us"] == 5000
    assert from_events["meta"]["source"] == "<events>"
    assert len(from_file["times"]) > 0
    assert np.all(np.diff(from_file["times"][from_file["units"] == 0]) >= 0)


def test_transduction_settings_are_checked():
    events = random_events(50)
    with pytest.raises(neurotac.NeurotacValueError, match="pool_s = 0.0: expected a finite number of seconds > 0"):
        neurotac.transduce(events, pool_s=0.0)
    # The old name in ms still works (with a DeprecationWarning), checked the same way.
    with pytest.warns(DeprecationWarning, match="pool_ms= is deprecated: use pool_s="):
        with pytest.raises(neurotac.NeurotacValueError, match="pool_s = 0.0"):
            neurotac.transduce(events, pool_ms=0.0)
    with pytest.warns(DeprecationWarning):
        old = neurotac.transduce(events, pool_ms=40.0, ba_window_us=2000)
    new = neurotac.transduce(events, pool_s=0.04, ba_window_s=0.002)
    assert np.array_equal(old["times"], new["times"]) and old["meta"] == new["meta"]
    with pytest.raises(neurotac.NeurotacError, match="re-centring gain = 2: in \\[0, 1\\]"):
        neurotac.transduce(events, gain=2.0)
    with pytest.raises(neurotac.NeurotacValueError, match="layout='auto'"):
        neurotac.transduce(events, layout="auto")
    unsorted = events.copy()
    unsorted["t"][1] = unsorted["t"][0] - 1
    with pytest.raises(neurotac.NeurotacError, match="^transducing <events>: event 1: timestamp .* earlier than the previous"):
        neurotac.transduce(unsorted)
    unlabelled = neurotac.transduce(events)
    assert len(unlabelled["labels"]) == 0 and unlabelled["class_names"] == []
