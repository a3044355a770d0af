"""neurotac → NIR: :func:`description_to_graph`, the ``nir.NIRGraph`` of a network description
(the mapping is in the docs of :mod:`neurotac.nir`)."""

import json as _json
import math as _math

import numpy as _np
import nir as _nir

from .common import (
    FORMAT,
    IF,
    LIF,
    META_FORMAT,
    META_VERSION,
    METADATA_KEY,
    NirError,
    full,
    is_one_step,
    projection_name,
    size_of,
)


def _dense_weights(projection, n_pre, n_post):
    """The ``(n_post, n_pre)`` weight matrix of a projection's wiring."""
    name = projection_name(projection)
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
        raise NirError(name, f"{kind} wiring has no NIR export (build the network first)")
    return w


def _model_settings(node):
    """The model name and settings of a population node, refusing what NIR cannot express."""
    model = node["model"]
    name = f"population '{node['name']}'"
    if model["model"] not in (LIF, IF):
        raise NirError(
            name, f"{model['model']} neurons have no NIR equivalent (LIF and IF do)"
        )
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
    return model["model"], settings


def _one_step_gain(model, settings, dt_s):
    """How far a one-step input of 1 moves the membrane of a population (the step's gain):
    LIF ``1 − e^(−dt/τ_m)`` (exact) or ``dt/τ_m`` (Euler), IF ``dt/τ_m``."""
    params = settings["params"]
    h = dt_s / params["tau_m_s"]
    if model == LIF and settings["integrator"] in ("exact", "exp-euler"):
        return -_math.expm1(-h)
    if model == IF or settings["integrator"] == "euler":
        return h
    raise NirError(
        "population",
        f"a one-step synapse into a {model} population integrated with "
        f"{settings['integrator']} has no NIR equivalent",
    )


def description_to_graph(description):
    """The ``nir.NIRGraph`` of a network description (the dict of
    :meth:`neurotac.Network.description`); see :mod:`neurotac.nir` for the mapping."""
    if description.get("format") != FORMAT:
        raise NirError(
            "description", f"format is {description.get('format')!r}, expected {FORMAT!r}"
        )
    dt_s = float(description["dt_s"])
    nodes = {n["name"]: n for n in description["nodes"]}
    graph_nodes = {}
    edges = []
    meta_nodes = {}
    models = {}

    def add(name, node):
        if name in graph_nodes:
            raise NirError(name, "two nodes of the NIR graph would have this name; rename one")
        graph_nodes[name] = node

    incoming = {name: [] for name in nodes}
    for p in description["projections"]:
        if p.get("plasticity") is not None:
            raise NirError(projection_name(p), "is plastic (STDP); NIR has no plasticity rules")
        incoming[p["post"]].append(p)

    for name, node in nodes.items():
        kind = node["kind"]
        if kind == "population":
            model, settings = _model_settings(node)
            models[name] = (model, settings)
            params = settings["params"]
            n = node["model"]["size"]
            if model == IF:
                # τ_m·dv/dt = I is NIR's dv/dt = R·I with R = 1/τ_m.
                add(name, _nir.IF(r=full(n, 1.0 / params["tau_m_s"]),
                                  v_threshold=full(n, params["v_th"]),
                                  v_reset=full(n, params["v_reset"])))
            else:
                exp_taus = {p["tau_s"] for p in incoming[name] if not is_one_step(p, dt_s)}
                direct = any(is_one_step(p, dt_s) for p in incoming[name])
                common = {
                    "r": full(n, 1.0),
                    "v_leak": full(n, params["v_rest"]),
                    "v_threshold": full(n, params["v_th"]),
                    "v_reset": full(n, params["v_reset"]),
                }
                if len(exp_taus) == 1 and not direct:
                    (tau_syn,) = exp_taus
                    add(name, _nir.CubaLIF(tau_syn=full(n, tau_syn),
                                           tau_mem=full(n, params["tau_m_s"]),
                                           w_in=full(n, tau_syn), **common))
                else:
                    add(name, _nir.LIF(tau=full(n, params["tau_m_s"]), **common))
            meta_nodes[name] = {
                "model": model,
                "settings": {k: v for k, v in settings.items() if k != "params"},
            }
        elif kind == "source":
            add(name, _nir.Input(input_type=_np.array([size_of(node)])))
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
        n_pre, n_post = size_of(nodes[pre]), size_of(nodes[post])
        weight = _dense_weights(p, n_pre, n_post)
        model, settings = models[post]
        one_step = is_one_step(p, dt_s)
        if one_step:
            # A current that lasts one step moves v by w·gain: a jump, NIR's Dirac through
            # W = jump·τ_m/R (LIF, R = 1) or W = jump/R (IF, R = 1/τ_m): W = jump·τ_m.
            try:
                gain = _one_step_gain(model, settings, dt_s)
            except NirError as e:
                raise NirError(projection_name(p), str(e).split(": ", 1)[1]) from e
            weight = weight * gain * settings["params"]["tau_m_s"]
        source = pre
        if p["delay_steps"] > 0:
            add(f"{base}_delay", _nir.Delay(delay=full(n_pre, p["delay_steps"] * dt_s)))
            edges.append((source, f"{base}_delay"))
            source = f"{base}_delay"
        add(f"{base}_linear", _nir.Linear(weight=weight))
        edges.append((source, f"{base}_linear"))
        source = f"{base}_linear"
        if not one_step and not isinstance(graph_nodes[post], _nir.CubaLIF):
            tau = full(n_post, p["tau_s"])
            add(f"{base}_synapse", _nir.LI(tau=tau, r=tau.copy(), v_leak=full(n_post, 0.0)))
            edges.append((source, f"{base}_synapse"))
            source = f"{base}_synapse"
        edges.append((source, post))

    feeding = {p["pre"] for p in description["projections"]}
    for name, node in nodes.items():
        if node["kind"] == "population" and name not in feeding:
            add(f"output_{name}", _nir.Output(output_type=_np.array([size_of(node)])))
            edges.append((name, f"output_{name}"))

    metadata = {
        "format": META_FORMAT,
        "version": META_VERSION,
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
