"""Full-scale towing system benchmark: run time against error with ship motion and compensation.

Scene ``full_scale`` (winch, sheave, 450 m cable, towed body) driven for 120 s by a regular
ship motion of the size the reference shows (heave +-1 m at 9 s, pitch +-2 deg at 8 s,
roll +-5 deg at 10 s, ramped in over 10 s) with the simplified-sheave set-point.
Errors: RMS over the run of the difference to a converged reference (finer step and mesh),
divided by the reference's mean, for the tension at the sheave, the total sheave contact
force and the towed-body depth (the latter relative to the reference's RMS motion about
its mean). The reference is shown converged by a second, finer reference.
"""

from __future__ import annotations

import time

import numpy as np

from common import (RESULTS, machine_header, markdown_table, relative_rms_errors, scene_time_step,
                    timed_scene_runs)

DURATION = 120.0
INTERVAL = 0.1
MOTION = {"type": "regular", "ramp": 10.0,
          "heave": {"amplitude": 1.0, "period": 9.0},
          "pitch": {"amplitude": 2.0, "period": 8.0},
          "roll": {"amplitude": 5.0, "period": 10.0}}
QUANTITIES = ("tension.sheave", "contact.sheave_force", "towbody.z")


def overrides(time_step: float, refine: int = 1) -> dict:
    """Scene overrides: motion, compensation, step and a mesh refined ``refine`` times."""
    out = {"motion": MOTION, "compensation": {"algorithm": "simplified_sheave"}, "solver.time_step": time_step}
    for i, n in enumerate((10, 5, 40, 8, 6)):
        out[f"cable.segments[{i}].elements"] = n * refine
    return out


def simulate(time_step: float, refine: int = 1, repeats: int = 1):
    """Median wall time [s] of the run (statics excluded), the series and the statistics."""
    return timed_scene_runs("full_scale", overrides(time_step, refine), DURATION, INTERVAL, repeats)


def errors(series: dict, ref: dict) -> dict[str, float]:
    """Relative RMS errors of the quantities users read."""
    return relative_rms_errors(series, ref, QUANTITIES)


def shipped_rows(repeats: int, quick: bool) -> list[tuple]:
    """The scene as shipped (its default sea, compensation and solver settings) for the
    whole run, sampled every 0.05 s (its default) and every 0.1 s: speed (median of
    ``repeats``), steps (which must not depend on the interval) and the RMS sheave-tension
    error against the same scene with the mesh refined twice and h = 5 ms, relative to
    the reference's mean."""
    from towcable_fmu.ancf.simulation import Simulation

    ref_overrides = {} if quick else {f"cable.segments[{i}].elements": 2 * n for i, n in enumerate((10, 5, 40, 8, 6))}
    ref = Simulation.from_scene("full_scale", {**ref_overrides, "solver.time_step": 0.005})
    ref.initialize()
    reference = ref.run(DURATION, interval=0.05)
    rows = []
    for interval in (0.05, 0.1):
        walls = []
        for _ in range(repeats):
            sim = Simulation.from_scene("full_scale")
            sim.initialize()
            start = time.perf_counter()
            series = sim.run(DURATION, interval=interval)
            walls.append(time.perf_counter() - start)
        stats = sim.statistics()
        step = int(round(interval / 0.05))
        tension, ref_tension = series["tension.sheave"], reference["tension.sheave"][::step]
        error = np.sqrt(np.mean((tension - ref_tension) ** 2)) / np.mean(np.abs(ref_tension))
        rows.append((interval, DURATION / float(np.median(walls)), 100 * error, stats["solver.steps"],
                     stats["solver.jacobian_factorisations"]))
    return rows


def main(quick: bool = False) -> str:
    """Run the benchmark, write results/full_scale.md and its plot; return the Markdown."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, ref, _ = simulate(0.001, refine=2)
    if quick:
        check = {k: float("nan") for k in QUANTITIES}
    else:
        _, finer, _ = simulate(0.0005, refine=3)
        check = errors(ref, finer)
    h_default = scene_time_step("full_scale")
    grid = ([(0.1, 1), (0.08, 1), (0.05, 1), (0.02, 1), (0.01, 1), (0.005, 1), (0.05, 2)] if not quick
            else [(h_default, 1)])
    rows, points = [], []
    for h, refine in grid:
        wall, series, stats = simulate(h, refine, repeats=1 if quick else 3)
        err = errors(series, ref)
        points.append((h, refine, wall / DURATION, err["tension.sheave"]))
        rows.append((h, refine, DURATION / wall, 100 * err["tension.sheave"], 100 * err["contact.sheave_force"],
                     100 * err["towbody.z"], stats["solver.newton_iterations"] / stats["solver.steps"],
                     stats["solver.jacobian_factorisations"]))
    text = ("# Full-scale towing system: `full_scale` with ship motion and compensation\n\n" + machine_header()
            + f"\n{DURATION:g} s of regular ship motion (heave 1 m / 9 s, pitch 2 deg / 8 s, roll 5 deg / 10 s, "
              "ramped in over 10 s), simplified-sheave set-point, outputs every 0.1 s. Errors: RMS of the "
              "difference to the reference (mesh refined twice, h = 1 ms) relative to its mean (tension, "
              "contact force) or to its RMS motion (towed-body depth). Reference against a finer one (mesh x3, "
              f"h = 0.5 ms): tension {100 * check['tension.sheave']:.3g} %, contact force "
              f"{100 * check['contact.sheave_force']:.3g} %, depth {100 * check['towbody.z']:.3g} %.\n\n"
              "Speed: simulated seconds per wall-clock second, one core, median of 3 runs, statics excluded.\n\n"
            + markdown_table(["time step [s]", "mesh x", "x real time", "sheave tension error [%]",
                              "contact force error [%]", "depth error [%]", "Newton iterations / step",
                              "factorisations"], rows)
            + "\n![work-precision](full_scale_work_precision.png)\n"
            + "\n## The scene as shipped\n\n`full_scale` with its own settings (default sea, "
              f"simplified-sheave compensation, h = {h_default:g} s), {DURATION:g} s, median of 3; error: RMS "
              "sheave tension against the same scene with the mesh refined twice and h = 5 ms, relative to its "
              "mean (target: >= 100 x real time at <= 1 %). Samples inside a step are read from the step's "
              "interpolant, so the output interval does not change the steps.\n\n"
            + markdown_table(["output interval [s]", "x real time", "sheave tension error [%]", "steps",
                              "factorisations"], shipped_rows(1 if quick else 3, quick)))
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "full_scale.md").write_text(text)
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for refine in sorted({p[1] for p in points}):
        sel = [p for p in points if p[1] == refine]
        ax.loglog([100 * p[3] for p in sel], [p[2] for p in sel], "o-", label=f"mesh x{refine}")
        for p in sel:
            ax.annotate(f"h={p[0]:g}", (100 * p[3], p[2]), fontsize=7, xytext=(3, 3), textcoords="offset points")
    default = [p for p in points if p[0] == h_default and p[1] == 1]
    if default:
        ax.loglog(100 * default[0][3], default[0][2], "r*", ms=14, label="default")
    ax.axhline(1 / 50, color="gray", ls="--", lw=0.8, label="50x real time")
    ax.axvline(1.0, color="gray", ls=":", lw=0.8, label="1 % error")
    ax.set_xlabel("RMS sheave-tension error [%]")
    ax.set_ylabel("wall time per simulated second [s]")
    ax.set_title("full_scale: work-precision")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(RESULTS / "full_scale_work_precision.png", dpi=110)
    return text


if __name__ == "__main__":
    import sys

    print(main(quick="--quick" in sys.argv))
