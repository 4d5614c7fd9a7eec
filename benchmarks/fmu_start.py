"""How long a TowCable FMU takes to start: instantiate + initialise on ``full_scale``.

Each measurement is a new process that loads the FMU with fmpy (the FMU's own code is
imported from the machine cache, the kernels compiled or loaded), as a host does:

* **warm**: the machine has run this FMU before (its code and kernels are cached); median
  of 3 processes;
* **cold, compiles**: a machine that never ran it, made by an empty
  ``TOWCABLE_CACHE_DIR``, and an FMU built without kernels (``--no-kernels``): the
  kernels are compiled; one process;
* **new machine, precompiled kernels**: the FMU as ``build_fmu.py`` writes it (it carries
  its kernels for x86-64-v3), in a fresh venv without towcable (fmpy and the FMU's
  requirements, numba and llvmlite at the versions it was built with) and an empty
  ``TOWCABLE_CACHE_DIR``; median of 3 processes, each with a new empty cache;
* **standalone, warm**: the standalone FMU in fmpy, for the cost of unzipping its Python
  runtime (fmpy unzips every FMU into a new folder; the runtime is not used in a Python
  host). Runs without any Python are tested in tests/test_fmu_standalone.py.

Writes ``results/fmu_start.md``. Run from the repository root:
``python benchmarks/fmu_start.py`` (about 10 minutes on 2 cores; the cold run, the
fresh venv and, on the first build of the code, compiling the kernels the FMU carries
dominate).
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
carried = {k: v for m in list(sys.modules.values()) for k, v in getattr(m, "CARRIED_KERNELS", {}).items()}
print(json.dumps({"instantiate": t1 - t0, "initialise": t2 - t1, "first_step": t3 - t2, "carried": carried}))
"""


def start(fmu: Path, env: dict[str, str] | None = None, python: Path | None = None) -> dict[str, float]:
    """One start of ``fmu`` in a new process of ``python`` (default: this one); times [s]."""
    import os

    proc = subprocess.run([str(python or sys.executable), "-c", CHILD, str(fmu)], capture_output=True, text=True,
                          check=True, env={**os.environ, **(env or {})}, cwd=fmu.parent)  # not the checkout's folder
    lines = proc.stdout.strip().splitlines()
    run = json.loads(lines[-1])
    run["compiled"] = any("compiled the numerical kernels" in line for line in lines[:-1])
    return run


def fresh_venv(folder: Path) -> Path:
    """Python of a new venv with fmpy and the FMUs' requirements (numba and llvmlite at
    this Python's versions), without towcable."""
    import os
    from importlib.metadata import version

    from towcable_fmu.fmu_build.build import requirements_text

    subprocess.run([sys.executable, "-m", "venv", str(folder)], check=True)
    (folder / "requirements.txt").write_text(requirements_text(), encoding="utf-8")
    (folder / "constraints.txt").write_text("".join(f"{n}=={version(n)}\n" for n in ("numba", "llvmlite")))
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    subprocess.run([str(folder / "bin" / "python"), "-m", "pip", "install", "--quiet", "fmpy", "-r",
                    str(folder / "requirements.txt"), "-c", str(folder / "constraints.txt")], check=True, env=env)
    return folder / "bin" / "python"


def main() -> int:
    from towcable_fmu.fmu_build.build import build_fmus

    with tempfile.TemporaryDirectory(prefix="fmu_start_") as tmp:
        tmp = Path(tmp)
        fmu = build_fmus(tmp / "fmus", ["TowCable"])["TowCable"]
        carrying = build_fmus(tmp / "carrying", ["TowCable"], kernels=True)["TowCable"]
        standalone = build_fmus(tmp / "standalone", ["TowCable"], standalone=True, kernels=True)["TowCable"]
        start(fmu)  # fills the machine cache (compiles once if needed)
        warm = [start(fmu) for _ in range(3)]
        start(standalone)
        warm_standalone = [start(standalone) for _ in range(3)]
        cold = start(fmu, {"TOWCABLE_CACHE_DIR": str(tmp / "empty_cache")})
        python = fresh_venv(tmp / "venv")
        new_machine = [start(carrying, {"TOWCABLE_CACHE_DIR": str(tmp / f"new_machine_{k}")}, python)
                       for k in range(3)]
        sizes = {"without kernels": fmu.stat().st_size, "default": carrying.stat().st_size,
                 "standalone": standalone.stat().st_size}

    def total(run: dict[str, float]) -> float:
        return run["instantiate"] + run["initialise"]

    cases = [("warm (kernels cached)", warm),
             ("cold, compiles (empty cache, FMU built --no-kernels)", [cold]),
             ("new machine, precompiled kernels (fresh venv, empty cache)", new_machine),
             ("standalone, warm", warm_standalone)]
    lines = ["# TowCable FMU start-up (full_scale)", "", machine_header(),
             "Instantiate + initialise (statics of the 450 m cable included) in a new fmpy process; "
             "`python benchmarks/fmu_start.py`. Targets (issue 17): warm under 5 s, first instantiation on a "
             "fresh machine under 60 s. 'compiled': the FMU logged that it compiled kernels (runs of the case "
             "that did / all runs).", "",
             "| case | instantiate + initialise [s] | first 0.01 s step [s] | compiled |", "|---|---|---|---|"]
    for name, runs in cases:
        lines.append(f"| {name} | {statistics.median(total(r) for r in runs):.2f} | "
                     f"{statistics.median(r['first_step'] for r in runs):.3f} | "
                     f"{sum(r['compiled'] for r in runs)}/{len(runs)} |")
    reasons = {reason for r in new_machine for reason in r["carried"].values() if reason}
    if reasons:
        lines += ["", "Precompiled kernels not used: " + "; ".join(sorted(reasons))]
    lines += ["", "FMU sizes (zipped): " + ", ".join(f"{k} {v / 1e6:.1f} MB" for k, v in sizes.items())
              + " (default and standalone carry the precompiled kernels).", ""]
    (RESULTS / "fmu_start.md").write_text("\n".join(lines), encoding="utf-8")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
