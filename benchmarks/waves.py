"""The cost of wave kinematics on the cable and the body (issue 42): ``full_scale`` (its
default sea, 200 components) run with ``[water] waves = "motion"`` against ``"off"``, the
two alternating in the same process, median of the repeats of the wall and the CPU time
(``time.process_time``, which a shared machine's load inflates less; statics excluded),
with the solver's work per step (Newton iterations, Jacobians), the cable's point loads
and, in waves, the full evaluations of the kinematics (the references of a time step,
ancf/forces/wave_quadrature.py) per step.

Then the accuracy of the default with waves, by the method of ``benchmarks/defaults.py``:
the scene's signal (:data:`defaults.SCENES`) against the converged run with waves (every
segment's elements doubled, the time step / 8, the Newton tolerance / 10), RMS error over
the run, and the default's speed (median of the repeats). Prints markdown
(results/waves.md) with the load average before and after (the machine may be shared).

Usage: ``python benchmarks/waves.py [duration_s] [repeats]`` (defaults 60 s, 3).
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from common import machine_header
from defaults import SCENES, reference_overrides, relative_error

SCENE = "full_scale"


def run(overrides: dict, duration: float) -> tuple[float, float, dict, dict]:
    """Wall and CPU time [s] of one run, its work per step (Newton iterations, Jacobians,
    point loads and time steps' references of the waves) and its outputs."""
    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene(SCENE, overrides)
    sim.initialize()
    hydro = sim.model.terms.hydrodynamics
    calls, generations = int(hydro.calls[0]), float(hydro.wave_clock[1])
    stats = sim.statistics()
    start, cpu = time.perf_counter(), time.process_time()
    outputs = sim.run(duration, interval=0.05)
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    after = sim.statistics()
    steps = after["solver.steps"] - stats["solver.steps"]
    work = {"iterations": (after["solver.newton_iterations"] - stats["solver.newton_iterations"]) / steps,
            "jacobians": (after["solver.jacobian_factorisations"] - stats["solver.jacobian_factorisations"]) / steps,
            "point loads": (int(hydro.calls[0]) - calls) / steps,
            "reference sets": (float(hydro.wave_clock[1]) - generations) / steps}
    return wall, cpu, work, outputs


def cost(duration: float, repeats: int) -> None:
    """Waves off against on, alternating; prints the table."""
    times = {"off": ([], []), "motion": ([], [])}
    work = {}
    for _ in range(repeats):
        for waves in times:
            wall, cpu, work[waves], _ = run({"water.waves": waves}, duration)
            times[waves][0].append(wall)
            times[waves][1].append(cpu)
    print(f"{SCENE}, {duration:g} s simulated, median of {repeats} (alternating, same process)\n")
    print("| waves | wall [s] | CPU [s] | x real time (CPU) | CPU runs [s] | per step: iterations, Jacobians, "
          "point loads, reference sets |")
    print("| --- | --- | --- | --- | --- | --- |")
    median = {}
    for waves, (walls, cpus) in times.items():
        median[waves] = (float(np.median(walls)), float(np.median(cpus)))
        per_step = ", ".join(f"{value:.2f}" for value in work[waves].values())
        print(f"| {waves} | {median[waves][0]:.2f} | {median[waves][1]:.2f} | {duration / median[waves][1]:.1f} | "
              f"{' '.join(f'{x:.2f}' for x in cpus)} | {per_step} |")
    print(f"\nwaves add {100.0 * (median['motion'][1] / median['off'][1] - 1.0):.1f} % to the CPU time "
          f"({100.0 * (median['motion'][0] / median['off'][0] - 1.0):.1f} % to the wall time)\n")


def accuracy(repeats: int) -> None:
    """The default with waves against its converged run with waves; prints the table."""
    from towcable_fmu.scene import load_scene

    case = SCENES[SCENE]
    waves = {"water.waves": "motion"}
    reference = run({**reference_overrides(load_scene(SCENE)), **waves}, case.duration)
    runs = [run(waves, case.duration) for _ in range(repeats)]
    error = relative_error(runs[-1][3][case.signal], reference[3][case.signal], case.scale)
    wall, cpu = (float(np.median([r[i] for r in runs])) for i in (0, 1))
    print(f"The default with waves against its converged run with waves ({case.signal}, {case.duration:g} s, "
          f"RMS error / {'mean absolute value' if case.scale == 'mean' else 'RMS'} of the reference; "
          f"reference: elements x 2, time step / 8, Newton tolerance / 10; speed: median of {repeats})\n")
    print("| run | error [%] | x real time (wall) | x real time (CPU) |")
    print("| --- | --- | --- | --- |")
    print(f"| reference | - | {case.duration / reference[0]:.1f} | {case.duration / reference[1]:.1f} |")
    print(f"| default, waves on | {100.0 * error:.3f} | {case.duration / wall:.1f} | {case.duration / cpu:.1f} |")


def main() -> None:
    duration = float(sys.argv[1]) if len(sys.argv) > 1 else 60.0
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    run({"water.waves": "off"}, 1.0)  # compile (both share the kernels)
    run({"water.waves": "motion"}, 1.0)
    load = os.getloadavg()[0]
    print(machine_header())
    cost(duration, repeats)
    accuracy(repeats)
    print(f"\n- load average (1 min) {load:.1f} at the start, {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
