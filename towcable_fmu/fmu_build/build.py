"""Build the three FMUs, each carrying the code it runs, and validate them.

:func:`build_fmus` is what ``python build_fmu.py`` (repository root), the tests and the
co-simulation master call. For every FMU of the contract (``[fmus]`` in
``towcable_fmu/common/contract.toml``) it writes one zip archive, byte for byte the same for
the same sources (sorted entries, fixed dates):

* ``modelDescription.xml``: pythonfmu's description of the slave's variables, with
  units, descriptions, ranges and a DefaultExperiment from the contract, outputs
  ``initial="calculated"`` and listed in ``ModelStructure/InitialUnknowns``, and a GUID
  derived from the archive's content (:func:`annotate_model_description`);
* ``resources/``: the bundle of our packages under a private name
  (:mod:`towcable_fmu.fmu_build.bundle`), its activation module
  (:mod:`towcable_fmu.jit.machine_cache`), a one-statement entry script per FMU, pythonfmu's
  Python package (as pythonfmu's own builder embeds it), ``requirements.txt`` (the
  third-party packages, pythonfmu's convention, so ``pythonfmu deploy`` installs them),
  for a standalone FMU a Python runtime (:mod:`towcable_fmu.fmu_build.runtime`) and, with
  ``kernels=True`` (``build_fmu.py``'s default), TowCable's numerical kernels precompiled
  (:mod:`towcable_fmu.fmu_build.kernels`);
* ``binaries/linux64/<model>.so``: the loader layer (:mod:`towcable_fmu.fmu_build.native`,
  compiled here) in front of pythonfmu's library; ``binaries/win64/<model>.dll``:
  pythonfmu's (not in standalone FMUs: it needs an installed Python).

No path of the building machine is written into an FMU. ``check=True`` runs ``fmpy
validate`` and ``fmutool -check`` and raises if either reports a problem. A stamp file
(``build_stamp.json``) records a hash of the sources: :func:`ensure_fmus` rebuilds only
when it changed.
"""

from __future__ import annotations

import hashlib
import json
import re
import subprocess
import sys
import tempfile
import uuid
import xml.etree.ElementTree as ET
import zipfile
from importlib import import_module
from pathlib import Path
from typing import Iterable

from ..common import contract
from ..jit import machine_cache
from . import bundle as code_bundle
from . import native

#: Communication step written as DefaultExperiment/stepSize [s].
DEFAULT_STEP = 0.01
STAMP = "build_stamp.json"
#: Third-party packages the FMUs import at run time, with the lowest versions they need
#: (those of pyproject.toml).
REQUIREMENTS = {"numpy": "1.26", "scipy": "1.11", "numba": "0.59"}
#: The FMU that carries precompiled kernels (the others compile at most a small kernel
#: of the heave compensation's rigorous algorithms, which that FMU installs for them).
KERNEL_FMU = "TowCable"
#: The copy of modelDescription.xml the loader layer reads (csrc/model_table.c).
DESCRIPTION_COPY = "resources/modelDescription.xml"
#: The GUID written before the real one is known.
_GUID_PLACEHOLDER = "00000000-0000-0000-0000-000000000000"
#: Date of every archive entry (reproducible archives).
_ZIP_DATE = (2020, 1, 1, 0, 0, 0)


class FmuCheckError(RuntimeError):
    """A validator reported problems; ``problems`` maps FMU file -> messages."""

    def __init__(self, problems: dict[str, list[str]]) -> None:
        self.problems = problems
        lines = [f"{fmu}: {msg}" for fmu, msgs in problems.items() for msg in msgs]
        super().__init__("FMU validation failed:\n" + "\n".join(lines))


def source_hash(standalone: bool = False) -> str:
    """Hash of everything an FMU is made of: our packages, the loader sources, pythonfmu's
    version, the Python version and the kind of build."""
    import pythonfmu

    h = hashlib.sha256(f"{pythonfmu.__version__} {sys.version} {standalone}".encode())
    h.update(machine_cache.code_digest(code_bundle.package_files()).encode())
    for path in sorted(native.LOADER_SOURCE.parent.iterdir()):
        h.update(path.read_bytes())
    return h.hexdigest()


# ------------------------------------------------------------------ modelDescription.xml
def _unit_element(name: str, exponents: dict[str, float]) -> ET.Element:
    unit = ET.Element("Unit", name=name)
    base = {k: str(int(v)) for k, v in exponents.items() if k in contract.BASE_UNITS and v}
    for key in ("factor", "offset"):
        if key in exponents:
            base[key] = repr(float(exponents[key]))
    if base:
        ET.SubElement(unit, "BaseUnit", base)
    return unit


def _number_text(kind: str, value: float) -> str:
    return repr(float(value)) if kind == "Real" else str(int(value))


def annotate_model_description(xml: bytes, spec: contract.FmuSpec) -> bytes:
    """modelDescription.xml with the contract's metadata (see the module docstring).

    Parameters take their unit, description and range (``min``/``max`` of the contract);
    outputs are ``initial="calculated"`` (computed at initialisation) and listed as
    InitialUnknowns; ``generationDateAndTime`` is left out (reproducible archives).

    Raises
    ------
    ValueError
        If the variables (names, order, types, causality) differ from the contract.
    """
    root = ET.fromstring(xml)
    root.set("description", spec.description)
    root.attrib.pop("generationDateAndTime", None)
    variables = root.find("ModelVariables")
    scalars = list(variables.findall("ScalarVariable"))
    expected = spec.variables
    if [s.get("name") for s in scalars] != [v.name for v in expected]:
        raise ValueError(f"{spec.name}: modelDescription variables differ from the contract")
    used: list[str] = []
    for sv, var in zip(scalars, expected):
        element = sv.find(var.type)
        if sv.get("causality") != var.causality or element is None:
            raise ValueError(f"{spec.name}.{var.name}: causality/type differ from the contract")
        sv.set("description", var.description)
        if var.type == "Real":
            element.set("unit", var.unit)
            if var.unit not in used:
                used.append(var.unit)
        for bound in ("min", "max"):
            value = getattr(var, bound)
            if value is not None:
                element.set(bound, _number_text(var.type, value))
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
    structure = root.find("ModelStructure")
    for old in structure.findall("InitialUnknowns"):
        structure.remove(old)
    outputs = [str(i + 1) for i, var in enumerate(expected) if var.causality == "output"]
    if outputs:
        initial = ET.SubElement(structure, "InitialUnknowns")
        for index in outputs:
            ET.SubElement(initial, "Unknown", index=index)
    ET.indent(root)
    return b'<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="utf-8")


def model_description(spec: contract.FmuSpec, standalone: bool) -> bytes:
    """The annotated modelDescription.xml of one FMU, GUID still the placeholder."""
    module, cls = spec.slave.split(":")
    slave = getattr(import_module(module), cls)(instance_name="build", resources=None)
    slave.guid = _GUID_PLACEHOLDER
    options = {"needsExecutionTool": not standalone, "canHandleVariableCommunicationStepSize": True,
               "canInterpolateInputs": False, "canBeInstantiatedOnlyOncePerProcess": False,
               "canGetAndSetFMUstate": True, "canSerializeFMUstate": True}
    return annotate_model_description(ET.tostring(slave.to_xml(options), encoding="utf-8"), spec)


# ------------------------------------------------------------------ resources and binaries
def entry_script(spec: contract.FmuSpec, package: str) -> str:
    """The FMU's Python entry module.

    pythonfmu 0.7's C layer executes this file again at every fmi2Instantiate (to find the
    slave class) and then releases one reference to the module's globals dict that it
    never owned (``Py_DECREF`` of ``PyModule_GetDict``). A module without functions has
    few references to its dict, so after a few instantiations the dict is freed while
    still in use and the host crashes in the garbage collector. The last statement adds
    one reference per execution to balance that release. It also inserts the resources
    folder into ``sys.path`` at every instantiation: the statement before drops the
    repeats (the first occurrence, which decides an import, stays).
    """
    module, cls = spec.slave.split(":")
    return (f'"""{spec.name} FMU entry point, written by build_fmu.py: the slave {module}.{cls} of the\n'
            f'code this FMU carries (package {package}, see towcable_fmu/fmu_build/bundle.py)."""\n\n'
            "import sys\n\n"
            f"from {package}_activate import activate\n\n"
            f'{cls} = activate("{package}", "{module}", "{cls}", __file__)\n\n'
            "sys.path[:] = dict.fromkeys(sys.path)  # see towcable_fmu/fmu_build/build.py\n"
            'globals().setdefault("_pythonfmu_dict_refs", []).append(globals())  # see towcable_fmu/fmu_build/build.py\n')


def requirements_text() -> str:
    """``resources/requirements.txt``: the packages the FMUs import, with the versions
    they need and (as a comment) the versions they were built and tested with."""
    from importlib.metadata import version

    lines = ["# Python packages the towcable FMUs import (pythonfmu deploy installs them);",
             "# built with " + ", ".join(f"{name} {version(name)}" for name in REQUIREMENTS)
             + f" on Python {sys.version_info.major}.{sys.version_info.minor}"]
    lines += [f"{name}>={low}" for name, low in REQUIREMENTS.items()]
    return "\n".join(lines) + "\n"


def _pythonfmu_files() -> dict[str, bytes]:
    """pythonfmu's Python package (its own builder embeds it in every FMU the same way)."""
    import pythonfmu

    folder = Path(pythonfmu.__file__).parent
    return {f"resources/pythonfmu/{p.name}": p.read_bytes() for p in sorted(folder.glob("*.py"))}


def _pythonfmu_binaries(model_identifier: str, standalone: bool) -> dict[str, bytes]:
    import pythonfmu

    folder = Path(pythonfmu.__file__).parent / "resources" / "binaries"
    out = {f"binaries/linux64/{model_identifier}.so": (folder / "linux64" / "libpythonfmu-export.so").read_bytes()}
    if not standalone:
        out[f"binaries/win64/{model_identifier}.dll"] = (folder / "win64" / "pythonfmu-export.dll").read_bytes()
    return out


def fmu_files(spec: contract.FmuSpec, package: str, carried: dict[str, bytes], loader: Path | None,
              runtime: dict[str, bytes] | None, kernels: dict[str, bytes] | None = None) -> dict[str, bytes]:
    """Every entry of one FMU's archive (name -> content), GUID set.

    Parameters
    ----------
    spec
        The FMU.
    package, carried
        The bundle's package name and its files (:func:`towcable_fmu.fmu_build.bundle.bundle`,
        paths relative to ``resources/``).
    loader
        The compiled loader layer, or None to keep pythonfmu's Linux binary.
    runtime
        A standalone FMU's Python runtime (paths relative to ``resources/python/``), or None.
    kernels
        Precompiled kernels (:func:`towcable_fmu.fmu_build.kernels.carried_kernels`), or None.
        They are a cache of the carried code, not byte-reproducible: the GUID leaves them out.
    """
    entry = f"{spec.name.lower()}_entry_{package.removeprefix('towcable_')}"
    files = {"modelDescription.xml": model_description(spec, runtime is not None),
             f"resources/{entry}.py": entry_script(spec, package).encode(),
             "resources/slavemodule.txt": entry.encode(),
             "resources/requirements.txt": requirements_text().encode(),
             f"resources/{package}_activate.py": Path(machine_cache.__file__).read_bytes()}
    files.update({f"resources/{name}": data for name, data in carried.items()})
    files.update(_pythonfmu_files())
    files.update(_pythonfmu_binaries(spec.name, runtime is not None))
    if loader is not None:
        files = native.loader_entries(files, spec.name, loader)
    if runtime is not None:
        files.update({f"resources/python/{name}": data for name, data in runtime.items()})
    # the loader layer reads the variables and the GUID from resources/ (hosts need not
    # extract the archive's root: fmpy's simulate_fmu does not)
    files[DESCRIPTION_COPY] = files["modelDescription.xml"]
    h = hashlib.sha256()
    for name in sorted(files):  # before the kernels: the GUID is the same with and without them
        h.update(name.encode() + b"\0" + hashlib.sha256(files[name]).digest())
    guid = str(uuid.UUID(bytes=h.digest()[:16], version=5))
    for name in ("modelDescription.xml", DESCRIPTION_COPY):
        files[name] = files[name].replace(_GUID_PLACEHOLDER.encode(), guid.encode())
    files.update(kernels or {})
    return files


def _kernel_entries(name: str, compiled: dict[str, bytes] | None, kernels: bool) -> dict[str, bytes] | None:
    """The kernel entries of FMU ``name``: every FMU of a build with kernels names their CPU
    target (``resources/kernels/TARGET``, so that whichever is instantiated first chooses
    it), :data:`KERNEL_FMU` also carries them."""
    if not kernels:
        return None
    named = {"resources/kernels/TARGET": (machine_cache.CARRIED_TARGET + "\n").encode()}
    return named | (compiled or {}) if name == KERNEL_FMU else named


def write_archive(path: Path, files: dict[str, bytes]) -> Path:
    """Write a zip archive with the entries in name order and fixed dates (atomically)."""
    tmp = path.with_suffix(path.suffix + ".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name in sorted(files):
            info = zipfile.ZipInfo(name, date_time=_ZIP_DATE)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = (0o755 if name.endswith((".so", ".dll")) else 0o644) << 16
            z.writestr(info, files[name])
    tmp.replace(path)
    return path


def carried_package(fmu: str | Path) -> str:
    """The name of the package an FMU carries (``towcable_<digest>``, from its entry script)."""
    with zipfile.ZipFile(fmu) as z:
        entry = z.read("resources/slavemodule.txt").decode()
        script = z.read(f"resources/{entry}.py").decode()
    return re.search(r'activate\("(towcable_[0-9a-f]+)"', script).group(1)


# ------------------------------------------------------------------ building
def build_fmus(outdir: str | Path = "fmus", names: Iterable[str] | None = None, check: bool = False,
               native_loader: bool = True, standalone: bool = False, kernels: bool = False) -> dict[str, Path]:
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
        Install the loader layer (:mod:`towcable_fmu.fmu_build.native`): the FMUs then also run
        in hosts without Python, report errors whatever the host's logging setting and
        return ``fmi2Error`` for them. Without a C compiler it is left out with a warning.
    standalone
        Also carry a Python runtime (:mod:`towcable_fmu.fmu_build.runtime`): the FMUs then run
        on a Linux x86-64 machine without any Python installed (needs the loader layer).
    kernels
        The FMUs that compile kernels (TowCable) carry them precompiled
        (:mod:`towcable_fmu.fmu_build.kernels`): their first use on another machine compiles
        nothing. The first build of a version of the code compiles them (minutes).

    Returns
    -------
    dict
        FMU name -> path of the ``.fmu`` file.
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    specs = contract.fmus()
    names = list(specs) if names is None else list(names)
    package, carried = code_bundle.bundle()
    runtime = None
    if standalone:
        from .runtime import runtime_files

        runtime = runtime_files()
    compiled = None
    if kernels and KERNEL_FMU in names:
        from .kernels import carried_kernels

        resources = dict(carried, **{f"{package}_activate.py": Path(machine_cache.__file__).read_bytes(),
                                     "requirements.txt": requirements_text().encode()})
        compiled = carried_kernels(package, resources)
    with tempfile.TemporaryDirectory(prefix="towcable_loader_") as tmp:
        loader = native.loader_or_warning(tmp) if native_loader else None
        if standalone and loader is None:
            raise native.NativeBuildError("a standalone FMU needs the loader layer (a C compiler)")
        paths = {name: write_archive(outdir / f"{name}.fmu", fmu_files(specs[name], package, carried, loader, runtime,
                                                                       _kernel_entries(name, compiled, kernels)))
                 for name in names}
    if set(names) == set(specs):
        (outdir / STAMP).write_text(json.dumps({"hash": source_hash(standalone), "fmus": sorted(names)}),
                                    encoding="utf-8")
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


# ------------------------------------------------------------------ validation
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
