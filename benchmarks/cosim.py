"""Co-simulation of the three FMUs: speed and FMU overhead.

The full-scale system (ShipMotion in the default sea -> HeaveCompensation with the
simplified-sheave set-point -> TowCable ``full_scale``) run by the fmpy master
(``towcable_fmu.cosim.run_cosim``) for 120 s at communication steps of 0.01 s (the
issue's figure) and 0.02 s (the scene's own time step), three repeats each (medians).
Overhead = the share of the loop's wall time spent outside the three models' own
computations (FMI calls through ctypes and pythonfmu, the master's bookkeeping).
The standalone ``Simulation`` on the same scene and sea is given for comparison.

Run: ``python benchmarks/cosim.py``; writes ``results/cosim.md``.
"""

from __future__ import annotations

import statistics
import time

from common import RESULTS, machine_header, markdown_table

DURATION = 120.0
STEPS = (0.01, 0.02)
REPEATS = 3


def cosim(step: float) -> dict:
    """Median timing of REPEATS co-simulations at communication step ``step`` [s]."""
    from towcable_fmu.cosim import CosimConfig, run_cosim

    runs = [run_cosim(CosimConfig(duration=DURATION, step=step, compensation="simplified_sheave",
                                  fmu_dir="fmus"), echo=False).timing for _ in range(REPEATS)]
    return {key: statistics.median(r[key] for r in runs) for key in runs[0]}


def standalone() -> float:
    """Median simulated seconds per wall second of the Simulation alone (same scene and sea)."""
    from towcable_fmu.simulation import Simulation

    speeds = []
    for _ in range(REPEATS):
        sim = Simulation.from_scene("full_scale", {"compensation": {"algorithm": "simplified_sheave"}})
        sim.initialize()
        start = time.perf_counter()
        sim.run(DURATION, interval=0.1)
        speeds.append(DURATION / (time.perf_counter() - start))
    return statistics.median(speeds)


def main() -> None:
    cosim(0.01)  # build the FMUs if needed and load the compiled kernels
    rows = []
    for step in STEPS:
        t = cosim(step)
        rows.append([f"{step:g}", f"{t['realtime_factor']:.1f}", f"{t['wall']:.2f}", f"{t['model.TowCable']:.2f}",
                     f"{t['model.ShipMotion']:.3f}", f"{t['model.HeaveCompensation']:.3f}",
                     f"{1e6 * (t['wall'] - t['model']) / t['steps']:.1f}", f"{100 * t['overhead_share']:.1f}"])
    alone = standalone()
    text = ["# Co-simulation: speed and FMU overhead\n", machine_header(),
            f"\nfull_scale in the default sea with the simplified-sheave set-point, {DURATION:g} s, fmpy master "
            f"(`run_cosim`, compiled stepping loop), medians of {REPEATS} runs. 'outside' is the loop's wall "
            "time outside the three models per communication step (the slaves' glue, pythonfmu's C layer, "
            "the master); 'overhead' is 1 - (time in the three models) / (loop wall time).\n\n",
            markdown_table(["communication step [s]", "x real time", "wall [s]", "TowCable model [s]",
                            "ShipMotion model [s]", "HeaveCompensation model [s]", "outside [us/step]",
                            "overhead [%]"],
                           rows),
            f"\nThe `Simulation` alone on the same scene, sea and set-point (recording every 0.1 s): "
            f"{alone:.1f} x real time.\n"]
    (RESULTS / "cosim.md").write_text("".join(text), encoding="utf-8")
    print("".join(text))


if __name__ == "__main__":
    main()
