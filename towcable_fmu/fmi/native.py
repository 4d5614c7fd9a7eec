"""Make the FMUs self-sufficient in hosts without Python (issue 9).

pythonfmu 0.7 puts a library into ``binaries/linux64/<model>.so`` that leaves the Python
symbols unresolved: it only loads in a process that already runs Python (fmpy,
libcosimpy). :func:`install_loader` replaces that binary by a thin C layer
(``towcable_fmu/fmi/csrc/fmu_loader.c``, compiled by :func:`compile_loader` with the
machine's C compiler), keeps pythonfmu's library beside it as
``binaries/linux64/libpythonfmu-export.so`` and records the Python environment of the
build in ``resources/python_env.json`` (:func:`python_environment`). At the first
``fmi2Instantiate`` the layer uses the Python already in the process if there is one, and
otherwise loads and starts the recorded one; then it forwards every FMI call to
pythonfmu's library.

Linux only: the ``win64`` binary of pythonfmu is left as it is.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import warnings
from pathlib import Path

#: C source of the loader layer.
LOADER_SOURCE = Path(__file__).with_name("csrc") / "fmu_loader.c"
#: Name of pythonfmu's library inside ``binaries/linux64/``.
REAL_LIBRARY = "libpythonfmu-export.so"
#: The environment record inside the FMU.
ENV_RESOURCE = "resources/python_env.json"


class NativeBuildError(RuntimeError):
    """The loader layer cannot be built on this machine (no compiler, no shared libpython)."""


def python_library() -> Path:
    """The shared libpython of the running interpreter.

    Raises
    ------
    NativeBuildError
        If this Python was built without a shared library (``--enable-shared``).
    """
    libdir = Path(sysconfig.get_config_var("LIBDIR") or "")
    for name in (sysconfig.get_config_var("INSTSONAME"), sysconfig.get_config_var("LDLIBRARY")):
        if name and ".so" in name and (libdir / name).is_file():
            return (libdir / name).resolve()
    raise NativeBuildError(f"{sys.executable} has no shared libpython (Py_ENABLE_SHARED = "
                           f"{sysconfig.get_config_var('Py_ENABLE_SHARED')}): the FMUs can only run in Python hosts")


def python_environment() -> dict:
    """The record written to ``resources/python_env.json``.

    Returns
    -------
    dict
        ``executable`` (``sys.executable``: a venv's interpreter, so that the FMU's Python
        finds the venv as this one does), ``library`` (the shared libpython), ``version``,
        ``prefix``, ``base_prefix`` (for people reading the file) and ``sys_path`` (the
        existing entries of ``sys.path``, which become the embedded interpreter's module
        search path; ``.pth`` files in them are processed again at start-up).
    """
    return {
        "executable": sys.executable,
        "library": str(python_library()),
        "version": sys.version.split()[0],
        "prefix": sys.prefix,
        "base_prefix": sys.base_prefix,
        "sys_path": [os.path.abspath(p) for p in sys.path if p and os.path.exists(p)],
    }


def c_compiler() -> str | None:
    """The C compiler: ``$CC`` if set, else ``cc`` or ``gcc`` on the PATH; None if none."""
    if os.environ.get("CC"):
        return os.environ["CC"]
    return shutil.which("cc") or shutil.which("gcc")


def fmi_headers() -> Path:
    """The folder with the FMI 2.0 headers (``fmi2Functions.h``, shipped with fmpy)."""
    import fmpy

    return Path(fmpy.__file__).parent / "c-code"


def compile_loader(outdir: str | Path) -> Path:
    """Compile the loader layer into ``outdir/fmu_loader.so``.

    Raises
    ------
    NativeBuildError
        If there is no C compiler or the compilation fails.
    """
    cc = c_compiler()
    if cc is None:
        raise NativeBuildError("no C compiler found (cc, gcc or $CC)")
    target = Path(outdir) / "fmu_loader.so"
    cmd = [cc, "-shared", "-fPIC", "-O2", "-g", "-std=gnu11", "-Wall", "-Wextra", "-Wno-format-truncation",
           "-fvisibility=hidden", "-Wl,-Bsymbolic", f"-I{sysconfig.get_paths()['include']}",
           f"-I{fmi_headers()}", str(LOADER_SOURCE), "-o", str(target), "-ldl", "-lpthread"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise NativeBuildError(f"compiling {LOADER_SOURCE.name} failed:\n{' '.join(cmd)}\n{proc.stderr}")
    return target


def loader_or_warning(outdir: str | Path) -> Path | None:
    """:func:`compile_loader`, or None with a warning that the FMUs will need a Python host."""
    try:
        python_library()
        return compile_loader(outdir)
    except NativeBuildError as exc:
        warnings.warn(f"{exc}; building FMUs that load only in Python hosts (fmpy, libcosimpy)", stacklevel=2)
        return None


def loader_entries(files: dict[str, bytes], model_identifier: str, loader: Path) -> dict[str, bytes]:
    """The FMU's files (archive name -> content) with the loader layer installed.

    ``binaries/linux64/<model_identifier>.so`` (pythonfmu's library) moves to
    ``binaries/linux64/libpythonfmu-export.so``, the loader takes its place and
    ``resources/python_env.json`` records this Python.
    """
    binary = f"binaries/linux64/{model_identifier}.so"
    out = dict(files)
    out[f"binaries/linux64/{REAL_LIBRARY}"] = out.pop(binary)
    out[binary] = Path(loader).read_bytes()
    out[ENV_RESOURCE] = (json.dumps(python_environment(), indent=2, ensure_ascii=False) + "\n").encode()
    return out
