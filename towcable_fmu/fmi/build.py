"""Build the three FMUs with pythonfmu, write units and descriptions, validate them.

:func:`build_fmus` is what ``python build_fmu.py`` (repository root), the tests and the
co-simulation master call. For every FMU of the contract (``[fmus]`` in
``towcable_fmu/contract.toml``) it

1. writes a one-line entry script ``<name>_slave.py`` (``from <module> import <Class>``):
   the slave itself stays in the installed packages (all pythonfmu FMUs share the
   calling interpreter; the script names differ so that their modules do not collide);
2. runs ``pythonfmu build`` with ``--handle-state --serialize-state``;
3. rewrites modelDescription.xml: UnitDefinitions of the units used, the unit of every
   Real variable and the description of every variable from the contract, a
   DefaultExperiment, and checks that the variables are exactly those of the contract;
4. installs the loader layer of :mod:`towcable_fmu.fmi.native` (C, compiled here) as the
   Linux binary, so that the FMU also runs in hosts without Python;
5. (``check=True``) runs ``fmpy validate`` and ``fmutool -check`` and raises if either
   reports a problem.

A stamp file (``build_stamp.json``) records a hash of the contract and the slave sources:
:func:`ensure_fmus` rebuilds only when it changed.
"""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import zipfile
from importlib import import_module
from pathlib import Path
from typing import Iterable

from .. import contract
from . import native

#: Communication step written as DefaultExperiment/stepSize [s].
DEFAULT_STEP = 0.01
STAMP = "build_stamp.json"


class FmuCheckError(RuntimeError):
    """A validator reported problems; ``problems`` maps FMU file -> messages."""

    def __init__(self, problems: dict[str, list[str]]) -> None:
        self.problems = problems
        lines = [f"{fmu}: {msg}" for fmu, msgs in problems.items() for msg in msgs]
        super().__init__("FMU validation failed:\n" + "\n".join(lines))


def _sources() -> list[Path]:
    """Files whose content defines the FMUs (for the stamp)."""
    files = [Path(contract.__file__), Path(contract.__file__).with_suffix(".toml"), Path(__file__),
             Path(__file__).with_name("slave.py"), Path(native.__file__), native.LOADER_SOURCE]
    for spec in contract.fmus().values():
        files.append(Path(import_module(spec.slave.split(":")[0]).__file__))
    return files


def source_hash() -> str:
    """Hash of the contract, the slave modules and the pythonfmu version."""
    import pythonfmu

    h = hashlib.sha256(pythonfmu.__version__.encode())
    for f in _sources():
        h.update(f.name.encode())
        h.update(f.read_bytes())
    return h.hexdigest()


#: The FMU's Python entry module. pythonfmu 0.7's C layer executes this file again at every
#: fmi2Instantiate (to find the slave class) and then releases one reference to the
#: module's globals dict that it never owned (``Py_DECREF`` of ``PyModule_GetDict``). A
#: module without functions has few references to its dict, so after a few instantiations
#: the dict is freed while still in use and the host crashes in the garbage collector.
#: The second statement adds one reference per execution to balance that release.
ENTRY_SCRIPT = '''"""{name} FMU entry point, written by build_fmu.py: the slave is {module}.{cls} in the
installed towcable package."""

from {module} import {cls}  # noqa: F401

globals().setdefault("_pythonfmu_dict_refs", []).append(globals())  # see towcable_fmu/fmi/build.py
'''


def _entry_script(folder: Path, spec: contract.FmuSpec) -> Path:
    module, cls = spec.slave.split(":")
    script = folder / f"{spec.name.lower()}_slave.py"
    script.write_text(ENTRY_SCRIPT.format(name=spec.name, module=module, cls=cls), encoding="utf-8")
    return script


def _unit_element(name: str, exponents: dict[str, float]) -> ET.Element:
    unit = ET.Element("Unit", name=name)
    base = {k: str(int(v)) for k, v in exponents.items() if k in contract.BASE_UNITS and v}
    for key in ("factor", "offset"):
        if key in exponents:
            base[key] = repr(float(exponents[key]))
    if base:
        ET.SubElement(unit, "BaseUnit", base)
    return unit


def annotate_model_description(xml: bytes, spec: contract.FmuSpec) -> bytes:
    """modelDescription.xml with units, descriptions and a DefaultExperiment from the contract.

    Raises
    ------
    ValueError
        If the variables (names, order, types, causality) differ from the contract.
    """
    root = ET.fromstring(xml)
    root.set("description", spec.description)
    variables = root.find("ModelVariables")
    scalars = list(variables.findall("ScalarVariable"))
    expected = spec.variables
    if [s.get("name") for s in scalars] != [v.name for v in expected]:
        raise ValueError(f"{spec.name}: modelDescription variables differ from the contract")
    used: list[str] = []
    for sv, var in zip(scalars, expected):
        if sv.get("causality") != var.causality or sv.find(var.type) is None:
            raise ValueError(f"{spec.name}.{var.name}: causality/type differ from the contract")
        sv.set("description", var.description)
        if var.type == "Real":
            sv.find("Real").set("unit", var.unit)
            if var.unit not in used:
                used.append(var.unit)
    for old in root.findall("UnitDefinitions") + root.findall("DefaultExperiment"):
        root.remove(old)
    units = ET.Element("UnitDefinitions")
    table = contract.units()
    for name in used:
        units.append(_unit_element(name, table[name]))
    children = list(root)
    position = next(i for i, child in enumerate(children) if child.tag == "CoSimulation") + 1
    root.insert(position, units)
    children = list(root)
    before = next(i for i, child in enumerate(children) if child.tag in ("VendorAnnotations", "ModelVariables"))
    root.insert(before, ET.Element("DefaultExperiment", startTime="0.0", stepSize=repr(DEFAULT_STEP)))
    ET.indent(root)
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8")


def _rewrite(fmu: Path, spec: contract.FmuSpec, loader: Path | None = None) -> None:
    with zipfile.ZipFile(fmu) as src:
        files = {info.filename: src.read(info.filename) for info in src.infolist()}
    files["modelDescription.xml"] = annotate_model_description(files["modelDescription.xml"], spec)
    if loader is not None:
        identifier = ET.fromstring(files["modelDescription.xml"]).find("CoSimulation").get("modelIdentifier")
        files = native.loader_entries(files, identifier, loader)
    tmp = fmu.with_suffix(".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as dst:
        for name, data in files.items():
            dst.writestr(name, data)
    tmp.replace(fmu)


def build_fmu(spec: contract.FmuSpec, outdir: Path, loader: Path | None = None) -> Path:
    """Build one FMU into ``outdir`` (``<name>.fmu``) and annotate its modelDescription.xml.

    ``loader``: the compiled loader layer (:func:`towcable_fmu.fmi.native.compile_loader`)
    to install as the Linux binary, or None to keep pythonfmu's (Python hosts only).
    """
    from pythonfmu.builder import FmuBuilder

    outdir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="towcable_fmu_") as tmp:
        script = _entry_script(Path(tmp), spec)
        saved_path = list(sys.path)
        try:
            fmu = FmuBuilder.build_FMU(script, dest=outdir, canGetAndSetFMUstate=True, canSerializeFMUstate=True)
        finally:
            sys.path[:] = saved_path
            sys.modules.pop(script.stem, None)
    fmu = Path(fmu)
    _rewrite(fmu, spec, loader)
    return fmu


def build_fmus(outdir: str | Path = "fmus", names: Iterable[str] | None = None, check: bool = False,
               native_loader: bool = True) -> dict[str, Path]:
    """Build the FMUs of the contract into ``outdir``.

    Parameters
    ----------
    outdir
        Target folder (created).
    names
        FMU names to build (default: all three).
    check
        Run :func:`check_fmus` on the result.
    native_loader
        Install the loader layer that lets the FMUs run in hosts without Python
        (:mod:`towcable_fmu.fmi.native`); without a C compiler or a shared libpython it is
        left out with a warning.

    Returns
    -------
    dict
        FMU name -> path of the ``.fmu`` file.
    """
    outdir = Path(outdir)
    specs = contract.fmus()
    names = list(specs) if names is None else list(names)
    with tempfile.TemporaryDirectory(prefix="towcable_loader_") as tmp:
        loader = native.loader_or_warning(tmp) if native_loader else None
        paths = {name: build_fmu(specs[name], outdir, loader) for name in names}
    if set(names) == set(specs):
        (outdir / STAMP).write_text(json.dumps({"hash": source_hash(), "fmus": sorted(names)}), encoding="utf-8")
    if check:
        check_fmus(paths.values())
    return paths


def ensure_fmus(outdir: str | Path = "fmus") -> dict[str, Path]:
    """The three FMUs in ``outdir``, rebuilt if missing or built from other sources."""
    outdir = Path(outdir)
    paths = {name: outdir / f"{name}.fmu" for name in contract.fmus()}
    try:
        stamp = json.loads((outdir / STAMP).read_text(encoding="utf-8"))
        fresh = stamp.get("hash") == source_hash() and all(p.is_file() for p in paths.values())
    except (OSError, ValueError):
        fresh = False
    return paths if fresh else build_fmus(outdir)


def fmpy_problems(fmu: str | Path) -> list[str]:
    """Problems ``fmpy validate`` reports (empty: none)."""
    from fmpy.validation import validate_fmu

    return [str(p) for p in validate_fmu(str(fmu))]


def fmutool_problems(fmu: str | Path) -> list[str]:
    """Warnings and errors of ``fmutool -input FMU -check`` (empty: none)."""
    cmd = [sys.executable, "-c", "import sys; from fmu_manipulation_toolbox.cli.fmutool import fmutool; "
                                 "sys.exit(fmutool())", "-input", str(fmu), "-check"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    text = proc.stdout + proc.stderr
    problems = [line.strip() for line in text.splitlines()
                if any(tag in line for tag in ("WARNING", "ERROR", "Error", "Traceback"))]
    if proc.returncode != 0 and not problems:
        problems.append(f"fmutool exited with status {proc.returncode}: {text.strip()[-500:]}")
    return problems


def check_fmus(fmus: Iterable[str | Path]) -> dict[str, list[str]]:
    """Run both validators on each FMU; raise :class:`FmuCheckError` listing any problem.

    Returns
    -------
    dict
        FMU file -> [] for each FMU (all clean).
    """
    problems = {}
    for fmu in fmus:
        found = [f"fmpy validate: {p}" for p in fmpy_problems(fmu)]
        found += [f"fmutool -check: {p}" for p in fmutool_problems(fmu)]
        problems[str(fmu)] = found
    if any(problems.values()):
        raise FmuCheckError({k: v for k, v in problems.items() if v})
    return problems


def main(argv: list[str] | None = None) -> int:
    """Command line of ``build_fmu.py``."""
    import argparse

    parser = argparse.ArgumentParser(prog="build_fmu.py", description="Build the ShipMotion, HeaveCompensation "
                                     "and TowCable FMUs (FMI 2.0 Co-Simulation, pythonfmu) from the contract.")
    parser.add_argument("-o", "--output", default="fmus", help="output folder (default: fmus/)")
    parser.add_argument("--check", action="store_true", help="validate with fmpy validate and fmutool -check")
    parser.add_argument("--ssp", action="store_true", help="also write the SSP file of the system (TowedCableSystem.ssp)")
    parser.add_argument("--no-native", action="store_true", help="keep pythonfmu's binary (the FMUs then load "
                        "only in Python hosts) instead of compiling the loader layer with the C compiler")
    parser.add_argument("--crosscheck", metavar="DIR", help="also write the FMI Cross-Check artefacts (FMU, "
                        "_ref.csv, _in.csv, _ref.opt) under DIR/fmus/2.0/cs/linux64/towcable/<version>/")
    parser.add_argument("names", nargs="*", help="FMUs to build (default: all)")
    args = parser.parse_args(argv)
    paths = build_fmus(args.output, args.names or None, native_loader=not args.no_native)
    for name, path in paths.items():
        print(f"built {path}")
    if args.ssp:
        from .ssp import write_ssp

        print(f"wrote {write_ssp(Path(args.output) / 'TowedCableSystem.ssp', paths)}")
    if args.crosscheck:
        from .crosscheck import write_crosscheck

        if set(paths) != set(contract.fmus()):
            parser.error("--crosscheck needs all three FMUs (give no NAME)")

        for folder in write_crosscheck(paths, args.crosscheck).values():
            print(f"wrote {folder}")
    if args.check:
        try:
            check_fmus(paths.values())
        except FmuCheckError as exc:
            print(exc, file=sys.stderr)
            return 1
        print("fmpy validate and fmutool -check: no problems")
    return 0
