"""The paper's four spike codings of a dataset dict.

``intensive(ds)``, ``spatial(ds)`` and ``temporal(ds, dt_s, duration_s=None)`` return feature
matrices (one row per sample); ``spatiotemporal(ds, tau_s, cos)`` the Van Rossum distance
matrix; ``distances(ds, coding, dt_s=…, tau_s=…, cos=…)`` the N × N distance matrix of any of
the four, as ``neurotac distances`` computes it (Euclidean on the features, Van Rossum for
spatiotemporal). Times are seconds (``dt_s``, ``duration_s``, ``tau_s``); the older names
``dt``, ``duration`` and ``tau`` still work, with a ``DeprecationWarning``.
"""

from . import _native
from ._native import intensive, spatial
from ._units import renamed

__all__ = ["distances", "intensive", "spatial", "spatiotemporal", "temporal"]


def temporal(dataset, dt_s=None, duration_s=None, **old):
    """Temporal coding: an ``N × W`` matrix; feature ``s`` of a sample is the number of spikes
    of all units in the window ``[s, s + dt)`` ms divided by ``n_units``, for ``s = 0, 1, …,
    T − dt`` ms (``W = T − dt + 1``). ``dt_s`` and ``duration_s`` are seconds, whole
    milliseconds; ``duration_s`` (``T``) defaults to ``meta["duration_s"]``, else one ms past
    the latest spike."""
    kwargs = {"dt_s": dt_s, "duration_s": duration_s}
    kwargs = {k: v for k, v in kwargs.items() if v is not None}
    kwargs.update(old)
    renamed(kwargs, "dt", "dt_s")
    renamed(kwargs, "duration", "duration_s")
    _refuse_unknown(kwargs, ("dt_s", "duration_s"), "temporal")
    if kwargs.get("dt_s") is None:
        raise TypeError("temporal() needs dt_s, the window (s)")
    return _native.temporal(dataset, kwargs["dt_s"], kwargs.get("duration_s"))


def spatiotemporal(dataset, tau_s=None, cos=None, *, threads=None, **old):
    """Spatiotemporal coding: the ``N × N`` multi-unit Van Rossum distances of the samples at
    ``tau_s`` (s) and ``cos`` ∈ [0, 1] (pymuvr's normalisation). The GIL is released while
    computing."""
    kwargs = {"tau_s": tau_s} if tau_s is not None else {}
    kwargs.update(old)
    renamed(kwargs, "tau", "tau_s")
    _refuse_unknown(kwargs, ("tau_s",), "spatiotemporal")
    if kwargs.get("tau_s") is None or cos is None:
        raise TypeError("spatiotemporal() needs tau_s (s) and cos")
    return _native.spatiotemporal(dataset, kwargs["tau_s"], cos, threads=threads)


def distances(dataset, coding, *, dt_s=None, duration_s=None, tau_s=None, cos=None,
              threads=None, **old):
    """The ``N × N`` distance matrix of ``dataset`` under ``coding`` (``"intensive"``,
    ``"spatial"``, ``"temporal"`` — Euclidean distances of the features — or
    ``"spatiotemporal"``, the Van Rossum distance), as ``neurotac distances`` computes it: the
    temporal coding needs ``dt_s`` (s, whole ms; ``duration_s`` as in :func:`temporal`), the
    spatiotemporal ``tau_s`` (s) and ``cos``. ``threads`` as in
    ``van_rossum.square_distance_matrix``."""
    kwargs = {"dt_s": dt_s, "duration_s": duration_s, "tau_s": tau_s}
    kwargs = {k: v for k, v in kwargs.items() if v is not None}
    kwargs.update(old)
    renamed(kwargs, "dt", "dt_s")
    renamed(kwargs, "duration", "duration_s")
    renamed(kwargs, "tau", "tau_s")
    _refuse_unknown(kwargs, ("dt_s", "duration_s", "tau_s"), "distances")
    return _native.distances(
        dataset,
        coding,
        dt=kwargs.get("dt_s"),
        duration=kwargs.get("duration_s"),
        tau=kwargs.get("tau_s"),
        cos=cos,
        threads=threads,
    )


def _refuse_unknown(kwargs, known, function):
    extra = sorted(set(kwargs) - set(known))
    if extra:
        raise TypeError(f"{function}() got an unexpected keyword argument '{extra[0]}'")
