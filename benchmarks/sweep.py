"""Sweep throughput: cases per hour of full-scale cases on 1 and 2 local processes and on
a Dask LocalCluster of 2 single-threaded worker processes (loopback).

    python benchmarks/sweep.py [--cases 8] [--duration 120] [--repeats 3] [--output benchmarks/results/sweep.md]

Every case is the ``full_scale`` scene (scene mode: Simulation with its own irregular sea and
simplified-sheave compensation) for ``--duration`` simulated seconds, the cases differing in
the sea's seed. Each configuration runs the same cases ``--repeats`` times into a fresh
table; the three configurations take turns, so that a change of the machine's load touches
each of them alike.

All three paths warm up alike: every worker process loads the kernels (one recording
interval of the scene, :func:`towcable_fmu.sweep.case.warm_up`) before it takes its first
case; the local pool starts fresh processes for every repeat, the Dask workers stay up.
The throughput is ``cases / busy span``, where the busy span runs from the start of the
first case to the end of the last one by the workers' clocks: starting the processes and
warming up are left out (the whole call, with both, is reported beside it). Per case the
table gives the wall time and the CPU time of the worker process; on a machine shared
with other jobs the wall time grows and the CPU time does not, unless threads of the
same process compete for the cores (oversubscription).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

from common import RESULTS, machine_header  # noqa: E402



def _kernel_files() -> dict[str, int]:
    """The compiled-kernel files of this code in the machine cache, with their sizes."""
    from towcable_fmu.jit.kernel_cache import kernel_folder

    folder = kernel_folder()
    return {str(p): p.stat().st_size for p in folder.rglob("*.nb*")} if folder.exists() else {}


def make_spec(cases: int, duration: float, output: Path):
    """The benchmark sweep: ``cases`` seeds of the full-scale scene."""
    from towcable_fmu.sweep.spec import spec_from_table

    return spec_from_table({"sweep": {"scene": "full_scale", "duration": duration, "settle": min(40.0, duration / 2),
                                      "interval": 0.05, "output": str(output)},
                            "fixed": {"sheave.contact.stiffness": 1e8},
                            "parameters": {"seed": list(range(1, cases + 1))}})


def measure(label: str, cases: int, duration: float, **kwargs) -> dict:
    """One run of the sweep; its throughput, timings per case and per worker."""
    from towcable_fmu.sweep import run_sweep

    before = _kernel_files()
    with tempfile.TemporaryDirectory() as tmp:
        spec = make_spec(cases, duration, Path(tmp))
        load = os.getloadavg()[0]
        report = run_sweep(spec, progress=False, **kwargs)
    # a worker compiled (a kernel source changed, e.g. another job editing the tree)
    recompiled = _kernel_files() != before
    if report.failed:
        raise RuntimeError(f"{label}: {report.failed} cases failed")
    span = report.busy_span
    workers: dict[str, list] = {}
    for t in report.timings:
        workers.setdefault(t.worker, []).append(t)
    row = {"label": label, "rate": 3600.0 * report.ran / span, "span": span, "call": report.wall_time, "load": load,
           "wall": statistics.median(t.wall_time for t in report.timings),
           "cpu": statistics.median(t.cpu_time for t in report.timings),
           "workers": [(len(ts), sum(t.wall_time for t in ts), sum(t.cpu_time for t in ts))
                       for ts in workers.values()],
           "recompiled": recompiled}
    print(f"{label}: {report.ran} cases, busy span {span:.1f} s = {row['rate']:.0f} cases/h (whole call "
          f"{report.wall_time:.1f} s), per case median wall {row['wall']:.2f} s, CPU {row['cpu']:.2f} s; per worker "
          + ", ".join(f"{n} cases {w:.1f} s wall {c:.1f} s CPU" for n, w, c in row["workers"])
          + f"; load average before {load:.2f}" + ("; KERNELS RECOMPILED" if recompiled else ""), file=sys.stderr)
    return row


def summarise(runs: list[dict]) -> dict:
    """Medians over the repeats of one configuration."""
    med = {k: statistics.median(r[k] for r in runs) for k in ("rate", "span", "call", "wall", "cpu", "load")}
    shares = [c / w for r in runs for _, w, c in r["workers"] if w > 0]
    med["cpu_share"] = statistics.median(shares) if shares else float("nan")
    med["label"] = runs[0]["label"]
    med["repeats"] = len(runs)
    med["spread"] = (min(r["rate"] for r in runs), max(r["rate"] for r in runs))
    med["note"] = ("numba recompiled the kernels during a repeat (another job edited a kernel source): in the "
                   "warm-up, left out, but competing for the cores" if any(r["recompiled"] for r in runs) else "")
    return med


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=8, help="cases per run (default 8; even, to share 2 workers)")
    parser.add_argument("--duration", type=float, default=120.0, help="simulated time per case [s] (default 120)")
    parser.add_argument("--repeats", type=int, default=3, help="runs per configuration (default 3; medians)")
    parser.add_argument("--output", default=str(RESULTS / "sweep.md"), help="Markdown table to write")
    parser.add_argument("--no-dask", action="store_true", help="skip the Dask cluster")
    args = parser.parse_args(argv)

    from towcable_fmu.ancf.simulation import Simulation

    start = time.perf_counter()
    Simulation.from_scene("full_scale").run(1.0)  # compile into numba's cache once, before any worker starts
    print(f"kernels ready in {time.perf_counter() - start:.1f} s", file=sys.stderr)
    configs = [("local, 1 process", {"workers": 1}), ("local, 2 processes", {"workers": 2})]
    runs: dict[str, list[dict]] = {label: [] for label, _ in configs}
    cluster = None
    if not args.no_dask:
        from distributed import LocalCluster

        # the nanny starts the workers with OMP/OPENBLAS/MKL_NUM_THREADS = 1 (pre-spawn-environ)
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None)
        label = "Dask LocalCluster, 2 workers x 1 thread"
        configs.append((label, {"scheduler": cluster.scheduler_address}))
        runs[label] = []
    try:
        for repeat in range(args.repeats):
            for label, kwargs in configs:
                runs[label].append(measure(f"{label} (repeat {repeat + 1})", args.cases, args.duration, **kwargs))
    finally:
        if cluster is not None:
            cluster.close()
    rows = [summarise(r) for r in runs.values()]
    for row, (label, _) in zip(rows, configs):
        row["label"] = label
    base = rows[0]["rate"]
    for row, (label, kwargs) in zip(rows, configs):
        # the speed-up if every worker had a core to itself: workers x CPU per case of 1 process / CPU per case
        row["cpu_speedup"] = (2 if kwargs.get("scheduler") else kwargs["workers"]) * rows[0]["cpu"] / row["cpu"]
    command = (f"python benchmarks/sweep.py --cases {args.cases} --duration {args.duration:g} "
               f"--repeats {args.repeats}" + (" --no-dask" if args.no_dask else ""))
    lines = ["# Sweep throughput", "", machine_header().rstrip(), "",
             f"{args.cases} cases of the `full_scale` scene (scene mode, irregular default sea with seeds "
             f"1..{args.cases}, simplified-sheave compensation, `sheave.contact.stiffness = 1e8`), "
             f"{args.duration:g} s simulated each, recorded every 0.05 s. Command: `{command}`.", "",
             "Throughput = cases / busy span (start of the first case to the end of the last, by the workers' "
             "clocks): starting the worker processes and loading the kernels (done by every worker before its "
             "first case, alike in all three paths) are left out; the whole call with both is given beside it. "
             f"Medians over {args.repeats} repeats (the configurations take turns); the range of the throughput "
             "over the repeats in brackets. Per case: wall time and CPU time of the worker process (all its "
             "threads). CPU/wall: the share of a core each worker process got while running cases.", "",
             "| execution | cases per hour (min-max) | speed-up vs 1 process | busy span [s] | whole call [s] "
             "| wall per case [s] | CPU per case [s] | CPU/wall per worker | speed-up from CPU time | "
             "load average before | note |",
             "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"]
    for row in rows:
        lines.append(f"| {row['label']} | {row['rate']:.0f} ({row['spread'][0]:.0f}-{row['spread'][1]:.0f}) | "
                     f"{row['rate'] / base:.2f} | {row['span']:.1f} | {row['call']:.1f} | {row['wall']:.2f} | "
                     f"{row['cpu']:.2f} | {row['cpu_share']:.2f} | {row['cpu_speedup']:.2f} | {row['load']:.2f} | "
                     f"{row['note']} |")
    lines += ["", "The load average counts every process on the machine (other jobs included). With other jobs "
                  "running, CPU/wall falls below 1 and the speed-up from 1 to 2 processes below 2 while the CPU "
                  "time per case stays: compare the CPU time per case between the rows to see the cost of running "
                  "two cases at once (memory bandwidth, caches, extra threads). \"Speed-up from CPU time\" = "
                  "workers x (CPU per case of 1 process) / (CPU per case): the speed-up when every worker has a "
                  "core to itself; it is a projection, the measured one is the column \"speed-up vs 1 process\".",
              "",
              "Local worker processes are started with the `spawn` method and `OMP_NUM_THREADS`, "
              "`OPENBLAS_NUM_THREADS`, `MKL_NUM_THREADS`, `NUMBA_NUM_THREADS` = 1 "
              "(`towcable_fmu.sweep.execute.WORKER_ENVIRONMENT`), as Dask's nanny starts its workers. Before "
              "(forked workers inheriting the master's two OpenBLAS threads) a case used 2.5 to 3 times the CPU "
              "time (the ship's irregular sea is a complex matrix product per block of samples, and the idle "
              "OpenBLAS thread spins on the second core), and 2 processes ran at 0.63x the throughput of one "
              "(the CPU times were compared side by side on a busy machine). On an idle machine one process gains a little from a second "
              "OpenBLAS thread (1775 cases/h were measured that way before, about 10 % more than one "
              "single-threaded process), but that thread takes the core a second worker needs."]
    Path(args.output).write_text("\n".join(lines) + "\n", encoding="utf-8")
    print(f"wrote {args.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
