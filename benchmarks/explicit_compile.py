"""Cold compile of the nodal-position kernels (the explicit path's step loop among them).

Each of :func:`towcable_fmu.nodal.simulation_kernels.kernel_jobs`'s jobs compiled in order in
one new process whose kernel cache (``TOWCABLE_CACHE_DIR``) is an empty temporary folder: the
CPU time [s] of each job and their sum (a job's callees compile within the first job that
calls them). With ``--baseline DIR`` the package from DIR is measured too, in processes
alternating with the current code's (the order swapped every round).

Run: ``python benchmarks/explicit_compile.py [--baseline DIR] [--rounds N]``. Writes
``results/explicit_compile.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

from common import RESULTS, machine_header, markdown_table

#: The child: compile every nodal job in order into an empty cache, print CPU seconds per job.
_CHILD = """
import json, time
from towcable_fmu.nodal.simulation_kernels import kernel_jobs
out = {}
for job in kernel_jobs():
    c0 = time.process_time()
    job.compile()
    out[job.name] = time.process_time() - c0
print(json.dumps(out))
"""


def compile_cost(package_root: str | None) -> dict[str, float]:
    """CPU seconds per nodal job, compiled cold in a new process (``package_root``: the
    folder to import the package from; None: the current code)."""
    with tempfile.TemporaryDirectory(prefix="towcable_cold_") as cache:
        env = dict(os.environ, TOWCABLE_CACHE_DIR=cache)
        if package_root is not None:
            env["PYTHONPATH"] = os.pathsep.join([package_root, env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
        out = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, check=True,
                             cwd=tempfile.gettempdir())
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--baseline", help="a checkout of an earlier commit: its compile timed alternately")
    parser.add_argument("--rounds", type=int, default=1, help="processes per side (medians)")
    args = parser.parse_args()
    sides = {"after": None} if args.baseline is None else {"before": args.baseline, "after": None}
    load = os.getloadavg()[0]
    runs = {side: [] for side in sides}
    for r in range(args.rounds):
        for side in (list(sides) if r % 2 == 0 else list(sides)[::-1]):
            runs[side].append(compile_cost(sides[side]))
            print(side, runs[side][-1], file=sys.stderr)
    jobs = list(runs["after"][0])
    med = {side: {job: statistics.median(x[job] for x in runs[side]) for job in jobs} for side in runs}
    rows = []
    for job in jobs + ["total"]:
        values = [sum(med[side].values()) if job == "total" else med[side][job] for side in runs]
        rows.append([job] + [f"{v:.1f}" for v in values])
    lines = ["# Cold compile of the nodal-position kernels\n", machine_header(),
             f"- load average at the start: {load:.1f}, at the end: {os.getloadavg()[0]:.1f} on 2 cores (above 2 the "
             "machine is shared with other jobs; CPU times of the compiling process)\n\n",
             __doc__.split("\n\n")[1].replace("\n", " "), f" Medians of {args.rounds} process(es) per side"
             + (f"; before: the package from `{args.baseline}`" if args.baseline else "") + ".\n\n",
             markdown_table(["job"] + [f"{side} [s CPU]" for side in runs], rows)]
    (RESULTS / "explicit_compile.md").write_text("".join(lines), encoding="utf-8")


if __name__ == "__main__":
    main()
