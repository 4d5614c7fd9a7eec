"""Snapping cable: run time against error, ours and the peers (MoorDyn, Exudyn) in one run.

The case (``benchmarks/peers/snapping_case.py``; our scene ``snapping_cable``): a
submerged steel cable with a 12.2 kg sphere, top moved abruptly, z = z0 + 0.05 sin(2 pi
f t), at 1.27 Hz (the cable goes slack and snaps taut) and 0.807 Hz; 15 s. Outputs: T0,
Tmax/T0 and Tmin/T0 of the top tension over the run, and the RMS of (T - T_ref)/T0 over
0.05-5 s (phase errors of the snaps). Each code's error is measured against its own
converged solution (finest mesh and step of its own sweep) and against ours.

Run: ``python benchmarks/snapping.py`` (about 5 minutes; the peers need
``pip install ".[bench]"``: without them only our sweep is run). Writes
``results/snapping.md`` and ``results/snapping_work_precision.png``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from common import RESULTS, machine_header, markdown_table

sys.path.insert(0, str(Path(__file__).parent / "peers"))
import snapping_case as case  # noqa: E402

DURATION = case.DURATION
FREQUENCIES = (1.27, 0.807)
SERIES_WINDOW = (0.05, 5.0)
#: our sweep: (elements, time step [s], integration points per element)
OURS = [(20, 0.004, 2), (20, 0.002, 2), (20, 0.001, 2), (20, 0.0005, 2), (20, 0.0004, 2), (16, 0.0005, 2),
        (12, 0.0005, 2), (10, 0.0005, 2), (40, 0.0005, 4), (20, 0.00025, 4)]
OURS_REFERENCE = (40, 0.00025, 4)
#: the scene's own settings (snapping_cable.toml)
DEFAULT = (20, 0.0005, 2)
#: MoorDyn's set-up matched to our default (20 segments); its speed is the yardstick
MATCHED = (20, 0.0002)
#: timing repeats of our default and of the matched peer run (medians)
REPEATS = 3
#: peers: (segments, time step [s]); their references are the last entries
MOORDYN = [(2, 0.002), (5, 0.0008), (20, 0.0002), (80, 2e-5)]
EXUDYN = [(2, 0.004), (10, 0.0005), (20, 0.001), (40, 0.00025)]


def ours(frequency: float, elements: int, time_step: float, points: int, repeats: int = 1) -> dict:
    """Our solver on the case: top tension series and wall time of the run (statics
    excluded; the median of ``repeats`` runs)."""
    from towcable_fmu.simulation import Simulation

    period = 1.0 / frequency
    still = Simulation.from_scene("snapping_cable", {"motion": {"type": "none"},
                                                     "cable.segments[0].elements": elements})
    still.initialize()
    t0 = still.outputs()["tension.top"]  # the static tension, before the abrupt start
    walls = []
    for _ in range(repeats):
        sim = Simulation.from_scene("snapping_cable", {
            "motion.heave.period": period, "solver.time_step": time_step,
            "cable.segments[0].elements": elements, "cable.segments[0].integration_points": points})
        sim.initialize()
        start = time.perf_counter()
        series = sim.run(DURATION, interval=5e-4)  # samples as the peers take them, read between steps
        walls.append(time.perf_counter() - start)
    wall = float(np.median(walls))
    tension = series["tension.top"]
    return {"peer": "towcable", "frequency_hz": frequency, "n_segments": elements, "time_step_s": time_step,
            "points": points, "T0": t0, "Tmax_over_T0": tension.max() / t0, "Tmin_over_T0": tension.min() / t0,
            "wall_time_s": wall, "time": series["time"], "tension_top": tension,
            "steps": sim.statistics()["solver.steps"], "rejected": sim.statistics()["solver.rejected_steps"]}


def peer(name: str, frequency: float, segments: int, time_step: float, repeats: int = 1) -> dict:
    """One peer run (``run`` of the peer script; the median wall time of ``repeats``)."""
    if name == "MoorDyn":
        from moordyn_snapping import run
    else:
        from exudyn_snapping import run
    runs = [run(frequency, DURATION, segments, time_step) for _ in range(repeats)]
    res = runs[-1]
    res["wall_time_s"] = float(np.median([r["wall_time_s"] for r in runs]))
    res["peer"] = name
    return res


def series_error(res: dict, ref: dict) -> float:
    """RMS of (T - T_ref)/T0 over SERIES_WINDOW, on the reference's samples [-]."""
    t_ref = np.asarray(ref["time"])
    mask = (t_ref >= SERIES_WINDOW[0]) & (t_ref <= SERIES_WINDOW[1])
    interp = np.interp(t_ref[mask], res["time"], res["tension_top"])
    return float(np.sqrt(np.mean((interp - np.asarray(ref["tension_top"])[mask]) ** 2)) / ref["T0"])


def peers_available() -> dict[str, bool]:
    """Which peer packages are installed."""
    import importlib.util

    return {"MoorDyn": importlib.util.find_spec("moordyn") is not None,
            "Exudyn": importlib.util.find_spec("exudyn") is not None}


def main() -> None:
    available = peers_available()
    rows: list[dict] = []
    series: dict[tuple, dict] = {}
    for f in FREQUENCIES:
        runs: dict[str, list[dict]] = {"towcable": []}
        sweep = OURS if f == FREQUENCIES[0] else [(20, 0.004, 2), (20, 0.002, 2), (20, 0.001, 2), DEFAULT,
                                                  OURS_REFERENCE]
        for setting in sweep + ([OURS_REFERENCE] if OURS_REFERENCE not in sweep else []):
            res = ours(f, *setting, repeats=REPEATS if setting == DEFAULT else 1)
            print(f"towcable f={f} {setting}: Tmax/T0 {res['Tmax_over_T0']:.4f}, {res['wall_time_s']:.2f} s "
                  f"({res['steps']} steps, {res['rejected']} rejected)", file=sys.stderr)
            runs["towcable"].append(res)
        for name, ladder in (("MoorDyn", MOORDYN), ("Exudyn", EXUDYN)):
            if not available[name]:
                continue
            runs[name] = []
            for setting in ladder:
                res = peer(name, f, *setting, repeats=REPEATS if (name, setting) == ("MoorDyn", MATCHED) else 1)
                print(f"{name} f={f} {setting}: Tmax/T0 {res['Tmax_over_T0']:.4f}, {res['wall_time_s']:.2f} s",
                      file=sys.stderr)
                runs[name].append(res)
        our_ref = next(r for r in runs["towcable"] if (r["n_segments"], r["time_step_s"], r["points"])
                       == OURS_REFERENCE)
        for name, results in runs.items():
            own_ref = our_ref if name == "towcable" else results[-1]
            for res in results:
                row = {k: v for k, v in res.items() if k not in ("time", "tension_top")}
                row["error_own"] = res["Tmax_over_T0"] / own_ref["Tmax_over_T0"] - 1.0
                row["error_ours"] = res["Tmax_over_T0"] / our_ref["Tmax_over_T0"] - 1.0
                row["series_own"] = series_error(res, own_ref)
                row["speed"] = DURATION / res["wall_time_s"]
                rows.append(row)
            series[(name, f)] = own_ref
    write_report(rows, series, available)


def write_report(rows: list[dict], series: dict, available: dict[str, bool]) -> None:
    """Markdown table and the work-precision plot."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    lines = ["# Snapping cable: run time against error, ours and the peers\n", machine_header(),
             "\nThe case: `benchmarks/peers/snapping_case.py` (README there); our scene `snapping_cable`. "
             "15 s simulated; wall time of the time stepping (statics excluded), one process at a time. "
             "err = Tmax/T0 relative to the code's own converged run (last row of its block) and to ours; "
             "series = RMS of (T - T_ref)/T0 over 0.05-5 s against the code's own reference. "
             f"Our default setting: {DEFAULT[0]} elements, h = {DEFAULT[1] * 1e3:g} ms, N_I = {DEFAULT[2]}.\n"]
    if not all(available.values()):
        lines.append("\nPeers not installed here: " + ", ".join(k for k, v in available.items() if not v) + ".\n")
    for f in FREQUENCIES:
        lines.append(f"\n## f = {f} Hz\n\n")
        table = []
        for r in rows:
            if r["frequency_hz"] != f:
                continue
            table.append([r["peer"], r["n_segments"], f"{r['time_step_s'] * 1e3:g}", r.get("points", "-"),
                          f"{r['T0']:.4f}", f"{r['Tmax_over_T0']:.4f}", f"{r['Tmin_over_T0']:.4f}",
                          f"{100 * r['error_own']:+.2f}", f"{100 * r['error_ours']:+.2f}",
                          f"{100 * r['series_own']:.2f}", f"{r['speed']:.1f}"])
        lines.append(markdown_table(["code", "elements", "h [ms]", "N_I", "T0 [N]", "Tmax/T0", "Tmin/T0",
                                     "err own [%]", "err vs ours [%]", "series [%]", "sim s / wall s"], table))
        lines.append(_verdict(rows, f))
    (RESULTS / "snapping.md").write_text("".join(lines), encoding="utf-8")

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for ax, f in zip(axes, FREQUENCIES):
        for name, marker in (("towcable", "o"), ("MoorDyn", "s"), ("Exudyn", "^")):
            pts = [r for r in rows if r["peer"] == name and r["frequency_hz"] == f and r["series_own"] > 0.0]
            if pts:
                ax.loglog([max(r["series_own"], 1e-5) for r in pts], [r["speed"] for r in pts], marker,
                          label=name, linestyle="none")
        default = [r for r in rows if r["peer"] == "towcable" and r["frequency_hz"] == f
                   and (r["n_segments"], r["time_step_s"], r["points"]) == DEFAULT]
        if default:
            ax.loglog([max(default[0]["series_own"], 1e-5)], [default[0]["speed"]], "r*", markersize=14,
                      label="our default")
        ax.axvline(0.01, color="grey", linestyle=":", linewidth=1)
        ax.set_xlabel("RMS tension error / T0 over 0.05-5 s against the code's own converged run [-]")
        ax.set_ylabel("simulated seconds per wall second")
        ax.set_title(f"snapping cable, f = {f} Hz")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(RESULTS / "snapping_work_precision.png", dpi=120)


def _verdict(rows: list[dict], f: float) -> str:
    """Our default settings (errors, speed) against MoorDyn's matched set-up, and the
    fastest of our runs within 1 % series error."""
    def find(name: str, segments: int, step: float) -> dict | None:
        return next((r for r in rows if r["peer"] == name and r["frequency_hz"] == f and r["n_segments"] == segments
                     and r["time_step_s"] == step), None)

    mine = find("towcable", DEFAULT[0], DEFAULT[1])
    matched = find("MoorDyn", *MATCHED)
    if mine is None:
        return "\n"
    text = (f"\nOur default ({DEFAULT[0]} elements, h = {DEFAULT[1] * 1e3:g} ms, median of {REPEATS}): series "
            f"error {100 * mine['series_own']:.2f} %, Tmax/T0 {100 * mine['error_own']:+.2f} %, "
            f"{mine['speed']:.1f} x real time")
    if matched is not None:
        text += (f"; MoorDyn {MATCHED[0]} segments, h = {MATCHED[1] * 1e3:g} ms (median of {REPEATS}): series "
                 f"{100 * matched['series_own']:.2f} %, {matched['speed']:.1f} x: ratio "
                 f"{mine['speed'] / matched['speed']:.2f}")
    ok = [r for r in rows if r["peer"] == "towcable" and r["frequency_hz"] == f and r["series_own"] <= 0.01
          and r["series_own"] > 0.0]
    if ok:
        best = max(ok, key=lambda r: r["speed"])
        text += (f". Fastest of our runs within 1 % series error: {best['n_segments']} elements, h = "
                 f"{best['time_step_s'] * 1e3:g} ms, {best['speed']:.1f} x")
    return text + ".\n"


if __name__ == "__main__":
    main()
