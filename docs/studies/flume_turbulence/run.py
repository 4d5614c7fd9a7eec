"""The flume tank's turbulence-only case (Westin 2018, section 4.3, Table 4): the towed
sphere's 95 % ellipsoid against the turbulence filter.

The reference gives the flow's standard deviation per axis, the filter type (Chebyshev
type II low-pass, 80 dB stop-band attenuation) and the 100 Hz series, not the cut-off
(``water.turbulence.cutoff``, the stop-band edge) or the order. This script

* checks the generated flow: its standard deviation per axis (over the whole series and
  over 40 s windows) and its power spectrum against the filter's, for every filter of
  the sweep; and the flow the compiled kernels read between the samples;
* runs the ``flume`` scene (winch held, no motion: turbulence only) for every cut-off
  and order of the sweep and several seeds, and fits Calnan's 95 % ellipsoid to the
  sphere's track in consecutive 40 s windows: volume and standard deviation along its
  principal axes X_E, Y_E, Z_E, beside Table 4's experiment and the reference's model.

Writes ``results.json``, the tables ``results.md`` and the plots ``sphere.png`` and
``flow_spectrum.png`` next to this file.
Run: ``python docs/studies/flume_turbulence/run.py`` (about 13 minutes on 2 cores).
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy import signal

from towcable_fmu.analysis import enclosing_ellipsoid
from towcable_fmu.hydro.turbulence import TurbulenceSeries
from towcable_fmu.hydro.water import turbulence
from towcable_fmu.scene import load_scene
from towcable_fmu.ancf.simulation import Simulation

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from study_machine import machine  # noqa: E402

HERE = Path(__file__).resolve().parent
SCENE = "flume"
CUTOFFS = (0.5, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 14.0, 20.0)  # [Hz] stop-band edges
ORDERS = (2, 4, 8)
SEEDS = (1, 2, 3)
SETTLE = 10.0  # [s] left out after the start from the statics
WINDOW = 40.0  # [s] of track per ellipsoid
WINDOWS = 5    # per seed
INTERVAL = 0.02  # [s] between recorded sphere positions
FLOW_SECONDS = 3600.0  # [s] of generated flow per filter for its statistics
#: Table 4 (turbulence only): volume [cm^3] and standard deviations along X_E, Y_E, Z_E [cm]
TABLE4 = {"experiment": (4.82, (1.19, 0.78, 0.13)), "reference model": (7.76, (1.56, 1.23, 0.07))}


def turbulence_settings(cutoff: float, order: int, seed: int = 1):
    """The flume scene's turbulence with another filter and seed."""
    cfg = load_scene(SCENE).water.turbulence
    return dataclasses.replace(cfg, cutoff=cutoff, order=order, seed=seed)


def filter_properties(cfg) -> dict[str, float]:
    """Half-power frequency [Hz] and equivalent noise bandwidth [Hz] of the filter: the flow's
    low-frequency spectral level is std^2 / bandwidth."""
    sos = signal.cheby2(cfg.order, cfg.attenuation, cfg.cutoff, btype="low", fs=cfg.sample_rate, output="sos")
    f, h = signal.sosfreqz(sos, worN=2 ** 20, fs=cfg.sample_rate)
    power = np.abs(h) ** 2
    half = float(f[np.argmax(power < 0.5 * power[0])])
    bandwidth = float(np.trapezoid(power, f) / power[0])
    return {"half_power_hz": half, "bandwidth_hz": bandwidth}


def theoretical_psd(cfg, f: np.ndarray) -> np.ndarray:
    """One-sided spectrum [(m/s)^2/Hz] of unit white noise through the filter, scaled to std 1."""
    sos = signal.cheby2(cfg.order, cfg.attenuation, cfg.cutoff, btype="low", fs=cfg.sample_rate, output="sos")
    _, h = signal.sosfreqz(sos, worN=f, fs=cfg.sample_rate)
    _, hh = signal.sosfreqz(sos, worN=2 ** 20, fs=cfg.sample_rate)
    gain2 = np.mean(np.abs(hh) ** 2)  # sum of the squared impulse response
    return 2.0 / cfg.sample_rate * np.abs(h) ** 2 / gain2


def flow_statistics(cfg) -> dict:
    """Standard deviation per axis (whole series, 40 s windows) and the spectrum against the
    filter's: in the pass band (within 10 dB of the low-frequency level) the mean ratio and the
    largest deviation of 16-bin means, beyond the stop-band edge the power against the filter's
    and as a fraction of the whole."""
    series = TurbulenceSeries(cfg)
    series.extend_to(FLOW_SECONDS)
    x = series.samples[: int(FLOW_SECONDS * cfg.sample_rate)]
    std = np.asarray(cfg.std)
    n = int(WINDOW * cfg.sample_rate)
    windows = np.array([x[k:k + n].std(axis=0) for k in range(0, x.shape[0] - n + 1, n)]) / std
    f, p = signal.welch(x / std, fs=cfg.sample_rate, window="blackmanharris", nperseg=2 ** 15, axis=0)
    theory = theoretical_psd(cfg, f)
    band = (theory >= 0.1 * theory[0]) & (f >= 3.0 * f[1])  # the lowest bins lose the segments' means
    ratio = p[band] / theory[band, None]
    groups = ratio[: ratio.shape[0] // 16 * 16].reshape(-1, 16, 3).mean(axis=1) if ratio.shape[0] >= 16 else ratio
    stop = f >= cfg.cutoff
    return {"std_ratio": (x.std(axis=0) / std).tolist(),
            "window_std_ratio_min": windows.min(axis=0).tolist(), "window_std_ratio_max": windows.max(axis=0).tolist(),
            "passband_bins": int(band.sum()), "passband_mean_db": (10.0 * np.log10(ratio.mean(axis=0))).tolist(),
            "passband_max_abs_db": np.abs(10.0 * np.log10(groups)).max(axis=0).tolist(),
            "stopband_power_db": (10.0 * np.log10(p[stop].sum(axis=0) / theory[stop].sum())).tolist(),
            "stopband_fraction_db": (10.0 * np.log10(p[stop].sum(axis=0) / p.sum(axis=0))).tolist(),
            "_spectrum": (f, p[:, 0], theory)}


def kernel_flow(cfg, step: float = 0.002, seconds: float = 600.0) -> dict:
    """The fluctuation the compiled kernels read at the solver's steps (cubic Hermite between
    the samples): its standard deviation per axis against the samples' over the same time."""
    water = Simulation.from_scene(SCENE).model.water
    series = TurbulenceSeries(cfg)
    series.extend_to(seconds)
    w = water._replace(turb=series.samples, turb_t0=series.t0, turb_dt=series.dt)
    times = np.arange(0.0, seconds, step)
    read = np.array([turbulence(w, t)[:3] for t in times])
    samples = series.samples[: int(seconds * cfg.sample_rate)]
    return {"std_ratio": (read.std(axis=0) / samples.std(axis=0)).tolist()}


def sphere_windows(cutoff: float, order: int, seed: int) -> list[dict]:
    """Ellipsoid volume [cm^3] and standard deviations along X_E, Y_E, Z_E [cm] of the sphere's
    track in each 40 s window."""
    sim = Simulation.from_scene(SCENE, {"water.turbulence.cutoff": cutoff, "water.turbulence.order": order,
                                        "water.turbulence.seed": seed})
    sim.initialize()
    res = sim.run(SETTLE + WINDOWS * WINDOW, interval=INTERVAL)
    track = np.column_stack([res["towbody.x"], res["towbody.y"], res["towbody.z"]])
    out = []
    for k in range(WINDOWS):
        start = SETTLE + k * WINDOW
        inside = (res["time"] >= start - 1e-9) & (res["time"] < start + WINDOW - 1e-9)
        ell = enclosing_ellipsoid(track[inside])
        local = (track[inside] - ell.centre) @ ell.axes.T
        out.append({"volume_cm3": ell.volume * 1e6, "std_cm": (local.std(axis=0) * 100.0).tolist()})
    return out


def scale(volume: float, std: tuple[float, ...]) -> float:
    """The ellipsoid's radii over the standard deviations, k = (V / (4/3 pi s1 s2 s3))^(1/3)
    (2.80 for a normal distribution and 95 %)."""
    return (volume / (4.0 / 3.0 * math.pi * float(np.prod(std)))) ** (1.0 / 3.0)


def summarise(windows: list[dict]) -> dict:
    """Median, least and largest over the windows of every seed."""
    volume = np.array([w["volume_cm3"] for w in windows])
    std = np.array([w["std_cm"] for w in windows])
    k = np.array([scale(w["volume_cm3"], w["std_cm"]) for w in windows])
    return {"volume_cm3": [float(np.median(volume)), float(volume.min()), float(volume.max())],
            "std_cm": [[float(np.median(s)), float(s.min()), float(s.max())] for s in std.T],
            "scale": [float(np.median(k)), float(k.min()), float(k.max())], "windows": len(windows)}


def main() -> None:
    start = time.perf_counter()
    scene = load_scene(SCENE)
    results: dict = {"scene": SCENE, "scene_cutoff": scene.water.turbulence.cutoff,
                     "scene_order": scene.water.turbulence.order, "seeds": list(SEEDS), "settle_s": SETTLE,
                     "window_s": WINDOW, "windows_per_seed": WINDOWS, "interval_s": INTERVAL, "table4": TABLE4,
                     "filters": []}
    spectra = {}
    for order in ORDERS:
        for cutoff in CUTOFFS:
            cfg = turbulence_settings(cutoff, order)
            flow = flow_statistics(cfg)
            spectra[(cutoff, order)] = flow.pop("_spectrum")
            windows = [w for seed in SEEDS for w in sphere_windows(cutoff, order, seed)]
            row = {"cutoff_hz": cutoff, "order": order, **filter_properties(cfg), "flow": flow,
                   "sphere": summarise(windows), "sphere_windows": windows}
            results["filters"].append(row)
            print(json.dumps({k: v for k, v in row.items() if k != "sphere_windows"}), flush=True)
    default = turbulence_settings(scene.water.turbulence.cutoff, scene.water.turbulence.order)
    results["kernel_flow"] = kernel_flow(default)
    results["machine"] = machine()
    results["wall_time_s"] = time.perf_counter() - start
    (HERE / "results.json").write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    (HERE / "results.md").write_text(tables(results), encoding="utf-8")
    plot_sphere(results)
    plot_spectra(spectra, results)


def _stat(s: list[float], digits: int) -> str:
    return f"{s[0]:.{digits}f} ({s[1]:.{digits}f}-{s[2]:.{digits}f})"


def matching_bandwidth(results: dict, quantity: int, target: float) -> float:
    """The noise bandwidth B [Hz] at which the median over the windows (orders 4 and 8, B above
    0.3 Hz, where they agree) equals ``target``: log-log interpolation; NaN if never.
    ``quantity``: 0 the volume [cm^3], 1-3 the standard deviation along X_E, Y_E, Z_E [cm]."""
    rows = sorted((r for r in results["filters"] if r["order"] in (4, 8) and r["bandwidth_hz"] > 0.3),
                  key=lambda r: r["bandwidth_hz"])
    b = np.log([r["bandwidth_hz"] for r in rows])
    q = np.log([r["sphere"]["volume_cm3"][0] if quantity == 0 else r["sphere"]["std_cm"][quantity - 1][0]
                for r in rows])
    for k in range(len(rows) - 1):
        if (q[k] - math.log(target)) * (q[k + 1] - math.log(target)) <= 0.0 and q[k] != q[k + 1]:
            return float(np.exp(b[k] + (math.log(target) - q[k]) * (b[k + 1] - b[k]) / (q[k + 1] - q[k])))
    return math.nan


def cutoff_for(results: dict, order: int, bandwidth: float) -> str:
    """The cut-off [Hz] that gives the noise bandwidth ``bandwidth`` [Hz] with ``order``
    (log-log interpolation over the sweep), as text; outside the sweep, the bound passed."""
    rows = [r for r in results["filters"] if r["order"] == order]
    b = np.log([r["bandwidth_hz"] for r in rows])
    cut = np.log([r["cutoff_hz"] for r in rows])
    if math.log(bandwidth) > b[-1]:
        return f"> {math.exp(cut[-1]):g} Hz"
    if math.log(bandwidth) < b[0]:
        return f"< {math.exp(cut[0]):g} Hz"
    return f"{math.exp(np.interp(math.log(bandwidth), b, cut)):.1f} Hz"


def tables(results: dict) -> str:
    """The study's tables (markdown)."""
    lines = [f"Sphere of the `{results['scene']}` scene (turbulence only), Calnan's 95 % ellipsoid over "
             f"{results['window_s']:g} s windows: median (least-largest) over {len(results['seeds'])} seeds x "
             f"{results['windows_per_seed']} windows. Cut-off: the filter's stop-band edge; f_1/2: its "
             "half-power frequency; B: its equivalent noise bandwidth.", "",
             "| order | cut-off [Hz] | f_1/2 [Hz] | B [Hz] | volume [cm^3] | std X_E [cm] | std Y_E [cm] "
             "| std Z_E [cm] | k |", "|---|---|---|---|---|---|---|---|---|"]
    for name, (volume, std) in results["table4"].items():
        lines.append(f"| Table 4, {name} | | | | {volume:.2f} | {std[0]:.2f} | {std[1]:.2f} | {std[2]:.2f} "
                     f"| {scale(volume, std):.2f} |")
    for row in results["filters"]:
        s = row["sphere"]
        lines.append(f"| {row['order']} | {row['cutoff_hz']:g} | {row['half_power_hz']:.3f} "
                     f"| {row['bandwidth_hz']:.3f} | {_stat(s['volume_cm3'], 2)} | {_stat(s['std_cm'][0], 2)} "
                     f"| {_stat(s['std_cm'][1], 2)} | {_stat(s['std_cm'][2], 3)} | {_stat(s['scale'], 2)} |")
    lines += ["", "k: the ellipsoid's radii over the standard deviations, (V / (4/3 pi s_X s_Y s_Z))^(1/3); "
              "2.80 for normally distributed positions."]
    lines += ["", "The noise bandwidth B [Hz] at which our median reaches Table 4's value (orders 4 and 8 together, "
              "log-log interpolation), and the cut-off that gives that B with order 4 and with order 8; '-': not "
              "reached in the sweep.", "",
              "| Table 4 | volume | std X_E | std Y_E | std Z_E |", "|---|---|---|---|---|"]
    for name, (volume, std) in results["table4"].items():
        cells = []
        for quantity, target in enumerate((volume, *std)):
            b = matching_bandwidth(results, quantity, target)
            cells.append("-" if math.isnan(b) else f"B = {b:.2f} (order 4: {cutoff_for(results, 4, b)}, "
                                                   f"order 8: {cutoff_for(results, 8, b)})")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines += ["", f"The generated flow ({int(FLOW_SECONDS)} s at 100 Hz, seed 1), per axis x / y / z: standard "
              "deviation over the whole series and the range over its 40 s windows, as a fraction of the "
              "scene's; the Welch spectrum (Blackman-Harris, 2^15 samples) against the filter's: in the pass "
              "band (within 10 dB of the low-frequency level) the mean ratio and the largest deviation of "
              "16-bin means; beyond the stop-band edge the power against the filter's, and as a fraction of "
              "the whole.", "",
              "| order | cut-off [Hz] | std / stated | 40 s windows: std / stated | pass-band bins | mean ratio "
              "[dB] | largest 16-bin deviation [dB] | stop band / filter's [dB] | stop band / all [dB] |",
              "|---|---|---|---|---|---|---|---|---|"]
    for row in results["filters"]:
        fl = row["flow"]
        windows = " / ".join(f"{a:.2f}-{b:.2f}" for a, b in zip(fl["window_std_ratio_min"], fl["window_std_ratio_max"]))
        lines.append(f"| {row['order']} | {row['cutoff_hz']:g} | " + " / ".join(f"{r:.3f}" for r in fl["std_ratio"])
                     + f" | {windows} | {fl['passband_bins']} | "
                     + " / ".join(f"{d:+.2f}" for d in fl["passband_mean_db"]) + " | "
                     + " / ".join(f"{d:.2f}" for d in fl["passband_max_abs_db"]) + " | "
                     + " / ".join(f"{d:+.1f}" for d in fl["stopband_power_db"]) + " | "
                     + " / ".join(f"{d:.0f}" for d in fl["stopband_fraction_db"]) + " |")
    ratio = " / ".join(f"{r:.4f}" for r in results["kernel_flow"]["std_ratio"])
    lines += ["", f"The flow the kernels read at 2 ms steps (cubic Hermite between the 100 Hz samples; the "
              f"scene's filter, cut-off {results['scene_cutoff']:g} Hz, order {results['scene_order']}): "
              f"standard deviation over that of the samples, x / y / z: {ratio}."]
    return "\n".join(lines) + "\n"


def plot_sphere(results: dict) -> None:
    """Volume and standard deviations against the cut-off (per order), volume against the
    noise bandwidth, with Table 4's two columns."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(18, 5.5))
    styles = {"experiment": ("k", "--"), "reference model": ("tab:red", ":")}
    for order in ORDERS:
        rows = [r for r in results["filters"] if r["order"] == order]
        cut = np.array([r["cutoff_hz"] for r in rows])
        vol = np.array([r["sphere"]["volume_cm3"] for r in rows])
        band = np.array([r["bandwidth_hz"] for r in rows])
        colour = {2: "tab:blue", 4: "tab:orange", 8: "tab:green"}[order]
        axes[0].errorbar(cut, vol[:, 0], yerr=[vol[:, 0] - vol[:, 1], vol[:, 2] - vol[:, 0]], capsize=3,
                         marker="o", color=colour, label=f"order {order}")
        for k, marker in ((0, "o"), (1, "s")):
            s = np.array([r["sphere"]["std_cm"][k] for r in rows])
            axes[2].errorbar(band, s[:, 0], yerr=[s[:, 0] - s[:, 1], s[:, 2] - s[:, 0]], capsize=2, marker=marker,
                             mfc="none" if k else colour, color=colour, ls="none",
                             label=f"{('X_E', 'Y_E')[k]}, order {order}")
        if order == 4:
            for k, axis in enumerate(("X_E", "Y_E", "Z_E")):
                s = np.array([r["sphere"]["std_cm"][k] for r in rows])
                axes[1].errorbar(cut, s[:, 0], yerr=[s[:, 0] - s[:, 1], s[:, 2] - s[:, 0]], capsize=3, marker="o",
                                 label=f"std along {axis} (order 4)")
    for name, (volume, std) in results["table4"].items():
        colour, ls = styles[name]
        axes[0].axhline(volume, color=colour, ls=ls, label=f"Table 4, {name}")
        for k in range(3):
            axes[1].axhline(std[k], color=colour, ls=ls, lw=0.8, label=f"Table 4, {name}" if k == 0 else None)
        for k in range(2):
            axes[2].axhline(std[k], color=colour, ls=ls, lw=0.8, label=f"Table 4, {name}" if k == 0 else None)
    axes[0].set(xscale="log", yscale="log", xlabel="stop-band edge (cut-off) [Hz]", ylabel="ellipsoid volume [cm^3]",
                title="95 % ellipsoid over 40 s (median, least-largest)")
    axes[1].set(xscale="log", yscale="log", xlabel="stop-band edge (cut-off) [Hz]",
                ylabel="standard deviation [cm]", title="along the ellipsoid's principal axes")
    b = np.geomspace(min(r["bandwidth_hz"] for r in results["filters"]),
                     max(r["bandwidth_hz"] for r in results["filters"]), 50)
    ref = [r for r in results["filters"] if r["order"] == 4 and r["cutoff_hz"] == 10.0][0]
    for k in range(2):
        axes[2].plot(b, ref["sphere"]["std_cm"][k][0] * (b / ref["bandwidth_hz"]) ** -0.5, "0.5", lw=0.8,
                     label="B^-1/2 through order 4, 10 Hz" if k == 0 else None)
    axes[2].set(xscale="log", yscale="log", xlabel="equivalent noise bandwidth B of the filter [Hz]",
                ylabel="standard deviation [cm]",
                title="std along X_E, Y_E: the flow's low-frequency level std^2/B")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(HERE / "sphere.png", dpi=110)
    plt.close(fig)


def plot_spectra(spectra: dict, results: dict) -> None:
    """Generated against the filter's spectrum (x axis) for a few filters."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(11, 5.5))
    for key in ((2.0, 4), (10.0, 4), (20.0, 4), (10.0, 8), (10.0, 2)):
        f, p, theory = spectra[key]
        ax.loglog(f[1:], p[1:], lw=0.8, label=f"generated, cut-off {key[0]:g} Hz, order {key[1]}")
        ax.loglog(f[1:], theory[1:], "k--", lw=0.7)
    ax.set(xlabel="frequency [Hz]", ylabel="spectrum of u_x / std [1/Hz]", ylim=(1e-12, 1e3),
           title="generated flow (solid) against the filter's spectrum (black, dashed), 3600 s at 100 Hz")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(HERE / "flow_spectrum.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
