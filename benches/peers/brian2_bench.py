#!/usr/bin/env python3
"""Brian2 (C++ standalone) on the cases `neurotac bench` measures, for same-run ratios.

Usage: python brian2_bench.py neurons MODEL N DURATION_S DT_S THREADS
       python brian2_bench.py cuba DURATION_S DT_S THREADS
Prints one JSON object: {"peer": "brian2 <version>", "run_s": <seconds>, "spikes": <count>}.
run_s is the simulation loop only (Brian2's own timer), as neurotac's wall_s; compilation is
excluded. THREADS = 1 runs without OpenMP. Needs `pip install brian2` and a C++ compiler.
"""
import json
import sys
import shutil
import tempfile

import brian2 as b2
from brian2 import ms, mV, second


# The standalone project is built in a temporary folder, removed once the results are read
# (`device.build` defaults to ./output, so the folder is passed to it, not only to set_device).
BUILD_DIR = tempfile.mkdtemp(prefix="brian2_")


def standalone(threads):
    b2.set_device("cpp_standalone", directory=BUILD_DIR, build_on_run=False)
    b2.prefs.devices.cpp_standalone.openmp_threads = 0 if threads <= 1 else threads
    b2.prefs.logging.console_log_level = "ERROR"


def finish(monitor_count):
    try:
        b2.device.build(directory=BUILD_DIR, run=True, compile=True)
        return {"peer": f"brian2 {b2.__version__}", "run_s": b2.device._last_run_time, "spikes": int(monitor_count())}
    finally:
        shutil.rmtree(BUILD_DIR, ignore_errors=True)


def neurons(model, n, duration, dt, threads):
    standalone(threads)
    b2.defaultclock.dt = dt * second
    if model == "lif":
        tau = 10 * ms
        g = b2.NeuronGroup(n, "dv/dt = (I - v) / tau : 1\nI : 1", threshold="v >= 1", reset="v = 0",
                           method="exact", namespace={"tau": tau})
        g.v = "rand()"
        g.I = 1.04
    elif model == "izhikevich":
        eqs = """dv/dt = (0.04 * v**2 + 5 * v + 140 - u + I) / ms : 1
                 du/dt = a * (b * v - u) / ms : 1
                 I : 1"""
        g = b2.NeuronGroup(n, eqs, threshold="v >= 30", reset="v = c; u += d", method="euler",
                           namespace={"a": 0.02, "b": 0.2, "c": -65.0, "d": 8.0})
        g.v = -65.0
        g.u = -13.0
        g.I = 10.0
    else:
        raise SystemExit(f"unknown model {model}")
    counter = b2.SpikeMonitor(g, record=False)
    b2.run(duration * second)
    return finish(lambda: counter.num_spikes)


def cuba(duration, dt, threads):
    standalone(threads)
    b2.defaultclock.dt = dt * second
    taum, taue, taui = 20 * ms, 5 * ms, 10 * ms
    vt, vr, el = -50 * mV, -60 * mV, -49 * mV
    eqs = """dv/dt  = (ge + gi - (v - el)) / taum : volt (unless refractory)
             dge/dt = -ge / taue : volt
             dgi/dt = -gi / taui : volt"""
    p = b2.NeuronGroup(4000, eqs, threshold="v > vt", reset="v = vr", refractory=5 * ms, method="exact",
                       namespace={"taum": taum, "taue": taue, "taui": taui, "vt": vt, "vr": vr, "el": el})
    p.v = "vr + rand() * (vt - vr)"
    we, wi = (60 * 0.27 / 10) * mV, (-20 * 4.5 / 10) * mV
    ce = b2.Synapses(p, p, on_pre="ge += we", namespace={"we": we})
    ci = b2.Synapses(p, p, on_pre="gi += wi", namespace={"wi": wi})
    ce.connect("i < 3200", p=0.02)
    ci.connect("i >= 3200", p=0.02)
    counter = b2.SpikeMonitor(p, record=False)
    b2.run(duration * second)
    return finish(lambda: counter.num_spikes)


if __name__ == "__main__":
    args = sys.argv[1:]
    if args[:1] == ["neurons"] and len(args) == 6:
        out = neurons(args[1], int(args[2]), float(args[3]), float(args[4]), int(args[5]))
    elif args[:1] == ["cuba"] and len(args) == 4:
        out = cuba(float(args[1]), float(args[2]), int(args[3]))
    else:
        raise SystemExit(__doc__)
    print(json.dumps(out))
