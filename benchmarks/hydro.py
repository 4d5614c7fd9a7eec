"""Hydrodynamics benchmark: cost per integration point and the statics of ``full_scale_pinned``."""

from __future__ import annotations

import statistics
import subprocess
import sys
import time

import numpy as np

from common import RESULTS, machine_header, markdown_table, per_call_us


def point_cost() -> dict[str, float]:
    """Residual cost of the wet full-scale scene minus the same scene dry, per wet point [us]."""
    from towcable_fmu.ancf.system import residual
    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene("full_scale_pinned", {"cable.segments[0].elements": 40,
                                               "cable.segments[1].elements": 20})
    sim.initialize()
    m, st = sim.model, sim.state
    dry = m._replace(water=m.water._replace(enabled=False))
    r = np.zeros_like(st.q)
    ship = np.zeros((3, 6))
    before = int(m.terms.hydrodynamics.calls[0])
    residual(m, st.q, st.v, st.a, 0.0, ship, r)
    points = int(m.terms.hydrodynamics.calls[0]) - before
    wet = per_call_us(lambda: residual(m, st.q, st.v, st.a, 0.0, ship, r))
    dry_cost = per_call_us(lambda: residual(dry, st.q, st.v, st.a, 0.0, ship, r))
    return {"elements": 60.0, "wet integration points": float(points), "residual, dry [us]": dry_cost,
            "residual, in water [us]": wet, "hydrodynamics per point [ns]": 1e3 * (wet - dry_cost) / points}


def static_wall_time(repeats: int = 3) -> float:
    """Median wall time of ``towcable static full_scale_pinned --json`` in a fresh process [s] (warm cache)."""
    cmd = [sys.executable, "-m", "towcable_fmu.cli", "static", "full_scale_pinned", "--json"]
    subprocess.run(cmd, check=True, capture_output=True)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> str:
    """Run the benchmark and write results/hydro.md."""
    cost = point_cost()
    wall = static_wall_time()
    text = ("# Hydrodynamics\n\n" + machine_header() + "\n"
            "Residual of `full_scale_pinned` meshed with 60 elements (10 trapezoidal points each), at its static "
            "equilibrium, with and without water; the difference divided by the submerged points evaluated.\n\n"
            + markdown_table(["quantity", "value"], list(cost.items()))
            + f"\n`towcable static full_scale_pinned --json` (fresh process, warm kernel cache, median of 3): "
              f"{wall:.2f} s wall time.\n")
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "hydro.md").write_text(text)
    return text


if __name__ == "__main__":
    print(main())
