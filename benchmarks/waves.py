"""The cost of wave kinematics on the cable and the body (issue 42): ``full_scale`` (its
default sea, 200 components) run with ``[water] waves = "motion"`` against ``"off"``, the
two alternating in the same process, median of the repeats (statics excluded), with
the solver's work per step (Newton iterations, Jacobians), the cable's point loads and,
in waves, the full evaluations of the kinematics (the references of a time step,
ancf/forces/wave_quadrature.py) per step. Prints markdown (results/waves.md) with the
load average before and after (the machine may be shared).

Usage: ``python benchmarks/waves.py [duration_s] [repeats]`` (defaults 60 s, 3).
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from common import machine_header

SCENE = "full_scale"


def run(waves: str, duration: float) -> tuple[float, dict]:
    """Wall time [s] of one run and its work per step: Newton iterations, Jacobians, point
    loads and time steps' references of the waves."""
    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene(SCENE, {"water.waves": waves})
    sim.initialize()
    hydro = sim.model.terms.hydrodynamics
    calls, generations = int(hydro.calls[0]), float(hydro.wave_clock[1])
    stats = sim.statistics()
    start = time.perf_counter()
    sim.run(duration, interval=0.05)
    wall = time.perf_counter() - start
    after = sim.statistics()
    steps = after["solver.steps"] - stats["solver.steps"]
    work = {"iterations": (after["solver.newton_iterations"] - stats["solver.newton_iterations"]) / steps,
            "jacobians": (after["solver.jacobian_factorisations"] - stats["solver.jacobian_factorisations"]) / steps,
            "point loads": (int(hydro.calls[0]) - calls) / steps,
            "reference sets": (float(hydro.wave_clock[1]) - generations) / steps}
    return wall, work


def main() -> None:
    duration = float(sys.argv[1]) if len(sys.argv) > 1 else 60.0
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    run("off", 1.0)  # compile (both share the kernels)
    run("motion", 1.0)
    times = {"off": [], "motion": []}
    work = {}
    load = os.getloadavg()[0]
    for _ in range(repeats):
        for waves in ("off", "motion"):
            wall, work[waves] = run(waves, duration)
            times[waves].append(wall)
    off, on = float(np.median(times["off"])), float(np.median(times["motion"]))
    print(machine_header())
    print(f"- load average (1 min) {load:.1f} at the start, {os.getloadavg()[0]:.1f} at the end\n")
    print(f"{SCENE}, {duration:g} s simulated, median of {repeats} (alternating, same process)\n")
    print("| waves | wall [s] | x real time | runs [s] | per step: iterations, Jacobians, point loads, "
          "reference sets |")
    print("| --- | --- | --- | --- | --- |")
    for waves, wall in (("off", off), ("motion", on)):
        per_step = ", ".join(f"{value:.2f}" for value in work[waves].values())
        runs = " ".join(f"{x:.2f}" for x in times[waves])
        print(f"| {waves} | {wall:.2f} | {duration / wall:.1f} | {runs} | {per_step} |")
    print(f"\nwaves add {100.0 * (on / off - 1.0):.1f} % to the run time")


if __name__ == "__main__":
    main()
