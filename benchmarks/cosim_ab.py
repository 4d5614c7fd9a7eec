"""`towcable cosim` of two source trees in alternating fresh processes (A/B).

For each communication step, REPEATS rounds; in each round both trees run
``python -m towcable_fmu.cli cosim`` (full_scale, default sea, simplified-sheave set-point,
DURATION s) in a fresh process with ``PYTHONPATH=<tree>`` and their own FMU folder (built
from that tree on the first run, untimed), in alternating order. Reported per tree: the
medians of the speed [x real time], of TowCable's model time and of the time outside it
(the two light FMUs, every FMI call, the master) per communication step [us], with the
load average at the start and the end.

Run: ``python benchmarks/cosim_ab.py TREE_A TREE_B [--duration S] [--steps 0.01,0.02]``
(prints a Markdown table).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from common import machine_header, markdown_table

REPEATS = 3


def run(tree: str, work: Path, step: float, duration: float) -> dict[str, float]:
    """One `towcable cosim` of ``tree`` in a fresh process; its timing (summary.json)."""
    out = work / "out"
    command = [sys.executable, "-m", "towcable_fmu.cli", "cosim", "--duration", str(duration), "--step", str(step),
               "--compensation", "simplified_sheave", "--fmus", str(work / "fmus"), "--output", str(out),
               "--no-plot", "--quiet"]
    done = subprocess.run(command, env=dict(os.environ, PYTHONPATH=tree), cwd=work, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"{tree}: {done.stderr.strip()[-2000:]}")
    t = json.loads((out / "summary.json").read_text())["timing"]
    n = t["steps"]
    return {"speed": t["realtime_factor"], "towcable_us": 1e6 * t["model.TowCable"] / n,
            "outside_us": 1e6 * (t["wall"] - t["model.TowCable"]) / n,
            "light_us": 1e6 * (t["model.ShipMotion"] + t["model.HeaveCompensation"]) / n}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("--duration", type=float, default=120.0)
    parser.add_argument("--steps", default="0.01,0.02")
    args = parser.parse_args()
    trees = {"A": str(Path(args.a).resolve()), "B": str(Path(args.b).resolve())}
    base = Path(tempfile.mkdtemp(prefix="cosim_ab_"))
    work = {name: base / name for name in trees}
    for name, tree in trees.items():  # build each tree's FMUs and compile their kernels (untimed)
        work[name].mkdir()
        run(tree, work[name], 0.01, 1.0)
    load0 = os.getloadavg()[0]
    rows = []
    for step in map(float, args.steps.split(",")):
        results: dict[str, list[dict]] = {name: [] for name in trees}
        for r in range(REPEATS):
            for name in (("A", "B") if r % 2 == 0 else ("B", "A")):
                results[name].append(run(trees[name], work[name], step, args.duration))
                print(step, name, results[name][-1], flush=True)
        for name in trees:
            m = {key: statistics.median(x[key] for x in results[name]) for key in results[name][0]}
            rows.append([f"{step:g}", name, f"{m['speed']:.1f}", f"{m['towcable_us']:.1f}", f"{m['outside_us']:.1f}",
                         f"{m['light_us']:.1f}"])
    report(f"A = {trees['A']}, B = {trees['B']}; {args.duration:g} s", load0,
           ["communication step [s]", "tree", "x real time", "TowCable model [us/step]", "outside TowCable [us/step]",
            "light FMUs' models [us/step]"], rows)


def report(what: str, load0: float, headers: list[str], rows: list[list[str]]) -> None:
    """Print the machine, ``what`` was run with the load average at the start (``load0``)
    and now, and the table."""
    print(machine_header())
    print(f"\n{what}; medians of {REPEATS} alternating fresh processes; load average {load0:.1f} at the start, "
          f"{os.getloadavg()[0]:.1f} at the end\n")
    print(markdown_table(headers, rows))


if __name__ == "__main__":
    main()
