"""The cost of wave kinematics on the cable and the body (issue 42): ``full_scale`` (its
default sea, 200 components) run with ``[water] waves = "motion"`` against ``"off"``, the
two alternating in the same process, median of the repeats (statics excluded), plus the
count of point evaluations of the cable's hydrodynamics.

Usage: ``python benchmarks/waves.py [duration_s] [repeats]`` (defaults 60 s, 3).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from common import machine_header

SCENE = "full_scale"


def run(waves: str, duration: float) -> tuple[float, float, dict]:
    """Wall time [s] of one run, its real-time factor, and the run's statistics."""
    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene(SCENE, {"water.waves": waves})
    sim.initialize()
    start = time.perf_counter()
    sim.run(duration, interval=0.05)
    wall = time.perf_counter() - start
    return wall, duration / wall, sim.statistics()


def main() -> None:
    duration = float(sys.argv[1]) if len(sys.argv) > 1 else 60.0
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    run("off", 1.0)  # compile (both share the kernels)
    run("motion", 1.0)
    times = {"off": [], "motion": []}
    for _ in range(repeats):
        for waves in ("off", "motion"):
            wall, _, stats = run(waves, duration)
            times[waves].append(wall)
    off, on = float(np.median(times["off"])), float(np.median(times["motion"]))
    print(machine_header())
    print(f"{SCENE}, {duration:g} s simulated, median of {repeats} (alternating, same process)")
    print(f"waves off:    {off:.2f} s wall, {duration / off:.1f}x real time  {times['off']}")
    print(f"waves motion: {on:.2f} s wall, {duration / on:.1f}x real time  {times['motion']}")
    print(f"waves add {100.0 * (on / off - 1.0):.1f} % to the run time")


if __name__ == "__main__":
    main()
