"""Drop-in FMUs (issue 17): they carry their code, hold no path of the building machine,
run where towcable is not installed, describe themselves honestly and say when they fail.

Each portability claim is tested by moving the artefact: an FMU built from a copy of the
sources that is renamed afterwards, an FMU from other sources run in this process (where
the checkout's towcable is imported), the FMUs in a fresh venv holding only fmpy and the
FMU's requirements.
"""

from __future__ import annotations

import ast
import os
import re
import shutil
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest

from towcable_fmu.common import contract
from towcable_fmu.jit import machine_cache
from towcable_fmu.fmu_build import bundle, build
from towcable_fmu.fmu_build import crosscheck as xc

from fmu_util import open_fmu

ROOT = Path(__file__).resolve().parents[1]
MODELS = ["ShipMotion", "HeaveCompensation", "TowCable"]


def model_description(path: Path) -> ET.Element:
    with zipfile.ZipFile(path) as z:
        return ET.fromstring(z.read("modelDescription.xml"))


def clean_env(**extra: str) -> dict[str, str]:
    """This process's environment without anything that points Python at the checkout."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    env.update(extra)
    return env


# ----------------------------------------------------------------------------- the bundle
def test_imports_are_rewritten_line_for_line():
    source = textwrap.dedent("""\
        import numpy as np
        from towcable_fmu.scene import load_scene
        from ship_motion import (DEFAULT_SEA,
                                 motion_from_config)
        import controllers.setpoint as sp
        from .errors import SceneError


        def f():
            from towcable_fmu.common.errors import SceneError  # a late import
            return SceneError
        """)
    out = bundle.rewrite_imports(source, "towcable_x")
    assert out.splitlines()[1] == "from towcable_x.towcable_fmu.scene import load_scene"
    assert out.splitlines()[2] == "from towcable_x.ship_motion import (DEFAULT_SEA,"
    assert out.splitlines()[4] == "import towcable_x.controllers.setpoint as sp"
    assert out.splitlines()[5] == "from .errors import SceneError"
    assert out.splitlines()[9].strip().startswith("from towcable_x.towcable_fmu.common.errors import")
    assert len(out.splitlines()) == len(source.splitlines())
    with pytest.raises(bundle.BundleError, match="cannot be bundled"):
        bundle.rewrite_imports("import towcable_fmu.scene\n", "towcable_x")


def test_the_bundle_imports_nothing_of_ours_by_the_public_names():
    name, files = bundle.bundle()
    assert re.fullmatch(r"towcable_[0-9a-f]{16}", name)
    assert bundle.bundle()[0] == name  # the same sources, the same name
    for path, data in files.items():
        if not path.endswith(".py"):
            continue
        for node in ast.walk(ast.parse(data, path)):
            modules = ([node.module] if isinstance(node, ast.ImportFrom) and node.level == 0 else
                       [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            assert not any(m and m.split(".")[0] in bundle.PACKAGES for m in modules), (path, node.lineno)
    assert f"{name}/{machine_cache.MANIFEST}" in files and f"{name}/towcable_fmu/builtin_scenes/full_scale.toml" in files


# ---------------------------------------------------------------------- the archives
@pytest.mark.parametrize("name", MODELS)
def test_the_fmu_carries_its_code_requirements_and_no_record_of_the_build_python(fmu_paths, name):
    with zipfile.ZipFile(fmu_paths[name]) as z:
        names = z.namelist()
        entry = z.read("resources/slavemodule.txt").decode()
        script = z.read(f"resources/{entry}.py").decode()
        requirements = z.read("resources/requirements.txt").decode()
    package = build.carried_package(fmu_paths[name])
    assert f'activate("{package}", ' in script
    module = contract.fmu(name).slave.split(":")[0].replace(".", "/")
    assert f"resources/{package}/{module}.py" in names
    assert f"resources/{package}_activate.py" in names
    assert not any(n.endswith("python_env.json") for n in names)
    required = {line.split(">=")[0] for line in requirements.splitlines() if line and not line.startswith("#")}
    assert required == {"numpy", "scipy", "numba"}


def build_machine_paths() -> set[str]:
    """Paths of this machine that an FMU must not mention."""
    import tempfile

    paths = {sys.prefix, sys.base_prefix, sys.executable, str(ROOT), str(Path.home()), tempfile.gettempdir() + "/"}
    return {p for p in paths if len(p) > 4}


@pytest.mark.parametrize("name", MODELS)
def test_no_path_of_the_building_machine_is_in_the_fmu(fmu_paths, name):
    with zipfile.ZipFile(fmu_paths[name]) as z:
        for info in z.infolist():
            data = z.read(info.filename)
            for path in build_machine_paths():
                assert path.encode() not in data, (info.filename, path)


def test_the_same_sources_build_the_same_bytes_and_guid(fmu_paths, tmp_path):
    again = build.build_fmus(tmp_path)
    for name, path in fmu_paths.items():
        assert again[name].read_bytes() == path.read_bytes(), name
    guids = {model_description(p).get("guid") for p in fmu_paths.values()}
    assert len(guids) == 3 and all(re.fullmatch(r"[0-9a-f]{8}(-[0-9a-f]{4}){3}-[0-9a-f]{12}", g) for g in guids)


@pytest.mark.parametrize("name", MODELS)
def test_outputs_are_calculated_initial_unknowns_and_parameters_fixed_with_their_ranges(fmu_paths, name):
    root = model_description(fmu_paths[name])
    spec = contract.fmu(name)
    scalars = root.find("ModelVariables").findall("ScalarVariable")
    initial = [int(u.get("index")) for u in root.find("ModelStructure/InitialUnknowns").findall("Unknown")]
    outputs = [i + 1 for i, sv in enumerate(scalars) if sv.get("causality") == "output"]
    assert initial == outputs and outputs
    for sv, var in zip(scalars, spec.variables):
        element = sv.find(var.type)
        if var.causality == "output":
            assert sv.get("initial") == "calculated" and element.get("start") is None, var.name
        if var.causality == "parameter":
            assert sv.get("variability") == "fixed", var.name
            for bound in ("min", "max"):
                expected = getattr(var, bound)
                got = element.get(bound)
                assert (got is None) == (expected is None), (var.name, bound)
                if got is not None:
                    assert float(got) == expected
    assert root.find("CoSimulation").get("needsExecutionTool") == "true"
    assert root.get("generationDateAndTime") is None


# ------------------------------------------------- the declared ranges are the models'
def _rejects(check, value) -> bool:
    from towcable_fmu.common.errors import SceneError

    try:
        check(value)
    except SceneError:
        return True
    return False


def _ship_check(name: str):
    from ship_motion import motion_from_config
    from ship_motion.fmu import motion_table

    spec = contract.fmu("ShipMotion")
    kind = {"motion.speed_ramp": "manoeuvre", "motion.turn_rate": "manoeuvre", "motion.speed": "manoeuvre",
            "motion.turn_angle": "manoeuvre", "motion.turn_start": "manoeuvre",
            "motion.heave.amplitude": "regular", "motion.roll.amplitude": "regular",
            "motion.pitch.amplitude": "regular"}.get(name, "irregular")

    def check(value):
        params = {v.name: v.start for v in spec.parameters} | {"motion.type": kind, name: value}
        if name == "motion.turn_rate":
            params["motion.turn_angle"] = 360.0  # a whole turn: more than the ramps take
        if name == "motion.turn_angle":
            params["motion.turn_rate"] = 0.1 if value else 0.0
        table, base = motion_table(params)
        motion_from_config(table, key="motion", base_dir=base)
    return check


def _controller_check(name: str):
    from controllers.fmu import HeaveCompensation

    def check(value):
        slave = HeaveCompensation(instance_name="range")
        slave.values[name] = value
        slave._initialize()  # raises SceneError for a value the algorithm rejects
    return check


def _cable_check(name: str):
    from towcable_fmu.scene import load_scene

    def check(value):
        if value == {"solver.time_step": 0.0, "solver.rho_inf": -1.0, "towbody.mass": 0.0}[name]:
            return  # the sentinel: keep the scene's value
        load_scene(str(ROOT / "tests" / "data" / "fmu_tow.toml"), [(name, value)])
    return check


@pytest.mark.parametrize("fmu,name", [(spec.name, v.name) for spec in contract.fmus().values()
                                      for v in spec.parameters if v.min is not None or v.max is not None])
def test_each_declared_range_is_the_range_the_model_accepts(fmu, name):
    """The bound itself is accepted, a value just beyond it rejected (for the use of the
    parameter that accepts the widest range)."""
    var = contract.fmu(fmu).variable(name)
    check = {"ShipMotion": _ship_check, "HeaveCompensation": _controller_check, "TowCable": _cable_check}[fmu](name)
    step = 1 if var.type == "Integer" else 1e-6 * max(1.0, abs(var.min or 0.0), abs(var.max or 0.0))
    if var.min is not None:
        assert not _rejects(check, var.min), f"{name} = {var.min} (min) rejected"
        if not (fmu == "TowCable" and name == "solver.rho_inf"):  # below -1: neither sentinel nor in [0, 1]
            assert _rejects(check, var.min - step), f"{name} = {var.min - step} accepted"
    if var.max is not None:
        assert not _rejects(check, var.max), f"{name} = {var.max} (max) rejected"
        assert _rejects(check, var.max + step), f"{name} = {var.max + step} accepted"


# ------------------------------------------------------------- errors reach the host
def test_a_setter_out_of_range_is_an_fmi2_error_naming_the_value(fmu_paths):
    from fmpy.fmi1 import FMICallException

    fmu = open_fmu(fmu_paths, "HeaveCompensation")
    try:
        mark = len(fmu.messages)
        with pytest.raises(FMICallException, match="status 3"):
            fmu.set_parameters({"theta_nom": -0.5})
        assert "parameter theta_nom = -0.5 is invalid: allowed >= 0 rad; the value is not set" in fmu.log_text(mark)
    finally:
        fmu.free()


@pytest.mark.parametrize("fmu,name,value,message", [
    ("TowCable", "scene", "nope", "scene = 'nope' is invalid: allowed a built-in scene name"),
    ("HeaveCompensation", "algorithm", "nope", "algorithm = 'nope' is invalid: allowed one of none,"),
    ("TowCable", "solver.rho_inf", "5", "parameter solver.rho_inf = 5.0 is invalid: allowed [-1, 1]"),
])
def test_fmpy_simulate_exits_non_zero_on_a_bad_parameter_and_says_why(fmu_paths, tmp_path, fmu, name, value,
                                                                      message):
    proc = subprocess.run([str(Path(sys.executable).with_name("fmpy")), "simulate", str(fmu_paths[fmu]),
                           "--stop-time", "0.02", "--start-values", name, value],
                          capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert proc.returncode != 0
    assert message in proc.stdout + proc.stderr
    assert "status 3 (error)" in proc.stdout + proc.stderr


# ------------------------------------------------------- moved, foreign and fresh
@pytest.fixture(scope="module")
def foreign(tmp_path_factory):
    """ShipMotion built from a copy of the sources whose ship rises 1 m higher, in a
    subprocess; the copy is then renamed (the build folder no longer exists)."""
    tmp = tmp_path_factory.mktemp("foreign")
    src = tmp / "src"
    for package in bundle.PACKAGES:
        shutil.copytree(ROOT / package, src / package, ignore=shutil.ignore_patterns("__pycache__"))
    # the difference in the sum of harmonic components, which the slave's Python and the
    # step the loader layer calls (ship_motion/fmu_step.py) both evaluate
    source = src / "ship_motion" / "irregular.py"
    text = source.read_text(encoding="utf-8")
    old = "            out[2, j] = f2 * g0 + 2.0 * f1 * g1 + f0 * g2\n    return out\n"
    assert text.count(old) == 1
    source.write_text(text.replace(old, old.replace("    return out\n", "    out[0, 2] += 1.0  # the foreign sources' "
                                                                         "difference\n    return out\n")),
                      encoding="utf-8")
    out = tmp / "out"
    subprocess.run([sys.executable, "-c", "import sys; from towcable_fmu.fmu_build.build import build_fmus; "
                    f"build_fmus({str(out)!r}, ['ShipMotion'])"], check=True, cwd=tmp,
                   env=clean_env(PYTHONPATH=str(src)), timeout=600)
    src.rename(tmp / "src_moved")
    return {"fmu": out / "ShipMotion.fmu", "source": src}


def test_an_fmu_from_moved_sources_mentions_none_of_them(foreign):
    with zipfile.ZipFile(foreign["fmu"]) as z:
        for info in z.infolist():
            assert str(foreign["source"]).encode() not in z.read(info.filename), info.filename


def test_an_fmu_runs_the_code_it_carries_beside_another_towcable(fmu_paths, foreign):
    """The foreign ShipMotion's sources differ from this Python's towcable: it runs its
    own copy (from the machine cache), whose ship rises 1 m higher, while ours runs the
    installed code (the same files: see the next test); neither disturbs the other."""
    import ship_motion.fmu

    installed = ship_motion.fmu.__file__
    exp = xc.Experiment(0.0, 0.5, 0.01, 1e-4, ("ship.z",))
    ours = xc.simulate(fmu_paths["ShipMotion"], exp, None, exp.outputs)
    theirs = xc.simulate(foreign["fmu"], exp, None, exp.outputs)
    assert np.any(ours["ship.z"] != 0.0)
    np.testing.assert_allclose(theirs["ship.z"] - 1.0, ours["ship.z"], rtol=0, atol=1e-14)
    assert sys.modules["ship_motion.fmu"].__file__ == installed  # this process's towcable is untouched
    package = build.carried_package(foreign["fmu"])
    assert package != build.carried_package(fmu_paths["ShipMotion"])
    module = sys.modules[f"{package}.ship_motion.fmu"]
    assert Path(module.__file__).is_relative_to(machine_cache.cache_root() / "code" / package)


def test_an_fmu_of_the_installed_sources_runs_the_installed_code(fmu_paths):
    """Built from the files this Python imports, the FMUs import those modules (one copy
    of the code, and the kernels the command line compiled), not their carried copy."""
    import ship_motion.fmu

    package = build.carried_package(fmu_paths["ShipMotion"])
    assert machine_cache.installed_code() == package
    exp = xc.Experiment(0.0, 0.5, 0.01, 1e-4, ("ship.z",))
    out = xc.simulate(fmu_paths["ShipMotion"], exp, None, exp.outputs)
    assert np.any(out["ship.z"] != 0.0)
    assert not any(name == package or name.startswith(package + ".") for name in sys.modules)
    assert sys.modules["ship_motion.fmu"] is ship_motion.fmu


def test_fmpy_in_a_fresh_venv_runs_towcable_on_full_scale_as_the_master_does(fmu_paths, fresh_venv, tmp_path):
    from towcable_fmu.cosim import CosimConfig, run_cosim

    config = CosimConfig(scene="full_scale", duration=0.3, step=0.01)
    master = run_cosim(config, fmus=fmu_paths, echo=False)
    spec = contract.fmu("TowCable")
    inputs = {"time": master.series["time"]} | {n: master.series[n] for n in spec.names("input")}
    # the cable was initialised with the nominal set-point (the master's order, see towcable_fmu/cosim)
    inputs["winch.phi_sp"] = inputs["winch.phi_sp"].copy()
    inputs["winch.phi_sp_rate"] = inputs["winch.phi_sp_rate"].copy()
    inputs["winch.phi_sp"][0] = master.geometry["phi_nom"]
    inputs["winch.phi_sp_rate"][0] = 0.0
    xc.write_csv(tmp_path / "in.csv", inputs)
    outputs = ["tension.sheave", "contact.sheave_force", "towbody.z", "winch.phi"]
    script = textwrap.dedent(f"""
        import csv, importlib.util, json, sys
        import numpy as np
        from fmpy import simulate_fmu
        assert importlib.util.find_spec("towcable_fmu") is None, "towcable is installed in the fresh venv"
        rows = list(csv.reader(open("in.csv")))
        names = [h.strip('"') for h in rows[0]]
        signals = np.array([tuple(float(x) for x in r) for r in rows[1:]], dtype=[(n, float) for n in names])
        result = simulate_fmu({str(fmu_paths['TowCable'])!r}, start_time=0.0, stop_time=0.3, step_size=0.01,
                              output_interval=0.01, input=signals, output={outputs!r},
                              start_values={master.parameters['TowCable']!r})
        json.dump({{n: result[n].tolist() for n in result.dtype.names}}, open("out.json", "w"))
        """)
    proc = subprocess.run([str(fresh_venv), "-c", script], capture_output=True, text=True, cwd=tmp_path,
                          env=clean_env(), timeout=1800)
    assert proc.returncode == 0, proc.stderr[-3000:]
    import json

    got = json.loads((tmp_path / "out.json").read_text())
    assert np.array_equal(got["time"], master.series["time"])
    here = xc.simulate(fmu_paths["TowCable"], xc.Experiment(0.0, 0.3, 0.01, 1e-4, tuple(outputs)), inputs,
                       tuple(outputs), master.parameters["TowCable"])
    for name in outputs:
        assert np.array_equal(got[name], here[name]), name  # the same FMU, the same numbers
        scale = 1.0 + np.max(np.abs(master.series[name]))
        assert np.max(np.abs(np.array(got[name]) - master.series[name])) <= 1e-9 * scale, name


# ------------------------------------------------------------ the machine cache
def _resources(tmp_path: Path, name: str) -> Path:
    """An FMU's resources folder holding a one-module bundle ``name`` and its activation."""
    resources = tmp_path / "resources"
    package = resources / name
    package.mkdir(parents=True)
    files = {"__init__.py": b"VALUE = 1\n"}
    for rel, data in files.items():
        (package / rel).write_bytes(data)
    (package / machine_cache.MANIFEST).write_text(machine_cache.manifest_text(files), encoding="utf-8")
    (resources / "requirements.txt").write_text("numpy>=1.26\n", encoding="utf-8")
    shutil.copy(machine_cache.__file__, resources / f"{name}_activate.py")
    return resources


def _import_bundle(resources: Path, name: str) -> Path:
    import importlib.util

    spec = importlib.util.spec_from_file_location(f"{name}_activate", resources / f"{name}_activate.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.import_bundle(name)


def test_activation_installs_the_code_once_and_replaces_an_altered_copy(tmp_path, monkeypatch):
    name = "towcable_0000000000000001"
    resources = _resources(tmp_path, name)
    monkeypatch.setenv("TOWCABLE_CACHE_DIR", str(tmp_path / "cache"))
    target = tmp_path / "cache" / "code" / name
    assert _import_bundle(resources, name) == target and (target / "__init__.py").read_bytes() == b"VALUE = 1\n"
    assert sys.modules[name].__file__ == str(target / "__init__.py") and sys.modules[name].VALUE == 1
    del sys.modules[name]
    stamp = (target / "__init__.py").stat().st_mtime_ns
    assert _import_bundle(resources, name) == target and (target / "__init__.py").stat().st_mtime_ns == stamp
    del sys.modules[name]
    (target / "__init__.py").write_bytes(b"VALUE = 2\n")  # somebody edits the installed copy
    assert _import_bundle(resources, name) == target and sys.modules[name].VALUE == 1
    del sys.modules[name]


def test_activation_without_a_writable_cache_runs_the_code_in_place(tmp_path, monkeypatch):
    name = "towcable_0000000000000002"
    resources = _resources(tmp_path, name)
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    monkeypatch.setenv("TOWCABLE_CACHE_DIR", str(blocked))
    with pytest.warns(UserWarning, match="cannot install the FMU's code"):
        assert _import_bundle(resources, name) == resources / name
    assert sys.modules.pop(name).__file__ == str(resources / name / "__init__.py")


def test_activation_names_missing_requirements(tmp_path, monkeypatch):
    name = "towcable_0000000000000003"
    resources = _resources(tmp_path, name)
    (resources / "requirements.txt").write_text("# comment\nnumpy>=1.26\nno_such_package_xyz>=1\n")
    monkeypatch.setenv("TOWCABLE_CACHE_DIR", str(tmp_path / "cache"))
    with pytest.raises(ImportError, match="needs the Python packages no_such_package_xyz "):
        _import_bundle(resources, name)
