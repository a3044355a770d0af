"""Define a spiking network in Python: :class:`NetworkBuilder`, the Python twin of the Rust
``NetworkBuilder``, and :class:`Stdp`, a projection's learning rule.

A builder collects nodes — populations of a neuron model, spike inputs (recorded trains or
Poisson), current inputs — and projections between them, then :meth:`NetworkBuilder.build`
makes a runnable :class:`neurotac.Network` (Rust checks everything once more and builds it).
Every time is in seconds and named ``…_s``; a rate is ``…_hz``.

.. code-block:: python

    b = neurotac.NetworkBuilder(dt_s=1e-4)
    b.add_spike_input("taxels", trains)                       # one array of times (s) per channel
    b.add_population("afferents", 49, model="lif", tau_m_s=0.01)
    b.connect("taxels", "afferents", "one_to_one", weight=5.0, tau_syn_s=5e-3)
    b.monitor_state("afferents", "v", every_s=1e-3)
    net = b.build()
    net.run(2.0)
    times, neurons = net.spikes("afferents")                   # every spike of every node
    t, v = net.state_trace("afferents", "v")                   # (samples,), (samples, 49)
    start, rate_hz = net.population_rate("afferents", bin_s=0.02)
    w = net.weights("taxels->afferents")                       # or net.weights("taxels")

Populations, by ``model``:

- ``"lif"`` (``τ_m·dv/dt = (v_rest − v) + I``, spike at ``v ≥ v_th``, reset to ``v_reset``):
  ``tau_m_s`` (0.01), ``v_rest`` (0), ``v_th`` (1), ``v_reset`` (0), ``t_ref_s`` (0), ``v_min``
  (``None``: no floor); integrators ``exact`` (default), ``exp-euler``, ``euler``, ``rk2``,
  ``rk4``.
- ``"izhikevich"`` (Izhikevich 2003, v in mV, time in ms): ``a``, ``b``, ``c``, ``d``,
  ``v_peak``, ``v_min``, ``rest_tolerance``, from ``preset`` ``"rs"`` (default), ``"ib"``,
  ``"ch"``, ``"fs"``, ``"lts"``, ``"tc"`` or ``"rz"``; integrators ``izhikevich2003``
  (default), ``euler``, ``exp-euler``, ``rk2``, ``rk4``.

A projection's synapses are exponential currents (``I ← I + w`` per arriving spike, decaying
with ``tau_syn_s``) in the target model's input units; ``delay_s`` is a whole number of steps
(0 from an input, at least one step from a population). Connectivity: ``"one_to_one"``,
``"all_to_all"``, ``"random"`` (``probability``, ``seed``: the same pairs as the Rust
``Connectivity::Random``) or ``"sparse"`` (``pre``, ``post`` index arrays and one weight each).

Bad arguments raise :class:`neurotac.NeurotacValueError` (a ``ValueError``) naming the
argument; a network Rust refuses raises it with Rust's message, naming the node or field.
"""

import json as _json
import math as _math

import numpy as _np

from . import _native
from ._native import Network, NeurotacValueError
from ._units import seconds

__all__ = ["NetworkBuilder", "Stdp"]

_FORMAT = "neurotac-network"
_VERSION = 1
_CONNECTIVITIES = ("one_to_one", "all_to_all", "random", "sparse")


def _refuse(argument, value, expected):
    raise NeurotacValueError(f"{argument} = {value!r}: expected {expected}")


def _name(argument, value):
    if not isinstance(value, str) or not value:
        _refuse(argument, value, "a non-empty str")
    return value


def _count(argument, value):
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)) or value < 1:
        _refuse(argument, value, "a whole number ≥ 1")
    return int(value)


def _finite(argument, value):
    try:
        x = float(value)
    except (TypeError, ValueError):
        _refuse(argument, value, "a number")
    if not _math.isfinite(x):
        _refuse(argument, value, "a finite number")
    return x


class Stdp:
    """Pair-based STDP of a plastic projection (the Rust ``Stdp``): one trace per presynaptic
    and per postsynaptic neuron, ``Δw = a_plus·x_pre`` at a postsynaptic spike and
    ``−a_minus·x_post`` at an arriving presynaptic one, weights kept in ``[w_min, w_max]``.

    ``dependence``: ``"additive"`` (Song, Miller & Abbott 2000) or ``"multiplicative"``
    (soft bounds); ``interaction``: ``"all_to_all"`` or ``"nearest"`` traces.
    """

    def __init__(self, tau_plus_s, tau_minus_s, a_plus, a_minus, w_max, w_min=0.0,
                 dependence="additive", interaction="all_to_all"):
        self.tau_plus_s = seconds("tau_plus_s", tau_plus_s)
        self.tau_minus_s = seconds("tau_minus_s", tau_minus_s)
        self.a_plus = _finite("a_plus", a_plus)
        self.a_minus = _finite("a_minus", a_minus)
        self.w_min = _finite("w_min", w_min)
        self.w_max = _finite("w_max", w_max)
        if dependence not in ("additive", "multiplicative"):
            _refuse("dependence", dependence, "'additive' or 'multiplicative'")
        if interaction not in ("all_to_all", "nearest"):
            _refuse("interaction", interaction, "'all_to_all' or 'nearest'")
        self.dependence = dependence
        self.interaction = interaction

    @classmethod
    def additive(cls, tau_plus_s, tau_minus_s, a_plus, a_minus, w_max):
        """Additive STDP with all-to-all traces and weights in ``[0, w_max]``."""
        return cls(tau_plus_s, tau_minus_s, a_plus, a_minus, w_max)

    def to_description(self):
        """The rule as the network description writes it."""
        return {
            "tau_plus_s": self.tau_plus_s,
            "tau_minus_s": self.tau_minus_s,
            "a_plus": self.a_plus,
            "a_minus": self.a_minus,
            "w_min": self.w_min,
            "w_max": self.w_max,
            "dependence": self.dependence,
            "interaction": self.interaction,
        }

    def __repr__(self):
        return (
            f"Stdp(tau_plus_s={self.tau_plus_s}, tau_minus_s={self.tau_minus_s}, "
            f"a_plus={self.a_plus}, a_minus={self.a_minus}, w_min={self.w_min}, "
            f"w_max={self.w_max}, dependence={self.dependence!r}, "
            f"interaction={self.interaction!r})"
        )


class NetworkBuilder:
    """Describes a network node by node; :meth:`build` makes the :class:`neurotac.Network`.

    ``dt_s`` is the time step (s). ``stepping``: ``"clock"`` (every neuron every step, the
    default) or ``"event"`` (only neurons with input; the same spikes, faster when few taxels
    fire). Every ``add_…`` and ``connect`` returns the name it registered (a projection's is
    ``"pre->post"``), which :class:`neurotac.Network` takes.
    """

    def __init__(self, dt_s=1e-4, stepping="clock"):
        self.dt_s = seconds("dt_s", dt_s)
        if stepping not in ("clock", "event"):
            _refuse("stepping", stepping, "'clock' or 'event'")
        self._stepping = stepping
        self._nodes = []
        self._sizes = {}
        self._kinds = {}
        self._projections = []
        self._monitors = []

    # -- nodes -------------------------------------------------------------------------------

    def _add(self, name, kind, size, node):
        name = _name("name", name)
        if name in self._sizes:
            raise NeurotacValueError(f"name = {name!r}: the network already has a node of that name")
        self._nodes.append(node)
        self._sizes[name] = size
        self._kinds[name] = kind
        return name

    def add_population(self, name, size, model="lif", preset=None, *, integrator=None,
                       precision="f64", initial_v=None, **params):
        """A population of ``size`` neurons of ``model`` (``"lif"`` or ``"izhikevich"``),
        with the parameters of ``preset`` (Izhikevich) changed by ``params`` by name (module
        docs), integrated with ``integrator`` at ``precision`` (``"f64"`` or ``"f32"``).
        ``initial_v``: the starting potential, one number or one per neuron (default: at
        rest)."""
        size = _count("size", size)
        description = _json.loads(
            _native.model_description(model, size, preset, precision, integrator)
        )
        settings = description["settings"]
        known = settings["params"]
        for field, value in params.items():
            if field not in known:
                raise NeurotacValueError(
                    f"{field}: not a parameter of {model} (its parameters: {', '.join(known)})"
                )
            if field == "v_min" and value is None:
                known[field] = None
            else:
                known[field] = _finite(field, value)
        if model == "lif" and initial_v is None:
            settings["initial"] = {"constant": known["v_rest"]}
        if initial_v is not None:
            values = _np.asarray(initial_v, dtype=_np.float64)
            if values.ndim == 0:
                settings["initial"] = {"constant": _finite("initial_v", values)}
            elif values.shape == (size,) and _np.all(_np.isfinite(values)):
                settings["initial"] = {"values": values.tolist()}
            else:
                _refuse("initial_v", initial_v, f"a finite number or {size} of them")
        return self._add(name, "population", size,
                         {"kind": "population", "name": name, "model": description})

    def add_spike_input(self, name, trains):
        """A spike input replaying ``trains``: one sequence of spike times (s) per channel
        (``Network.run(inputs=…)`` replaces them later)."""
        try:
            channels = [sorted(_finite("trains", t) for t in train) for train in trains]
        except TypeError as e:
            raise NeurotacValueError(
                f"trains: expected one sequence of spike times (s) per channel ({e})"
            ) from e
        if not channels:
            _refuse("trains", trains, "at least one channel")
        return self._add(name, "input", len(channels),
                         {"kind": "source", "name": name,
                          "source": {"spike_array": {"trains": channels}}})

    def add_poisson_input(self, name, size, rate_hz, seed):
        """``size`` independent Poisson spike trains at ``rate_hz``, drawn from ``seed``."""
        size = _count("size", size)
        rate_hz = _finite("rate_hz", rate_hz)
        if rate_hz < 0:
            _refuse("rate_hz", rate_hz, "a rate ≥ 0")
        if isinstance(seed, bool) or not isinstance(seed, (int, _np.integer)) or not 0 <= seed < 2**64:
            _refuse("seed", seed, "a whole number from 0 to 2⁶⁴ − 1")
        return self._add(name, "input", size,
                         {"kind": "source", "name": name,
                          "source": {"poisson": {"size": size, "rate_hz": rate_hz, "seed": int(seed)}}})

    def add_current_input(self, name, into, amplitude=None, steps=None):
        """A current injected into the populations ``into`` (a name or a list), in their
        model's input units: constant ``amplitude`` (one number, or one per neuron), or
        ``steps``, a list of ``(time_s, amplitude)`` changes (0 before the first)."""
        targets = [into] if isinstance(into, str) else list(into)
        for target in targets:
            if self._kinds.get(target) != "population":
                _refuse("into", target, f"a population of the network ({self._names('population')})")
        if (amplitude is None) == (steps is None):
            raise NeurotacValueError("add_current_input: give either amplitude or steps")
        if amplitude is not None:
            values = _np.atleast_1d(_np.asarray(amplitude, dtype=_np.float64))
            if values.ndim != 1 or not _np.all(_np.isfinite(values)):
                _refuse("amplitude", amplitude, "a finite number or one per neuron")
            current = {"constant": {"amplitude": values.tolist()}}
            size = values.size
        else:
            changes = [(seconds("steps time_s", t, positive=False), _finite("steps amplitude", a))
                       for t, a in steps]
            if [t for t, _ in changes] != sorted(t for t, _ in changes):
                _refuse("steps", steps, "changes sorted by time")
            current = {"steps": {"size": 1, "changes": changes}}
            size = 1
        return self._add(name, "current", size,
                         {"kind": "current", "name": name, "current": current, "into": targets})

    # -- projections -------------------------------------------------------------------------

    def connect(self, pre, post, connectivity="all_to_all", *, weight=None, tau_syn_s=5e-3,
                delay_s=None, probability=None, seed=None, pre_indices=None,
                post_indices=None, stdp=None):
        """A projection from the population or spike input ``pre`` onto the population
        ``post`` through exponential synapses (``tau_syn_s``), with ``connectivity``:
        ``"one_to_one"``/``"all_to_all"`` (``weight``), ``"random"`` (``probability``,
        ``weight``, ``seed``) or ``"sparse"`` (``pre_indices``, ``post_indices``, ``weight``
        one per synapse or one for all). ``delay_s``: whole steps; default 0 from an input,
        one step from a population. ``stdp``: a :class:`Stdp` makes it plastic. Returns its
        name, ``"pre->post"``."""
        if self._kinds.get(pre) not in ("population", "input"):
            _refuse("pre", pre, f"a population or spike input ({self._names('population', 'input')})")
        if self._kinds.get(post) != "population":
            _refuse("post", post, f"a population ({self._names('population')})")
        tau_syn_s = seconds("tau_syn_s", tau_syn_s)
        if delay_s is None:
            delay_steps = 0 if self._kinds[pre] == "input" else 1
        else:
            delay_steps = self._steps("delay_s", delay_s)
        if connectivity not in _CONNECTIVITIES:
            _refuse("connectivity", connectivity, "one of " + ", ".join(map(repr, _CONNECTIVITIES)))
        if weight is None:
            raise NeurotacValueError(f"weight: connect('{pre}', '{post}') needs the synapses' weight")
        if connectivity in ("one_to_one", "all_to_all"):
            wiring = {connectivity: {"weight": _finite("weight", weight)}}
        elif connectivity == "random":
            p = _finite("probability", 0.0 if probability is None else probability)
            if probability is None or not 0.0 <= p <= 1.0:
                _refuse("probability", probability, "a probability in [0, 1]")
            if isinstance(seed, bool) or not isinstance(seed, (int, _np.integer)) or not 0 <= seed < 2**64:
                _refuse("seed", seed, "a whole number from 0 to 2⁶⁴ − 1 (random connectivity is seeded)")
            wiring = {"random": {"probability": p, "weight": _finite("weight", weight), "seed": int(seed)}}
        else:
            wiring = {"sparse": self._sparse(pre, post, pre_indices, post_indices, weight)}
        if stdp is not None and not isinstance(stdp, Stdp):
            _refuse("stdp", stdp, "a neurotac.Stdp")
        base = f"{pre}->{post}"
        name, k = base, 2
        while name in (p["_name"] for p in self._projections):
            name, k = f"{base}_{k}", k + 1
        self._projections.append({
            "_name": name,
            "pre": pre,
            "post": post,
            "tau_s": tau_syn_s,
            "delay_steps": delay_steps,
            "wiring": wiring,
            "plasticity": None if stdp is None else stdp.to_description(),
        })
        return name

    def _sparse(self, pre, post, pre_indices, post_indices, weight):
        if pre_indices is None or post_indices is None:
            raise NeurotacValueError("sparse connectivity needs pre_indices and post_indices")
        pre_i = _np.asarray(pre_indices)
        post_i = _np.asarray(post_indices)
        if pre_i.ndim != 1 or post_i.shape != pre_i.shape or not (
            _np.issubdtype(pre_i.dtype, _np.integer) and _np.issubdtype(post_i.dtype, _np.integer)
        ):
            _refuse("pre_indices, post_indices", (pre_indices, post_indices),
                    "two integer arrays of one length")
        for argument, idx, node in (("pre_indices", pre_i, pre), ("post_indices", post_i, post)):
            if idx.size and (idx.min() < 0 or idx.max() >= self._sizes[node]):
                _refuse(argument, int(idx.max() if idx.max() >= self._sizes[node] else idx.min()),
                        f"indices of '{node}' (0 to {self._sizes[node] - 1})")
        w = _np.broadcast_to(_np.asarray(weight, dtype=_np.float64), pre_i.shape)
        if not _np.all(_np.isfinite(w)):
            _refuse("weight", weight, "finite weights, one for all or one per synapse")
        return {"pre": pre_i.tolist(), "post": post_i.tolist(), "weight": w.tolist()}

    # -- monitors ----------------------------------------------------------------------------

    def monitor_state(self, population, variable="v", every_s=None, neurons=None):
        """Samples state variable ``variable`` (LIF: ``"v"``; Izhikevich: ``"v"``, ``"u"``) of
        ``neurons`` (indices; default all) of ``population`` at the end of every step, or every
        ``every_s`` seconds (a whole number of steps). ``Network.state_trace(population,
        variable)`` returns the samples. Spikes need no monitor: every node's are recorded."""
        if self._kinds.get(population) != "population":
            _refuse("population", population, f"a population ({self._names('population')})")
        every_steps = 1 if every_s is None else self._steps("every_s", every_s)
        if every_steps == 0:
            _refuse("every_s", every_s, f"at least one step ({self.dt_s} s)")
        if neurons is not None:
            neurons = [int(i) for i in neurons]
            bad = [i for i in neurons if not 0 <= i < self._sizes[population]]
            if bad:
                _refuse("neurons", bad[0], f"indices of '{population}' (0 to {self._sizes[population] - 1})")
        if any(m[0] == population and m[1] == variable for m in self._monitors):
            raise NeurotacValueError(f"'{population}'.{variable} already has a state monitor")
        self._monitors.append((population, _name("variable", variable), every_steps, neurons))
        return (population, variable)

    # -- building ----------------------------------------------------------------------------

    def description(self):
        """The network as a description dict (the schema of ``Network.description()``;
        random connectivity stays random until built)."""
        return {
            "format": _FORMAT,
            "version": _VERSION,
            "dt_s": self.dt_s,
            "stepping": self._stepping,
            "nodes": list(self._nodes),
            "projections": [{k: v for k, v in p.items() if k != "_name"} for p in self._projections],
        }

    def build(self):
        """The runnable :class:`neurotac.Network`, at time 0; the builder can be changed and
        built again."""
        return Network.from_description(_json.dumps(self.description()), list(self._monitors))

    def _steps(self, argument, value_s):
        """``value_s`` (s, ≥ 0) as a whole number of steps of ``dt_s``, refused otherwise."""
        value_s = seconds(argument, value_s, positive=False)
        steps = round(value_s / self.dt_s)
        if abs(steps * self.dt_s - value_s) > 1e-9 * max(value_s, self.dt_s):
            _refuse(argument, value_s, f"a whole number of steps of dt_s = {self.dt_s} s")
        return int(steps)

    def _names(self, *kinds):
        names = [n for n, k in self._kinds.items() if k in kinds]
        return ", ".join(names) if names else "none yet"

    def __repr__(self):
        return (
            f"NetworkBuilder(dt_s={self.dt_s}, nodes=[{', '.join(self._kinds)}], "
            f"projections=[{', '.join(p['_name'] for p in self._projections)}])"
        )
