"""Deploy and recovery benchmark: ``full_scale_deploy`` (veer 150 m -> 450 m at 1 m/s while
towing at 2.2 m/s, hold, haul back) as shipped, run time against error, and how the cost
follows the deployed length.

Errors: RMS over the whole 720 s of the difference to a converged reference (the gear and
the cable meshed twice as fine, the fed segment's nominal element 12.5 m instead of 25 m,
h = 5 ms), divided by the reference's mean, for the tension at the spool (``tension.top``,
the winch's pull: the issue's top tension), at the sheave, and the towed body's depth
(relative to the reference's RMS motion about its mean). The reference is checked against
h = 2.5 ms on the same mesh.
"""

from __future__ import annotations

import time

import numpy as np

from common import RESULTS, machine_header, markdown_table, relative_rms_errors, scene_time_step, timed_scene_runs

SCENE = "full_scale_deploy"
DURATION = 720.0
INTERVAL = 0.05
QUANTITIES = ("tension.top", "tension.sheave", "towbody.z")
#: elements of the scene's segments (gear: drum, drum to sheave, over the sheave; fed: bare; faired)
ELEMENTS = (10, 5, 40, 1, 5)


def overrides(time_step: float | None = None, refine: int = 1) -> dict:
    """The scene's step (None: its own) and its mesh refined ``refine`` times."""
    out = {} if time_step is None else {"solver.time_step": time_step}
    if refine != 1:
        out.update({f"cable.segments[{i}].elements": n * refine for i, n in enumerate(ELEMENTS)})
    return out


def simulate(time_step: float | None = None, refine: int = 1, repeats: int = 1) -> tuple[float, dict, dict]:
    """Median wall time [s] of the run (statics excluded), the series and the statistics."""
    return timed_scene_runs(SCENE, overrides(time_step, refine), DURATION, INTERVAL, repeats)


def errors(series: dict, ref: dict) -> dict[str, float]:
    """Relative RMS errors of the quantities users read."""
    return relative_rms_errors(series, ref, QUANTITIES)


def cost_by_length(window: float = 20.0) -> list[tuple]:
    """The scene as shipped run in windows of ``window`` [s]: deployed length, elements and
    wall time per step in each (one run; statics excluded)."""
    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene(SCENE)
    sim.initialize()
    rows = []
    while sim.time < DURATION - 1e-9:
        steps = sim.statistics()["solver.steps"]
        start = time.perf_counter()
        series = sim.run(window, interval=INTERVAL)
        wall = time.perf_counter() - start
        steps = sim.statistics()["solver.steps"] - steps
        rows.append((sim.time, float(np.mean(series["winch.deployed"])), sim.n_elements, 1e6 * wall / steps,
                     window / wall))
    return rows


def main(quick: bool = False) -> str:
    """Run the benchmark, write results/full_scale_deploy.md and its plot; return the Markdown."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, ref, _ = simulate(0.005, refine=2)
    check = {k: float("nan") for k in QUANTITIES} if quick else errors(ref, simulate(0.0025, refine=2)[1])
    h_scene = scene_time_step(SCENE)
    grid = [(None, 1)] if quick else [(2 * h_scene, 1), (None, 1), (h_scene / 2, 1), (h_scene / 5, 1),
                                      (h_scene / 10, 1), (None, 2)]
    rows, points = [], []
    for h, refine in grid:
        wall, series, stats = simulate(h, refine, repeats=1 if quick else 3)
        err = errors(series, ref)
        step = stats["solver.time_step"] if h is None else h
        points.append((h, refine, wall / DURATION, err["tension.top"], step))
        rows.append((f"{step:g}" + (" (scene)" if h is None else ""), refine, DURATION / wall,
                     100 * err["tension.top"], 100 * err["tension.sheave"], 100 * err["towbody.z"],
                     stats["solver.steps"], stats["solver.jacobian_factorisations"]))
    cost = cost_by_length()
    text = ("# Deploy and recovery: `full_scale_deploy`\n\n" + machine_header()
            + f"\n{DURATION:g} s as shipped (default sea, towing at 2.2 m/s; the payout program holds 20 s, veers "
              "300 m at 1 m/s, holds 60 s and hauls back), outputs every 0.05 s. Errors: RMS of the difference to "
              "the reference (gear and cable meshed twice as fine: the fed segment's nominal element 12.5 m; "
              "h = 5 ms) relative to its mean (tensions) or its RMS motion (depth). Reference against h = 2.5 ms: "
              f"spool tension {100 * check['tension.top']:.3g} %, sheave tension "
              f"{100 * check['tension.sheave']:.3g} %, depth {100 * check['towbody.z']:.3g} %.\n\n"
              "Speed: simulated seconds per wall-clock second, one core, median of 3 runs, statics excluded "
              "(target: >= 50 x real time at <= 1 % RMS spool-tension error).\n\n"
            + markdown_table(["time step [s]", "mesh x", "x real time", "spool tension error [%]",
                              "sheave tension error [%]", "depth error [%]", "steps", "factorisations"], rows)
            + "\n![work-precision](full_scale_deploy_work_precision.png)\n"
            + "\n## Cost against deployed length\n\nThe scene as shipped in windows of 20 s: mean deployed "
              "length (`winch.deployed`, from the spool; 10 m of it is the gear over drum and sheave), elements "
              "at the window's end, wall time per step and speed. The gear's 55 elements are the fixed part; "
              "the fed segment adds one element per 25 m.\n\n"
            + markdown_table(["t end [s]", "deployed [m]", "elements", "us / step", "x real time"], cost))
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "full_scale_deploy.md").write_text(text)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.5))
    for refine in sorted({p[1] for p in points}):
        sel = sorted((p for p in points if p[1] == refine), key=lambda p: p[4])
        ax.loglog([100 * p[3] for p in sel], [p[2] for p in sel], "o-", label=f"mesh x{refine}")
        for p in sel:
            ax.annotate(f"h={p[4]:g}", (100 * p[3], p[2]), fontsize=7, xytext=(3, 3), textcoords="offset points")
    default = [p for p in points if p[0] is None and p[1] == 1]
    ax.loglog(100 * default[0][3], default[0][2], "r*", ms=14, label="as shipped")
    ax.axhline(1 / 50, color="gray", ls="--", lw=0.8, label="50x real time")
    ax.axvline(1.0, color="gray", ls=":", lw=0.8, label="1 % error")
    ax.set_xlabel("RMS spool-tension error [%]")
    ax.set_ylabel("wall time per simulated second [s]")
    ax.set_title("full_scale_deploy: work-precision")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    bx.plot([c[2] for c in cost], [c[3] for c in cost], "o")
    bx.set_xlabel("elements")
    bx.set_ylabel("wall time per step [us]")
    bx.set_title("cost against mesh size during the run")
    bx.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(RESULTS / "full_scale_deploy_work_precision.png", dpi=110)
    return text


if __name__ == "__main__":
    import sys

    print(main(quick="--quick" in sys.argv))
