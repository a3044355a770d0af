"""Network descriptions (the JSON schema of `Network.description()`) for the network and NIR
tests."""

DT_S = 1e-4


def network(nodes, projections, stepping="clock"):
    """A network description of `nodes` and `projections` at `DT_S`."""
    return {
        "format": "neurotac-network",
        "version": 1,
        "dt_s": DT_S,
        "stepping": stepping,
        "nodes": nodes,
        "projections": projections,
    }


def lif(n, tau_m_s=0.01, v_th=1.0, v_reset=0.0, **settings):
    """A LIF model description of `n` neurons (the schema of Network.description())."""
    return {
        "model": "lif",
        "size": n,
        "settings": {
            "precision": "f64",
            "integrator": "exact",
            "interpolate": False,
            "initial": {"constant": 0.0},
            "params": {
                "tau_m_s": tau_m_s,
                "v_rest": 0.0,
                "v_th": v_th,
                "v_reset": v_reset,
                "t_ref_s": 0.0,
                "v_min": None,
            },
            **settings,
        },
    }


def projection(pre, post, wiring, tau_s=0.005, delay_steps=1):
    return {
        "pre": pre,
        "post": post,
        "tau_s": tau_s,
        "delay_steps": delay_steps,
        "wiring": wiring,
        "plasticity": None,
    }


def sparse(pre, post, weight):
    return {"sparse": {"pre": pre, "post": post, "weight": weight}}
