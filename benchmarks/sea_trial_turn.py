"""Sea-trial turn with a rigid towed body: run time against error for the nodal-position cable.

Scene ``sea_trial_turn_rigid`` (nodal-position cable, rigid 6-DOF towed body, the ship
accelerating to 6.17 m/s and turning through 270 deg from t = 400 s) for DURATION
seconds, outputs every second, at several time steps. Errors: RMS over the run of the
difference to a converged reference (step REFERENCE), divided by the reference's mean,
for the tension at the tow point (``tension.towbody``) and at the top; the towed body's
depth as an RMS difference [m]. The reference is shown converged by a second one at half
its step. Writes ``results/sea_trial_turn.md``. Run: ``python benchmarks/sea_trial_turn.py``.
"""

from __future__ import annotations

import time

import numpy as np

from common import RESULTS, machine_header, markdown_table

SCENE = "sea_trial_turn_rigid"
DURATION = 700.0
STEPS = (1.0, 0.4, 0.2, 0.1, 0.05, 0.025)
REFERENCE = 0.0125
DEFAULT = 0.05  # the scene's [solver] time_step
TENSIONS = ("tension.towbody", "tension.top")


def simulate(time_step: float, repeats: int = 1) -> tuple[float, dict[str, np.ndarray], int]:
    """Median wall time [s] of the run (initialisation excluded), its series and steps."""
    from towcable_fmu.models import simulation_from

    walls = []
    for _ in range(repeats):
        sim = simulation_from(SCENE, {"solver.time_step": time_step})
        sim.initialize()
        start = time.perf_counter()
        series = sim.run(DURATION, interval=1.0)
        walls.append(time.perf_counter() - start)
    return float(np.median(walls)), series, int(sim.statistics()["solver.steps"])


def errors(series: dict[str, np.ndarray], reference: dict[str, np.ndarray]) -> list[float]:
    """RMS errors [%] of the tensions (of the reference's mean) and of the depth [m]."""
    out = [100.0 * float(np.sqrt(np.mean((series[k] - reference[k]) ** 2)) / np.mean(reference[k]))
           for k in TENSIONS]
    out.append(float(np.sqrt(np.mean((series["towbody.z"] - reference["towbody.z"]) ** 2))))
    return out


def main() -> None:
    simulate(DEFAULT)  # compiles or loads the kernels outside the timing
    _, reference, _ = simulate(REFERENCE)
    _, check, _ = simulate(REFERENCE / 2)
    rows = []
    for h in STEPS:
        wall, series, steps = simulate(h, repeats=3)
        rows.append([f"{h:g}" + (" (default)" if h == DEFAULT else ""), steps, wall, DURATION / wall,
                     *errors(series, reference)])
    lines = ["# Sea-trial turn with a rigid towed body: run time against error", "", machine_header(),
             f"`{SCENE}` for {DURATION:g} s (the turn starts at 400 s), outputs every 1 s; wall time is the median of "
             "3 runs, initialisation excluded. Errors: RMS difference to the reference "
             f"(h = {REFERENCE:g} s) over the run, tensions in % of the reference's mean, depth in m.", "",
             markdown_table(["time step [s]", "steps", "wall [s]", "x real time", "tow-point tension error [%]",
                             "top tension error [%]", "depth error [m]"], rows),
             f"Reference converged: h = {REFERENCE / 2:g} s differs from it by "
             + ", ".join(f"{e:.3g}" for e in errors(check, reference)) + " (same columns).", ""]
    (RESULTS / "sea_trial_turn.md").write_text("\n".join(lines), encoding="utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
