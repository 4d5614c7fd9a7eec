"""Heave-compensation study: the same scene and sea with several set-point algorithms.

:func:`run_study` co-simulates the three FMUs (:func:`towcable_fmu.cosim.run_cosim`)
once per algorithm on the ``full_scale`` scene in the default irregular sea
(:data:`ship_motion.DEFAULT_SEA`: same seed, so every algorithm sees the same waves),
drops the first ``settle`` seconds and measures, on the rest:

* Calnan's 95 % ellipsoid of the towed-body track (:mod:`.ellipsoid`), its radii and
  volume, and the volume reduction against ``"none"`` [%];
* the towed-body depth (standard deviation and range);
* the tension where the cable leaves the sheave and at the towed body (mean, standard
  deviation, extremes, 1 % and 99 % percentiles);
* the peak sheave contact force and the share of time the cable is out of the groove;
* the winch payout range and how closely the payout follows the set-point;
* the wall time of each run.

It writes ``study.md`` (the table), ``statistics.csv`` and four PNG plots
(``track.png``, ``tension_time.png``, ``tension_distribution.png``, ``payout.png``).

Settling: the sea ramps in over its first 20 s (``DEFAULT_SEA["ramp"]``), and the towed
body's mean depth then moves to a new level (the oscillating cable has a larger mean drag
and lifts the body by several centimetres) with a time constant of about 33 s: with a
regular 0.6 m heave of 9.7 s period its deviation from the final mean fell by a factor 3.3
per 39 s. The default ``settle`` of 120 s is the ramp plus three such time constants
(the start-up transient of the mean depth is then below 5 %).
"""

from __future__ import annotations

import csv
import dataclasses
import math
import sys
import time
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from ..common.errors import SceneError
from .ellipsoid import Ellipsoid, enclosing_ellipsoid, projected_outline

#: Algorithms compared by default.
DEFAULT_ALGORITHMS: tuple[str, ...] = ("none", "simplified_sheave", "rigorous_sheave")

#: Default gain of the constant-tension winch [m/(s N)]: on full_scale in the default sea at a
#: 0.01 s step it takes the sheave tension's standard deviation from 161 N to 99 N; 5e-3
#: makes the sampled loop unstable there (bandwidth g k with k ~ 1.5e4 N/m against 1 / (1.5 h)).
DEFAULT_TENSION_GAIN = 1e-3

#: Start-up time left out of the statistics [s]: the 20 s ramp-in of the default sea plus
#: three time constants (about 33 s each) of the towed body's mean-depth response.
DEFAULT_SETTLE = 120.0

#: Statistics in table order: key -> (unit, description).
COLUMNS: dict[str, tuple[str, str]] = {
    "ellipsoid.a": ("m", "ellipsoid radius along X_E (best-fit line)"),
    "ellipsoid.b": ("m", "ellipsoid radius along Y_E (in the best-fit plane)"),
    "ellipsoid.c": ("m", "ellipsoid radius along Z_E (normal of the plane)"),
    "ellipsoid.volume": ("m3", "ellipsoid volume 4/3 pi a b c"),
    "ellipsoid.volume_reduction": ("%", "volume reduction against 'none'"),
    "ellipsoid.fraction_inside": ("1", "share of the track inside the ellipsoid"),
    "towbody.depth_std": ("m", "standard deviation of towbody.z"),
    "towbody.depth_range": ("m", "max - min of towbody.z"),
    **{f"tension.{where}.{stat}": ("N", f"{label}, {text}")
       for where, label in (("sheave", "tension leaving the sheave"), ("towbody", "tension at the towed body"))
       for stat, text in (("mean", "mean"), ("std", "standard deviation"), ("min", "minimum"), ("max", "maximum"),
                          ("p01", "1 % percentile"), ("p99", "99 % percentile"))},
    "contact.sheave_force.max": ("N", "peak sheave contact force"),
    "contact.detached.share": ("%", "share of time the cable is out of the sheave groove"),
    "winch.payout.range": ("m", "max - min of the winch payout"),
    "winch.payout.tracking_rms": ("m", "RMS of payout minus set-point payout r_w (phi_nom - phi_sp)"),
    "wall_time": ("s", "wall time of the co-simulation (FMU loading, initialisation, stepping)"),
    "realtime_factor": ("1", "simulated time / wall time of the stepping loop"),
}


@dataclasses.dataclass(frozen=True, eq=False)
class AlgorithmRun:
    """One algorithm's run.

    Attributes
    ----------
    algorithm
        Set-point algorithm name (``controllers.ALGORITHMS``).
    series
        The co-simulation's output series, settling period included (contract names).
    window
        Boolean mask of the samples used for the statistics (``time >= settle``).
    ellipsoid
        The ellipsoid fitted to the towed-body track in the window.
    stats
        Statistic key (:data:`COLUMNS`) -> value in its unit; None where undefined.
    payout_setpoint
        The set-point as a payout ``r_w (phi_nom - phi_sp)`` [m], for every sample.
    """

    algorithm: str
    series: dict[str, np.ndarray]
    window: np.ndarray
    ellipsoid: Ellipsoid
    stats: dict[str, float | None]
    payout_setpoint: np.ndarray


@dataclasses.dataclass(frozen=True, eq=False)
class StudyResult:
    """Outcome of :func:`run_study`: the runs by algorithm, the settings and the files written."""

    runs: dict[str, AlgorithmRun]
    duration: float
    step: float
    settle: float
    fraction: float
    files: dict[str, Path]


def track(series: Mapping[str, np.ndarray], window: np.ndarray) -> np.ndarray:
    """(n, 3) towed-body positions [m] in the window."""
    return np.column_stack([series[f"towbody.{c}"][window] for c in "xyz"])


def window_statistics(series: Mapping[str, np.ndarray], window: np.ndarray, payout_setpoint: np.ndarray,
                      fraction: float = 0.95) -> tuple[Ellipsoid, dict[str, float | None]]:
    """The ellipsoid and the statistics of one run over the samples in ``window``.

    Parameters
    ----------
    series
        Co-simulation outputs (contract names; equally spaced samples).
    window
        Boolean mask of the samples to use.
    payout_setpoint
        Set-point payout [m] per sample.
    fraction
        Share of the track the ellipsoid must contain [-].

    Returns
    -------
    (Ellipsoid, dict)
        The ellipsoid and the statistics of :data:`COLUMNS` that depend on the series
        alone (not the reduction against 'none' nor the timing).
    """
    ell = enclosing_ellipsoid(track(series, window), fraction)
    depth = series["towbody.z"][window]
    payout = series["winch.payout"][window]
    stats: dict[str, float | None] = {
        "ellipsoid.a": float(ell.radii[0]), "ellipsoid.b": float(ell.radii[1]), "ellipsoid.c": float(ell.radii[2]),
        "ellipsoid.volume": ell.volume, "ellipsoid.fraction_inside": ell.fraction_inside,
        "towbody.depth_std": float(np.std(depth)), "towbody.depth_range": float(np.ptp(depth)),
    }
    for where in ("sheave", "towbody"):
        tension = series[f"tension.{where}"][window]
        p01, p99 = np.percentile(tension, [1.0, 99.0])
        stats.update({f"tension.{where}.mean": float(np.mean(tension)), f"tension.{where}.std": float(np.std(tension)),
                      f"tension.{where}.min": float(np.min(tension)), f"tension.{where}.max": float(np.max(tension)),
                      f"tension.{where}.p01": float(p01), f"tension.{where}.p99": float(p99)})
    stats["contact.sheave_force.max"] = float(np.max(series["contact.sheave_force"][window]))
    stats["contact.detached.share"] = 100.0 * float(np.mean(series["contact.detached"][window] != 0.0))
    stats["winch.payout.range"] = float(np.ptp(payout))
    stats["winch.payout.tracking_rms"] = float(np.sqrt(np.mean((payout - payout_setpoint[window]) ** 2)))
    return ell, stats


def run_study(algorithms: Sequence[str] = DEFAULT_ALGORITHMS, duration: float = 300.0, step: float = 0.01,
              output_dir: str | Path = "out/compensation", settle: float = DEFAULT_SETTLE, *,
              fraction: float = 0.95, scene: str = "full_scale", fmu_dir: str | Path = "fmus",
              fmus: Mapping[str, Path] | None = None, verbose: bool = True, tension_target: float | None = None,
              tension_gain: float = DEFAULT_TENSION_GAIN) -> StudyResult:
    """Co-simulate ``scene`` once per algorithm in the default sea and compare.

    Parameters
    ----------
    algorithms
        Set-point algorithms (``controllers.ALGORITHMS``); include ``"none"`` for the
        volume reduction.
    duration
        Simulated time of each run [s], settling included.
    step
        Communication step [s] (every step is recorded).
    output_dir
        Folder for ``study.md``, ``statistics.csv`` and the plots (created).
    settle
        Start-up time left out of the statistics [s], in [0, duration).
    fraction
        Share of the towed-body track the ellipsoid must contain [-].
    scene
        TowCable scene (built-in name or TOML file) with a winch, a sheave and a towed body.
    fmu_dir, fmus
        Where the FMUs are (see :func:`towcable_fmu.cosim.run_cosim`).
    verbose
        Progress lines on stderr.
    tension_target, tension_gain
        The ``constant_tension`` winch's target [N] (default: the scene's static tension at
        the winch at t0) and gain [m/(s N)] (controllers/README.md).

    Returns
    -------
    StudyResult
        The runs and the files written.

    Raises
    ------
    SceneError
        No algorithm, a repeated algorithm, ``settle`` outside [0, duration) or
        ``fraction`` outside (0, 1].
    """
    from ..common.run_io import Progress
    from ..cosim import CosimConfig, run_cosim

    if not algorithms or len(set(algorithms)) != len(algorithms):
        raise SceneError("algorithms", list(algorithms), "one or more distinct algorithm names")
    if not (math.isfinite(settle) and 0.0 <= settle < duration):
        raise SceneError("settle", settle, f"a time in [0, duration = {duration:g}) s")
    if not (math.isfinite(fraction) and 0.0 < fraction <= 1.0):
        raise SceneError("fraction", fraction, "a share in (0, 1]")
    control: dict[str, float] = {}
    if "constant_tension" in algorithms:
        if tension_target is None:
            from ..ancf.simulation import Simulation

            tension_target = Simulation.from_scene(scene).initialize()["tension.winch"]
        control = {"tension_target": float(tension_target), "tension_gain": float(tension_gain)}
    runs: dict[str, AlgorithmRun] = {}
    for k, algorithm in enumerate(algorithms, 1):
        if verbose:
            print(f"[{k}/{len(algorithms)}] {algorithm}: {duration:g} s of co-simulation", file=sys.stderr)
        start = time.perf_counter()
        result = run_cosim(CosimConfig(scene=scene, compensation=algorithm, duration=duration, step=step,
                                       fmu_dir=fmu_dir,
                                       controller_parameters=control if algorithm == "constant_tension" else {}), progress=Progress() if verbose else None, echo=verbose,
                           fmus=fmus)
        wall = time.perf_counter() - start
        series = result.series
        geo = result.geometry
        payout_sp = geo["winch_radius"] * (geo["phi_nom"] - series["winch.phi_sp"])
        window = series["time"] >= settle - 1e-9 * max(1.0, settle)
        ell, stats = window_statistics(series, window, payout_sp, fraction)
        stats.update({"wall_time": wall, "realtime_factor": result.timing["realtime_factor"]})
        runs[algorithm] = AlgorithmRun(algorithm, series, window, ell, stats, payout_sp)
        if verbose:
            print(f"[{k}/{len(algorithms)}] {algorithm}: {wall:.1f} s wall, ellipsoid volume "
                  f"{ell.volume:.4g} m3", file=sys.stderr)
    base = runs.get("none")
    for run in runs.values():
        ok = base is not None and base.ellipsoid.volume > 0.0
        run.stats["ellipsoid.volume_reduction"] = (100.0 * (1.0 - run.ellipsoid.volume / base.ellipsoid.volume)
                                                   if ok else None)
    out = Path(output_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = {"table": out / "study.md", "csv": out / "statistics.csv", "track": out / "track.png",
             "tension_time": out / "tension_time.png", "tension_distribution": out / "tension_distribution.png",
             "payout": out / "payout.png"}
    settings = {"scene": scene, "duration": duration, "step": step, "settle": settle, "fraction": fraction,
                **{f"constant_tension.{k}": v for k, v in control.items()}}
    write_table(runs, settings, files["table"])
    write_statistics_csv(runs, files["csv"])
    plot_tracks(runs, files["track"])
    plot_tension_time(runs, settle, files["tension_time"])
    plot_tension_distribution(runs, files["tension_distribution"])
    plot_payout(runs, files["payout"])
    if verbose:
        print(f"wrote {', '.join(str(f) for f in files.values())}", file=sys.stderr)
    return StudyResult(runs=runs, duration=duration, step=step, settle=settle, fraction=fraction, files=files)


# ---------------------------------------------------------------------------- tables
def _format(value: float | None) -> str:
    if value is None:
        return "–"
    if value == 0.0:
        return "0"
    return f"{value:.4g}"


def write_table(runs: Mapping[str, AlgorithmRun], settings: Mapping[str, object], path: Path) -> None:
    """``study.md``: the settings and one row per statistic, one column per algorithm."""
    from ship_motion import DEFAULT_SEA

    names = list(runs)
    first = next(iter(runs.values()))
    n_window = int(np.count_nonzero(first.window))
    lines = [
        "# Heave-compensation study",
        "",
        f"Scene `{settings['scene']}`, default irregular sea (JONSWAP H_s = {DEFAULT_SEA['hs']} m, "
        f"T_p = {DEFAULT_SEA['tp']} s, gamma = {DEFAULT_SEA['gamma']}, heading {DEFAULT_SEA['heading']} deg, "
        f"seed {DEFAULT_SEA['seed']}, {DEFAULT_SEA['ramp']} s ramp-in). "
        f"{settings['duration']:g} s per algorithm at a communication step of {settings['step']:g} s; "
        f"the first {settings['settle']:g} s are left out, the statistics use {n_window} samples "
        f"(t = {settings['settle']:g} ... {settings['duration']:g} s). Ellipsoid: Calnan's fit containing "
        f"{100 * float(settings['fraction']):g} % of the towed-body positions (principal axes, radii proportional "
        "to the standard deviation along each)."
        + ("" if "constant_tension.tension_target" not in settings else
           f" Constant-tension winch: target {settings['constant_tension.tension_target']:.6g} N, gain "
           f"{settings['constant_tension.tension_gain']:g} m/(s N)."),
        "",
        "| quantity | unit | " + " | ".join(f"`{n}`" for n in names) + " |",
        "| --- | --- | " + " | ".join("---:" for _ in names) + " |",
    ]
    for key, (unit, text) in COLUMNS.items():
        lines.append(f"| {key} ({text}) | {unit} | " + " | ".join(_format(runs[n].stats[key]) for n in names) + " |")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def write_statistics_csv(runs: Mapping[str, AlgorithmRun], path: Path) -> None:
    """``statistics.csv``: one row per algorithm; header ``key [unit]``; empty where undefined."""
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["algorithm"] + [f"{key} [{unit}]" for key, (unit, _) in COLUMNS.items()])
        for name, run in runs.items():
            writer.writerow([name] + ["" if run.stats[key] is None else f"{run.stats[key]:.10g}" for key in COLUMNS])


# ---------------------------------------------------------------------------- plots
def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path) -> None:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    _pyplot().close(fig)


#: The three track projections: (horizontal index, vertical index) into x, y, z.
PROJECTIONS = ((0, 2), (1, 2), (0, 1))


def plot_tracks(runs: Mapping[str, AlgorithmRun], path: Path) -> None:
    """Towed-body track relative to its centroid in the x-z, y-z and x-y planes, one row
    per algorithm (shared scales per column), with the ellipsoid's projected outline."""
    from matplotlib.ticker import MaxNLocator

    plt = _pyplot()
    fig, axes = plt.subplots(len(runs), 3, figsize=(13, 3.2 * len(runs)), sharex="col", sharey="col", squeeze=False)
    for row, (name, run) in zip(axes, runs.items()):
        rel = track(run.series, run.window) - run.ellipsoid.centre
        for ax, dims in zip(row, PROJECTIONS):
            ax.plot(rel[:, dims[0]], rel[:, dims[1]], ",", color="tab:blue", alpha=0.4, rasterized=True)
            outline = projected_outline(run.ellipsoid, dims)
            ax.plot(outline[:, 0], outline[:, 1], color="tab:red", lw=1.2)
            ax.set_xlabel(f"towbody.{'xyz'[dims[0]]} - centroid [m]")
            ax.set_ylabel(f"towbody.{'xyz'[dims[1]]} - centroid [m]")
            ax.grid(alpha=0.3)
            ax.xaxis.set_major_locator(MaxNLocator(5))
        row[0].set_title(f"{name}: ellipsoid volume {run.ellipsoid.volume:.3g} m3 (red: projected outline)",
                         fontsize=9, loc="left")
    _save(fig, path)


def plot_tension_time(runs: Mapping[str, AlgorithmRun], settle: float, path: Path) -> None:
    """Tension leaving the sheave and at the towed body against time; settling shaded."""
    plt = _pyplot()
    fig, axes = plt.subplots(2, 1, figsize=(12, 7), sharex=True)
    for ax, where in zip(axes, ("sheave", "towbody")):
        for name, run in runs.items():
            ax.plot(run.series["time"], run.series[f"tension.{where}"], lw=0.6, label=name)
        ax.axvspan(0.0, settle, color="0.85", label="settling (not in the statistics)")
        ax.set_ylabel(f"tension.{where} [N]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    axes[-1].set_xlabel("time [s]")
    _save(fig, path)


def plot_tension_distribution(runs: Mapping[str, AlgorithmRun], path: Path) -> None:
    """Histogram of the tension leaving the sheave; box plots at the sheave and at the body
    (whiskers at the 1 % and 99 % percentiles)."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    names = list(runs)
    for name, run in runs.items():
        axes[0].hist(run.series["tension.sheave"][run.window], bins=80, histtype="step", density=True, label=name)
    axes[0].set_xlabel("tension.sheave [N]")
    axes[0].set_ylabel("probability density [1/N]")
    axes[0].legend(fontsize=8)
    for ax, where in zip(axes[1:], ("sheave", "towbody")):
        ax.boxplot([runs[n].series[f"tension.{where}"][runs[n].window] for n in names], whis=(1, 99),
                   showfliers=False)
        ax.set_xticks(range(1, len(names) + 1), names, fontsize=8)
        ax.set_ylabel(f"tension.{where} [N]")
    for ax in axes:
        ax.grid(alpha=0.3)
    _save(fig, path)


def plot_payout(runs: Mapping[str, AlgorithmRun], path: Path, zoom: float = 60.0) -> None:
    """Winch payout and its set-point against time, one row per algorithm: the whole
    window and its first ``zoom`` seconds [s]."""
    plt = _pyplot()
    fig, axes = plt.subplots(len(runs), 2, figsize=(13, 2.8 * len(runs)), squeeze=False,
                             gridspec_kw={"width_ratios": (2, 1)})
    for row, (name, run) in zip(axes, runs.items()):
        t = run.series["time"][run.window]
        payout = run.series["winch.payout"][run.window]
        setpoint = run.payout_setpoint[run.window]
        for ax, mask in zip(row, (np.ones_like(t, dtype=bool), t <= t[0] + zoom)):
            ax.plot(t[mask], setpoint[mask], lw=2.5, color="0.75", label="set-point r_w (phi_nom - phi_sp)")
            ax.plot(t[mask], payout[mask], lw=0.7, color="tab:blue", label="winch.payout")
            ax.set_ylabel("payout [m]")
            ax.grid(alpha=0.3)
        row[0].set_title(f"{name}: tracking RMS {run.stats['winch.payout.tracking_rms']:.3g} m", fontsize=9,
                         loc="left")
        row[1].set_title(f"first {zoom:g} s", fontsize=9, loc="left")
        row[0].legend(fontsize=8, loc="upper right")
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    _save(fig, path)
