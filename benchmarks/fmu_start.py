"""How long a TowCable FMU takes to start: instantiate + initialise on ``full_scale``.

Each measurement is a new process that loads the FMU with fmpy (the FMU's own code is
imported from the machine cache, the kernels compiled or loaded), as a host does:

* **warm**: the machine has run this FMU before (its code and kernels are cached); median
  of 3 processes;
* **cold**: a machine that never ran it, made by an empty ``TOWCABLE_CACHE_DIR`` (the
  kernels are compiled); one process, the compile time the FMU logs beside it;
* **standalone, warm**: the standalone FMU in fmpy, for the cost of unzipping its Python
  runtime (fmpy unzips every FMU into a new folder; the runtime is not used in a Python
  host). Runs without any Python are tested in tests/test_fmu_standalone.py.

Writes ``results/fmu_start.md``. Run from the repository root:
``python benchmarks/fmu_start.py`` (about 10 minutes on 2 cores; the cold run dominates).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

from common import RESULTS, machine_header  # noqa: E402

#: One start of TowCable in fmpy, timed in the child; prints a JSON line.
CHILD = """
import json, sys, time
t0 = time.perf_counter()
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
path = sys.argv[1]
md = read_model_description(path)
unzipped = extract(path)
fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName="TowCable")
fmu.instantiate(loggingOn=True, callbacks=None)
t1 = time.perf_counter()
fmu.setupExperiment(startTime=0.0)
fmu.enterInitializationMode()
fmu.exitInitializationMode()
t2 = time.perf_counter()
fmu.doStep(0.0, 0.01)
t3 = time.perf_counter()
fmu.terminate(); fmu.freeInstance()
print(json.dumps({"instantiate": t1 - t0, "initialise": t2 - t1, "first_step": t3 - t2}))
"""


def start(fmu: Path, env: dict[str, str] | None = None) -> dict[str, float]:
    """One start of ``fmu`` in a new process (times [s])."""
    import os

    proc = subprocess.run([sys.executable, "-c", CHILD, str(fmu)], capture_output=True, text=True, check=True,
                          env={**os.environ, **(env or {})})
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> int:
    from towcable_fmu.fmi.build import build_fmus

    with tempfile.TemporaryDirectory(prefix="fmu_start_") as tmp:
        tmp = Path(tmp)
        fmu = build_fmus(tmp / "fmus", ["TowCable"])["TowCable"]
        standalone = build_fmus(tmp / "standalone", ["TowCable"], standalone=True)["TowCable"]
        start(fmu)  # fills the machine cache (compiles once if needed)
        warm = [start(fmu) for _ in range(3)]
        start(standalone)
        warm_standalone = [start(standalone) for _ in range(3)]
        cold = start(fmu, {"TOWCABLE_CACHE_DIR": str(tmp / "empty_cache")})
        sizes = {"default": fmu.stat().st_size, "standalone": standalone.stat().st_size}

    def total(run: dict[str, float]) -> float:
        return run["instantiate"] + run["initialise"]

    rows = [("warm (kernels cached)", statistics.median(total(r) for r in warm),
             statistics.median(r["first_step"] for r in warm)),
            ("cold (empty cache: compiles)", total(cold), cold["first_step"]),
            ("standalone, warm", statistics.median(total(r) for r in warm_standalone),
             statistics.median(r["first_step"] for r in warm_standalone))]
    lines = ["# TowCable FMU start-up (full_scale)", "", machine_header(),
             "Instantiate + initialise (statics of the 450 m cable included) in a new fmpy process; "
             "`python benchmarks/fmu_start.py`. Targets (issue 17): warm under 5 s, cold under 60 s.", "",
             "| case | instantiate + initialise [s] | first 0.01 s step [s] |", "|---|---|---|"]
    lines += [f"| {name} | {t:.2f} | {s:.3f} |" for name, t, s in rows]
    lines += ["", f"FMU sizes: default {sizes['default'] / 1e6:.1f} MB, standalone {sizes['standalone'] / 1e6:.1f} MB "
              "(zipped).", ""]
    (RESULTS / "fmu_start.md").write_text("\n".join(lines), encoding="utf-8")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
