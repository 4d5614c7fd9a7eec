"""Standalone FMUs (issue 17): they carry a Python runtime and run in hosts on a machine
where no Python is installed.

"No Python installed" is made real: the C host and the Open Simulation Platform's ``ecos``
run in a mount namespace (``unshare -m``, as root) where every Python installation of this
machine - the interpreter's prefix, the system Python's library folders and programs, the
virtual environments, the checkout - is covered by an empty tmpfs, with an empty
environment (``env -i``).
"""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
import sys
import sysconfig
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest

from towcable_fmu.common import contract
from towcable_fmu.jit import machine_cache
from towcable_fmu.fmu_build import crosscheck as xc
from towcable_fmu.fmu_build import native
from towcable_fmu.fmu_build.runtime import glibc_needed
from towcable_fmu.common.run_io import read_csv

from test_fmu_native import assert_round_off, write_plan

ROOT = Path(__file__).resolve().parents[1]
#: Zipped size each standalone FMU must stay under [bytes] (issue 17).
SIZE_LIMIT = 150e6

needs_namespaces = pytest.mark.skipif(
    os.geteuid() != 0 or shutil.which("unshare") is None or native.c_compiler() is None,
    reason="hiding the Python installations needs root, unshare and a C compiler")


@pytest.fixture(scope="session")
def standalone_paths(tmp_path_factory):
    """The three standalone FMUs, built once per test session."""
    from towcable_fmu.fmu_build.build import build_fmus

    return build_fmus(tmp_path_factory.mktemp("standalone"), standalone=True)


def python_installations() -> list[Path]:
    """Folders holding a Python of this machine (and the checkout)."""
    candidates = {Path(sys.prefix), Path(sys.base_prefix), ROOT, Path(sysconfig.get_paths()["stdlib"]).parent}
    candidates.update(Path("/usr/lib").glob("python3*"))
    candidates.update(Path("/usr/local/lib").glob("python3*"))
    candidates.add(Path.home() / ".pyenv")  # pyenv's shims and versions, where present
    folders = sorted({p.resolve() for p in candidates if p.is_dir()})
    return [f for f in folders if not any(f != g and f.is_relative_to(g) for g in folders)]  # outermost only


def python_programs() -> list[Path]:
    """Python executables outside those folders (the system's /usr/bin/python3.X)."""
    found = set()
    for folder in (Path("/usr/bin"), Path("/usr/local/bin"), Path("/bin")):
        found.update(p.resolve() for p in folder.glob("python3*") if p.is_file())
    return sorted(found)


def without_python(command: list[str], cwd: Path, env: dict[str, str] | None = None,
                   timeout: float = 900) -> subprocess.CompletedProcess:
    """Run ``command`` in a mount namespace where every Python is hidden, with ``env -i``
    (plus ``env``); first proves that no libpython and no python program is left."""
    hide = [f"mount -t tmpfs none '{p}'" for p in python_installations()]
    hide += [f"mount --bind /dev/null '{p}'" for p in python_programs()]
    probe = ("if find /usr/lib/python3* /usr/local/lib/python3* -mindepth 1 2>/dev/null | grep -q .; then exit 97; fi; "
             f"test ! -e '{sys.base_prefix}/lib/libpython3.so' || exit 98; "
             "for p in /usr/bin/python3*; do test -s \"$p\" && exit 99; done; true")
    settings = " ".join(f"{k}='{v}'" for k, v in (env or {}).items())
    script = " && ".join(hide + [probe, f"exec env -i {settings} " + " ".join(f"'{c}'" for c in command)])
    return subprocess.run(["unshare", "-m", "sh", "-c", script], capture_output=True, text=True, cwd=cwd,
                          timeout=timeout)


# ------------------------------------------------------------------------------ archives
@pytest.mark.parametrize("name", ["ShipMotion", "HeaveCompensation", "TowCable"])
def test_standalone_fmu_is_under_the_size_limit_and_declares_no_tool(standalone_paths, name):
    path = standalone_paths[name]
    assert path.stat().st_size < SIZE_LIMIT, f"{path.stat().st_size / 1e6:.1f} MB"
    with zipfile.ZipFile(path) as z:
        names = set(z.namelist())
        root = ET.fromstring(z.read("modelDescription.xml"))
        runtime = z.read("resources/python/runtime.txt").decode().split()
        libraries = {n: z.read(n) for n in names if n.endswith(".so") or ".so." in n}
    assert root.find("CoSimulation").get("needsExecutionTool") == "false"
    assert not any(n.startswith("binaries/win64/") for n in names)  # pythonfmu's needs an installed Python
    assert f"resources/python/{runtime[0]}" in names and f"resources/python/{runtime[1]}/os.py" in names
    for package in ("numpy", "scipy", "numba", "llvmlite"):
        assert f"resources/python/{runtime[1]}/site-packages/{package}/__init__.py" in names, package
    assert not any("/tests/" in n or "/test/" in n for n in names)
    version = glibc_needed(libraries)
    assert tuple(int(x) for x in version.split(".")) <= tuple(int(x) for x in os.confstr("CS_GNU_LIBC_VERSION")
                                                                  .split()[1].split("."))


# ----------------------------------------------------------- hosts without any Python
@needs_namespaces
def test_standalone_towcable_runs_in_a_c_host_with_every_python_hidden(host, standalone_paths, fmu_paths,
                                                                       tmp_path):
    name = "TowCable"
    exp = xc.Experiment(0.0, 2.0, 0.01, 1e-4, xc.EXPERIMENTS[name].outputs)
    ship = xc.simulate(fmu_paths["ShipMotion"], exp, None, tuple(contract.fmu("ShipMotion").names("output")[:18]))
    inputs = {"time": ship["time"]} | {n: ship[n] for n in contract.fmu(name).names("input") if n in ship}
    inputs["winch.phi_sp"] = np.full_like(ship["time"], 3.8)
    inputs["winch.phi_sp_rate"] = np.zeros_like(ship["time"])
    csv = xc.write_csv(tmp_path / "in.csv", inputs)
    ref = xc.simulate(fmu_paths[name], exp, inputs, exp.outputs)  # fmpy, the non-standalone FMU
    fmu_dir = tmp_path / name
    with zipfile.ZipFile(standalone_paths[name]) as z:
        z.extractall(fmu_dir)
    plan = write_plan(tmp_path / "plan.txt", fmu_dir, name, exp, list(exp.outputs), csv, instances=2)
    proc = without_python([str(host), str(fmu_dir), str(plan), str(tmp_path / "out.csv")], cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "instance 2: largest difference to instance 1: 0\n" in proc.stdout
    # round-off as in test_fmu_native: the stiff sheave contact amplifies a last-bit
    # difference of the hosts' time arithmetic; allowed: what a one-ulp nudge of the inputs does
    nudged = {k: v if k == "time" else np.nextafter(v, np.inf) for k, v in inputs.items()}
    moved = xc.simulate(fmu_paths[name], exp, nudged, exp.outputs)
    sensitivity = {var: np.max(np.abs(moved[var] - ref[var])) for var in exp.outputs}
    assert_round_off(read_csv(tmp_path / "out.csv"), ref, list(exp.outputs), sensitivity)


@pytest.mark.slow
@needs_namespaces
def test_standalone_towcable_with_its_kernels_compiles_nothing_on_a_machine_without_python(host, fmu_paths,
                                                                                         tmp_path):
    """The FMU ``build_fmu.py --standalone`` writes, on a machine that never ran it (empty
    cache) and has no Python: initialised without compiling a kernel."""
    from towcable_fmu.fmu_build.build import build_fmus

    fmu = build_fmus(tmp_path / "built", ["TowCable"], standalone=True, kernels=True)["TowCable"]
    exp = xc.Experiment(0.0, 0.2, 0.01, 1e-4, ("tension.sheave", "towbody.z"))
    ship = xc.simulate(fmu_paths["ShipMotion"], exp, None, tuple(contract.fmu("ShipMotion").names("output")[:18]))
    inputs = {"time": ship["time"]} | {n: ship[n] for n in contract.fmu("TowCable").names("input") if n in ship}
    inputs["winch.phi_sp"] = np.full_like(ship["time"], 3.8)
    inputs["winch.phi_sp_rate"] = np.zeros_like(ship["time"])
    csv = xc.write_csv(tmp_path / "in.csv", inputs)
    fmu_dir = tmp_path / "TowCable"
    with zipfile.ZipFile(fmu) as z:
        z.extractall(fmu_dir)
    plan = write_plan(tmp_path / "plan.txt", fmu_dir, "TowCable", exp, list(exp.outputs), csv, instances=1)
    proc = without_python([str(host), str(fmu_dir), str(plan), str(tmp_path / "out.csv")], cwd=tmp_path,
                          env={"TOWCABLE_CACHE_DIR": str(tmp_path / "new-machine")})
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "initialised" in proc.stderr  # the FMU's messages reach the host
    assert "compiled the numerical kernels" not in proc.stderr, proc.stderr[-3000:]
    assert any((tmp_path / "new-machine" / "kernels").glob(f"*/{machine_cache.CARRIED_MARK}"))
    ref = xc.simulate(fmu_paths["TowCable"], exp, inputs, exp.outputs)
    out = read_csv(tmp_path / "out.csv")
    for name in exp.outputs:
        assert np.allclose(out[name], ref[name], rtol=1e-6, atol=1e-6 * (1.0 + np.max(np.abs(ref[name])))), name


def ecos_command(tmp_path: Path) -> tuple[list[str], dict[str, str]]:
    """The ``ecos`` program of the ecospy wheel (made executable) and the folder of the
    TBB library it links (the tbb wheel's)."""
    import importlib.util

    spec = importlib.util.find_spec("ecospy")  # not imported: its Python module needs libtbb on the loader path
    if spec is None:
        pytest.skip("ecospy is not installed")
    exe = tmp_path / "ecos"
    shutil.copy(Path(spec.submodule_search_locations[0]) / "binaries" / "ecos", exe)
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    libs = [p.parent for p in Path(sys.prefix).glob("lib/libtbb.so.12*")]
    if not libs:
        pytest.skip("libtbb.so.12 (pip install tbb) not found")
    # ecos and its TBB library are copied out of the venv, which is hidden
    tbb = tmp_path / "tbb"
    tbb.mkdir()
    for lib in libs[0].glob("libtbb.so*"):
        shutil.copy(lib, tbb / lib.name)
    return [str(exe)], {"LD_LIBRARY_PATH": str(tbb)}


#: A regular sea from t = 0 (as tests/test_fmu_cosim.py), by the ShipMotion parameters
#: (ecos writes String values into its CSV unquoted: no TOML text with commas or new lines).
WAVES = {"motion.config": "", "motion.type": "regular", "motion.ramp": 0.0, "motion.heave.amplitude": 0.8,
         "motion.heave.period": 6.0, "motion.pitch.amplitude": 2.0, "motion.pitch.period": 7.0}


@needs_namespaces
def test_ecos_runs_the_ssp_of_standalone_fmus_as_the_master_does(standalone_paths, fmu_paths, tmp_path):
    """The OSP's C++ host, with no Python in its process or on the machine, runs the SSP
    file of a master run (full_scale in regular waves) and gives the master's numbers.

    ecos exchanges values after all components stepped (the master feeds the set-point
    within the step, see towcable_fmu/cosim); without compensation the set-point is constant, so
    both see the same inputs. ecos writes 6 decimals."""
    from towcable_fmu.cosim import CosimConfig, run_cosim
    from towcable_fmu.fmu_build.ssp import PARAMETER_SET, write_ssp

    master = run_cosim(CosimConfig(duration=1.0, step=0.01, compensation="none", ship_parameters=WAVES),
                       fmus=fmu_paths, echo=False)
    ssp = write_ssp(tmp_path / "TowedCableSystem.ssp", standalone_paths, master.parameters, stop_time=1.0)
    command, env = ecos_command(tmp_path)
    proc = without_python(command + ["simulate", "--path", str(ssp), "--stopTime", "1", "--stepSize", "0.01",
                                     "--parameterSet", PARAMETER_SET], cwd=tmp_path, env=env, timeout=1800)
    assert proc.returncode == 0, (proc.stdout + proc.stderr)[-3000:]
    ecos = read_ecos_csv(tmp_path / "TowedCableSystem.csv")
    assert np.all(ecos["time"][1:] > 0.0) and np.ptp(ecos["ship.z"]) > 0.1  # the bound regular sea was applied
    s = master.series
    rows = np.searchsorted(s["time"], ecos["time"] - 1e-9)
    assert np.allclose(s["time"][rows], ecos["time"], atol=1e-9) and len(rows) == 100
    for name in ("ship.z", "tension.sheave", "tension.towbody", "contact.sheave_force", "towbody.z", "sheave_angle"):
        expected = s[name][rows]
        assert np.any(expected != expected[0]), name  # the signal moves
        np.testing.assert_allclose(ecos[name], expected, rtol=1e-8, atol=1e-6, err_msg=name)


def read_ecos_csv(path: Path) -> dict[str, np.ndarray]:
    """ecos's result file: ``iterations, time, <Component>::<variable>[<TYPE>], ...``
    (variables by name; the first component's, when two have the same name)."""
    import csv

    with open(path, newline="", encoding="utf-8") as f:
        rows = [row for row in csv.reader(f) if row]
    data = {}
    for i, head in enumerate(h.strip() for h in rows[0]):
        name = head.split("::", 1)[-1].split("[")[0]
        if head.endswith(("[REAL]", "[BOOL]", "[INT]")) or name in ("time", "iterations"):
            data.setdefault(name, np.array([float(r[i]) for r in rows[1:]]))
    return data
