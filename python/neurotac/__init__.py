"""neurotac: spiking neural networks for neuromorphic touch (NeuroTac), from Python.

The work is done in Rust (the neurotac crates); this package is a thin layer over the extension
module ``neurotac._native``.

- Event files: :func:`read_events`, :func:`write_events` (AEDAT 2.0 / 3.1 / 4.0, ECD text, CSV),
  as NumPy structured arrays of :data:`EVENT_DTYPE`.
- Taxel spike trains: :func:`transduce` (pixel events → 49 taxels), :func:`simulate` (the
  simulated texture sets), :func:`load_dataset`, :func:`save_dataset`.
- A spike dataset is a dict of flat NumPy arrays: ``times`` (float64 s), ``units`` (uint32),
  ``offsets`` (int64, ``n_samples + 1``), ``n_units``, ``labels`` (int64), ``class_names``,
  ``meta``; :func:`to_pymuvr` / :func:`from_pymuvr` convert to and from pymuvr's nested lists.
- :mod:`neurotac.van_rossum`: pymuvr's ``square_distance_matrix`` and ``distance_matrix``.
- :mod:`neurotac.coding`: the paper's four codings; :class:`Knn`: the KNN head.
- :class:`NetworkBuilder`: define a spiking network — LIF and Izhikevich populations, spike,
  Poisson and current inputs, projections with exponential synapses, delays and STDP, state
  monitors — and build it; :class:`Network`: a built network (or one loaded from a saved file
  or a JSON description), run with input spike trains, its spikes, population rates, sampled
  state, weights and learning switch read and set, saved again; :mod:`neurotac.nir`
  (``import neurotac.nir``, needs the ``nir`` package) turns it into a NIR graph and back.
- Units: every time is in seconds and named ``…_s`` (``dt_s``, ``tau_s``, ``pool_s``), every
  rate ``…_hz``; older names still work with a ``DeprecationWarning``.
- Errors: :class:`NeurotacError` (and its subclasses :class:`NeurotacValueError`, also a
  ``ValueError``, and :class:`NeurotacOSError`, also an ``OSError``), carrying the message the
  ``neurotac`` CLI prints.
"""

import os as _os

import numpy as _np

from . import _native
from ._native import (
    Knn,
    Network,
    NeurotacError,
    NeurotacOSError,
    NeurotacValueError,
    __version__,
    from_pymuvr,
    load_dataset,
    save_dataset,
    simulate,
    to_pymuvr,
)
from . import coding, van_rossum
from ._units import renamed, seconds
from .network import NetworkBuilder, Stdp

#: The structured dtype of events: t (int64 µs), x and y (uint16, top-left), p (bool, ON).
EVENT_DTYPE = _np.dtype([("t", "<i8"), ("x", "<u2"), ("y", "<u2"), ("p", "?")])

__all__ = [
    "EVENT_DTYPE",
    "Knn",
    "Network",
    "NetworkBuilder",
    "NeurotacError",
    "NeurotacOSError",
    "NeurotacValueError",
    "coding",
    "from_pymuvr",
    "load_dataset",
    "read_events",
    "save_dataset",
    "simulate",
    "Stdp",
    "to_pymuvr",
    "transduce",
    "van_rossum",
    "write_events",
]


def read_events(path):
    """Read every event of an event file as a structured array of :data:`EVENT_DTYPE`.

    The format (AEDAT 2.0, 3.1, 4.0, ECD text or CSV) is detected from the file's first bytes.
    Events the reader skips (outside the sensor, non-polarity records) or timestamps going
    backwards are reported by a ``UserWarning``, as the CLI reports them.
    """
    t, x, y, p = _native.read_event_arrays(path)
    events = _np.empty(len(t), dtype=EVENT_DTYPE)
    events["t"], events["x"], events["y"], events["p"] = t, x, y, p
    return events


def _fields(events):
    """The arrays (t, x, y, p) of a structured array or a mapping with those keys."""
    try:
        return tuple(_np.asarray(events[k]) for k in ("t", "x", "y", "p"))
    except (KeyError, ValueError, IndexError, TypeError) as e:
        raise NeurotacValueError(
            "events must be a structured array (or a dict) with fields t, x, y, p"
        ) from e


def write_events(path, events, sensor=None):
    """Write events (a structured array or a dict with t, x, y, p) to ``path``.

    The format comes from the extension: ``.aedat``/``.aedat2`` AEDAT 2.0, ``.aedat3`` AEDAT 3.1,
    ``.aedat4`` AEDAT 4.0 (LZ4), ``.txt`` ECD text, ``.csv`` CSV. The file is replaced
    atomically. ``p`` may be bool or any integer type (non-zero is ON). ``sensor`` is the
    ``(width, height)`` the file states (default ``(240, 180)``): AEDAT 4.0 as ``sizeX``/``sizeY``,
    AEDAT 2.0 and 3.1 by camera name (DAVIS240 or DAVIS346 only), text and CSV by a first line
    ``# sensor WIDTHxHEIGHT``; a size the format cannot state, or an event outside it, raises.
    """
    t, x, y, p = _fields(events)
    _native.write_event_arrays(path, t, x, y, p != 0, sensor)


def transduce(source, layout=None, **settings):
    """The 49 taxel spike trains of pixel events, as a one-sample dataset dict.

    ``source`` is an event-file path (as ``neurotac transduce FILE``) or events in memory (a
    structured array or a dict with t, x, y, p). ``layout``: ``None``/``"default"`` (the
    NeuroTac pins), ``"auto"`` (detected from the head of a file) or a JSON file of ``[x, y]``
    centres. Keyword settings, with the CLI's defaults (times in seconds): ``label=None``,
    ``ba_window_s=0.005`` (0 disables the background-activity filter),
    ``ba_empty_start=False``, ``rf_radius_px=3.0``, ``pool_s=0.02``, ``gain=0.5``
    (re-centring) and, for files, ``calibration_s=1.0`` and ``accept_uncertain_layout=False``
    (``layout="auto"``: a layout whose confidence is below the calibrated threshold raises
    ``NeurotacValueError`` unless accepted). The older ``ba_window_us``, ``pool_ms`` and
    ``calibration_ms`` still work, with a ``DeprecationWarning``.
    """
    renamed(settings, "ba_window_us", "ba_window_s", 1e-6)
    renamed(settings, "pool_ms", "pool_s", 1e-3)
    renamed(settings, "calibration_ms", "calibration_s", 1e-3)
    native = {k: v for k, v in settings.items() if k not in _TRANSDUCE_SECONDS}
    if "ba_window_s" in settings:
        native["ba_window_us"] = int(round(seconds("ba_window_s", settings["ba_window_s"], False) * 1e6))
    if "pool_s" in settings:
        native["pool_ms"] = seconds("pool_s", settings["pool_s"]) * 1e3
    is_file = isinstance(source, (str, bytes, _os.PathLike))
    if is_file:
        native["calibration_ms"] = seconds("calibration_s", settings.get("calibration_s", 1.0)) * 1e3
        return _native.transduce_path(source, layout, **native)
    if "calibration_s" in settings:
        raise NeurotacValueError("calibration_s: only a file is calibrated (layout='auto' needs a file)")
    t, x, y, p = _fields(source)
    return _native.transduce_events(t, x, y, p != 0, layout, **native)


#: transduce's settings in seconds, converted to the native call's units.
_TRANSDUCE_SECONDS = ("ba_window_s", "pool_s", "calibration_s")
