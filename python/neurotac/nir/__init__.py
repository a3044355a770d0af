"""Networks in and out of NIR, the Neuromorphic Intermediate Representation (PyPI ``nir`` 1.0).

:func:`to_nir` turns a :class:`neurotac.Network` (or its JSON description) into a
``nir.NIRGraph``; :func:`from_nir` turns a ``nir.NIRGraph`` (yours, or one written by snnTorch,
Norse, Sinabs, Lava-dl, Rockpool… and read with ``nir.read``) into a runnable
:class:`neurotac.Network`. Both go through the network's JSON description
(:meth:`neurotac.Network.description`), so the Rust library never needs HDF5;
:func:`description_to_graph` and :func:`graph_to_description` are the dict-level halves.

Needs ``pip install neurotac[nir]`` (the ``nir`` package and its ``h5py``).

**Time.** neurotac steps time in steps of ``dt``: the synaptic currents a step starts with are
held over it, the membrane is advanced (the exact solution for a constant input, or Euler),
then a neuron with ``v ≥ v_th`` spikes (stamped at the step's end) and is reset. NIR states
continuous-time ODEs whose input spikes are impulses of mass ``m``: a Dirac impulse, ``m = 1``
(``input_spikes="dirac"``, the default and what :func:`to_nir` writes), or 1 held for one step,
``m = dt`` (``input_spikes="step"``, the reading of discrete-time exporters: snnTorch's
``Leaky``/``Synaptic`` with ``r = τ/dt``, Norse's box cells).

**The mapping, node by node** (``W`` a ``Linear``'s weight, shape ``(n_post, n_pre)``; ``w``
neurotac's weight, the jump of a synaptic current per spike in potential units):

.. code-block:: text

    CubaLIF   τ_syn·dI/dt = −I + w_in·S,  τ_mem·dv/dt = (v_leak − v) + R·I
              → LIF population (τ_m = τ_mem, v_rest = v_leak, v_th, v_reset) fed by an
                exponential synapse of τ_syn:      w = W·R·w_in·m/τ_syn
    LI → LIF  τ_LI·dI/dt = (0 − I) + R_LI·S,  τ·dv/dt = (v_leak − v) + R·I
              → the same, τ_syn = τ_LI:            w = W·R·R_LI·m/τ_LI
    LIF       τ·dv/dt = (v_leak − v) + R·S      (a spike jumps v by a = W·R·m/τ)
              → a synapse whose current lasts one step (τ_syn = dt/1000: e^(−1000) = 0),
                w = a/g with the step's gain g = 1 − e^(−dt/τ) (exact) or dt/τ (Euler):
                v_{k+1} = v_rest + (v_k − v_rest)·e^(−dt/τ) + a   (exact)
    IF        dv/dt = R·S                        (a spike jumps v by a = W·R·m)
              → an "if" population (τ_m·dv/dt = I with τ_m = dt, so g = 1) fed by a one-step
                current of w = a:                  v_{k+1} = v_k + a
    LI → IF   dv/dt = R·I_LI  → "if" population, exponential synapse τ_LI:
                                                    w = W·R·dt·R_LI·m/τ_LI
    Affine    W·S + b: W as Linear; b ≠ 0 into a LIF or IF fed without a synapse is the
              constant current R·b (LIF) or R·b·dt (IF); into a synapse it is refused
    Scale     s ⊙ x: multiplies W's columns (before the Linear) or rows (after it)
    Delay     d seconds → d/dt whole steps (from a population, at least one)
    Input     a spike input (its trains from the metadata, else empty); Output: the spikes
              of the population or input it reads

Every threshold is NIR's ``v > v_threshold`` read as ``v ≥ v_th`` (they differ only when ``v``
lands exactly on the threshold); a spiking neuron is reset to ``v_reset`` (NIR's reset; a tool
that trained with reset by subtraction, snnTorch's and Sinabs' default, exports the same nodes,
and its network runs here with reset to ``v_reset``).

**Per-neuron parameters.** ``R``, ``w_in``, ``R_LI`` and ``Scale`` may differ between neurons
(they scale the rows of ``W``). A population has one ``τ``, ``v_leak`` and ``v_reset``; per-neuron
thresholds are taken when ``v_reset/v_threshold`` and ``v_leak/v_threshold`` are the same for
every neuron (e.g. both 0): each neuron's potential is then read in units of its threshold
(``v_th = 1``, its row of ``W`` and its bias divided by ``θ_i``), which gives the same spikes.

**neurotac → NIR.** A LIF population with its exponential synapses is a ``CubaLIF`` fed by a
``Linear`` (projections with different τ_syn, or one-step ones: a ``LIF`` with one ``LI``
synapse each and one-step projections straight into it); an ``if`` population is an ``IF`` with
``R = 1/τ_m``; delays are ``Delay`` nodes, spike sources ``Input``\\ s, populations that feed no
other ``Output``\\ s; dt, the integrator, the precision and the input trains travel in the
graph's metadata (``"neurotac"``, JSON), so neurotac → NIR → neurotac gives the same network
(one-step weights within rounding) and the same spikes. Exported graphs use ``R = 1`` and
``w_in = τ_syn`` (the factor is exactly 1, so ``W`` holds neurotac's weights unchanged).

**Defaults of a foreign graph.** What NIR does not say: the exact integrator (``integrator=``
chooses Euler), f64, spike times on the grid, clock-driven stepping, LIF membranes starting at
``v_leak`` and IF ones at 0; a delay must be a whole number of steps of ``dt_s``; ``dt_s``
longer than the graph's shortest time constant is refused, longer than a tenth of it warned
about (not with ``input_spikes="step"``: such a graph was made at its own dt). The metadata never overrides a NIR field, so a graph edited in another tool imports with
its edits.

**Refused** with one line, :class:`NirError` (a ``ValueError``) naming the node: on the way out,
Izhikevich populations, plastic (STDP) projections, a refractory period or a potential floor
``v_min``, current sources; on the way in, ``Conv1d``, ``Conv2d``, pooling, ``Flatten``, ``I``,
``Threshold``, ``CubaLI``, nested graphs, an ``LI`` that is not a synapse (a non-spiking
readout), a bias into a synapse, per-neuron time constants, leaks or resets, thresholds that
do not scale (above), and whatever a malformed graph breaks (every edge a ``(source, target)``
pair of node names the graph has, listed once, never into an ``Input`` nor out of an
``Output``; at most :data:`MAX_SIZE` neurons or channels per node and :data:`MAX_DELAY_STEPS`
steps of delay).
"""

import json as _json

try:
    import nir as _nir  # noqa: F401  (checked here, used by the modules below)
except ImportError as e:  # pragma: no cover - exercised only without the optional extra
    raise ImportError(
        "neurotac.nir needs the nir package: pip install 'neurotac[nir]' (or pip install nir)"
    ) from e

from .. import Network, NeurotacValueError
from .common import MAX_DELAY_STEPS, MAX_SIZE, METADATA_KEY, NirError
from .export import description_to_graph
from .read import INPUT_SPIKES, INTEGRATORS, graph_to_description

__all__ = [
    "INPUT_SPIKES",
    "INTEGRATORS",
    "MAX_DELAY_STEPS",
    "MAX_SIZE",
    "METADATA_KEY",
    "NirError",
    "description_to_graph",
    "from_nir",
    "graph_to_description",
    "to_nir",
]


def to_nir(network):
    """The ``nir.NIRGraph`` of a :class:`neurotac.Network`, its JSON description (``str``) or the
    description as a dict. Raises :class:`NirError` for what NIR cannot express."""
    if isinstance(network, dict):
        description = network
    elif isinstance(network, str):
        description = _json.loads(network)
    else:
        description = _json.loads(network.description())
    return description_to_graph(description)


def from_nir(graph, dt_s=None, *, input_spikes="dirac", integrator="exact"):
    """A runnable :class:`neurotac.Network` from a ``nir.NIRGraph``.

    ``dt_s`` is the time step in seconds; by default the one in the graph's neurotac metadata
    (a graph :func:`to_nir` made), required for any other graph. ``input_spikes``: how a spike
    enters NIR's equations, ``"dirac"`` (an impulse of mass 1) or ``"step"`` (1 for one step,
    mass ``dt_s``: snnTorch's and Norse's box cells' reading). ``integrator``: ``"exact"`` or
    ``"euler"`` for the LIF populations of a foreign graph. Raises :class:`NirError` naming the
    node neurotac cannot run; see the module docs for the mapping and its equations.
    """
    description = _json.dumps(graph_to_description(graph, dt_s, input_spikes, integrator))
    try:
        return Network.from_description(description)
    except NeurotacValueError as e:
        raise NirError("graph", f"its network does not build: {e}") from e
