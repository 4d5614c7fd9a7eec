"""The Python runtime a standalone FMU carries (``build_fmu.py --standalone``).

A host without Python (a C or C++ FMI tool on a machine with no Python installed) needs
the interpreter, its standard library and the third-party packages the model imports.
:func:`runtime_files` collects them from the Python that builds the FMU, into the
layout the loader layer (``csrc/fmu_loader.c``) starts from ``resources/python/``::

    runtime.txt                    the shared libpython and the library folder (relative)
    lib/libpython3.X.so.1.0        (it and llvmlite's library stripped of symbol tables
                                   when ``strip`` is available)
    lib/python3.X/                 the standard library, without its tests, IDLE, tkinter,
                                   ensurepip, lib2to3, the static library and caches
    lib/python3.X/lib-dynload/     its extension modules (without _tkinter and the tests)
    lib/python3.X/site-packages/   the distributions the model imports (traced: see
                                   :func:`imported_distributions`), without tests

Byte code: the modules the model imports are shipped precompiled (``unchecked-hash``
.pyc files, valid whatever the files' dates after unzipping), the rest as sources.

What dominates the size is llvmlite's LLVM library (numba's compiler, about 160 MB
unpacked, 55 MB compressed), then numpy's and scipy's OpenBLAS builds. The runtime needs
the glibc of the building machine or newer (see :func:`glibc_needed`).
"""

from __future__ import annotations

import json
import os
import py_compile
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

#: Standard-library folders not carried.
_STDLIB_SKIP = {"test", "idlelib", "tkinter", "turtledemo", "ensurepip", "lib2to3", "pydoc_data",
                "site-packages", "dist-packages", "__pycache__"}
#: Folders not carried anywhere.
_ANYWHERE_SKIP = {"__pycache__", "tests", "test"}
#: Extension modules of the standard library not carried.
_DYNLOAD_SKIP = re.compile(r"^(_tkinter|_test|_xxtest|xx).*")

#: Shared libraries carried without their symbol tables. Not the wheels' vendored
#: libraries (numpy.libs, scipy.libs): auditwheel's patchelf edits do not survive strip.
_STRIPPED = {"libllvmlite.so"}
#: Imports the model makes, run in a fresh interpreter to trace what it loads.
_TRACE = """
import importlib, json, pkgutil, sys
import towcable_fmu.fmu, ship_motion.fmu, controllers.fmu
import towcable_fmu, ship_motion, controllers
skip = ("towcable_fmu.cli", "towcable_fmu.common.plots", "towcable_fmu.animation", "towcable_fmu.sweep",
        "towcable_fmu.docs_gen", "towcable_fmu.analysis", "towcable_fmu.cosim")
for pkg in (towcable_fmu, ship_motion, controllers):
    for info in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + "."):
        if not info.name.startswith(skip):
            importlib.import_module(info.name)
print(json.dumps(sorted(getattr(m, "__file__", None) or "" for m in list(sys.modules.values()))))
"""


def imported_files() -> list[Path]:
    """Files of every module the FMUs' code imports (traced in a fresh interpreter)."""
    proc = subprocess.run([sys.executable, "-c", _TRACE], capture_output=True, text=True, check=True,
                          env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"})
    return [Path(f) for f in json.loads(proc.stdout.strip().splitlines()[-1]) if f]


def site_packages() -> Path:
    """The site-packages folder of the building Python (a venv's, if one is active)."""
    return Path(sysconfig.get_paths()["purelib"])


def imported_distributions(files: list[Path]) -> list[str]:
    """Top-level names in site-packages that the traced imports load (our own packages and
    pythonfmu, which the FMU carries anyway, left out)."""
    site = site_packages()
    tops = set()
    for f in files:
        try:
            tops.add(f.resolve().relative_to(site.resolve()).parts[0])
        except ValueError:
            continue
    ours = {"towcable_fmu", "ship_motion", "controllers", "pythonfmu"}
    return sorted(t.removesuffix(".py") for t in tops if not t.endswith((".pth", ".dist-info")) and t not in ours
                  and not t.startswith("__editable__"))


def _carried(rel: Path) -> bool:
    return not _ANYWHERE_SKIP.intersection(rel.parts) and rel.suffix not in (".pyc", ".pyo")


def _tree(folder: Path, prefix: str, skip_top: set[str] = frozenset()) -> dict[str, Path]:
    """Files below ``folder`` (archive name under ``prefix`` -> path)."""
    out = {}
    for path in sorted(folder.rglob("*")):
        rel = path.relative_to(folder)
        if path.is_file() and rel.parts[0] not in skip_top and _carried(rel):
            out[f"{prefix}/{rel.as_posix()}"] = path
    return out


def _strip(path: Path, tmp: Path) -> bytes:
    """The shared library's bytes without symbol tables (unchanged if ``strip`` is missing)."""
    tool = shutil.which("strip")
    if tool is None:
        return path.read_bytes()
    out = tmp / path.name
    subprocess.run([tool, "--strip-unneeded", str(path), "-o", str(out)], check=True)
    return out.read_bytes()


def python_library() -> Path:
    """The shared libpython of the building interpreter.

    Raises
    ------
    RuntimeError
        If this Python has no shared library (built without ``--enable-shared``).
    """
    libdir = Path(sysconfig.get_config_var("LIBDIR") or "")
    for name in (sysconfig.get_config_var("INSTSONAME"), sysconfig.get_config_var("LDLIBRARY")):
        if name and ".so" in name and (libdir / name).is_file():
            return (libdir / name).resolve()
    raise RuntimeError(f"{sys.executable} has no shared libpython: a standalone FMU needs a Python built "
                       "with --enable-shared")


def runtime_files() -> dict[str, bytes]:
    """The runtime's files (path relative to ``resources/python/`` -> content)."""
    version = f"python{sys.version_info.major}.{sys.version_info.minor}"
    stdlib = Path(sysconfig.get_paths()["stdlib"])
    platstdlib = Path(sysconfig.get_paths()["platstdlib"])
    lib = f"lib/{version}"
    sources = _tree(stdlib, lib, _STDLIB_SKIP | {p.name for p in stdlib.glob("config-*")})
    dynload = Path(sysconfig.get_config_var("DESTSHARED") or platstdlib / "lib-dynload")
    sources.update({f"{lib}/lib-dynload/{p.name}": p for p in sorted(dynload.glob("*.so"))
                    if not _DYNLOAD_SKIP.match(p.name)})
    traced = imported_files()
    site = site_packages()
    for top in imported_distributions(traced):
        for name in [top, f"{top}.libs"] + [p.name for p in site.glob(f"{top}-*.dist-info")]:
            path = site / name
            if path.is_dir():
                sources.update(_tree(path, f"{lib}/site-packages/{name}"))
            elif (site / f"{name}.py").is_file():
                sources[f"{lib}/site-packages/{name}.py"] = site / f"{name}.py"
    library = python_library()
    with tempfile.TemporaryDirectory(prefix="towcable_runtime_") as tmp:
        files = {f"lib/{library.name}": _strip(library, Path(tmp))}
        files.update({name: _strip(path, Path(tmp)) if path.name in _STRIPPED else path.read_bytes()
                      for name, path in sources.items()})
        files.update(_byte_code(sources, {f.resolve() for f in traced}, Path(tmp)))
    files["runtime.txt"] = f"lib/{library.name}\n{lib}\n".encode()
    return files


def _byte_code(sources: dict[str, Path], traced: set[Path], tmp: Path) -> dict[str, bytes]:
    """``__pycache__`` entries (unchecked-hash .pyc) for the carried modules that are imported."""
    tag = sys.implementation.cache_tag
    out = {}
    for name, path in sources.items():
        if path.suffix != ".py" or path.resolve() not in traced:
            continue
        folder, stem = name.rsplit("/", 1)
        target = tmp / "pyc"
        py_compile.compile(str(path), cfile=str(target), dfile=name, doraise=True,
                           invalidation_mode=py_compile.PycInvalidationMode.UNCHECKED_HASH)
        out[f"{folder}/__pycache__/{stem[:-3]}.{tag}.pyc"] = target.read_bytes()
    return out


def glibc_needed(files: dict[str, bytes]) -> str:
    """The newest GLIBC symbol version the runtime's shared libraries ask for (e.g. ``2.28``).

    Read from the ``GLIBC_x.y`` version strings of every ``.so`` (``objdump``-free: the
    strings are in each library's version-needs section).
    """
    found = set()
    for name, data in files.items():
        if ".so" in name:
            found.update(re.findall(rb"GLIBC_(\d+\.\d+(?:\.\d+)?)", data))
    versions = sorted({v.decode() for v in found}, key=lambda v: tuple(int(x) for x in v.split(".")))
    return versions[-1] if versions else "unknown"
