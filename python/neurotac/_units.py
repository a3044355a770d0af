"""The package's one rule for quantities: every time is in seconds and its name ends in ``_s``
(``dt_s``, ``tau_s``, ``pool_s``), as in the Rust library; a rate ends in ``_hz``.

:func:`renamed` keeps the older names (``dt=``, ``pool_ms=``, ``ba_window_us=``…) working
for one more release, converted and with a ``DeprecationWarning`` naming the new one.
"""

import warnings

from ._native import NeurotacValueError


def renamed(kwargs, old, new, scale=1.0, stacklevel=3):
    """Moves ``kwargs[old]`` (a deprecated name) to ``kwargs[new]``, multiplied by ``scale``
    (``pool_ms`` → ``pool_s``: 1e-3), warning once per call site. Giving both raises
    :class:`NeurotacValueError` naming them."""
    if old not in kwargs:
        return
    value = kwargs.pop(old)
    if new in kwargs:
        raise NeurotacValueError(f"{old} and {new} given: {old} is the old name of {new}")
    warnings.warn(
        f"{old}= is deprecated: use {new}= (seconds)" if scale != 1.0
        else f"{old}= is deprecated: use {new}=",
        DeprecationWarning,
        stacklevel=stacklevel,
    )
    kwargs[new] = None if value is None else value * scale


def seconds(name, value, positive=True):
    """``value`` as a float number of seconds, refused (naming ``name``) unless finite and
    > 0 (``positive``) or ≥ 0."""
    try:
        x = float(value)
    except (TypeError, ValueError) as e:
        raise NeurotacValueError(f"{name} = {value!r}: expected a number of seconds") from e
    if not (x == x and abs(x) != float("inf")) or (x <= 0 if positive else x < 0):
        raise NeurotacValueError(
            f"{name} = {value!r}: expected a finite number of seconds "
            + ("> 0" if positive else "≥ 0")
        )
    return x
