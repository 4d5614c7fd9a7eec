"""The FMUs in hosts without Python (issue 9): the loader layer, a C host, valgrind, cross-check.

The C host (``tests/c_host/fmu_host.c``) is compiled here with the system C compiler and
runs with an environment stripped of every PYTHON* variable: the FMU must find and start a
Python by itself, here the machine Python named by ``TOWCABLE_PYTHON`` (this venv's; the
standalone FMUs, which carry their own, are tested in test_fmu_standalone.py). Its
outputs are compared with fmpy's (the cross-check reference,
``towcable_fmu.fmu_build.crosscheck``) for the same inputs.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from importlib.metadata import version
from pathlib import Path

import numpy as np
import pytest

from towcable_fmu.common import contract
from towcable_fmu.common.run_io import read_csv
from towcable_fmu.fmu_build import crosscheck as xc
from towcable_fmu.fmu_build import native

VALGRIND = shutil.which("valgrind") or "/usr/bin/valgrind"
needs_valgrind = pytest.mark.skipif(not os.access(VALGRIND, os.X_OK), reason="no valgrind")
MODELS = ["ShipMotion", "HeaveCompensation", "TowCable"]
#: Instantiations in each host run: the second one must reproduce the first.
INSTANCES = 2

pytestmark = pytest.mark.skipif(native.c_compiler() is None, reason="no C compiler")


# ------------------------------------------------------------------------------ fixtures
@pytest.fixture(scope="module")
def crosscheck(fmu_paths, tmp_path_factory) -> dict[str, Path]:
    """The cross-check folders of the three FMUs (fmpy reference runs)."""
    return xc.write_crosscheck(fmu_paths, tmp_path_factory.mktemp("crosscheck"))


# ------------------------------------------------------------------------------- helpers
def model_variables(fmu_dir: Path) -> tuple[str, dict[str, tuple[int, str]]]:
    """GUID and name -> (value reference, type) of an extracted FMU."""
    root = ET.parse(fmu_dir / "modelDescription.xml").getroot()
    variables = {}
    for sv in root.find("ModelVariables").findall("ScalarVariable"):
        kind = next(child.tag for child in sv if child.tag in ("Real", "Integer", "Boolean", "String"))
        variables[sv.get("name")] = (int(sv.get("valueReference")), kind)
    return root.get("guid"), variables


def write_plan(path: Path, fmu_dir: Path, model: str, exp: xc.Experiment, outputs: list[str],
               inputs_csv: Path | None, instances: int = INSTANCES, params: dict | None = None) -> Path:
    """A plan file of the C host (format: tests/c_host/fmu_host.c)."""
    guid, variables = model_variables(fmu_dir)
    lines = [f"model {model}", f"guid {guid}", f"start {exp.start!r}", f"stop {exp.stop!r}",
             f"step {exp.step!r}", f"instances {instances}"]
    for name, value in (params or {}).items():
        vr, kind = variables[name]
        lines.append(f"param {kind[0]} {vr} {value!r}" if kind == "Real" else f"param S {vr} {value}")
    if inputs_csv is not None:
        lines.append(f"inputs {inputs_csv}")
        header = read_csv(inputs_csv)
        lines += [f"input {variables[name][0]}" for name in list(header)[1:]]
    for name in outputs:
        vr, kind = variables[name]
        lines.append(f"output {kind[0]} {vr} {name}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def host_env() -> dict[str, str]:
    """An environment without any hint of Python (no PYTHON*, no virtualenv) but the
    interpreter the FMUs are to start, this venv's (``TOWCABLE_PYTHON``)."""
    return {"PATH": "/usr/bin:/bin", "LANG": "C", "TOWCABLE_PYTHON": sys.executable}


def run_host(host: Path, fmu_dir: Path, plan: Path, out: Path, prefix: list[str] | None = None,
             timeout: float = 900, extra_env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    """Run the C host on ``fmu_dir`` with ``plan`` (under ``prefix``, e.g. valgrind), output to ``out``."""
    return subprocess.run((prefix or []) + [str(host), str(fmu_dir), str(plan), str(out)], capture_output=True,
                          text=True, env=host_env() | (extra_env or {}), cwd=out.parent, timeout=timeout)


def truncated_inputs(src: Path, dst: Path, rows: int) -> Path:
    """The first ``rows`` data rows of an input CSV."""
    lines = src.read_text(encoding="utf-8").splitlines()
    dst.write_text("\n".join(lines[: rows + 1]) + "\n", encoding="utf-8")
    return dst


# -------------------------------------------------------------------------- the loader
@pytest.mark.parametrize("name", MODELS)
def test_fmu_binary_is_the_loader_in_front_of_pythonfmu(fmu_paths, name):
    with zipfile.ZipFile(fmu_paths[name]) as z:
        loader = z.read(f"binaries/linux64/{name}.so")
        real = z.read(f"binaries/linux64/{native.REAL_LIBRARY}")
    # pythonfmu's library needs Python's symbols from the process; the loader does not
    assert b"_Py_NoneStruct" in real and b"_Py_NoneStruct" not in loader


def test_pythonfmu_library_alone_does_not_load_in_a_c_host(host, extracted, tmp_path):
    """The problem the loader solves: pythonfmu's own binary leaves Python unresolved."""
    fmu_dir = tmp_path / "ShipMotion"
    shutil.copytree(extracted["ShipMotion"], fmu_dir)
    binaries = fmu_dir / "binaries" / "linux64"
    shutil.copy(binaries / native.REAL_LIBRARY, binaries / "ShipMotion.so")
    exp = xc.EXPERIMENTS["ShipMotion"]
    plan = write_plan(tmp_path / "plan.txt", fmu_dir, "ShipMotion", exp, ["ship.z"], None)
    proc = run_host(host, fmu_dir, plan, tmp_path / "out.csv")
    assert proc.returncode == 1 and "undefined symbol" in proc.stderr


@needs_valgrind
@pytest.mark.parametrize("python,expected", [
    ("/nonexistent/venv/bin/python", "this FMU needs a Python: it runs inside Python hosts"),
    ("/bin/sh", "this FMU needs a Python"),
])
def test_no_usable_python_fails_instantiate_with_a_message(host, extracted, tmp_path, python, expected):
    fmu_dir = extracted["ShipMotion"]
    plan = write_plan(tmp_path / "plan.txt", fmu_dir, "ShipMotion", xc.EXPERIMENTS["ShipMotion"], ["ship.z"], None)
    proc = run_host(host, fmu_dir, plan, tmp_path / "out.csv", prefix=[VALGRIND, "--error-exitcode=9", "-q"],
                    extra_env={"TOWCABLE_PYTHON": python})
    assert proc.returncode == 2, proc.stderr  # fmi2Instantiate returned NULL; no crash, no memory error
    logged = [line for line in proc.stderr.splitlines() if line.startswith("[ShipMotion_1] status 3 ")]
    assert len(logged) == 1 and expected in logged[0], proc.stderr


def test_a_python_without_the_requirements_is_named_with_the_missing_packages(host, extracted, tmp_path):
    """The machine's own Python (no numpy, numba, scipy): the FMU says what to install."""
    bare = tmp_path / "bare"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(bare)], check=True)
    plan = write_plan(tmp_path / "plan.txt", extracted["ShipMotion"], "ShipMotion", xc.EXPERIMENTS["ShipMotion"],
                      ["ship.z"], None)
    proc = run_host(host, extracted["ShipMotion"], plan, tmp_path / "out.csv",
                    extra_env={"TOWCABLE_PYTHON": str(bare / "bin" / "python")})
    assert proc.returncode == 2, proc.stderr
    assert "this FMU needs the Python packages numpy, scipy, numba" in proc.stderr
    assert "pythonfmu deploy" in proc.stderr


def test_fmpy_host_uses_its_own_python_never_the_machine_one(fmu_paths, monkeypatch):
    """In a Python host the loader must not start (or even look for) a second interpreter."""
    monkeypatch.setenv("TOWCABLE_PYTHON", "/nonexistent/python")
    exp = xc.Experiment(0.0, 0.1, 0.01, 1e-4, ("ship.z",))
    result = xc.simulate(fmu_paths["ShipMotion"], exp, None, exp.outputs)
    assert np.any(result["ship.z"] != 0.0)


@pytest.mark.parametrize("logging", ["on", "off"])
def test_a_bad_parameter_is_an_error_the_c_host_sees_with_logging_on_or_off(host, extracted, tmp_path, logging):
    fmu_dir = extracted["HeaveCompensation"]
    exp = xc.EXPERIMENTS["HeaveCompensation"]
    plan = write_plan(tmp_path / "plan.txt", fmu_dir, "HeaveCompensation", exp, ["winch.phi_sp"], None,
                      params={"algorithm": "nope"}, instances=1)
    plan.write_text(plan.read_text(encoding="utf-8") + f"logging {logging}\n", encoding="utf-8")
    proc = run_host(host, fmu_dir, plan, tmp_path / "out.csv")
    assert proc.returncode == 3, proc.stderr  # fmi2ExitInitializationMode returned fmi2Error
    logged = [line for line in proc.stderr.splitlines() if line.startswith("[HeaveCompensation_1] status 3 ")]
    assert len(logged) == 1 and "algorithm = 'nope' is invalid: allowed one of none" in logged[0], proc.stderr


# ------------------------------------------------------------- C host against fmpy
@pytest.mark.parametrize("name", MODELS)
def test_c_host_reproduces_the_fmpy_reference(host, crosscheck, name, tmp_path):
    folder = crosscheck[name]
    ref = read_csv(folder / f"{name}_ref.csv")
    exp = xc.read_opt(folder / f"{name}_ref.opt")
    inputs = folder / f"{name}_in.csv"
    fmu_dir = tmp_path / name
    with zipfile.ZipFile(folder / f"{name}.fmu") as z:
        z.extractall(fmu_dir)
    outputs = list(ref)[1:]
    plan = write_plan(tmp_path / "plan.txt", fmu_dir, name, exp, outputs, inputs if inputs.exists() else None)
    out = tmp_path / "host.csv"
    proc = run_host(host, fmu_dir, plan, out)
    assert proc.returncode == 0, proc.stderr
    assert f"instance {INSTANCES}: largest difference to instance 1: 0\n" in proc.stdout
    got = read_csv(out)
    # Round-off, for a model that amplifies it (TowCable: the stiff sheave contact turns a
    # 1e-14 difference into 1e-9 relative within 10 s): what fmpy itself shows when every
    # input moves by one unit in the last place.
    sensitivity = {var: 0.0 for var in outputs}
    if inputs.exists():
        nudged = {k: v if k == "time" else np.nextafter(v, np.inf) for k, v in read_csv(inputs).items()}
        moved = xc.simulate(folder / f"{name}.fmu", exp, nudged, tuple(outputs))
        sensitivity = {var: np.max(np.abs(moved[var] - ref[var])) for var in outputs}
    assert_round_off(got, ref, outputs, sensitivity)
    print(f"{name}: largest difference C host - fmpy:",
          {var: float(np.max(np.abs(got[var] - ref[var]))) for var in outputs})


def test_c_host_sets_parameters_as_fmpy_does(host, crosscheck, tmp_path):
    """HeaveCompensation's default algorithm is "none" (a constant set-point): compensate."""
    name, params = "HeaveCompensation", {"algorithm": "simplified_sheave", "phi_nom": 3.5}
    folder = crosscheck[name]
    exp = xc.read_opt(folder / f"{name}_ref.opt")
    inputs = folder / f"{name}_in.csv"
    outputs = ["winch.phi_sp", "winch.phi_sp_rate"]
    ref = xc.simulate(folder / f"{name}.fmu", exp, read_csv(inputs), tuple(outputs), params)
    fmu_dir = tmp_path / name
    with zipfile.ZipFile(folder / f"{name}.fmu") as z:
        z.extractall(fmu_dir)
    plan = write_plan(tmp_path / "plan.txt", fmu_dir, name, exp, outputs, inputs, params=params)
    out = tmp_path / "host.csv"
    proc = run_host(host, fmu_dir, plan, out)
    assert proc.returncode == 0, proc.stderr
    got = read_csv(out)
    assert_round_off(got, ref, outputs)
    assert ref["winch.phi_sp"][0] != 3.8 and np.ptp(ref["winch.phi_sp"]) > 0  # the parameters took effect


def assert_round_off(got: dict[str, np.ndarray], ref: dict[str, np.ndarray], names: list[str],
                     sensitivity: dict[str, float] | None = None) -> None:
    """Same times; every column equal to round-off: 1e-13 of the column's magnitude, or
    twice the change a one-ulp nudge of the inputs causes (``sensitivity``)."""
    assert np.array_equal(got["time"], ref["time"])
    for var in names:
        tol = max(1e-13 * (1.0 + np.max(np.abs(ref[var]))), 2.0 * (sensitivity or {}).get(var, 0.0))
        assert np.max(np.abs(got[var] - ref[var])) <= tol, var


# ------------------------------------------------------------------- cross-check files
@pytest.mark.parametrize("name", MODELS)
def test_crosscheck_artefacts_follow_the_rules_and_fmpy_reproduces_them(fmu_paths, crosscheck, name):
    folder = crosscheck[name]
    assert folder.parts[-7:] == ("fmus", "2.0", "cs", "linux64", "towcable", version("towcable"), name)
    spec = contract.fmu(name)
    opt = xc.read_opt(folder / f"{name}_ref.opt")
    ref_text = (folder / f"{name}_ref.csv").read_text(encoding="utf-8")
    header = ref_text.splitlines()[0].split(",")
    assert header[0] == '"time"' and all(h.startswith('"') and h.endswith('"') for h in header)
    ref = read_csv(folder / f"{name}_ref.csv")
    assert 1 <= len(ref) - 1 <= 10 and set(list(ref)[1:]) <= set(spec.names("output"))
    assert ref["time"][0] == opt.start and ref["time"][-1] == opt.stop
    inputs_csv = folder / f"{name}_in.csv"
    assert inputs_csv.exists() == bool(spec.names("input"))
    inputs = read_csv(inputs_csv) if inputs_csv.exists() else None
    if inputs is not None:
        assert list(inputs)[1:] == list(spec.names("input"))
        assert inputs["time"][0] <= opt.start and inputs["time"][-1] >= opt.stop
    for path in folder.glob("*.csv"):
        assert path.stat().st_size < 1_000_000
    again = xc.simulate(fmu_paths[name], opt, inputs, tuple(list(ref)[1:]))
    for var in ref:
        assert np.array_equal(again[var], ref[var]), var


# ------------------------------------------------------------------------------ valgrind
def frames_attributed(error: ET.Element, ours: tuple[str, ...]) -> bool:
    """Whether the first frame outside valgrind's own objects is in one of ``ours``."""
    for frame in error.find("stack").findall("frame"):
        obj = frame.findtext("obj") or ""
        if "vgpreload" in Path(obj).name:
            continue
        return any(obj.endswith(o) for o in ours)
    return False


def valgrind_run(host, fmu_dir: Path, model: str, tmp_path: Path, inputs: Path | None, steps: int):
    exp = xc.EXPERIMENTS[model]
    short = xc.Experiment(exp.start, exp.start + steps * exp.step, exp.step, exp.rel_tol, ())
    if inputs is not None:
        inputs = truncated_inputs(inputs, tmp_path / "in.csv", steps + 1)
    plan = write_plan(tmp_path / "plan.txt", fmu_dir, model, short, list(exp.outputs[:2]), inputs)
    # Valgrind's virtual CPU reports other features than the real one, so numba's cache (keyed on
    # the CPU) would miss and LLVM would compile every kernel under memcheck. With a generic CPU the
    # cache written by a plain run first is the one the run under valgrind loads.
    numba_env = {"NUMBA_CPU_NAME": "generic", "NUMBA_CACHE_DIR": str(tmp_path / "numba_cache")}
    warm = run_host(host, fmu_dir, plan, tmp_path / "warm.csv", extra_env=numba_env)
    assert warm.returncode == 0, warm.stderr[-3000:]
    xml = tmp_path / "memcheck.xml"
    proc = run_host(host, fmu_dir, plan, tmp_path / "out.csv",
                    prefix=[VALGRIND, "--tool=memcheck", "--leak-check=full", "--num-callers=40", "--xml=yes",
                            f"--xml-file={xml}"], timeout=3000, extra_env=numba_env)
    assert proc.returncode == 0, proc.stderr[-3000:]
    root = ET.parse(xml).getroot()
    assert root.find("status/state") is not None
    ours = (f"/binaries/linux64/{model}.so", f"/{host.name}")
    errors = root.findall("error")
    kinds = [e.findtext("kind") for e in errors]
    mine = [(e.findtext("kind"), e.findtext("what") or e.findtext("xwhat/text")) for e in errors
            if frames_attributed(e, ours)]
    return kinds, mine


@needs_valgrind
@pytest.mark.parametrize("name", [
    "ShipMotion", "HeaveCompensation",
    pytest.param("TowCable", marks=pytest.mark.slow),  # a plain run first fills numba's cache
])
def test_valgrind_finds_no_memory_error_in_the_loader_or_the_host(host, crosscheck, name, tmp_path):
    folder = crosscheck[name]
    fmu_dir = tmp_path / name
    with zipfile.ZipFile(folder / f"{name}.fmu") as z:
        z.extractall(fmu_dir)
    inputs = folder / f"{name}_in.csv"
    kinds, mine = valgrind_run(host, fmu_dir, name, tmp_path, inputs if inputs.exists() else None, steps=3)
    assert mine == []
    # the other reports are Python's and the dynamic loader's; no invalid write anywhere
    assert "InvalidWrite" not in kinds and "InvalidFree" not in kinds
