"""Sweep throughput: cases per hour of full-scale cases on 1 and 2 local processes and on
a Dask LocalCluster of 2 single-threaded worker processes (loopback).

    python benchmarks/sweep.py [--cases 8] [--duration 120] [--output benchmarks/results/sweep.md]

Every case is the ``full_scale`` scene (scene mode: Simulation with its own irregular sea and
simplified-sheave compensation) for ``--duration`` simulated seconds, the cases differing in
the sea's seed. Each configuration runs the same cases into a fresh table; the wall time
includes starting the worker processes (and, for Dask, connecting to the cluster, not
starting it). The numba kernels are compiled once before the measurement.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

from common import RESULTS, machine_header  # noqa: E402


def make_spec(cases: int, duration: float, output: Path):
    from towcable_fmu.sweep.spec import spec_from_table

    return spec_from_table({"sweep": {"scene": "full_scale", "duration": duration, "settle": min(40.0, duration / 2),
                                      "interval": 0.05, "output": str(output)},
                            "fixed": {"sheave.contact.stiffness": 1e8},
                            "parameters": {"seed": list(range(1, cases + 1))}})


def measure(label: str, cases: int, duration: float, **kwargs) -> dict:
    from towcable_fmu.sweep import run_sweep
    from towcable_fmu.sweep.store import column, read_table

    stamp = Path(__file__).parents[1] / "towcable_fmu" / "__pycache__" / "kernel_sources.sha256"
    before = stamp.stat().st_mtime if stamp.exists() else None
    with tempfile.TemporaryDirectory() as tmp:
        spec = make_spec(cases, duration, Path(tmp))
        load = os.getloadavg()[0]
        report = run_sweep(spec, progress=False, **kwargs)
        per_case = float(np.mean(column(read_table(report.table), "wall_time [s]")))
    # the workers refresh numba's cache when a kernel source changed (another job editing the tree)
    recompiled = (stamp.stat().st_mtime if stamp.exists() else None) != before
    if report.failed:
        raise RuntimeError(f"{label}: {report.failed} cases failed")
    print(f"{label}: {report.ran} cases in {report.wall_time:.1f} s = {report.cases_per_hour:.0f} cases/h "
          f"(mean case {per_case:.1f} s, load average before {load:.2f})", file=sys.stderr)
    return {"label": label, "wall": report.wall_time, "rate": report.cases_per_hour, "load": load,
            "per_case": per_case, "note": "kernels recompiled during the run: not valid" if recompiled else ""}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=8, help="cases per configuration (default 8)")
    parser.add_argument("--duration", type=float, default=120.0, help="simulated time per case [s] (default 120)")
    parser.add_argument("--output", default=str(RESULTS / "sweep.md"), help="Markdown table to write")
    parser.add_argument("--no-dask", action="store_true", help="skip the Dask cluster")
    args = parser.parse_args(argv)

    from towcable_fmu.simulation import Simulation

    start = time.perf_counter()
    Simulation.from_scene("full_scale").run(1.0)  # compile / load the kernels once
    print(f"kernels ready in {time.perf_counter() - start:.1f} s", file=sys.stderr)
    rows = [measure("local, 1 process", args.cases, args.duration, workers=1),
            measure("local, 2 processes", args.cases, args.duration, workers=2)]
    if not args.no_dask:
        from distributed import LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=None) as cluster:
            rows.append(measure("Dask LocalCluster, 2 workers x 1 thread", args.cases, args.duration,
                                scheduler=cluster.scheduler_address))
    base = rows[0]["rate"]
    lines = ["# Sweep throughput", "", machine_header().rstrip(), "",
             f"{args.cases} cases of the `full_scale` scene (scene mode, irregular default sea with seeds "
             f"1..{args.cases}, simplified-sheave compensation, `sheave.contact.stiffness = 1e8`), "
             f"{args.duration:g} s simulated each, recorded every 0.05 s; wall time includes starting the worker "
             "processes and the statics of every case. Command: "
             f"`python benchmarks/sweep.py --cases {args.cases} --duration {args.duration:g}`.", "",
             "| execution | wall time [s] | cases per hour | speed-up vs 1 process | mean wall time of a case [s] "
             "| load average before | note |",
             "| --- | ---: | ---: | ---: | ---: | ---: | --- |"]
    for row in rows:
        lines.append(f"| {row['label']} | {row['wall']:.1f} | {row['rate']:.0f} | {row['rate'] / base:.2f} | "
                     f"{row['per_case']:.1f} | {row['load']:.2f} | {row['note']} |")
    lines += ["", "The load average counts every process on the machine (other jobs included): with more runnable "
                  "processes than cores the speed-up from 1 to 2 processes falls below 2."]
    Path(args.output).write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(f"wrote {args.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
