"""FMU build: validators, units and descriptions from the contract, the contract itself."""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
import zipfile

import pytest

from towcable_fmu.common import contract
from towcable_fmu.fmu_build import build


def model_description(path) -> ET.Element:
    with zipfile.ZipFile(path) as z:
        return ET.fromstring(z.read("modelDescription.xml"))


def test_builds_three_fmus(fmu_paths):
    assert set(fmu_paths) == {"ShipMotion", "HeaveCompensation", "TowCable"}
    for name, path in fmu_paths.items():
        assert path.name == f"{name}.fmu" and path.is_file()


@pytest.mark.parametrize("name", ["ShipMotion", "HeaveCompensation", "TowCable"])
def test_fmpy_validate_and_fmutool_check_find_no_problem(fmu_paths, name):
    assert build.fmpy_problems(fmu_paths[name]) == []
    assert build.fmutool_problems(fmu_paths[name]) == []


@pytest.mark.parametrize("name", ["ShipMotion", "HeaveCompensation", "TowCable"])
def test_every_variable_has_the_contract_unit_and_description(fmu_paths, name):
    root = model_description(fmu_paths[name])
    spec = contract.fmu(name)
    defined = {u.get("name"): u for u in root.find("UnitDefinitions").findall("Unit")}
    scalars = root.find("ModelVariables").findall("ScalarVariable")
    assert [s.get("name") for s in scalars] == [v.name for v in spec.variables]
    assert [int(s.get("valueReference")) for s in scalars] == list(range(len(scalars)))
    for sv, var in zip(scalars, spec.variables):
        assert sv.get("description") == var.description and var.description
        assert sv.get("causality") == var.causality
        if var.type == "Real":
            unit = sv.find("Real").get("unit")
            assert unit == var.unit and unit in defined, var.name
        else:
            assert sv.find(var.type) is not None  # FMI 2.0 has no unit on Integer/Boolean/String
    # unit definitions carry the SI exponents (and the factor of degrees)
    for uname, unit in defined.items():
        exps = contract.units()[uname]
        base = unit.find("BaseUnit")
        got = {} if base is None else {k: float(v) for k, v in base.attrib.items()}
        assert got == {k: float(v) for k, v in exps.items() if v}, uname
    assert root.find("CoSimulation").get("canGetAndSetFMUstate") == "true"
    assert root.find("CoSimulation").get("canSerializeFMUstate") == "true"


def test_contract_connections_cover_every_input_once():
    conns = contract.connections()
    for spec in contract.fmus().values():
        for name in spec.names("input"):
            assert sum(1 for c in conns if c.target == spec.name and c.signal == name) == 1
    assert [c.signal for c in conns if c.delayed] == ["sheave_angle", "tension.winch"]  # the measurements
    # the ship signals are the (3, 6) ship state in row-major order
    from towcable_fmu.fmi.slave import ship_signal_names
    from towcable_fmu.numerics.kinematics import SHIP_DOF_NAMES

    names = ship_signal_names()
    assert names[:6] == tuple(f"ship.{d}" for d in SHIP_DOF_NAMES)
    assert names[6:9] == ("ship.vx", "ship.vy", "ship.vz") and names[15:] == (
        "ship.roll_acc", "ship.pitch_acc", "ship.yaw_acc")


def test_ship_motion_defaults_are_the_default_sea():
    from ship_motion import DEFAULT_SEA
    from ship_motion.fmu import motion_table

    spec = contract.fmu("ShipMotion")
    table, _ = motion_table({v.name: v.start for v in spec.parameters})
    for key, value in table.items():
        assert DEFAULT_SEA[key] == value, key


def test_cable_outputs_use_the_simulation_names():
    """Every TowCable output is a contract signal; the ones the Simulation already gives
    keep their names (the slave copies by name)."""
    spec = contract.fmu("TowCable")
    for name in ("tension.top", "tension.towbody", "towbody.z", "winch.phi", "angle.top"):
        assert name in spec.names("output")


def test_ensure_fmus_reuses_a_fresh_build(fmu_paths, tmp_path):
    folder = fmu_paths["TowCable"].parent
    before = {p: os.stat(p).st_mtime_ns for p in fmu_paths.values()}
    assert build.ensure_fmus(folder) == fmu_paths
    assert {p: os.stat(p).st_mtime_ns for p in fmu_paths.values()} == before
    built = build.ensure_fmus(tmp_path)  # empty folder: builds
    assert all(p.is_file() for p in built.values())


def test_annotation_rejects_variables_that_differ_from_the_contract(fmu_paths):
    with zipfile.ZipFile(fmu_paths["ShipMotion"]) as z:
        xml = z.read("modelDescription.xml")
    with pytest.raises(ValueError, match="differ from the contract"):
        build.annotate_model_description(xml, contract.fmu("TowCable"))


def test_the_installed_package_carries_every_source_of_the_loader_layer():
    """A non-editable install (``pip install .``) builds FMUs from the installed package: every
    file of ``fmu_build/csrc`` (sources and headers) must be package data, or the loader layer
    does not compile and the FMUs lose the FMI state machine."""
    import tomllib
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    patterns = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"][
        "package-data"]["towcable_fmu"]
    package = root / "towcable_fmu"
    sources = [p.relative_to(package) for p in (package / "fmu_build" / "csrc").iterdir() if p.is_file()]
    assert {p.suffix for p in sources} >= {".c", ".h"}
    missing = [str(p) for p in sources if not any(p.match(pattern) for pattern in patterns)]
    assert not missing, f"not package data in pyproject.toml: {missing}"
