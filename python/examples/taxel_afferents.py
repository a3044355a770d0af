"""Tutorial: the paper's taxel → afferent network, built in Python, on one simulated slide.

Run from the repository (after installing the package, python/README.md):

    python python/examples/taxel_afferents.py [RECORDING] [--figure raster.png]

It reads one slide's pixel events (default: the sample recording in examples/data, a
simulated slide over the 2.5 mm grid), turns them into the 49 taxel spike trains (the paper's
transduction: background-activity filter, receptive fields, 20 ms pooling), runs them through
49 LIF afferents — one per taxel, each fed by an exponential synapse (τ = 5 ms, weight 5: a lone
taxel spike makes one afferent spike about 3 ms later) — and prints what went in and came out.
With matplotlib installed (``pip install matplotlib``; optional) it draws the taxel and afferent
rasters and the afferents' membrane potential and population rate.
"""

import argparse
import pathlib

import numpy as np

import neurotac

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = REPOSITORY / "examples" / "data" / "grid-2.5mm-slide.aedat4"


# %% 1. Pixel events → 49 taxel spike trains
def taxel_trains(recording):
    """The 49 taxel spike trains (one array of times in s from the first event per taxel) of
    a recording, and the recording's duration (s)."""
    data = neurotac.transduce(recording)  # the CLI's defaults: BA 5 ms, r = 3 px, 20 ms pooling
    times, units = data["times"], data["units"]
    events = neurotac.read_events(recording)
    duration_s = (events["t"][-1] - events["t"][0]) * 1e-6
    return [times[units == taxel] for taxel in range(data["n_units"])], duration_s


# %% 2. The network: taxels → exponential synapses → LIF afferents, with monitors
def afferent_network(trains, dt_s=1e-4):
    b = neurotac.NetworkBuilder(dt_s=dt_s)
    b.add_spike_input("taxels", trains)
    b.add_population("afferents", 49, model="lif", tau_m_s=0.010, v_th=1.0, v_reset=0.0)
    b.connect("taxels", "afferents", "one_to_one", weight=5.0, tau_syn_s=0.005, delay_s=0.0)
    b.monitor_state("afferents", "v", every_s=1e-3)  # every millisecond
    return b.build()


# %% 3. Run the slide and read what the monitors hold
def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("recording", nargs="?", default=str(SAMPLE))
    parser.add_argument("--figure", help="write the figure here (PNG or SVG; needs matplotlib)")
    args = parser.parse_args()

    trains, recording_s = taxel_trains(args.recording)
    duration_s = recording_s + 0.05  # and 50 ms for the last taxel spike's answer
    net = afferent_network(trains)
    net.run(duration_s)

    taxel_times, taxel_ids = net.spikes("taxels")
    times, neurons = net.spikes("afferents")
    t_v, v = net.state_trace("afferents", "v")
    bins, rate_hz = net.population_rate("afferents", bin_s=0.02)
    print(f"{pathlib.Path(args.recording).name}: {duration_s:.2f} s simulated at dt = {net.dt_s * 1e3:g} ms")
    print(f"taxel spikes:    {taxel_times.size} ({taxel_times.size / 49:.2f} per taxel)")
    print(f"afferent spikes: {times.size} ({times.size / 49:.2f} per afferent)")
    if times.size:
        first = np.argmin(times)
        print(f"first afferent spike: afferent {neurons[first]} at {times[first] * 1e3:.1f} ms")
    busiest = np.argmax(np.bincount(neurons, minlength=49))
    print(f"busiest afferent: {busiest} ({np.count_nonzero(neurons == busiest)} spikes)")
    print(f"population rate: peak {rate_hz.max():.1f} Hz per afferent in a 20 ms bin "
          f"at {bins[np.argmax(rate_hz)]:.2f} s")
    print(f"membrane samples: {v.shape[0]} × {v.shape[1]} (every {t_v[1] - t_v[0]:.3f} s), "
          f"highest sampled v {v.max():.3f}")
    print(f"weights 'taxels->afferents': {np.count_nonzero(net.weights('taxels'))} synapses of 5.0")

    if args.figure:
        draw(args.figure, taxel_times, taxel_ids, times, neurons, t_v, v, bins, rate_hz, busiest)


# %% 4. The figure (optional: matplotlib)
def draw(path, taxel_times, taxel_ids, times, neurons, t_v, v, bins, rate_hz, busiest):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no figure: matplotlib is not installed (pip install matplotlib)")
        return
    fig, axes = plt.subplots(4, 1, figsize=(9, 8), sharex=True,
                             gridspec_kw={"height_ratios": [3, 3, 1.4, 1.4]})
    axes[0].scatter(taxel_times, taxel_ids, s=3, marker="|", color="#555555")
    axes[0].set_ylabel("taxel")
    axes[0].set_title("a simulated slide over the 2.5 mm grid: taxels → LIF afferents")
    axes[1].scatter(times, neurons, s=3, marker="|", color="#1b5e20")
    axes[1].set_ylabel("afferent")
    axes[2].plot(t_v, v[:, busiest], lw=0.8, color="#2b6cb0")
    axes[2].axhline(1.0, ls="--", lw=0.6, color="#999999")
    axes[2].set_ylabel(f"v, afferent {busiest}")
    axes[3].step(bins, rate_hz, where="post", color="#c62828", lw=1)
    axes[3].set_ylabel("rate (Hz)")
    axes[3].set_xlabel("time (s)")
    for ax in axes[:2]:
        ax.set_ylim(-1, 49)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"figure: {path}")


if __name__ == "__main__":
    main()
