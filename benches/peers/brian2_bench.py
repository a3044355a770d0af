#!/usr/bin/env python3
"""Brian2 (C++ standalone) on the cases `neurotac bench` measures, for same-run ratios.

Usage: python brian2_bench.py neurons MODEL N DURATION_S DT_S THREADS PRECISION METHOD
       python brian2_bench.py cuba DURATION_S DT_S THREADS PRECISION METHOD NEURONS PROBABILITY
       python brian2_bench.py stdp DURATION_S DT_S PRECISION METHOD INPUTS RATE_HZ SEED
PRECISION is float32 or float64 (Brian2's `prefs.core.default_float_dtype`: the state
variables' type). METHOD is the integration method, named as neurotac names it:
  exact      Brian2 "exact" (LIF under constant input)
  euler      Brian2 "euler"
  rk2        Heun's method, x + h/2·(f(x) + f(x + h·f(x))), as an explicit state updater
             (Brian2's own "rk2" is the midpoint method, which neurotac does not have)
  rk4        Brian2 "rk4" (classical Runge–Kutta)
  exp-euler  Brian2 "exponential_euler" (each equation exact in its own variable with the
             others held over the step; for CUBA this is neurotac's LIF step: the synaptic
             currents held over the step, v advanced exactly, the currents decayed exactly)
Prints one JSON object: {"peer": "brian2 <version>", "precision": ..., "method": ...,
"run_s": <seconds>, "spikes": <count>}, the precision read back from Brian2's preferences.
run_s is the simulation loop only (Brian2's own timer), as neurotac's wall_s; compilation is
excluded. THREADS = 1 runs without OpenMP. Needs `pip install brian2` and a C++ compiler.

`stdp` (Song, Miller & Abbott 2000; one thread) also prints "weights", the final weights (mV),
and "spike_times_s", the output neuron's spike times.
"""
import json
import sys
import shutil
import tempfile

import numpy as np
import brian2 as b2
from brian2 import ms, mV, second


# The standalone project is built in a temporary folder, removed once the results are read
# (`device.build` defaults to ./output, so the folder is passed to it, not only to set_device).
BUILD_DIR = tempfile.mkdtemp(prefix="brian2_")

HEUN = b2.ExplicitStateUpdater("""
    __k_1 = dt * f(x, t)
    __k_2 = dt * f(x + __k_1, t + dt)
    x_new = x + (__k_1 + __k_2) / 2""")
METHODS = {"exact": "exact", "euler": "euler", "rk2": HEUN, "rk4": "rk4",
           "exp-euler": "exponential_euler"}


def standalone(threads, precision):
    b2.set_device("cpp_standalone", directory=BUILD_DIR, build_on_run=False)
    b2.prefs.devices.cpp_standalone.openmp_threads = 0 if threads <= 1 else threads
    b2.prefs.logging.console_log_level = "ERROR"
    if precision not in ("float32", "float64"):
        raise SystemExit(f"unknown precision {precision} (float32 or float64)")
    b2.prefs.core.default_float_dtype = getattr(np, precision)


def method(name):
    if name not in METHODS:
        raise SystemExit(f"Brian2 has no counterpart of the integrator {name} "
                         f"(one of: {', '.join(METHODS)})")
    return METHODS[name]


def finish(monitor_count, method_name, cleanup=True):
    """Builds and runs the project; removes it unless `cleanup` is False (the caller still
    reads results from it and removes it)."""
    try:
        b2.device.build(directory=BUILD_DIR, run=True, compile=True)
        return {"peer": f"brian2 {b2.__version__}",
                "precision": np.dtype(b2.prefs.core.default_float_dtype).name,
                "method": method_name,
                "run_s": b2.device._last_run_time,
                "spikes": int(monitor_count())}
    finally:
        if cleanup:
            shutil.rmtree(BUILD_DIR, ignore_errors=True)


def neurons(model, n, duration, dt, threads, precision, method_name):
    standalone(threads, precision)
    b2.defaultclock.dt = dt * second
    if model == "lif":
        tau = 10 * ms
        g = b2.NeuronGroup(n, "dv/dt = (I - v) / tau : 1\nI : 1", threshold="v >= 1", reset="v = 0",
                           method=method(method_name), namespace={"tau": tau})
        g.v = "rand()"
        g.I = 1.04
    elif model == "izhikevich":
        eqs = """dv/dt = (0.04 * v**2 + 5 * v + 140 - u + I) / ms : 1
                 du/dt = a * (b * v - u) / ms : 1
                 I : 1"""
        g = b2.NeuronGroup(n, eqs, threshold="v >= 30", reset="v = c; u += d",
                           method=method(method_name),
                           namespace={"a": 0.02, "b": 0.2, "c": -65.0, "d": 8.0})
        g.v = -65.0
        g.u = -13.0
        g.I = 10.0
    else:
        raise SystemExit(f"unknown model {model}")
    counter = b2.SpikeMonitor(g, record=False)
    b2.run(duration * second)
    return finish(lambda: counter.num_spikes, method_name)


def cuba(duration, dt, threads, precision, method_name, neurons, probability):
    standalone(threads, precision)
    b2.defaultclock.dt = dt * second
    taum, taue, taui = 20 * ms, 5 * ms, 10 * ms
    vt, vr, el = -50 * mV, -60 * mV, -49 * mV
    eqs = """dv/dt  = (ge + gi - (v - el)) / taum : volt (unless refractory)
             dge/dt = -ge / taue : volt
             dgi/dt = -gi / taui : volt"""
    n_exc = neurons * 4 // 5
    p = b2.NeuronGroup(neurons, eqs, threshold="v > vt", reset="v = vr", refractory=5 * ms,
                       method=method(method_name),
                       namespace={"taum": taum, "taue": taue, "taui": taui, "vt": vt, "vr": vr, "el": el})
    p.v = "vr + rand() * (vt - vr)"
    we, wi = (60 * 0.27 / 10) * mV, (-20 * 4.5 / 10) * mV
    ce = b2.Synapses(p, p, on_pre="ge += we", namespace={"we": we})
    ci = b2.Synapses(p, p, on_pre="gi += wi", namespace={"wi": wi})
    ce.connect("i < n_exc", p=probability, namespace={"n_exc": n_exc})
    ci.connect("i >= n_exc", p=probability, namespace={"n_exc": n_exc})
    counter = b2.SpikeMonitor(p, record=False)
    b2.run(duration * second)
    return finish(lambda: counter.num_spikes, method_name)


def stdp(duration, dt, precision, method_name, inputs, rate_hz, seed):
    """Brian2's STDP example (examples/synapses/STDP.py) made current-based, as neurotac's
    `song_abbott` network: `tau_m dv/dt = (v_rest - v) + I`, `I` jumping by `w` per input spike
    and decaying with tau_syn; w_max = gmax * (E_e - v_reset) = 0.01 * 60 mV = 0.6 mV, the
    example's dApre = 0.01 w_max and dApost = -1.05 dApre; event-driven traces.

    The input pathway runs at the start of the step (`when = "before_groups"`): it delivers the
    previous step's input spikes before the neuron is integrated, as Brian2 does by default
    (there, after the integration of the step they fire in), and its STDP sees them at that
    step, which is neurotac's one-step delay and its pre-at-arrival timing. Post spikes act in
    the step they fire, after the integration, as neurotac's."""
    standalone(1, precision)
    b2.seed(seed)
    b2.defaultclock.dt = dt * second
    tau_m, tau_syn, tau_pre, tau_post = 10 * ms, 5 * ms, 20 * ms, 20 * ms
    v_rest, v_th, v_reset = -74 * mV, -54 * mV, -60 * mV
    w_max = 0.01 * (0 * mV - v_reset)
    d_apre = 0.01 * w_max
    d_apost = -d_apre * tau_pre / tau_post * 1.05
    eqs = """dv/dt = (v_rest - v + I) / tau_m : volt
             dI/dt = -I / tau_syn : volt"""
    neuron = b2.NeuronGroup(1, eqs, threshold="v >= v_th", reset="v = v_reset",
                            method=method(method_name),
                            namespace={"tau_m": tau_m, "tau_syn": tau_syn, "v_rest": v_rest,
                                       "v_th": v_th, "v_reset": v_reset})
    neuron.v = v_rest
    source = b2.PoissonGroup(inputs, rates=rate_hz * b2.Hz)
    synapses = b2.Synapses(
        source, neuron,
        """w : volt
           dApre/dt = -Apre / tau_pre : volt (event-driven)
           dApost/dt = -Apost / tau_post : volt (event-driven)""",
        on_pre="""I += w
                  Apre += d_apre
                  w = clip(w + Apost, 0 * mV, w_max)""",
        on_post="""Apost += d_apost
                   w = clip(w + Apre, 0 * mV, w_max)""",
        namespace={"tau_pre": tau_pre, "tau_post": tau_post, "d_apre": d_apre,
                   "d_apost": d_apost, "w_max": w_max})
    synapses.connect()
    synapses.w = "rand() * w_max"
    synapses.pre.when = "before_groups"
    spikes = b2.SpikeMonitor(neuron)
    b2.run(duration * second, namespace={})
    out = finish(lambda: spikes.num_spikes, method_name, cleanup=False)
    try:
        out["weights"] = [float(w) for w in synapses.w[:] / mV]
        out["spike_times_s"] = [float(t) for t in spikes.t[:] / second]
    finally:
        shutil.rmtree(BUILD_DIR, ignore_errors=True)
    return out


if __name__ == "__main__":
    args = sys.argv[1:]
    if args[:1] == ["neurons"] and len(args) == 8:
        out = neurons(args[1], int(args[2]), float(args[3]), float(args[4]), int(args[5]), args[6], args[7])
    elif args[:1] == ["cuba"] and len(args) == 8:
        out = cuba(float(args[1]), float(args[2]), int(args[3]), args[4], args[5], int(args[6]), float(args[7]))
    elif args[:1] == ["stdp"] and len(args) == 8:
        out = stdp(float(args[1]), float(args[2]), args[3], args[4], int(args[5]), float(args[6]),
                   int(args[7]))
    else:
        raise SystemExit(__doc__)
    print(json.dumps(out))
