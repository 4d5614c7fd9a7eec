"""Cable core benchmark (scene ``hanging_cable``): run time against top-tension error,
kernel costs, cold compile time and warm start-up time.

Error measure: RMS over the run of the top-tension difference to a converged reference
(finer mesh and step), divided by the reference's mean top tension. The reference is
shown converged by comparing it with an even finer run.
"""

from __future__ import annotations

import tempfile
import time

import numpy as np

from common import RESULTS, machine_header, markdown_table, per_call_us, run_python, scene_time_step

DURATION = 60.0   # simulated seconds (includes the 10 s ramp of the motion)
INTERVAL = 0.1    # output interval [s]
ELEMENTS = 70     # the scene's mesh


def simulate(elements: int, time_step: float, repeats: int = 1) -> tuple[float, np.ndarray, dict]:
    """Median wall time [s] of a run (statics excluded), top tension series and statistics."""
    from towcable_fmu.ancf.simulation import Simulation

    overrides = {"cable.segments[0].elements": elements, "solver.time_step": time_step}

    def timed():
        sim = Simulation.from_scene("hanging_cable", overrides)
        sim.initialize()
        start = time.perf_counter()
        series = sim.run(DURATION, interval=INTERVAL)
        return time.perf_counter() - start, series, sim.statistics()

    results = [timed() for _ in range(repeats)]
    wall = float(np.median([r[0] for r in results]))
    return wall, results[-1][1]["tension.top"], results[-1][2]


def rms_error(t: np.ndarray, ref: np.ndarray) -> float:
    """RMS of the difference, relative to the reference's mean."""
    return float(np.sqrt(np.mean((t - ref) ** 2)) / np.mean(ref))


def kernel_costs(elements: int = ELEMENTS) -> dict[str, float]:
    """Cost of one residual, one Jacobian assembly, one banded LU and one back-solve [us]."""
    from towcable_fmu.ancf.system import iteration_matrix, residual
    from towcable_fmu.numerics.banded import band_lu, band_solve
    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene("hanging_cable", {"cable.segments[0].elements": elements})
    sim.initialize()
    sim.run(2.0)
    m, st, ws = sim.model, sim.state, sim.workspace
    r = np.zeros_like(st.q)
    ship = np.zeros((3, 6))
    n = m.free_dofs.size
    iteration_matrix(m, st.q, st.v, 0.0, ship, 1.0, 1e-3, 1e-5, ws.ab)
    ab0 = ws.ab.copy()
    x = np.ones(n)

    def lu():
        ws.ab[:] = ab0
        band_lu(ws.ab, n, m.kl, m.ku, ws.ipiv)

    copy_cost = per_call_us(lambda: ws.ab.__setitem__(slice(None), ab0))
    lu()
    return {
        "residual": per_call_us(lambda: residual(m, st.q, st.v, st.a, 0.0, ship, r)),
        "jacobian assembly": per_call_us(lambda: iteration_matrix(m, st.q, st.v, 0.0, ship, 1.0, 1e-3, 1e-5,
                                                                  ws.ab)),
        "banded LU": per_call_us(lu) - copy_cost,
        "back-solve": per_call_us(lambda: band_solve(ws.ab, n, m.kl, m.ku, ws.ipiv, x)),
        "unknowns": float(n),
    }


START_CODE = ("from towcable_fmu.ancf.simulation import Simulation\n"
              "sim = Simulation.from_scene('hanging_cable')\n"
              "sim.initialize()\n"
              "sim.advance(0.1)\n")


def start_times() -> dict[str, float]:
    """Cold (empty numba cache) and warm start-up of a fresh process [s]."""
    with tempfile.TemporaryDirectory() as cache:
        cold = run_python(START_CODE, {"NUMBA_CACHE_DIR": cache})
    run_python(START_CODE)  # make sure the regular cache is filled
    warm = float(np.median([run_python(START_CODE) for _ in range(3)]))
    return {"cold start (compile)": cold, "warm start": warm}


def main(quick: bool = False) -> str:
    """Run the benchmark, write results/core.md and the plot; return the Markdown."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    starts = start_times()
    costs = kernel_costs()
    _, ref, _ = simulate(140, 0.001)
    _, finer, _ = simulate(280, 0.0005) if not quick else (None, ref, None)
    ref_check = rms_error(ref, finer)
    rows, points = [], []
    default_setting = (ELEMENTS, scene_time_step("hanging_cable"))
    grid = ([(35, h) for h in (0.01, 0.02, 0.04)]
            + [(ELEMENTS, h) for h in (0.005, 0.01, 0.02, 0.04, 0.08, 0.16, 0.32)])
    if quick:
        grid = [default_setting, (ELEMENTS, 0.04)]
    for elements, h in grid:
        wall, tension, stats = simulate(elements, h, repeats=1 if quick else 3)
        err = rms_error(tension, ref)
        speed = DURATION / wall
        points.append((elements, h, wall / DURATION, err))
        rows.append((elements, h, speed, 100 * err, stats["solver.steps"],
                     stats["solver.newton_iterations"] / stats["solver.steps"], stats["solver.jacobian_factorisations"]))
    md = ["# Cable core: `hanging_cable`\n", machine_header(), "\n",
          f"Top-tension error: RMS over {DURATION:g} s (outputs every {INTERVAL:g} s) of the difference to the "
          f"reference (140 elements, h = 1 ms), relative to its mean tension. The reference differs from an even "
          f"finer run (280 elements, h = 0.5 ms) by {100 * ref_check:.3g} %.\n\n",
          "Speed: simulated seconds per wall-clock second, one core, median of 3 runs (statics excluded; "
          "outputs recorded every 0.1 s).\n\n",
          markdown_table(["elements", "time step [s]", "x real time", "RMS tension error [%]", "steps",
                          "Newton iterations / step", "factorisations"], rows),
          f"\n## Where the time goes ({ELEMENTS} elements)\n\n",
          markdown_table(["kernel", "cost [us]"], [(k, v) for k, v in costs.items() if k != "unknowns"]),
          f"\n{int(costs['unknowns'])} unknowns, band half-width 11.\n\n",
          markdown_table(["start-up", "wall time [s]"], list(starts.items())),
          "\n![work-precision](core_work_precision.png)\n"]
    text = "".join(md)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "core.md").write_text(text)
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for elements in sorted({p[0] for p in points}):
        sel = [p for p in points if p[0] == elements]
        ax.loglog([p[3] * 100 for p in sel], [p[2] for p in sel], "o-", label=f"{elements} elements")
        for p in sel:
            ax.annotate(f"h={p[1]:g}", (p[3] * 100, p[2]), fontsize=7, xytext=(3, 3), textcoords="offset points")
    default = [p for p in points if (p[0], p[1]) == default_setting]
    if default:
        ax.loglog(default[0][3] * 100, default[0][2], "r*", ms=14, label="default")
    ax.axhline(1 / 200, color="gray", ls="--", lw=0.8, label="200x real time")
    ax.axvline(1.0, color="gray", ls=":", lw=0.8, label="1 % error")
    ax.set_xlabel("RMS top-tension error [%]")
    ax.set_ylabel("wall time per simulated second [s]")
    ax.set_title("hanging_cable: work-precision")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(RESULTS / "core_work_precision.png", dpi=110)
    return text


if __name__ == "__main__":
    import sys

    print(main(quick="--quick" in sys.argv))
