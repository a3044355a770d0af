"""Networks in and out of NIR, the Neuromorphic Intermediate Representation (PyPI ``nir`` 1.0).

:func:`to_nir` turns a :class:`neurotac.Network` (or its JSON description) into a
``nir.NIRGraph``; :func:`from_nir` turns a ``nir.NIRGraph`` (yours, or one written by snnTorch,
Norse, Lava-dl, Rockpool, Sinabs… and read with ``nir.read``) into a runnable
:class:`neurotac.Network`. Both go through the network's JSON description
(:meth:`neurotac.Network.description`), so the Rust library never needs HDF5;
:func:`description_to_graph` and :func:`graph_to_description` are the dict-level halves.

Needs ``pip install neurotac[nir]`` (the ``nir`` package and its ``h5py``).

**The mapping.** NIR states continuous-time dynamics with input spikes as Dirac impulses. A
neurotac LIF population with its exponential synapses,

.. code-block:: text

    τ_m·dv/dt = (v_rest − v) + I        I ← I + w per arriving spike, τ_syn·dI/dt = −I

is a NIR ``CubaLIF`` (``τ_syn·dI/dt = −I + w_in·S``, ``τ_mem·dv/dt = (v_leak − v) + r·I``)
fed by a ``Linear`` node (``S = W·spikes``, W of shape ``(n_post, n_pre)``): one spike through
``W[i, j]`` moves the NIR current by ``w_in·W[i, j]/τ_syn``, so the neurotac weight is
``w = W[i, j]·(r·w_in/τ_syn)``. Exported graphs use ``r = 1`` and ``w_in = τ_syn`` (the factor is
exactly 1, so ``W`` holds neurotac's weights unchanged and the round trip is exact);
imported graphs may use any ``r`` and ``w_in`` (also per neuron: they scale the rows of W).

| neurotac | NIR |
|---|---|
| spike input (recorded trains or Poisson) | ``Input`` (trains, rate and seed in the graph's metadata) |
| LIF population, its projections sharing one τ_syn | ``CubaLIF`` (tau_mem = τ_m, v_leak = v_rest, v_threshold = v_th, v_reset) |
| LIF population, projections with different τ_syn | ``LIF`` (r = 1) with one ``LI`` synapse per projection (tau = r = τ_syn, v_leak = 0) |
| LIF population without projections | ``LIF`` |
| projection (one-to-one, all-to-all, sparse) | ``Linear`` (dense weights; ``Affine`` with a zero bias on import) |
| delay of d steps | ``Delay`` of ``d·dt`` seconds before the ``Linear`` |
| population that feeds no other | ``Output`` (named ``output_<node>``) |
| dt, stepping, integrator, precision, interpolation, initial potentials | graph metadata ``"neurotac"`` (JSON) |

On import, a foreign graph's nodes take neurotac's defaults for what NIR does not say: the exact
integrator, f64, spike times on the grid, clock-driven stepping, membranes starting at
``v_leak``; a delay must be a whole number of steps of ``dt_s`` (population → population spikes
arrive one step later at the earliest, the discrete-time reading of every step-based NIR
backend); an ``Output`` must read a spiking node (a population or an ``Input``). NIR thresholds are ``v > v_threshold``, neurotac's ``v ≥ v_th`` (the same
except when ``v`` lands exactly on the threshold). The metadata never overrides a NIR field, so
a graph edited in another tool imports with its edits.

**Limits and checks on import.** A graph is checked before anything is made from it: every
edge a ``(source, target)`` pair of node names the graph has, listed once, never into an
``Input`` nor out of an ``Output`` (an Output ends a path); the neurotac metadata, when present,
of the types :func:`to_nir` writes; every time constant > 0; every weight finite after scaling;
at most :data:`MAX_SIZE` neurons or channels per node and :data:`MAX_DELAY_STEPS` steps of
delay. Whatever a malformed graph breaks raises :class:`NirError` naming the node or edge.

What one side cannot express is refused with :class:`NirError` naming the node: Izhikevich
populations, plastic (STDP) projections, a refractory period or a potential floor ``v_min``
(no NIR neuron has them); NIR nodes neurotac cannot run (``Conv1d``, ``Conv2d``, pooling,
``Flatten``, ``IF``, ``I``, ``Threshold``, ``Scale``, ``CubaLI``, nested graphs, an ``LI``
that is not a synapse, an ``Affine`` with a bias), per-neuron time constants, thresholds or
resets, and a ``LIF`` fed without a synapse.
"""

import json as _json

import numpy as _np

try:
    import nir as _nir
except ImportError as e:  # pragma: no cover - exercised only without the optional extra
    raise ImportError(
        "neurotac.nir needs the nir package: pip install 'neurotac[nir]' (or pip install nir)"
    ) from e

from . import NeurotacValueError

__all__ = [
    "NirError",
    "description_to_graph",
    "from_nir",
    "graph_to_description",
    "to_nir",
]

#: Key of neurotac's settings in ``NIRGraph.metadata`` (a JSON string, so it survives HDF5).
METADATA_KEY = "neurotac"
_FORMAT = "neurotac-network"
_VERSION = 1
#: The record in the metadata, and its version.
_META_FORMAT = "neurotac-nir"
_META_VERSION = 1
_LIF = "lif"
#: The most neurons of a population, or channels of an ``Input``, an imported graph may have (a
#: spike train, and parameter values, are made for each).
MAX_SIZE = 2**22
#: The longest delay of an imported projection, in steps (the library's
#: ``graph::limits::MAX_DELAY_STEPS``).
MAX_DELAY_STEPS = 2**20
#: Node types :func:`graph_to_description` understands.
_NEURONS = ("CubaLIF", "LIF")
_CHAIN = ("Linear", "Affine", "Delay", "LI")


class NirError(NeurotacValueError):
    """A network or NIR graph the mapping cannot translate; ``node`` names the node."""

    def __init__(self, node, message):
        super().__init__(f"{node}: {message}")
        #: The neurotac or NIR node (or projection) refused.
        self.node = node


# ---------------------------------------------------------------------------------------------
# neurotac → NIR


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


def _full(n, value):
    return _np.full(int(n), float(value), dtype=_np.float64)


def _dense_weights(projection, n_pre, n_post):
    """The ``(n_post, n_pre)`` weight matrix of a projection's wiring."""
    name = _projection_name(projection)
    ((kind, spec),) = projection["wiring"].items()
    w = _np.zeros((n_post, n_pre), dtype=_np.float64)
    if kind == "one_to_one":
        _np.fill_diagonal(w, spec["weight"])
    elif kind == "all_to_all":
        w[:] = spec["weight"]
    elif kind == "sparse":
        pre = _np.asarray(spec["pre"], dtype=_np.int64)
        post = _np.asarray(spec["post"], dtype=_np.int64)
        # Repeated pairs add up, as their currents do.
        _np.add.at(w, (post, pre), _np.asarray(spec["weight"], dtype=_np.float64))
    else:
        raise NirError(name, f"{kind} wiring has no NIR export")
    return w


def _size(node):
    """The number of neurons or channels of a description's node."""
    if node["kind"] == "population":
        return node["model"]["size"]
    ((kind, source),) = node["source"].items()
    return len(source["trains"]) if kind == "spike_array" else source["size"]


def _projection_name(projection):
    return f"projection '{projection['pre']}' → '{projection['post']}'"


def _lif_settings(node):
    """The LIF settings of a population node, refusing what NIR cannot express."""
    model = node["model"]
    name = f"population '{node['name']}'"
    if model["model"] != _LIF:
        raise NirError(name, f"{model['model']} neurons have no NIR equivalent (only LIF does)")
    settings = model["settings"]
    params = settings["params"]
    if params.get("t_ref_s", 0.0) != 0.0:
        raise NirError(
            name,
            f"refractory period t_ref_s = {params['t_ref_s']} s has no NIR equivalent "
            "(NIR's LIF has none); export with t_ref_s = 0",
        )
    if params.get("v_min") is not None:
        raise NirError(
            name,
            f"potential floor v_min = {params['v_min']} has no NIR equivalent; export without one",
        )
    return settings


def description_to_graph(description):
    """The ``nir.NIRGraph`` of a network description (the dict of
    :meth:`neurotac.Network.description`); see the module docs for the mapping."""
    if description.get("format") != _FORMAT:
        raise NirError(
            "description", f"format is {description.get('format')!r}, expected {_FORMAT!r}"
        )
    dt_s = float(description["dt_s"])
    nodes = {n["name"]: n for n in description["nodes"]}
    graph_nodes = {}
    edges = []
    meta_nodes = {}

    def add(name, node):
        if name in graph_nodes:
            raise NirError(name, "two nodes of the NIR graph would have this name; rename one")
        graph_nodes[name] = node

    incoming = {name: [] for name in nodes}
    for p in description["projections"]:
        if p.get("plasticity") is not None:
            raise NirError(_projection_name(p), "is plastic (STDP); NIR has no plasticity rules")
        incoming[p["post"]].append(p)

    for name, node in nodes.items():
        kind = node["kind"]
        if kind == "population":
            settings = _lif_settings(node)
            params = settings["params"]
            n = node["model"]["size"]
            taus = {p["tau_s"] for p in incoming[name]}
            common = {
                "r": _full(n, 1.0),
                "v_leak": _full(n, params["v_rest"]),
                "v_threshold": _full(n, params["v_th"]),
                "v_reset": _full(n, params["v_reset"]),
            }
            if len(taus) == 1:
                (tau_syn,) = taus
                add(
                    name,
                    _nir.CubaLIF(
                        tau_syn=_full(n, tau_syn),
                        tau_mem=_full(n, params["tau_m_s"]),
                        w_in=_full(n, tau_syn),
                        **common,
                    ),
                )
            else:
                add(name, _nir.LIF(tau=_full(n, params["tau_m_s"]), **common))
            meta_nodes[name] = {
                "model": node["model"]["model"],
                "settings": {k: v for k, v in settings.items() if k != "params"},
            }
        elif kind == "source":
            add(name, _nir.Input(input_type=_np.array([_size(node)])))
            meta_nodes[name] = {"source": node["source"]}
        else:
            raise NirError(
                f"{kind} source '{name}'", "has no NIR equivalent (NIR inputs are spikes)"
            )

    used = set()
    for p in description["projections"]:
        pre, post = p["pre"], p["post"]
        base = f"{pre}_to_{post}"
        k = 2
        while base in used:
            base = f"{pre}_to_{post}_{k}"
            k += 1
        used.add(base)
        n_pre, n_post = _size(nodes[pre]), _size(nodes[post])
        source = pre
        if p["delay_steps"] > 0:
            add(f"{base}_delay", _nir.Delay(delay=_full(n_pre, p["delay_steps"] * dt_s)))
            edges.append((source, f"{base}_delay"))
            source = f"{base}_delay"
        add(f"{base}_linear", _nir.Linear(weight=_dense_weights(p, n_pre, n_post)))
        edges.append((source, f"{base}_linear"))
        source = f"{base}_linear"
        if isinstance(graph_nodes[post], _nir.LIF):
            tau = _full(n_post, p["tau_s"])
            add(f"{base}_synapse", _nir.LI(tau=tau, r=tau.copy(), v_leak=_full(n_post, 0.0)))
            edges.append((source, f"{base}_synapse"))
            source = f"{base}_synapse"
        edges.append((source, post))

    feeding = {p["pre"] for p in description["projections"]}
    for name, node in nodes.items():
        if node["kind"] == "population" and name not in feeding:
            add(f"output_{name}", _nir.Output(output_type=_np.array([_size(node)])))
            edges.append((name, f"output_{name}"))

    metadata = {
        "format": _META_FORMAT,
        "version": _META_VERSION,
        "dt_s": dt_s,
        "stepping": description["stepping"],
        "order": list(nodes),
        "unfed": [
            n for n, node in nodes.items() if node["kind"] == "population" and not incoming[n]
        ],
        "nodes": meta_nodes,
    }
    return _nir.NIRGraph(
        nodes=graph_nodes, edges=edges, metadata={METADATA_KEY: _json.dumps(metadata)}
    )


# ---------------------------------------------------------------------------------------------
# NIR → neurotac


def from_nir(graph, dt_s=None):
    """A runnable :class:`neurotac.Network` from a ``nir.NIRGraph``.

    ``dt_s`` is the time step in seconds; by default the one in the graph's neurotac metadata
    (a graph :func:`to_nir` made), required for any other graph. Raises :class:`NirError`
    naming the node neurotac cannot run; see the module docs for the mapping and defaults.
    """
    from . import Network

    description = _json.dumps(graph_to_description(graph, dt_s))
    try:
        return Network.from_description(description)
    except NeurotacValueError as e:
        raise NirError("graph", f"its network does not build: {e}") from e


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
    if not isinstance(meta, dict) or meta.get("format") != _META_FORMAT:
        raise NirError("graph metadata", f"'{METADATA_KEY}' is not a {_META_FORMAT} record")
    if meta.get("version") != _META_VERSION:
        raise NirError(
            "graph metadata",
            f"'{METADATA_KEY}' has version {meta.get('version')}, "
            f"this neurotac reads {_META_VERSION}",
        )
    _check_metadata_types(meta)
    return meta


def _check_metadata_types(meta):
    """Refuses metadata fields of other types than :func:`description_to_graph` writes."""

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


def _label(name, node):
    return f"NIR node '{name}' ({type(node).__name__})"


def _edges(graph):
    """The graph's edges as ``(source, target)`` pairs, checked (see the module docs)."""
    nodes = graph.nodes
    if not isinstance(nodes, dict) or not all(isinstance(n, str) for n in nodes):
        raise NirError("graph", "nodes is not a dict from node names to nodes")
    try:
        edges = list(graph.edges)
    except TypeError as e:
        raise NirError("graph", "edges is not a list of (source, target) pairs") from e
    seen = set()
    for k, edge in enumerate(edges):
        label = f"edge {k} {edge!r}"
        try:
            a, b = edge
        except (TypeError, ValueError) as e:
            raise NirError(label, "is not a (source, target) pair") from e
        if isinstance(edge, (str, bytes)):
            raise NirError(label, "is not a (source, target) pair")
        for end in (a, b):
            if not isinstance(end, str):
                raise NirError(label, f"endpoint {end!r} is not a node name")
            if end not in nodes:
                raise NirError(label, f"names node '{end}', which the graph does not have")
        if (a, b) in seen:
            raise NirError(label, "is listed twice (its input would count twice)")
        if isinstance(nodes[b], _nir.Input):
            raise NirError(label, f"leads into Input '{b}', which receives nothing")
        if isinstance(nodes[a], _nir.Output):
            raise NirError(label, f"leaves Output '{a}', which ends a path")
        seen.add((a, b))
    return [tuple(e) for e in edges]


def _checked_size(name, node, size):
    """``size`` (neurons or channels of a node) as an int, refused beyond :data:`MAX_SIZE`."""
    if not 1 <= size <= MAX_SIZE:
        raise NirError(_label(name, node), f"size {size}, expected 1 to {MAX_SIZE}")
    return int(size)


def _positive(name, node, field, value):
    """A time constant, refused unless > 0."""
    if not value > 0:
        raise NirError(_label(name, node), f"{field} = {value}, expected > 0")
    return value


def _values(name, node, field, n=None):
    """A parameter as a float64 vector (of ``n`` values when it is a scalar)."""
    values = _np.asarray(getattr(node, field), dtype=_np.float64)
    if values.ndim == 0 and n is not None:
        values = _np.full(n, float(values))
    values = values.ravel()
    if n is not None and values.size != n:
        raise NirError(_label(name, node), f"{field} has {values.size} values, expected {n}")
    if not _np.all(_np.isfinite(values)):
        raise NirError(_label(name, node), f"{field} is not finite")
    return values


def _uniform(name, node, field, n=None):
    """A parameter that must be the same for every neuron, as a float."""
    values = _values(name, node, field, n)
    if values.size == 0:
        raise NirError(_label(name, node), f"{field} is empty")
    if not _np.all(values == values[0]):
        raise NirError(
            _label(name, node),
            f"{field} differs between neurons ({values.min()} to {values.max()}); "
            f"a neurotac population has one {field}",
        )
    return float(values[0])


def _shape_size(name, node, shape):
    """The number of values of an input or output ``shape`` (exact, never overflowing)."""
    dims = _np.asarray(shape).ravel().tolist()
    if not dims or not all(isinstance(d, int) and not isinstance(d, bool) and d >= 0 for d in dims):
        raise NirError(_label(name, node), f"shape {shape!r} is not a list of sizes")
    size = 1
    for d in dims:
        size *= d
    return _checked_size(name, node, size)


def _neuron_size(name, node):
    size = _np.asarray(node.v_threshold).size
    if _np.asarray(node.v_threshold).ndim == 0:
        shape = node.output_type.get("output") if isinstance(node.output_type, dict) else None
        if shape is None or _np.asarray(shape).size == 0:
            raise NirError(
                _label(name, node), "scalar parameters and no output shape: size unknown"
            )
        return _shape_size(name, node, shape)
    return _checked_size(name, node, size)


def _initial_at(v):
    """The initial potential `v` for every neuron, as the description states it."""
    return {"constant": v}


def _population(name, node, meta_node):
    """A description's population node from a NIR CubaLIF or LIF."""
    n = _neuron_size(name, node)
    tau_field = "tau_mem" if isinstance(node, _nir.CubaLIF) else "tau"
    tau_m = _positive(name, node, tau_field, _uniform(name, node, tau_field, n))
    v_leak = _uniform(name, node, "v_leak", n)
    params = {
        "tau_m_s": tau_m,
        "v_rest": v_leak,
        "v_th": _uniform(name, node, "v_threshold", n),
        "v_reset": _uniform(name, node, "v_reset", n),
        "t_ref_s": 0.0,
        "v_min": None,
    }
    settings = {
        "precision": "f64",
        "integrator": "exact",
        "interpolate": False,
        "initial": _initial_at(v_leak),
    }
    if meta_node.get("model") == _LIF:
        settings.update(meta_node.get("settings", {}))
    settings["params"] = params
    return {
        "kind": "population",
        "name": name,
        "model": {"model": _LIF, "size": n, "settings": settings},
    }


def _input(name, node, meta_node):
    """A description's spike source from a NIR Input (trains or Poisson from the metadata)."""
    shape = node.input_type.get("input") if isinstance(node.input_type, dict) else None
    if shape is None:
        raise NirError(_label(name, node), "input_type has no 'input' shape")
    size = _shape_size(name, node, shape)
    source = meta_node.get("source") or {"spike_array": {"trains": [[] for _ in range(size)]}}
    described = {"kind": "source", "name": name, "source": source}
    try:
        stated = _size(described)
    except (KeyError, TypeError, ValueError, AttributeError) as e:
        raise NirError(_label(name, node), f"its metadata source is malformed ({e!r})") from e
    if stated != size:
        raise NirError(
            _label(name, node), f"its metadata source has {stated!r} channels, the Input {size}"
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
    return {
        "sparse": {
            "pre": pre.tolist(),
            "post": post.tolist(),
            "weight": m[post, pre].tolist(),
        }
    }


def graph_to_description(graph, dt_s=None):
    """The network description (a dict, :meth:`neurotac.Network.description`'s schema) of a
    ``nir.NIRGraph``; see :func:`from_nir`."""
    meta = _metadata(graph)
    if dt_s is None:
        dt_s = meta.get("dt_s")
        if dt_s is None:
            raise NirError(
                "graph",
                "has no neurotac metadata, so its time step is unknown: "
                "pass from_nir(graph, dt_s=...)",
            )
    dt_s = float(dt_s)
    if not (_np.isfinite(dt_s) and dt_s > 0):
        raise NirError("graph", f"dt_s = {dt_s}, expected finite and > 0")
    edges = _edges(graph)
    nodes = graph.nodes
    for name, node in nodes.items():
        kind = type(node).__name__
        if kind not in ("Input", "Output") + _NEURONS + _CHAIN:
            raise NirError(_label(name, node), "neurotac cannot run this node type")
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
    for name in order:
        node = nodes[name]
        with _malformed(_label(name, node)):
            if isinstance(node, _nir.Input):
                described[name] = _input(name, node, meta_nodes.get(name, {}))
            elif isinstance(node, _NEURON_TYPES):
                described[name] = _population(name, node, meta_nodes.get(name, {}))
    visited = set(described) | added

    projections = []
    for src, post in edges:
        if src in added or not isinstance(nodes[post], _NEURON_TYPES):
            continue
        with _malformed(f"edge ('{src}', '{post}')"):
            projection, chain = _projection(graph, preds, described, src, post, dt_s)
        projections.append(projection)
        visited.update(chain)

    for name, node in nodes.items():
        if not isinstance(node, _nir.Output):
            continue
        visited.add(name)
        for src in preds[name]:
            if src not in described:
                raise NirError(
                    _label(src, nodes[src]),
                    f"feeds Output '{name}', but neurotac's outputs are the spikes of "
                    "populations and inputs (a non-spiking readout?)",
                )
    for name in nodes:
        if name not in visited:
            raise NirError(
                _label(name, nodes[name]),
                "is not on a path from a spiking node into a CubaLIF or LIF",
            )
    return {
        "format": _FORMAT,
        "version": _VERSION,
        "dt_s": dt_s,
        "stepping": meta.get("stepping") or "clock",
        "nodes": [described[n] for n in order if n in described],
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


_NEURON_TYPES = (_nir.CubaLIF, _nir.LIF)
_SPIKING_TYPES = (_nir.Input,) + _NEURON_TYPES


def _projection(graph, preds, described, src, post, dt_s):
    """The description's projection of the path ending with edge ``src → post``, and its
    nodes: ``pre → [Delay] → Linear|Affine → [LI, for a LIF] → post``, Delay anywhere."""
    nodes = graph.nodes
    target = nodes[post]
    chain = {}
    cur = src
    while not isinstance(nodes[cur], _SPIKING_TYPES):
        node = nodes[cur]
        kind = type(node).__name__
        slot = "Linear" if kind in ("Linear", "Affine") else kind
        if slot in chain:
            raise NirError(_label(cur, node), f"a second {slot} on the path into '{post}'")
        if slot == "LI" and "Linear" in chain:
            raise NirError(
                _label(cur, node),
                f"comes before a Linear on the path into '{post}'; a synapse is Linear → LI → LIF",
            )
        chain[slot] = cur
        if len(preds[cur]) != 1:
            raise NirError(
                _label(cur, node),
                f"has {len(preds[cur])} inputs; a neurotac projection starts at one spiking node",
            )
        cur = preds[cur][0]
    pre = cur
    n_pre, n_post = _size(described[pre]), _size(described[post])
    label = _label(post, target)

    if isinstance(target, _nir.CubaLIF):
        if "LI" in chain:
            raise NirError(
                _label(chain["LI"], nodes[chain["LI"]]),
                f"is a second synapse before CubaLIF '{post}'",
            )
        tau_s = _positive(post, target, "tau_syn", _uniform(post, target, "tau_syn", n_post))
        factor = (
            _values(post, target, "r", n_post) * _values(post, target, "w_in", n_post)
        ) / tau_s
    else:
        if "LI" not in chain:
            raise NirError(
                label,
                f"receives spikes from '{src}' without a synapse; neurotac populations receive "
                "spikes through exponential synapses (use CubaLIF, or an LI before the LIF)",
            )
        li_name = chain["LI"]
        li = nodes[li_name]
        tau_s = _positive(li_name, li, "tau", _uniform(li_name, li, "tau", n_post))
        if _np.any(_values(li_name, li, "v_leak", n_post) != 0):
            raise NirError(
                _label(li_name, li),
                "v_leak ≠ 0 is a constant current neurotac's synapses do not have",
            )
        factor = (_values(post, target, "r", n_post) * _values(li_name, li, "r", n_post)) / tau_s

    if "Linear" in chain:
        linear_name = chain["Linear"]
        linear = nodes[linear_name]
        weight = _np.asarray(linear.weight, dtype=_np.float64)
        if weight.shape != (n_post, n_pre):
            raise NirError(
                _label(linear_name, linear),
                f"weight has shape {weight.shape}, expected ({n_post}, {n_pre}) "
                f"for '{pre}' → '{post}'",
            )
        if isinstance(linear, _nir.Affine) and _np.any(_np.asarray(linear.bias) != 0):
            raise NirError(
                _label(linear_name, linear),
                "a bias is a constant current neurotac's projections do not have",
            )
        if not _np.all(_np.isfinite(weight)):
            raise NirError(_label(linear_name, linear), "weight is not finite")
    else:
        if n_pre != n_post:
            raise NirError(
                label, f"receives {n_pre} channels from '{pre}' directly, expected {n_post}"
            )
        weight = _np.eye(n_post)

    delay_steps = 0
    if "Delay" in chain:
        delay_name = chain["Delay"]
        delay = nodes[delay_name]
        delay_s = _uniform(delay_name, delay, "delay")
        steps = round(delay_s / dt_s)
        if delay_s < 0 or abs(steps * dt_s - delay_s) > 1e-9 * max(delay_s, dt_s):
            raise NirError(
                _label(delay_name, delay),
                f"delay {delay_s} s is not a whole number of steps of {dt_s} s",
            )
        delay_steps = int(steps)
        if delay_steps > MAX_DELAY_STEPS:
            raise NirError(
                _label(delay_name, delay),
                f"delay {delay_s} s is {delay_steps} steps of {dt_s} s, "
                f"more than the {MAX_DELAY_STEPS} a projection may have",
            )
    if isinstance(nodes[pre], _NEURON_TYPES):
        delay_steps = max(delay_steps, 1)
    with _np.errstate(over="ignore"):
        effective = weight * factor[:, None]
    if not _np.all(_np.isfinite(effective)):
        raise NirError(label, f"the weights from '{pre}' scaled by r·w_in/τ_syn are not finite")
    projection = {
        "pre": pre,
        "post": post,
        "tau_s": tau_s,
        "delay_steps": delay_steps,
        "wiring": _wiring(effective),
        "plasticity": None,
    }
    return projection, chain.values()
