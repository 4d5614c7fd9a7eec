"""Scene defaults of several source trees in alternating fresh processes (A/B/C...).

For each scene, ROUNDS rounds; in each round every tree runs the scene's default for the
given duration in a fresh process with ``PYTHONPATH=<tree>`` (after an untimed 0.2 s run
in the same process, which loads the kernels), the trees' order rotated from round to
round. Reported per tree: the medians of the speed [x real time] by CPU time of the
process (``time.process_time``) and by wall time, and the CPU speed's ratio to the first
tree's, with the load average at the start and the end (the machine may be shared).

Run: ``python benchmarks/defaults_ab.py TREE_A,TREE_B[,...] SCENE:DURATION ... [--rounds N]``
(prints a Markdown table; each tree's kernels must be compiled, e.g. by one earlier run).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

from common import markdown_table

ROUNDS = 3

#: The child: a warm-up run, then the timed run of a fresh simulation.
_CHILD = """
import json, sys, time
from towcable_fmu.models import simulation_from
name, duration = sys.argv[1], float(sys.argv[2])
sim = simulation_from(name, {}); sim.initialize(); sim.run(min(0.2, duration))
sim = simulation_from(name, {}); sim.initialize()
wall, cpu = time.perf_counter(), time.process_time()
sim.run(duration)
wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
import towcable_fmu
print(json.dumps({"wall": duration / wall, "cpu": duration / cpu, "file": towcable_fmu.__file__}))
"""


def run(tree: str, scene: str, duration: float) -> dict[str, float]:
    """One timed run of ``scene``'s default in a fresh process on ``tree``: speeds [x real time]."""
    done = subprocess.run([sys.executable, "-c", _CHILD, scene, str(duration)], env=dict(os.environ, PYTHONPATH=tree),
                          cwd="/", capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"{tree} {scene}: {done.stderr.strip()[-2000:]}")
    result = json.loads(done.stdout.strip().splitlines()[-1])
    if not result["file"].startswith(tree):
        raise RuntimeError(f"{tree}: the child imported towcable_fmu from {result['file']}")
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trees", help="comma-separated source trees; the first is the baseline")
    parser.add_argument("scenes", nargs="+", help="SCENE:DURATION [s]")
    parser.add_argument("--rounds", type=int, default=ROUNDS)
    args = parser.parse_args()
    trees = [str(Path(t).resolve()) for t in args.trees.split(",")]
    load0 = os.getloadavg()[0]
    rows = []
    for item in args.scenes:
        scene, _, duration = item.partition(":")
        cpu: dict[str, list[float]] = {t: [] for t in trees}
        wall: dict[str, list[float]] = {t: [] for t in trees}
        for k in range(args.rounds):
            for tree in trees[k % len(trees):] + trees[:k % len(trees)]:
                result = run(tree, scene, float(duration))
                cpu[tree].append(result["cpu"])
                wall[tree].append(result["wall"])
        base = statistics.median(cpu[trees[0]])
        for tree in trees:
            rows.append([f"{scene} {duration} s", Path(tree).name, f"{statistics.median(cpu[tree]):.1f}",
                         f"{statistics.median(cpu[tree]) / base:.3f}", f"{statistics.median(wall[tree]):.1f}",
                         ", ".join(f"{x:.1f}" for x in cpu[tree])])
        print(rows[-len(trees):], file=sys.stderr, flush=True)
    print(f"load average {load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end; {args.rounds} rounds\n")
    print(markdown_table(["scene", "tree", "x real time (CPU)", "ratio", "x real time (wall)", "CPU runs"], rows))


if __name__ == "__main__":
    main()
