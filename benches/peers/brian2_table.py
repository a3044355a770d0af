#!/usr/bin/env python3
"""The README's performance table: neurotac against Brian2, like for like, in one run.

Usage: python brian2_table.py NEUROTAC PYTHON [REPEATS]
  NEUROTAC  the neurotac binary (e.g. target/release/neurotac)
  PYTHON    a Python with Brian2 (see brian2_bench.py)
  REPEATS   interleaved runs of each side per case, the fastest counting (default 5)

Runs `neurotac bench neurons|cuba --threads 1 --brian2 PYTHON --json` for every case of the
table (both precisions; LIF exact and Euler at N = 10^5; Izhikevich RS Euler at N = 10^6;
CUBA at f64) and prints a Markdown table with the machine, its load before and
after, and each side's time, rate and spikes, the ratio and the share of this core's ceilings.
Needs nothing beyond the standard library.
"""
import json
import os
import platform
import subprocess
import sys

CASES = [
    ("neurons", "lif", "exact", "100000"),
    ("neurons", "lif", "euler", "100000"),
    ("neurons", "izhikevich", "euler", "1000000"),
]


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def run(neurotac, args):
    out = subprocess.run([neurotac, *args], check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    if len(sys.argv) not in (3, 4):
        raise SystemExit(__doc__)
    neurotac, python = sys.argv[1], sys.argv[2]
    repeats = sys.argv[3] if len(sys.argv) == 4 else "5"
    common = ["--threads", "1", "--repeats", repeats, "--brian2", python, "--json"]
    load = os.getloadavg()
    rows = []
    for precision in ("f32", "f64"):
        for _, model, integrator, n in CASES:
            r = run(neurotac, ["bench", "neurons", "--model", model, "--n", n, "--precision", precision,
                               "--integrator", integrator, *common])
            rows.append((f"{model} {integrator}, N = {int(n):.0e}", precision, r, r["updates"]))
    r = run(neurotac, ["bench", "cuba", *common])
    rows.append(("CUBA (4000 LIF, exp-euler)", "f64", r, r["duration_s"]))
    print(f"{cpu_model()}, {os.cpu_count()} cores; one thread per side; load average "
          f"{load[0]:.2f} before, {os.getloadavg()[0]:.2f} after; fastest of {repeats} interleaved "
          f"runs of each side\n")
    print("| case | precision | neurotac (s) | Brian2 (s) | ratio | spikes (neurotac / Brian2) "
          "| neurotac updates/s | of FMA peak | of bandwidth |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, precision, r, work in rows:
        ours = r.get("wall_s") if "updates" in r else r["run_s"]
        ratio = f"{r['speedup']:.2f}×" if "speedup" in r else r.get("no_ratio", "—")
        rate = f"{work / ours:.3g}" if "updates" in r else "—"
        ceiling = r.get("ceiling") or {}
        flops = f"{100 * ceiling['of_peak_flops']:.0f} %" if "of_peak_flops" in ceiling else "—"
        bandwidth = f"{100 * ceiling['of_bandwidth']:.0f} %" if "of_bandwidth" in ceiling else "—"
        print(f"| {name} | {precision} | {ours:.4f} | {r['peer_wall_s']:.4f} | {ratio} "
              f"| {r['spikes']} / {r['peer_spikes']} | {rate} | {flops} | {bandwidth} |")


if __name__ == "__main__":
    main()
