"""Side-by-side comparison of the two peers from their saved results.

Reads results/moordyn_snapping.json / .npz and results/exudyn_snapping.json / .npz
(written by the peer scripts' __main__), prints the converged and cheap settings of
both peers next to each other, the difference between the two reference time series,
and writes results/snapping_peers.png (top tension / T0 of both references).

    python benchmarks/peers/compare_peers.py
"""

from __future__ import annotations

import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results")


def _load(peer: str):
    with open(os.path.join(RESULTS, f"{peer}_snapping.json")) as fh:
        meta = json.load(fh)
    series = np.load(os.path.join(RESULTS, f"{peer}_snapping_series.npz"))
    return meta, series


def _series(meta, series, f: str, pick: str = "reference"):
    r = meta[pick][f]
    key = f"{f}_{r['n_segments']}_{r['time_step_s']:g}"
    return r, series[f"t_{key}"].astype(float), series[f"T_{key}"].astype(float)


def main() -> None:
    peers = {}
    for p in ("moordyn", "exudyn"):
        try:
            peers[p] = _load(p)
        except FileNotFoundError:
            print(f"missing results for {p}: run benchmarks/peers/{p}_snapping.py first")
            sys.exit(1)
    freqs = list(peers["moordyn"][0]["reference"].keys())
    print(f"{'peer':<8}{'f[Hz]':>6} {'setting':<11}{'nseg':>5}{'dt[s]':>9}{'T0[N]':>9}"
          f"{'Tmax/T0':>9}{'Tmin/T0':>9}{'late max':>9}{'late min':>9}{'err%':>7}"
          f"{'ser.rms%':>9}{'wall/sim':>9}{'cpu/sim':>9}")
    for f in freqs:
        for p, (meta, _) in peers.items():
            for pick in ("reference", "converged", "cheap", "cheap_series"):
                r = meta.get(pick, {}).get(f)
                if r is None:
                    continue
                print(f"{p:<8}{float(f):>6.3f} {pick:<11}{r['n_segments']:>5d}{r['time_step_s']:>9.2e}"
                      f"{r['T0']:>9.4f}{r['Tmax_over_T0']:>9.4f}{r['Tmin_over_T0']:>9.4f}"
                      f"{r['Tmax_over_T0_late']:>9.4f}{r['Tmin_over_T0_late']:>9.4f}"
                      f"{r['error_pct']:>7.2f}{r['series_rms_pct']:>9.3f}"
                      f"{r['wall_per_sim_s']:>9.4f}{r['cpu_per_sim_s']:>9.4f}")
    print("\nMoorDyn reference against Exudyn reference (Exudyn interpolated to MoorDyn's samples):")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(freqs), 2, figsize=(13, 3.4 * len(freqs)), squeeze=False)
    for i, f in enumerate(freqs):
        rm, tm, Tm = _series(*peers["moordyn"], f)
        rx, tx, Tx = _series(*peers["exudyn"], f)
        T0 = rm["T0"]
        for win in ((0.0, 0.05), (0.05, 5.0), (0.05, 15.0), (5.0, 15.0)):
            m = (tm >= win[0]) & (tm <= win[1])
            d = (np.interp(tm[m], tx, Tx) - Tm[m]) / T0
            print(f"  f={f} Hz, window {win} s: RMS {100*np.sqrt(np.mean(d*d)):.3f} % T0, "
                  f"max {100*np.abs(d).max():.2f} % T0; Tmax/T0 {rm['Tmax_over_T0']:.4f} (MoorDyn) "
                  f"vs {rx['Tmax_over_T0']:.4f} (Exudyn)")
        for j, (a, b) in enumerate(((0.0, 15.0), (0.0, 2.0))):
            ax = axes[i][j]
            m1 = (tm >= a) & (tm <= b)
            m2 = (tx >= a) & (tx <= b)
            ax.plot(tm[m1], Tm[m1] / T0, lw=0.8,
                    label=f"MoorDyn {rm['n_segments']} seg, dt {rm['time_step_s']:g} s")
            ax.plot(tx[m2], Tx[m2] / rx["T0"], lw=0.8, ls="--",
                    label=f"Exudyn {rx['n_segments']} el., h {rx['time_step_s']:g} s")
            ax.set_title(f"f = {f} Hz, t in [{a:g}, {b:g}] s")
            ax.set_xlabel("t [s]")
            ax.set_ylabel("T_top / T0")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7)
    fig.tight_layout()
    out = os.path.join(RESULTS, "snapping_peers.png")
    fig.savefig(out, dpi=90)
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()
