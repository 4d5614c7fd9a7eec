"""The command line's first run on a machine: compiling the kernels on every core against one.

Each case is a new ``towcable run SCENE --duration 1`` with an empty
``TOWCABLE_CACHE_DIR`` (a machine that never ran this code). It compiles the model's
kernels ahead (:mod:`towcable_fmu.jit.parallel_compile`) on every core the process may use,
and once more restricted to one core (``taskset -c 0``: the helpers inherit the
restriction, so the kernels compile one after the other, as they did before compiling
ahead). Reported: the compile time the command prints and the whole command's wall time.
Writes ``results/first_run.md``. Run: ``python benchmarks/first_run.py`` (about 5 minutes).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

from common import RESULTS, machine_header, markdown_table

SCENES = ("full_scale", "sea_trial_turn_rigid")


def first_run(scene: str, one_core: bool) -> tuple[float, float]:
    """Compile time the command reports [s] and its wall time [s], on an empty cache."""
    cache = tempfile.mkdtemp(prefix="towcable_first_run_")
    try:
        command = [sys.executable, "-m", "towcable_fmu.cli", "run", scene, "--duration", "1", "--interval", "0.5",
                   "--output", os.path.join(cache, "out.csv")]
        if one_core:
            command = ["taskset", "-c", "0"] + command
        start = time.perf_counter()
        proc = subprocess.run(command, env=dict(os.environ, TOWCABLE_CACHE_DIR=cache), capture_output=True,
                              text=True, check=True)
        wall = time.perf_counter() - start
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    found = re.search(r"compiled the kernels in ([0-9.]+) s", proc.stderr)
    if found is None:
        raise RuntimeError(f"no compile time in the output of {' '.join(command)}:\n{proc.stderr}")
    return float(found.group(1)), wall


def main() -> None:
    rows = []
    for scene in SCENES:
        serial = first_run(scene, one_core=True)
        parallel = first_run(scene, one_core=False)
        rows.append([scene, serial[0], parallel[0], serial[0] / parallel[0], serial[1], parallel[1]])
    lines = ["# The command line's first run: compiling on every core", "", machine_header(),
             f"`towcable run SCENE --duration 1` with an empty kernel cache, {os.cpu_count()} cores against one "
             "(`taskset -c 0`); one run each. 'compile' is what the command reports, 'wall' the whole command.",
             "", markdown_table(["scene", "compile, one core [s]", "compile, all cores [s]", "ratio",
                                 "wall, one core [s]", "wall, all cores [s]"], rows)]
    (RESULTS / "first_run.md").write_text("\n".join(lines), encoding="utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
