"""pymuvr vs neurotac: ``square_distance_matrix`` on the same data, in one Python process.

Data: 200 observations × 49 units, each unit a Poisson(35) number of spike times drawn
uniformly in [0, 1) s and sorted (seeded; plain Python lists, as pymuvr needs). Both libraries
compute the full matrix at cos = 0.4, τ = 0.076 s (pymuvr's cost does not depend on either).
Time is process CPU time (``time.process_time``), so the ratio is per CPU second; neurotac runs
on one thread (``threads=1``), and its time includes converting the Python lists. pymuvr runs
once (about a minute); neurotac ``--repeat`` times (default 3): the ratio uses the median, and
the first (cold) run's ratio is printed too. The two
matrices must agree: the maximum relative difference of D² over the off-diagonal entries is
printed, and the script fails when it exceeds 1e-9.

Needs pymuvr: ``pip install numpy wheel setuptools`` then ``pip install --no-build-isolation
pymuvr``. Run: ``python bench/pymuvr_compare.py [--samples N] [--units P] [--spikes S]``.
"""

import argparse
import sys
import time

import numpy as np


def observations(rng, samples, units, spikes):
    """Seeded random observations in pymuvr's form (sorted lists of floats)."""
    return [
        [sorted(rng.uniform(0.0, 1.0, rng.poisson(spikes)).tolist()) for _ in range(units)]
        for _ in range(samples)
    ]


def cpu_time(f):
    """(result, CPU seconds, wall seconds) of ``f()``."""
    cpu, wall = time.process_time(), time.perf_counter()
    result = f()
    return result, time.process_time() - cpu, time.perf_counter() - wall


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=200)
    parser.add_argument("--units", type=int, default=49)
    parser.add_argument("--spikes", type=float, default=35.0)
    parser.add_argument("--cos", type=float, default=0.4)
    parser.add_argument("--tau", type=float, default=0.076)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    try:
        import pymuvr
    except ImportError:
        sys.exit(
            "pymuvr is not installed: pip install numpy wheel setuptools && "
            "pip install --no-build-isolation pymuvr"
        )
    import neurotac

    obs = observations(np.random.default_rng(args.seed), args.samples, args.units, args.spikes)
    n_spikes = sum(len(u) for o in obs for u in o)
    print(
        f"{args.samples} observations × {args.units} units, {n_spikes / (args.samples * args.units):.1f} "
        f"spikes per unit (uniform in [0, 1) s), cos = {args.cos}, tau = {args.tau} s"
    )

    runs = [
        cpu_time(lambda: neurotac.van_rossum.square_distance_matrix(obs, args.cos, args.tau, threads=1))
        for _ in range(max(args.repeat, 1))
    ]
    ours = runs[0][0]
    assert all(np.array_equal(r[0], ours) for r in runs)
    ours_cpu = float(np.median([r[1] for r in runs]))
    cold_cpu = runs[0][1]
    each = ", ".join(f"{cpu:.3f}" for _, cpu, _ in runs)
    print(f"neurotac {neurotac.__version__} (1 thread): median {ours_cpu:.3f} s CPU of {len(runs)} runs ({each}; wall {runs[0][2]:.3f} s first)")
    theirs, theirs_cpu, theirs_wall = cpu_time(
        lambda: pymuvr.square_distance_matrix(obs, args.cos, args.tau)
    )
    print(f"pymuvr {getattr(pymuvr, '__version__', '')}: {theirs_cpu:.3f} s CPU ({theirs_wall:.3f} s wall)")

    off = ~np.eye(args.samples, dtype=bool)
    d2_ours, d2_theirs = ours[off] ** 2, np.asarray(theirs)[off] ** 2
    rel = np.max(np.abs(d2_ours - d2_theirs) / np.maximum(np.abs(d2_theirs), 1e-300))
    abs_d = np.max(np.abs(ours - np.asarray(theirs)))
    print(f"agreement: max relative difference of D² {rel:.2e}, max |ΔD| {abs_d:.2e}")
    print(
        f"ratio: neurotac is {theirs_cpu / ours_cpu:.0f}× faster per CPU second "
        f"({theirs_cpu / cold_cpu:.0f}× on its first run)"
    )
    if not rel <= 1e-9:
        sys.exit(f"the matrices disagree: max relative difference {rel:.2e} > 1e-9")


if __name__ == "__main__":
    main()
