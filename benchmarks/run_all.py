"""Regenerate every benchmark result under ``benchmarks/results/`` (tables and plots).

Runs the benchmark scripts one after another, each in its own process (the machine has
two cores and wall time is what is measured: nothing else should run meanwhile):
core (hanging cable), hydro (kernel costs, statics), full_scale (work-precision with
ship motion), full_scale_deploy (deploy and recovery: work-precision, cost against
deployed length), snapping (ours and the peers MoorDyn and Exudyn, if installed: each code's
front), snapping_physics (our converged runs against MoorDyn's, one difference at a time), profile
(where the time goes, scene by scene), cosim (the three FMUs, FMU overhead), bounds
(the fastest one Newton iteration per step could go, against the snapping and cosim targets),
fmu_start (TowCable's instantiate + initialise, warm and cold), sea_trial_turn
(the nodal cable with a rigid towed body through a turn, run time against error),
defaults (every built-in scene's default solver settings against its efficient front) and
first_run (the command line's first run: compiling on every core against one).

Run from the repository root: ``pip install ".[bench]" && python benchmarks/run_all.py``
(about 30 minutes). ``--only NAME ...`` runs a subset.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).parent
SCRIPTS = {"core": "core.py", "hydro": "hydro.py", "full_scale": "full_scale.py",
           "full_scale_deploy": "full_scale_deploy.py", "snapping": "snapping.py",
           "snapping_physics": "snapping_physics.py",
           "profile": "profile_scenes.py", "cosim": "cosim.py", "bounds": "bounds.py", "fmu_start": "fmu_start.py",
           "sea_trial_turn": "sea_trial_turn.py", "defaults": "defaults.py", "first_run": "first_run.py"}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="+", choices=sorted(SCRIPTS), help="run only these benchmarks")
    args = parser.parse_args(argv)
    failed = []
    for name in args.only or SCRIPTS:
        start = time.perf_counter()
        print(f"== {name} ({SCRIPTS[name]})", file=sys.stderr, flush=True)
        rc = subprocess.run([sys.executable, SCRIPTS[name]], cwd=HERE).returncode
        print(f"== {name}: {'ok' if rc == 0 else f'FAILED (exit {rc})'} in {time.perf_counter() - start:.0f} s",
              file=sys.stderr, flush=True)
        if rc != 0:
            failed.append(name)
    if failed:
        print("failed: " + ", ".join(failed), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
