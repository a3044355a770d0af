#!/usr/bin/env python3
"""dv-processing's BackgroundActivityNoiseFilter on the same events, for same-run ratios.

Usage: python dv_processing_ba.py EVENTS.csv WINDOW_US REPEATS
Reads a `t,x,y,on` CSV (t in µs), runs the C++ filter (dv-processing's Python binding) REPEATS
times on the whole store and prints {"peer": ..., "events_per_s": ..., "kept": ...} — the best
repeat, timing the filter call only (loading and conversion excluded). Needs
`pip install dv-processing numpy`.
"""
import json
import sys
import time
from datetime import timedelta

import dv_processing as dv
import numpy as np

path, window_us, repeats = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
data = np.loadtxt(path, delimiter=",", skiprows=1, dtype=np.int64)
store = dv.EventStore()
for t, x, y, on in data:
    store.push_back(int(t), int(x), int(y), bool(on))
best = float("inf")
kept = 0
for _ in range(repeats):
    f = dv.noise.BackgroundActivityNoiseFilter((240, 180), backgroundActivityDuration=timedelta(microseconds=window_us))
    start = time.perf_counter()
    f.accept(store)
    out = f.generateEvents()
    best = min(best, time.perf_counter() - start)
    kept = len(out)
print(json.dumps({"peer": f"dv-processing {dv.__version__}", "events_per_s": len(data) / best, "kept": kept}))
