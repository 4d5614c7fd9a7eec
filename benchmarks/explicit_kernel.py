"""The explicit path's cost per node and step on the snapping case, and MoorDyn's in the same run.

``snapping_cable_nodal`` (leapfrog, lumped masses, towcable_fmu/nodal/explicit_kernel.py) at
its default (16 elements, 0.247 ms, 1.27 Hz) and at 2 and 40 elements (0.807 Hz): the
compiled stepping kernel alone (one sample at the end of the run: kick, drift, the top node
from the drive, the forces, the lumped-mass solve) and the whole ``sim.run`` with the
case's 0.5 ms samples (interpolated outputs, the drive table, Python). Cost per node per
step [ns] = time / (steps x nodes), in CPU time of this process (the machine is shared:
CPU time is less disturbed by the other jobs than wall time, which is also given) and
median of REPEATS runs of 15 s. MoorDyn (RK4, 20 segments, 0.382 ms, the case's harness)
in the same run: its wall time per node and force evaluation (4 per RK4 step). The profile:
the kernel's time per step at 4, 16 and 64 elements, in the scene and with the whole cable
dry, fitted by a line: a cost per step and one per node, whose wet - dry difference is the
water's share (drag and buoyancy at the Gauss points, added mass, the 3x3 solve).

With ``--baseline DIR`` (a checkout of an earlier commit, e.g. ``git archive <commit> | tar
-x -C DIR``) the kernel and the whole run at 4, 16 (the scene default) and 40 elements are
also timed with the package imported from DIR, in processes alternating with the current
code's (same run, medians): the before/after.

Run: ``python benchmarks/explicit_kernel.py [--baseline DIR]``. Writes ``results/explicit_kernel.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from common import RESULTS, machine_header, markdown_table

sys.path.insert(0, str(Path(__file__).parent / "peers"))
import snapping_case as case  # noqa: E402

REPEATS = 5
DURATION = case.DURATION
#: (label, frequency [Hz], elements, time step [s] or None for the scene's explicit limit)
CASES = (("scene default, 1.27 Hz", 1.27, 16, 0.000247), ("2 elements, 0.807 Hz", 0.807, 2, None),
         ("40 elements, 0.807 Hz", 0.807, 40, None))


#: meshes of the split into a cost per step and a cost per node (1.27 Hz, one step for all)
SPLIT_ELEMENTS, SPLIT_STEP = (4, 16, 64), 0.00003
#: the scene with the surface 1 km down: the whole cable and body dry (no drag, buoyancy, added mass)
DRY = {"water.surface_z": -1000.0}


def _simulation(frequency: float, elements: int, step: float | None, extra: dict | None = None):
    from towcable_fmu.nodal.simulation import NodalSimulation
    from towcable_fmu.scene import load_scene

    overrides = {"motion.heave.period": 1.0 / frequency, "cable.segments[0].elements": elements, **(extra or {})}
    if step is None:
        step = load_scene("snapping_cable_nodal", {**overrides, "solver.integrator": "genalpha"}).explicit_step()
    return NodalSimulation.from_scene("snapping_cable_nodal", {**overrides, "solver.time_step": step})


def kernel_cost(frequency: float, elements: int, step: float | None, extra: dict | None = None) -> dict:
    """Median cost [ns per node per step] of the stepping kernel alone and of the whole run
    (``extra``: scene overrides)."""
    from towcable_fmu.nodal.explicit import leapfrog_recording

    sim = _simulation(frequency, elements, step, extra)
    sim.initialize()
    sim.run(0.05, interval=5e-4)  # kernels loaded
    nodes = sim.model.n_nodes
    kernel_cpu, kernel_wall, run_cpu, run_wall = [], [], [], []
    steps = 0
    for _ in range(REPEATS):
        sim.initialize()
        drive = sim._drive(np.array([0.0, DURATION + sim.options.h_max]), 10 * sim.options.h_max)
        values = np.zeros((1, 14))
        before = int(sim.state.stats[0])
        c0, w0 = time.process_time(), time.perf_counter()
        leapfrog_recording(sim.model, sim._lumped, sim.options, sim.state, np.array([DURATION]), *drive, values,
                           sim._interpolant, True, DURATION)
        kernel_cpu.append(time.process_time() - c0)
        kernel_wall.append(time.perf_counter() - w0)
        steps = int(sim.state.stats[0]) - before
        sim.initialize()
        c0, w0 = time.process_time(), time.perf_counter()
        sim.run(DURATION, interval=5e-4)
        run_cpu.append(time.process_time() - c0)
        run_wall.append(time.perf_counter() - w0)
    per = 1e9 / (steps * nodes)
    return {"nodes": nodes, "steps": steps, "h": sim.options.h_max,
            "kernel_cpu": statistics.median(kernel_cpu) * per, "kernel_wall": statistics.median(kernel_wall) * per,
            "run_cpu": statistics.median(run_cpu) * per, "run_wall": statistics.median(run_wall) * per,
            "speed": DURATION / statistics.median(run_wall)}


def split_rows() -> list[list[str]]:
    """The kernel's CPU time per step [ns] at SPLIT_ELEMENTS, wet and dry, and its least-squares
    line a + b nodes: a the cost per step (kick, drift, the drive, the loop), b per node."""
    rows, fits = [], {}
    for label, extra in (("wet (scene)", None), ("dry (surface 1 km down)", DRY)):
        nodes, per_step = [], []
        for n in SPLIT_ELEMENTS:
            r = kernel_cost(1.27, n, SPLIT_STEP, extra)
            nodes.append(r["nodes"])
            per_step.append(r["kernel_cpu"] * r["nodes"])
        slope, intercept = np.polyfit(nodes, per_step, 1)
        fits[label] = slope
        rows.append([label] + [f"{c:.0f}" for c in per_step] + [f"{intercept:.0f}", f"{slope:.1f}"])
    wet, dry = fits["wet (scene)"], fits["dry (surface 1 km down)"]
    rows.append(["wet - dry (the water's loads and the 3x3 solve)", "", "", "", "", f"{wet - dry:.1f}"])
    return rows


#: alternations of the before/after processes (each the median of REPEATS runs)
ROUNDS = 5
#: the before/after cases: 4 elements at 1.27 Hz and its explicit limit, the scene default, 40 elements
AB_CASES = (("4 elements, 1.27 Hz", 1.27, 4, None), CASES[0], CASES[2])


def _case_in_process(package_root: str | None, case_index: int) -> dict:
    """:func:`kernel_cost` of ``AB_CASES[case_index]`` measured in a new process, the package
    imported from ``package_root`` (None: the current code)."""
    env = dict(os.environ)
    if package_root is not None:
        env["PYTHONPATH"] = os.pathsep.join([package_root, env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    out = subprocess.run([sys.executable, __file__, "--case-only", str(case_index)], env=env, capture_output=True,
                         text=True, check=True, cwd=Path(__file__).parent)
    return json.loads(out.stdout.strip().splitlines()[-1])


def before_after(baseline: str) -> list[list[str]]:
    """Rows of the before/after table: for each of AB_CASES the medians [ns/node/step, CPU]
    of the kernel and of the whole run with the package from ``baseline`` and with the current
    code, measured in alternating processes (ROUNDS each, the order swapped every round)."""
    rows = []
    for index, (label, _, elements, _) in enumerate(AB_CASES):
        runs = {"before": [], "after": []}
        for r in range(ROUNDS):
            for side in (("before", "after") if r % 2 == 0 else ("after", "before")):
                runs[side].append(_case_in_process(baseline if side == "before" else None, index))
        print(label, runs, file=sys.stderr)
        med = {side: {key: statistics.median(x[key] for x in runs[side]) for key in ("kernel_cpu", "run_cpu")}
               for side in runs}
        b, a = med["before"], med["after"]
        rows.append([label, str(elements), f"{b['kernel_cpu']:.1f}", f"{a['kernel_cpu']:.1f}",
                     f"{a['kernel_cpu'] / b['kernel_cpu']:.3f}", f"{b['run_cpu']:.1f}", f"{a['run_cpu']:.1f}",
                     f"{a['run_cpu'] / b['run_cpu']:.3f}"])
    return rows


def moordyn_cost() -> dict | None:
    """MoorDyn RK4 at 20 segments, 0.382 ms: wall time per node and force evaluation [ns]."""
    try:
        from moordyn_snapping import run
    except ImportError:
        return None
    segments, step = 20, 0.000382
    walls = [run(1.27, DURATION, segments, step, scheme="RK4")["wall_time_s"] for _ in range(REPEATS)]
    wall = statistics.median(walls)
    steps = DURATION / step
    return {"wall": wall, "per_eval": wall * 1e9 / (4 * steps * (segments + 1)), "speed": DURATION / wall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--baseline", help="a checkout of an earlier commit: its kernel timed alternately")
    parser.add_argument("--case-only", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.case_only is not None:
        label, f, n, h = AB_CASES[args.case_only]
        print(json.dumps(kernel_cost(f, n, h)))
        return
    load = os.getloadavg()[0]
    comparison = before_after(args.baseline) if args.baseline else None
    load_after = os.getloadavg()[0]
    rows = []
    for label, f, n, h in CASES:
        r = kernel_cost(f, n, h)
        rows.append([label, str(n), f"{r['h'] * 1e3:.4g}", str(r["steps"]), f"{r['kernel_cpu']:.1f}",
                     f"{r['kernel_wall']:.1f}", f"{r['run_cpu']:.1f}", f"{r['run_wall']:.1f}", f"{r['speed']:.0f}"])
        print(label, r, file=sys.stderr)
    split = split_rows()
    md = moordyn_cost()
    lines = ["# The explicit kernel: cost per node and step\n", machine_header(),
             f"- load average at the start: {load:.1f} on 2 cores (above 2 the machine is shared with other jobs: wall "
             "times are then noisy and high, CPU times of this process the steadier figure)\n\n", __doc__.split("\n\n")[1].replace("\n", " "),
             "\n\n", markdown_table(["case", "elements", "step [ms]", "steps", "kernel CPU [ns/node/step]",
                                     "kernel wall", "whole run CPU", "whole run wall", "speed [x real time]"], rows)]
    lines += [f"\nThe kernel's CPU time per step [ns] at {SPLIT_STEP * 1e3:g} ms, 1.27 Hz, split by a least-squares "
              "line into a cost per step and one per node (same run, medians of each):\n\n",
              markdown_table(["case"] + [f"{n} el" for n in SPLIT_ELEMENTS] + ["per step [ns]", "per node [ns]"],
                             split)]
    if comparison is not None:
        lines += [f"\nBefore and after: CPU time [ns/node/step] with the package from `--baseline` ({args.baseline}) "
                  f"and with this commit's, in alternating processes (the order swapped every round; medians of "
                  f"{ROUNDS} processes, each the median of {REPEATS} runs; load average {load:.1f} at the start of "
                  f"the comparison, {load_after:.1f} at its end):\n\n",
                  markdown_table(["case", "elements", "kernel before", "kernel after", "after/before",
                                  "whole run before", "whole run after", "after/before"], comparison)]
    if md is not None:
        lines.append(f"\nMoorDyn 2.7 RK4, 20 segments, 0.382 ms, 1.27 Hz, same run: {md['per_eval']:.0f} ns wall per "
                     f"node and force evaluation ({4 * md['per_eval']:.0f} per node and RK4 step, the Python coupling "
                     f"every 0.5 ms included), {md['speed']:.0f}x real time (median of {REPEATS}).\n")
    (RESULTS / "explicit_kernel.md").write_text("".join(lines), encoding="utf-8")


if __name__ == "__main__":
    main()
