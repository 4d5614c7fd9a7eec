"""The pulley experiments of Westin 2018, sections 4.1 (Table 1) and 4.2 (Table 2), against
the measured ranges.

For each of the four built-in scenes (pulley_static, pulley_static_2, pulley_static_3,
pulley_moving): 10 s from the release (the reference's records), every solver step; the
tension the rope pulls the load with (``tension.load``), the least tension along the rope
(``tension.min``), the rope's angle below the horizontal between two points of the free
span as the experiment's camera markers measured it (static pulley), and the model's own
wrap angle (``contact.wrap_angle``); raw and low-passed as the measurements were
(4th-order Butterworth at 3 Hz, forward and backward). Also: the model's first natural
frequencies at the release, the filtered ranges under other filters, and the raw and
filtered tension ranges under the choices the reference does not give (contact stiffness
and damping, the load's link stiffness) and under a finer step and mesh.

Writes ``results.json``, the tables ``results.md`` and the plots ``time_series.png`` and
``spectrum.png`` next to this file.
Run: ``python docs/studies/pulley_experiments/run.py`` (about 2 minutes on 2 cores).
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg
from scipy import signal

from towcable_fmu.ancf.forces.rigid_load import held_load_forces
from towcable_fmu.ancf.system import iteration_matrix
from towcable_fmu.ancf.simulation import Simulation

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from study_machine import machine  # noqa: E402

HERE = Path(__file__).resolve().parent
DURATION = 10.0  # [s] the reference's records
CUTOFF, ORDER = 3.0, 4  # [Hz], [-] the low-pass of the comparison
MARKER_SPAN = 0.132  # [m] of rope between the two "markers", ending at the load (3 elements)
#: scene: (label, measured tension range [N], the reference model's largest tension error [N],
#: measured angle range [deg], the reference model's largest angle error [deg]); Westin 2018,
#: section 4.1 (configurations 1-3 of Table 1) and section 4.2 (the moving pulley)
CASES = {
    "pulley_static": ("configuration 1", (49.2, 162.0), 21.2, (36.7, 146.0), 2.77),
    "pulley_static_2": ("configuration 2", (119.0, 285.0), 40.9, (43.3, 139.0), 9.24),
    "pulley_static_3": ("configuration 3", (204.0, 367.0), 56.7, (52.4, 129.0), 4.30),
    "pulley_moving": ("moving pulley", (36.9, 51.5), 6.40, None, None),
}
#: choices the reference does not state, and numerical ones: label, overrides
VARIANTS = [
    ("scene as built", {}),
    ("contact stiffness 1e7 N/m^2.5", {"sheave.contact.stiffness": 1e7}),
    ("contact stiffness 1e9 N/m^2.5", {"sheave.contact.stiffness": 1e9}),
    ("contact damping D = 100 s/m", {"sheave.contact.damping": 100.0}),
    ("link stiffness k_L = 1e7 N", {"load.stiffness": 1e7}),
    ("time step 0.25 ms", {"solver.time_step": 0.00025}),
    ("40 + 8 elements", {"cable.segments[0].elements": 8, "cable.segments[1].elements": 40}),
]
FILTERS = [(2.0, 4), (3.0, 2), (3.0, 4), (3.0, 8), (5.0, 4)]  # (cut-off [Hz], order)


def low_pass(x: np.ndarray, rate: float, cutoff: float = CUTOFF, order: int = ORDER) -> np.ndarray:
    """Zero-phase Butterworth low-pass (forward and backward) of a series sampled at ``rate`` [Hz]."""
    return signal.sosfiltfilt(signal.butter(order, cutoff, fs=rate, output="sos"), x)


def rope_angle(sim: Simulation, first: int) -> float:
    """Angle [deg] of the chord from node ``first`` to the load below the horizontal (+x)."""
    x = sim.node_positions()
    d = x[-1] - x[first]
    return math.degrees(math.atan2(-d[2], d[0]))


def record(scene: str, overrides: dict | None = None, markers: bool = False) -> dict[str, np.ndarray]:
    """10 s from the release at every solver step: time, tension.load, tension.min,
    contact.wrap_angle [deg] and (``markers``) the rope angle [deg], the total energy and
    that of gravity [J]."""
    sim = Simulation.from_scene(scene, overrides or {})
    sim.initialize()
    h = sim.scene.solver.time_step
    if not markers:
        res = sim.run(DURATION, interval=h)
        return {"time": res["time"], "tension.load": res["tension.load"], "tension.min": res["tension.min"],
                "wrap": np.degrees(res["contact.wrap_angle"])}
    arc = sim.mesh.node_arc
    first = int(np.argmin(np.abs(arc - (arc[-1] - MARKER_SPAN))))
    n = int(round(DURATION / h)) + 1
    rows = np.empty((n, 7))
    out = sim.outputs()
    for k in range(n):
        if k:
            out = sim.advance(k * h)
        energy = sum(out[f"energy.{name}"] for name in ("kinetic", "strain", "gravity", "contact", "load"))
        rows[k] = (out["time"], out["tension.load"], out["tension.min"], math.degrees(out["contact.wrap_angle"]),
                   rope_angle(sim, first), energy, out["energy.gravity"])
    return {"time": rows[:, 0], "tension.load": rows[:, 1], "tension.min": rows[:, 2], "wrap": rows[:, 3],
            "angle": rows[:, 4], "energy": rows[:, 5], "energy.gravity": rows[:, 6]}


def natural_frequencies(scene: str, count: int = 6) -> tuple[list[float], list[float]]:
    """The lowest natural frequencies [Hz] in the plane of the swing about the held state
    (undamped, tangent stiffness: K v = w^2 M v over the free coordinates), and for each
    mode how much the load's point I moves along the rope (|cos| of the angle between its
    motion and cable.initial.direction)."""
    sim = Simulation.from_scene(scene)
    sim.initialize()
    m = sim.model
    held = m._replace(f_const=held_load_forces(sim.scene, m)) if sim.scene.load.held else m
    n = m.free_dofs.size
    q, v = sim.state.q, np.zeros_like(sim.state.q)

    def dense(ca: float, cq: float) -> np.ndarray:
        ab = np.zeros((2 * m.kl + m.ku + 1, n))
        iteration_matrix(held, q, v, 0.0, sim.workspace.ship, ca, 0.0, cq, ab)
        a = np.zeros((n, n))
        for j in range(n):
            for i in range(max(0, j - m.ku), min(n, j + m.kl + 1)):
                a[i, j] = ab[m.kl + m.ku + i - j, j]
        return a

    stiffness = dense(0.0, 1.0)
    omega2, modes = scipy.linalg.eigh(0.5 * (stiffness + stiffness.T), dense(1.0, 0.0))
    sideways = m.free_dofs % 3 == 1  # y of the nodes and slopes, and of the load's point I
    planar = np.linalg.norm(modes[sideways], axis=0) < 1e-6 * np.linalg.norm(modes, axis=0)
    rope = np.array(sim.scene.cable.initial.direction) / np.linalg.norm(sim.scene.cable.initial.direction)
    point = modes[m.free_idx[m.load_index:m.load_index + 3]][:, planar][:, :count]
    along = np.abs(rope @ point) / np.linalg.norm(point, axis=0)
    return ([float(math.sqrt(max(w2, 0.0)) / (2.0 * math.pi)) for w2 in omega2[planar][:count]],
            along.tolist())


def span(x: np.ndarray) -> list[float]:
    return [float(x.min()), float(x.max())]


def fast_part(time: np.ndarray, x: np.ndarray, rate: float) -> list[float]:
    """Half the range of the raw series less the filtered one in each second [same unit]."""
    fast = x - low_pass(x, rate)
    return [float(0.5 * np.ptp(fast[(time >= k) & (time < k + 1.0)])) for k in range(int(DURATION))]


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    start = time.perf_counter()
    results: dict = {"cutoff_hz": CUTOFF, "order": ORDER, "duration_s": DURATION, "cases": {}}
    series = {}
    for scene, (label, tension, t_err, angle, a_err) in CASES.items():
        res = record(scene, markers=angle is not None)
        series[scene] = res
        rate = 1.0 / (res["time"][1] - res["time"][0])
        row = {"label": label, "measured_tension": tension, "reference_tension_error": t_err,
               "tension_raw": span(res["tension.load"]),
               "tension_filtered": span(low_pass(res["tension.load"], rate)),
               "tension_min_raw": float(res["tension.min"].min()),
               "fast_part_per_second": fast_part(res["time"], res["tension.load"], rate),
               "tension_at_release": float(res["tension.load"][0]),
               "wrap_raw": span(res["wrap"]), "wrap_filtered": span(low_pass(res["wrap"], rate)),
               "filters": {f"{c:g} Hz order {o}": span(low_pass(res["tension.load"], rate, c, o))
                           for c, o in FILTERS}}
        if angle is not None:
            row.update(measured_angle=angle, reference_angle_error=a_err, angle_raw=span(res["angle"]),
                       angle_filtered=span(low_pass(res["angle"], rate)),
                       angle_at_release=float(res["angle"][0]))
            row["frequencies_hz"], row["mode_along_rope"] = natural_frequencies(scene)
            row["energy_variation_j"] = float(np.ptp(res["energy"]))
            row["swing_energy_j"] = float(np.ptp(res["energy.gravity"]))
            row["variants"] = {}
            for name, overrides in VARIANTS[1:]:
                var = record(scene, overrides)
                r = 1.0 / (var["time"][1] - var["time"][0])
                row["variants"][name] = {"raw": span(var["tension.load"]),
                                         "filtered": span(low_pass(var["tension.load"], r))}
            row["variants"][VARIANTS[0][0]] = {"raw": row["tension_raw"], "filtered": row["tension_filtered"]}
        results["cases"][scene] = row
        print(scene, json.dumps({k: v for k, v in row.items() if k not in ("variants", "filters")}))
    results["machine"] = machine()
    results["wall_time_s"] = time.perf_counter() - start
    (HERE / "results.json").write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    (HERE / "results.md").write_text(tables(results), encoding="utf-8")
    plot_series(plt, series)
    plot_spectrum(plt, series, results)


def _range(r: list[float], digits: int = 0) -> str:
    return f"{r[0]:.{digits}f} - {r[1]:.{digits}f}"


def _errors(r: list[float], measured: tuple[float, float], digits: int = 0) -> str:
    return f"{r[0] - measured[0]:+.{digits}f} / {r[1] - measured[1]:+.{digits}f}"


def tables(results: dict) -> str:
    """The study's tables (markdown)."""
    cases = results["cases"]
    lines = ["Tension the rope pulls the load with, 0-10 s from the release [N] (filtered: 4th-order "
             "Butterworth at 3 Hz, forward and backward); error = ours - measured, least / largest.", "",
             "| case | measured | reference model's largest error | ours, filtered | error | ours, raw "
             "| least tension along the rope, raw | pull at the release |",
             "|---|---|---|---|---|---|---|---|"]
    for row in cases.values():
        errors = _errors(row["tension_filtered"], row["measured_tension"], 1)
        lines.append(f"| {row['label']} | {_range(row['measured_tension'], 1)} | {row['reference_tension_error']:.1f} "
                     f"| {_range(row['tension_filtered'], 1)} | {errors} | {_range(row['tension_raw'], 1)} "
                     f"| {row['tension_min_raw']:.1f} | {row['tension_at_release']:.1f} |")
    lines += ["", "Rope angle below the horizontal [deg], 0-10 s: the chord of the last 13.2 cm of rope "
              "(the camera's two markers); the model's wrap angle (`contact.wrap_angle`, the turn between "
              "meeting and leaving the pulley) beside it.", "",
              "| case | measured | reference model's largest error | ours, filtered | error | ours, raw "
              "| at the release | wrap angle, filtered | wrap angle, raw |", "|---|---|---|---|---|---|---|---|---|"]
    for row in cases.values():
        if "measured_angle" in row:
            errors = _errors(row["angle_filtered"], row["measured_angle"], 1)
            lines.append(f"| {row['label']} | {_range(row['measured_angle'], 1)} | {row['reference_angle_error']:.2f} "
                         f"| {_range(row['angle_filtered'], 1)} | {errors} "
                         f"| {_range(row['angle_raw'], 1)} | {row['angle_at_release']:.2f} "
                         f"| {_range(row['wrap_filtered'], 1)} | {_range(row['wrap_raw'], 1)} |")
        else:
            lines.append(f"| {row['label']} | (not reported) | | | | | | {_range(row['wrap_filtered'], 1)} "
                         f"| {_range(row['wrap_raw'], 1)} |")
    lines += ["", "The fast part of the raw tension: half the range of raw less filtered in each second [N].", "",
              "| case | " + " | ".join(f"{k}-{k + 1} s" for k in range(int(DURATION))) + " |",
              "|---" * (int(DURATION) + 1) + "|"]
    for row in cases.values():
        lines.append(f"| {row['label']} | " + " | ".join(f"{a:.0f}" for a in row["fast_part_per_second"]) + " |")
    names = list(next(iter(cases.values()))["filters"])
    lines += ["", "Filtered tension range [N] under other low-pass filters (Butterworth, forward and backward).",
              "", "| case | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for row in cases.values():
        lines.append(f"| {row['label']} | " + " | ".join(_range(row["filters"][n], 1) for n in names) + " |")
    lines += ["", "Natural frequencies at the release [Hz] (in the plane of the swing, about the held state); "
              "in brackets how much the load's point I moves along the rope (|cos|, 1: along, 0: across).",
              "", "| case | f1 | f2 | f3 | f4 | f5 | f6 |", "|---|---|---|---|---|---|---|"]
    for row in cases.values():
        if "frequencies_hz" in row:
            lines.append(f"| {row['label']} | " + " | ".join(
                f"{f:.2f} ({a:.2f})" for f, a in zip(row["frequencies_hz"], row["mode_along_rope"])) + " |")
    lines += ["", "Total energy (kinetic, strain, gravity, contact, load) over the 10 s: its variation against "
              "the swing's exchange (range of the energy of gravity) [J].", "",
              "| case | variation of the total | range of gravity's |", "|---|---|---|"]
    for row in cases.values():
        if "energy_variation_j" in row:
            lines.append(f"| {row['label']} | {row['energy_variation_j']:.4f} | {row['swing_energy_j']:.2f} |")
    lines += ["", "Tension range [N], raw and filtered, under the choices the reference does not give and "
              "a finer step and mesh.", "",
              "| variant | " + " | ".join(f"{row['label']} raw | filtered" for row in cases.values()
                                       if "variants" in row) + " |",
              "|---" * 7 + "|"]
    for name, _ in VARIANTS:
        cells = [f"{_range(row['variants'][name]['raw'])} | {_range(row['variants'][name]['filtered'])}"
                 for row in cases.values() if "variants" in row]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def plot_series(plt, series: dict) -> None:
    """Tension and angle against time, raw and filtered, with the measured ranges."""
    fig, axes = plt.subplots(2, 4, figsize=(20, 8), sharex=True)
    for k, (scene, res) in enumerate(series.items()):
        label, tension, _, angle, _ = CASES[scene]
        rate = 1.0 / (res["time"][1] - res["time"][0])
        ax = axes[0, k]
        ax.plot(res["time"], res["tension.load"], lw=0.4, color="0.6", label="raw")
        ax.plot(res["time"], low_pass(res["tension.load"], rate), lw=1.5, label="filtered (3 Hz)")
        for value in tension:
            ax.axhline(value, color="k", ls="--", lw=0.8)
        ax.set_title(f"{label}: tension [N] (dashed: measured range)")
        ax.legend(loc="upper right", fontsize=8)
        ax = axes[1, k]
        name = "angle" if angle is not None else "wrap"
        ax.plot(res["time"], res[name], lw=0.4, color="0.6", label="raw")
        ax.plot(res["time"], low_pass(res[name], rate), lw=1.5, label="filtered (3 Hz)")
        if angle is not None:
            ax.plot(res["time"], low_pass(res["wrap"], rate), lw=0.8, ls=":", label="wrap angle, filtered")
            for value in angle:
                ax.axhline(value, color="k", ls="--", lw=0.8)
            ax.set_title("rope angle below the horizontal [deg]")
        else:
            ax.set_title("wrap angle [deg] (not measured)")
        ax.legend(loc="upper right", fontsize=8)
        ax.set_xlabel("time from the release [s]")
    fig.tight_layout()
    fig.savefig(HERE / "time_series.png", dpi=110)
    plt.close(fig)


def plot_spectrum(plt, series: dict, results: dict) -> None:
    """Power spectra of the raw tension, the model's natural frequencies and the filter's gain."""
    fig, ax = plt.subplots(figsize=(11, 5.5))
    for scene, res in series.items():
        rate = 1.0 / (res["time"][1] - res["time"][0])
        freq, power = signal.welch(res["tension.load"] - res["tension.load"].mean(), fs=rate, nperseg=4096)
        line, = ax.semilogy(freq, power, lw=1.0, label=CASES[scene][0])
        for f in results["cases"][scene].get("frequencies_hz", [])[1:]:
            ax.axvline(f, color=line.get_color(), ls=":", lw=0.8)
    sos = signal.butter(ORDER, CUTOFF, fs=1000.0, output="sos")
    f, h = signal.sosfreqz(sos, worN=4096, fs=1000.0)
    twin = ax.twinx()
    twin.plot(f, np.abs(h) ** 2, "k--", lw=1.0, label="filter gain (forward and backward)")
    twin.set_ylabel("filter gain [-]")
    twin.set_ylim(0.0, 1.05)
    ax.set_xlim(0.0, 40.0)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("power spectral density of the raw tension [N^2/Hz]")
    ax.set_title("raw tension: the swing below 3 Hz, the load's axial bounce at 10-20 Hz "
                 "(dotted: natural frequencies at the release)")
    ax.legend(loc="upper right", fontsize=8)
    twin.legend(loc="center right", fontsize=8)
    fig.tight_layout()
    fig.savefig(HERE / "spectrum.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
