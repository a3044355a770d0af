"""What the NIR export and import share: the error, the neurotac metadata record, the
description's format, and small readers of NIR node fields that name the node they refuse."""

import numpy as _np

from .. import NeurotacValueError

#: Key of neurotac's settings in ``NIRGraph.metadata`` (a JSON string, so it survives HDF5).
METADATA_KEY = "neurotac"
#: The network description's format and version.
FORMAT = "neurotac-network"
VERSION = 1
#: The record in the metadata, and its version.
META_FORMAT = "neurotac-nir"
META_VERSION = 1
#: neurotac's model names.
LIF = "lif"
IF = "if"
#: The most neurons of a population, or channels of an ``Input``, an imported graph may have (a
#: spike train, and parameter values, are made for each).
MAX_SIZE = 2**22
#: The longest delay of an imported projection, in steps (the library's
#: ``graph::limits::MAX_DELAY_STEPS``).
MAX_DELAY_STEPS = 2**20
#: A synapse whose current lasts one step: ``τ_syn = ONE_STEP·dt``, so that its decay factor
#: ``e^(−dt/τ_syn) = e^(−1000)`` is exactly 0 in float64. An imported NIR neuron fed without a
#: synapse receives its spikes through such projections (the module docs of ``neurotac.nir``).
ONE_STEP = 1e-3
#: A projection is a one-step one when ``e^(−dt/τ_syn)`` is 0 (below ``dt/745`` it underflows).
ONE_STEP_MAX = 1.0 / 745.0


class NirError(NeurotacValueError):
    """A network or NIR graph the mapping cannot translate; ``node`` names the node."""

    def __init__(self, node, message):
        super().__init__(f"{node}: {message}")
        #: The neurotac or NIR node (or projection) refused.
        self.node = node


def full(n, value):
    """``n`` copies of ``value`` as float64."""
    return _np.full(int(n), float(value), dtype=_np.float64)


def size_of(node):
    """The number of neurons or channels of a description's node."""
    if node["kind"] == "population":
        return node["model"]["size"]
    ((kind, source),) = node["source"].items()
    return len(source["trains"]) if kind == "spike_array" else source["size"]


def projection_name(projection):
    """A description projection as messages name it."""
    return f"projection '{projection['pre']}' → '{projection['post']}'"


def is_one_step(projection, dt_s):
    """Whether a description's projection carries one-step currents (see :data:`ONE_STEP`)."""
    return projection["tau_s"] <= ONE_STEP_MAX * dt_s


def label(name, node):
    """A NIR node as messages name it."""
    return f"NIR node '{name}' ({type(node).__name__})"
