"""NIR → neurotac: :func:`graph_to_description`, the network description of a ``nir.NIRGraph``
(the mapping, its equations and its refusals are in the docs of :mod:`neurotac.nir`)."""

import json as _json
import math as _math
import warnings as _warnings

import numpy as _np
import nir as _nir

from .common import (
    FORMAT,
    IF,
    LIF,
    MAX_DELAY_STEPS,
    MAX_SIZE,
    META_FORMAT,
    META_VERSION,
    METADATA_KEY,
    ONE_STEP,
    VERSION,
    NirError,
    label,
    size_of,
)

#: How an input spike enters a NIR ODE: ``"dirac"`` (a Dirac impulse of unit mass, NIR's
#: continuous reading) or ``"step"`` (1 for one time step: mass ``dt``, the reading of
#: discrete-time exporters such as snnTorch and Norse's box cells).
INPUT_SPIKES = ("dirac", "step")
#: The integrators an imported LIF population may use.
INTEGRATORS = ("exact", "euler")
_NEURON_TYPES = (_nir.CubaLIF, _nir.LIF, _nir.IF)
_SPIKING_TYPES = (_nir.Input,) + _NEURON_TYPES
_CHAIN = ("Linear", "Affine", "Delay", "LI", "Scale")


def _metadata(graph):
    """neurotac's settings in a graph's metadata (``{}`` for a foreign graph)."""
    raw = (graph.metadata or {}).get(METADATA_KEY) if isinstance(graph.metadata, dict) else None
    if raw is None:
        return {}
    if isinstance(raw, bytes):
        raw = raw.decode("utf-8")
    try:
        meta = _json.loads(raw)
    except (TypeError, ValueError) as e:
        raise NirError("graph metadata", f"'{METADATA_KEY}' is not JSON ({e})") from e
    if not isinstance(meta, dict) or meta.get("format") != META_FORMAT:
        raise NirError("graph metadata", f"'{METADATA_KEY}' is not a {META_FORMAT} record")
    if meta.get("version") != META_VERSION:
        raise NirError(
            "graph metadata",
            f"'{METADATA_KEY}' has version {meta.get('version')}, "
            f"this neurotac reads {META_VERSION}",
        )
    _check_metadata_types(meta)
    return meta


def _check_metadata_types(meta):
    """Refuses metadata fields of other types than the export writes."""

    def refuse(field, value, expected):
        raise NirError("graph metadata", f"'{field}' is {value!r}, expected {expected}")

    dt_s = meta.get("dt_s")
    if dt_s is not None and (isinstance(dt_s, bool) or not isinstance(dt_s, (int, float))):
        refuse("dt_s", dt_s, "a number of seconds")
    stepping = meta.get("stepping")
    if stepping is not None and not isinstance(stepping, (str, dict)):
        refuse("stepping", stepping, "a stepping (\"clock\", \"event\" or {\"auto\": …})")
    for field in ("order", "unfed"):
        names = meta.get(field, [])
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            refuse(field, names, "a list of node names")
    nodes = meta.get("nodes", {})
    if not isinstance(nodes, dict):
        refuse("nodes", nodes, "an object of node records")
    for name, record in nodes.items():
        field = f"nodes.{name}"
        if not isinstance(record, dict):
            refuse(field, record, "an object")
        for key, kind, expected in (
            ("source", dict, "a source description"),
            ("model", str, "a model name"),
            ("settings", dict, "an object of settings"),
        ):
            if key in record and not isinstance(record[key], kind):
                refuse(f"{field}.{key}", record[key], expected)


def _edges(graph):
    """The graph's edges as ``(source, target)`` pairs, checked: node names the graph has,
    each pair listed once, never into an ``Input`` nor out of an ``Output``."""
    nodes = graph.nodes
    if not isinstance(nodes, dict) or not all(isinstance(n, str) for n in nodes):
        raise NirError("graph", "nodes is not a dict from node names to nodes")
    try:
        edges = list(graph.edges)
    except TypeError as e:
        raise NirError("graph", "edges is not a list of (source, target) pairs") from e
    seen = set()
    for k, edge in enumerate(edges):
        where = f"edge {k} {edge!r}"
        try:
            a, b = edge
        except (TypeError, ValueError) as e:
            raise NirError(where, "is not a (source, target) pair") from e
        if isinstance(edge, (str, bytes)):
            raise NirError(where, "is not a (source, target) pair")
        for end in (a, b):
            if not isinstance(end, str):
                raise NirError(where, f"endpoint {end!r} is not a node name")
            if end not in nodes:
                raise NirError(where, f"names node '{end}', which the graph does not have")
        if (a, b) in seen:
            raise NirError(where, "is listed twice (its input would count twice)")
        if isinstance(nodes[b], _nir.Input):
            raise NirError(where, f"leads into Input '{b}', which receives nothing")
        if isinstance(nodes[a], _nir.Output):
            raise NirError(where, f"leaves Output '{a}', which ends a path")
        seen.add((a, b))
    return [tuple(e) for e in edges]


def _checked_size(name, node, size):
    """``size`` (neurons or channels of a node) as an int, refused beyond :data:`MAX_SIZE`."""
    if not 1 <= size <= MAX_SIZE:
        raise NirError(label(name, node), f"size {size}, expected 1 to {MAX_SIZE}")
    return int(size)


def _positive(name, node, field, value):
    """A time constant, refused unless > 0."""
    if not value > 0:
        raise NirError(label(name, node), f"{field} = {value}, expected > 0")
    return value


def _values(name, node, field, n=None):
    """A parameter as a float64 vector (of ``n`` values when it is a scalar); a ``v_reset``
    an older graph leaves out (``None``) is NIR 1.0's default, 0."""
    raw = getattr(node, field)
    if raw is None and field == "v_reset":
        raw = 0.0
    values = _np.asarray(raw, dtype=_np.float64)
    if values.ndim == 0 and n is not None:
        values = _np.full(n, float(values))
    values = values.ravel()
    if n is not None and values.size == 1 and n > 1:
        values = _np.full(n, float(values[0]))
    if n is not None and values.size != n:
        raise NirError(label(name, node), f"{field} has {values.size} values, expected {n}")
    if not _np.all(_np.isfinite(values)):
        raise NirError(label(name, node), f"{field} is not finite")
    return values


def _uniform(name, node, field, n=None, why=None):
    """A parameter that must be the same for every neuron, as a float."""
    values = _values(name, node, field, n)
    if values.size == 0:
        raise NirError(label(name, node), f"{field} is empty")
    if not _np.all(values == values[0]):
        raise NirError(
            label(name, node),
            f"{field} differs between neurons ({values.min()} to {values.max()}); "
            + (why or f"a neurotac population has one {field}"),
        )
    return float(values[0])


def _shape_size(name, node, shape):
    """The number of values of an input or output ``shape`` (exact, never overflowing)."""
    dims = _np.asarray(shape).ravel().tolist()
    if not dims or not all(isinstance(d, int) and not isinstance(d, bool) and d >= 0 for d in dims):
        raise NirError(label(name, node), f"shape {shape!r} is not a list of sizes")
    size = 1
    for d in dims:
        size *= d
    return _checked_size(name, node, size)


def _neuron_size(name, node):
    threshold = _np.asarray(node.v_threshold)
    if threshold.ndim == 0 or threshold.size == 1:
        shape = node.output_type.get("output") if isinstance(node.output_type, dict) else None
        if shape is None or _np.asarray(shape).size == 0:
            if threshold.size == 1:
                return 1
            raise NirError(label(name, node), "scalar parameters and no output shape: size unknown")
        return _shape_size(name, node, shape)
    return _checked_size(name, node, threshold.size)


def _potential_unit(name, node, n):
    """Per-neuron thresholds, when the rest of the node scales with them: the potential unit
    ``θ_i`` of each neuron (``v`` is read as ``v/θ_i``, so every threshold is 1), or ones."""
    theta = _values(name, node, "v_threshold", n)
    if _np.all(theta == theta[0]):
        return _np.ones(n)
    ratios = [("v_reset", _values(name, node, "v_reset", n))]
    if not isinstance(node, _nir.IF):
        ratios.append(("v_leak", _values(name, node, "v_leak", n)))
    scalable = _np.all(theta > 0) and all(
        _np.all(v / theta == v[0] / theta[0]) for _, v in ratios
    )
    if not scalable:
        raise NirError(
            label(name, node),
            f"v_threshold differs between neurons ({theta.min()} to {theta.max()}) and "
            f"{' and '.join(f for f, _ in ratios)} do not scale with it; a neurotac population "
            "has one threshold (per-neuron thresholds are taken when v_reset/v_threshold and "
            "v_leak/v_threshold are the same for every neuron)",
        )
    return theta


def _population(name, node, meta_node, dt_s, integrator, unit):
    """A description's population node from a NIR CubaLIF, LIF or IF, its potentials in the
    per-neuron ``unit`` (:func:`_potential_unit`)."""
    n = unit.size

    def in_unit(field):
        values = _values(name, node, field, n) / unit
        if not _np.all(values == values[0]):
            raise NirError(
                label(name, node),
                f"{field} differs between neurons ({values.min()} to {values.max()}); "
                f"a neurotac population has one {field}",
            )
        return float(values[0])

    v_reset = in_unit("v_reset")
    v_th = in_unit("v_threshold")
    if isinstance(node, _nir.IF):
        params = {"tau_m_s": dt_s, "v_th": v_th, "v_reset": v_reset, "v_min": None}
        model, start = IF, 0.0
        integrator = "exact"
    else:
        tau_field = "tau_mem" if isinstance(node, _nir.CubaLIF) else "tau"
        tau_m = _positive(name, node, tau_field, _uniform(name, node, tau_field, n))
        v_leak = in_unit("v_leak")
        params = {
            "tau_m_s": tau_m,
            "v_rest": v_leak,
            "v_th": v_th,
            "v_reset": v_reset,
            "t_ref_s": 0.0,
            "v_min": None,
        }
        model, start = LIF, v_leak
    settings = {
        "precision": "f64",
        "integrator": integrator,
        "interpolate": False,
        "initial": {"constant": start},
    }
    if meta_node.get("model") == model:
        settings.update(meta_node.get("settings", {}))
    settings["params"] = params
    return {"kind": "population", "name": name, "model": {"model": model, "size": n, "settings": settings}}


def _input(name, node, meta_node):
    """A description's spike source from a NIR Input (trains or Poisson from the metadata)."""
    shape = node.input_type.get("input") if isinstance(node.input_type, dict) else None
    if shape is None:
        raise NirError(label(name, node), "input_type has no 'input' shape")
    size = _shape_size(name, node, shape)
    source = meta_node.get("source") or {"spike_array": {"trains": [[] for _ in range(size)]}}
    described = {"kind": "source", "name": name, "source": source}
    try:
        stated = size_of(described)
    except (KeyError, TypeError, ValueError, AttributeError) as e:
        raise NirError(label(name, node), f"its metadata source is malformed ({e!r})") from e
    if stated != size:
        raise NirError(
            label(name, node), f"its metadata source has {stated!r} channels, the Input {size}"
        )
    return described


def _wiring(m):
    """The wiring of an effective ``(n_post, n_pre)`` weight matrix."""
    n_post, n_pre = m.shape
    if m.size and m.flat[0] != 0 and _np.all(m == m.flat[0]):
        return {"all_to_all": {"weight": float(m.flat[0])}}
    diagonal = _np.diagonal(m) if n_pre == n_post else None
    if (
        diagonal is not None
        and diagonal.size
        and diagonal[0] != 0
        and _np.all(diagonal == diagonal[0])
        and _np.count_nonzero(m) == n_pre
    ):
        return {"one_to_one": {"weight": float(diagonal[0])}}
    pre, post = _np.nonzero(m.T)  # by presynaptic neuron, as neurotac delivers them
    return {"sparse": {"pre": pre.tolist(), "post": post.tolist(), "weight": m[post, pre].tolist()}}


def _time_constants(nodes):
    """Every time constant of the graph's neurons and synapses: ``(τ, node name, field)``."""
    for name, node in nodes.items():
        fields = {
            _nir.CubaLIF: ("tau_mem", "tau_syn"),
            _nir.LIF: ("tau",),
            _nir.LI: ("tau",),
        }.get(type(node), ())
        for field in fields:
            with _malformed(label(name, node)):
                tau = _np.asarray(getattr(node, field), dtype=_np.float64)
            finite = tau[_np.isfinite(tau) & (tau > 0)]
            if finite.size:
                yield float(finite.min()), name, field


def _check_time_step(nodes, dt_s, warn):
    """Refuses a step longer than the graph's shortest time constant, and (``warn``) warns
    above a tenth of it: the network would be stepped more coarsely than its dynamics. A graph
    read with step spikes was made at its own dt (snnTorch's τ = dt/(1 − β)), so it is not
    warned about."""
    shortest = min(_time_constants(nodes), default=None)
    if shortest is None:
        return
    tau, name, field = shortest
    if dt_s > tau:
        raise NirError(
            "graph",
            f"dt_s = {dt_s} s is longer than its shortest time constant, {field} = {tau} s of "
            f"node '{name}': its dynamics would fall between steps; use dt_s ≤ {tau / 10:g} s",
        )
    if warn and dt_s > tau / 10:
        _warnings.warn(
            f"dt_s = {dt_s} s is more than a tenth of the graph's shortest time constant "
            f"({field} = {tau} s of node '{name}'); a smaller step follows its dynamics "
            "more closely",
            UserWarning,
            stacklevel=4,
        )


def graph_to_description(graph, dt_s=None, input_spikes="dirac", integrator="exact"):
    """The network description (a dict, :meth:`neurotac.Network.description`'s schema) and
    the state monitors of a ``nir.NIRGraph``; see :func:`neurotac.nir.from_nir`."""
    meta = _metadata(graph)
    if input_spikes not in INPUT_SPIKES:
        raise NirError("input_spikes", f"{input_spikes!r}, expected one of {INPUT_SPIKES}")
    if integrator not in INTEGRATORS:
        raise NirError("integrator", f"{integrator!r}, expected one of {INTEGRATORS}")
    edges = _edges(graph)
    nodes = graph.nodes
    if dt_s is None:
        dt_s = meta.get("dt_s")
        if dt_s is None:
            raise NirError(
                "graph",
                "has no neurotac metadata, so its time step is unknown: "
                "pass from_nir(graph, dt_s=...)",
            )
        foreign = False
    else:
        foreign = True
    dt_s = float(dt_s)
    if not (_np.isfinite(dt_s) and dt_s > 0):
        raise NirError("graph", f"dt_s = {dt_s}, expected finite and > 0")
    for name, node in nodes.items():
        kind = type(node).__name__
        if kind not in ("Input", "Output", "CubaLIF", "LIF", "IF") + _CHAIN:
            raise NirError(label(name, node), "neurotac cannot run this node type")
    if foreign:
        _check_time_step(nodes, dt_s, warn=input_spikes == "dirac")
    preds = {name: [] for name in nodes}
    for a, b in edges:
        preds[b].append(a)
    meta_nodes = meta.get("nodes", {})
    order = [n for n in meta.get("order", []) if n in nodes]
    order += [n for n in nodes if n not in order]

    # nir's type check gives a population without inputs an Input of its own ("input_<name>");
    # in a graph to_nir made, such an Input into a population that had none is not part of it.
    unfed = set(meta.get("unfed", []))
    added = {
        a
        for a, b in edges
        if b in unfed and a not in meta.get("order", []) and isinstance(nodes[a], _nir.Input)
    }
    order = [n for n in order if n not in added]

    described = {}
    units = {}
    for name in order:
        node = nodes[name]
        with _malformed(label(name, node)):
            if isinstance(node, _nir.Input):
                described[name] = _input(name, node, meta_nodes.get(name, {}))
            elif isinstance(node, _NEURON_TYPES):
                units[name] = _potential_unit(name, node, _neuron_size(name, node))
                described[name] = _population(
                    name, node, meta_nodes.get(name, {}), dt_s, integrator, units[name]
                )
    visited = set(described) | added

    context = _Context(graph, preds, described, units, dt_s,
                       1.0 if input_spikes == "dirac" else dt_s)
    projections = []
    currents = []
    for src, post in edges:
        if src in added or not isinstance(nodes[post], _NEURON_TYPES):
            continue
        with _malformed(f"edge ('{src}', '{post}')"):
            projection, chain, bias = _projection(context, src, post)
        projections.append(projection)
        visited.update(chain)
        if bias is not None:
            currents.append(bias)

    for name, node in nodes.items():
        if not isinstance(node, _nir.Output):
            continue
        visited.add(name)
        for src in preds[name]:
            if src not in described:
                raise NirError(
                    label(src, nodes[src]),
                    f"feeds Output '{name}', but neurotac's outputs are the spikes of "
                    "populations and inputs (a non-spiking readout?)",
                )
    for name in nodes:
        if name not in visited:
            raise NirError(
                label(name, nodes[name]),
                "is not on a path from a spiking node into a CubaLIF, LIF or IF",
            )
    return {
        "format": FORMAT,
        "version": VERSION,
        "dt_s": dt_s,
        "stepping": meta.get("stepping") or "clock",
        "nodes": [described[n] for n in order if n in described] + currents,
        "projections": projections,
    }


class _malformed:
    """Turns what a malformed node's fields break (a missing attribute, a wrong type) into a
    :class:`NirError` naming ``where``."""

    def __init__(self, where):
        self.where = where

    def __enter__(self):
        return self

    def __exit__(self, kind, error, trace):
        if kind is not None and issubclass(kind, (AttributeError, KeyError, TypeError, ValueError)):
            if isinstance(error, NirError):
                return False
            raise NirError(self.where, f"is malformed ({kind.__name__}: {error})") from error
        return False


class _Context:
    """What every projection of one import reads: the graph, each node's predecessors, the
    described nodes, the populations' potential units, the time step and a spike's mass."""

    def __init__(self, graph, preds, described, units, dt_s, spike_mass):
        self.graph = graph
        self.preds = preds
        self.described = described
        self.units = units
        self.dt_s = dt_s
        self.spike_mass = spike_mass


def _chain(ctx, src, post):
    """The nodes on the path that ends with edge ``src → post``, walking back to its spiking
    node: ``{slot: name}`` with the slots ``Delay``, ``Linear`` (or ``Affine``), ``LI`` and
    ``Scale_pre``/``Scale_post`` (a ``Scale`` before or after the ``Linear``), and the
    spiking node."""
    nodes = ctx.graph.nodes
    chain = {}
    cur = src
    while not isinstance(nodes[cur], _SPIKING_TYPES):
        node = nodes[cur]
        kind = type(node).__name__
        slot = {"Affine": "Linear"}.get(kind, kind)
        if slot == "Scale":
            slot = "Scale_pre" if "Linear" in chain else "Scale_post"
        if slot in chain:
            raise NirError(label(cur, node), f"a second {slot.split('_')[0]} on the path into '{post}'")
        if slot == "LI" and ("Linear" in chain or "Scale_pre" in chain):
            raise NirError(
                label(cur, node),
                f"comes before a Linear on the path into '{post}'; a synapse is Linear → LI → neuron",
            )
        chain[slot] = cur
        if len(ctx.preds[cur]) != 1:
            raise NirError(
                label(cur, node),
                f"has {len(ctx.preds[cur])} inputs; a neurotac projection starts at one spiking node",
            )
        cur = ctx.preds[cur][0]
    return chain, cur


def _projection(ctx, src, post):
    """The description's projection of the path ending with edge ``src → post``, the NIR nodes
    on it, and the constant current of an ``Affine``'s bias (or ``None``)."""
    nodes = ctx.graph.nodes
    target = nodes[post]
    chain, pre = _chain(ctx, src, post)
    n_pre, n_post = size_of(ctx.described[pre]), size_of(ctx.described[post])
    where = label(post, target)
    r = _values(post, target, "r", n_post)
    tau_m = ctx.described[post]["model"]["settings"]["params"]["tau_m_s"]
    model = ctx.described[post]["model"]["model"]
    m = ctx.spike_mass

    # `factor`: the neurotac weight of one spike through W[i, j] = 1 (per target neuron i);
    # `bias_gain`: the neurotac current of a constant NIR input of 1 into neuron i.
    if isinstance(target, _nir.CubaLIF):
        if "LI" in chain:
            raise NirError(label(chain["LI"], nodes[chain["LI"]]), f"is a second synapse before CubaLIF '{post}'")
        tau_s = _positive(post, target, "tau_syn", _uniform(post, target, "tau_syn", n_post))
        factor = r * _values(post, target, "w_in", n_post) * m / tau_s
        bias_gain = None
    elif "LI" in chain:
        li_name = chain["LI"]
        li = nodes[li_name]
        tau_s = _positive(li_name, li, "tau", _uniform(li_name, li, "tau", n_post))
        if _np.any(_values(li_name, li, "v_leak", n_post) != 0):
            raise NirError(label(li_name, li), "v_leak ≠ 0 is a constant current neurotac's synapses do not have")
        # LIF: τ·dv/dt = … + R·I_LI; IF: dv/dt = R·I_LI, i.e. τ_m·dv/dt = (R·τ_m)·I_LI.
        gain = r if model == LIF else r * tau_m
        factor = gain * _values(li_name, li, "r", n_post) * m / tau_s
        bias_gain = None
    else:
        # A spike jumps v by R·W·m/τ (LIF) or R·W·m (IF): a one-step current of that jump over
        # the step's gain (module docs).
        tau_s = ONE_STEP * ctx.dt_s
        jump = r * m / tau_m if model == LIF else r * m
        factor = jump / _step_gain(ctx.described[post], ctx.dt_s)
        # A constant input b: LIF's current R·b; IF's τ_m·R·b (τ_m = dt).
        bias_gain = r if model == LIF else r * tau_m
    unit = ctx.units[post]
    factor = factor / unit

    weight, bias = _linear(ctx, chain, pre, post, n_pre, n_post)
    delay_steps = _delay_steps(ctx, chain)
    if isinstance(nodes[pre], _NEURON_TYPES):
        delay_steps = max(delay_steps, 1)
    with _np.errstate(over="ignore", invalid="ignore"):
        effective = weight * factor[:, None]
    if not _np.all(_np.isfinite(effective)):
        raise NirError(where, f"the weights from '{pre}' scaled into neurotac's units are not finite")
    current = None
    if bias is not None:
        if bias_gain is None:
            raise NirError(
                label(chain["Linear"], nodes[chain["Linear"]]),
                "a bias into a synapse is a current that rises with τ_syn from 0, which "
                "neurotac's constant currents do not do",
            )
        amplitude = bias * bias_gain / unit
        current = {
            "kind": "current",
            "name": f"{chain['Linear']}_bias",
            "current": {"constant": {"amplitude": amplitude.tolist()}},
            "into": [post],
        }
    projection = {
        "pre": pre,
        "post": post,
        "tau_s": tau_s,
        "delay_steps": delay_steps,
        "wiring": _wiring(effective),
        "plasticity": None,
    }
    return projection, chain.values(), current


def _step_gain(population, dt_s):
    """How far a one-step input of 1 moves the membrane: LIF exact ``1 − e^(−dt/τ_m)``, LIF
    Euler ``dt/τ_m``, IF ``dt/τ_m`` (= 1: its τ_m is dt)."""
    settings = population["model"]["settings"]
    h = dt_s / settings["params"]["tau_m_s"]
    if population["model"]["model"] == LIF and settings["integrator"] in ("exact", "exp-euler"):
        return -_math.expm1(-h)
    return h


def _linear(ctx, chain, pre, post, n_pre, n_post):
    """The path's ``(n_post, n_pre)`` weight matrix, its Scales applied, and the Affine's bias
    (scaled by a Scale after it; ``None`` when there is none or it is 0)."""
    nodes = ctx.graph.nodes
    bias = None
    if "Linear" in chain:
        linear_name = chain["Linear"]
        linear = nodes[linear_name]
        weight = _np.asarray(linear.weight, dtype=_np.float64)
        if weight.shape != (n_post, n_pre):
            raise NirError(
                label(linear_name, linear),
                f"weight has shape {weight.shape}, expected ({n_post}, {n_pre}) for '{pre}' → '{post}'",
            )
        if not _np.all(_np.isfinite(weight)):
            raise NirError(label(linear_name, linear), "weight is not finite")
        if isinstance(linear, _nir.Affine):
            b = _values(linear_name, linear, "bias", n_post)
            bias = b if _np.any(b != 0) else None
    else:
        if n_pre != n_post:
            raise NirError(
                label(post, nodes[post]),
                f"receives {n_pre} channels from '{pre}' directly, expected {n_post}",
            )
        weight = _np.eye(n_post)
    if "Scale_pre" in chain:
        name = chain["Scale_pre"]
        weight = weight * _values(name, nodes[name], "scale", n_pre)[None, :]
    if "Scale_post" in chain:
        name = chain["Scale_post"]
        s = _values(name, nodes[name], "scale", n_post)
        weight = weight * s[:, None]
        bias = None if bias is None else bias * s
    return weight, bias


def _delay_steps(ctx, chain):
    """The path's Delay as whole steps of ``dt_s`` (0 without one)."""
    if "Delay" not in chain:
        return 0
    nodes = ctx.graph.nodes
    delay_name = chain["Delay"]
    delay = nodes[delay_name]
    delay_s = _uniform(delay_name, delay, "delay")
    steps = round(delay_s / ctx.dt_s)
    if delay_s < 0 or abs(steps * ctx.dt_s - delay_s) > 1e-9 * max(delay_s, ctx.dt_s):
        raise NirError(
            label(delay_name, delay),
            f"delay {delay_s} s is not a whole number of steps of {ctx.dt_s} s",
        )
    if steps > MAX_DELAY_STEPS:
        raise NirError(
            label(delay_name, delay),
            f"delay {delay_s} s is {steps} steps of {ctx.dt_s} s, "
            f"more than the {MAX_DELAY_STEPS} a projection may have",
        )
    return int(steps)
