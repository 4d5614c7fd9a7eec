"""The precompiled kernels an FMU carries, so that its first use on a new machine compiles
nothing.

numba keys a cached kernel by its CPU target, so the kernels are compiled for a
portable one, :data:`towcable_fmu.jit.machine_cache.CARRIED_TARGET` (x86-64-v3), by a separate
Python (``NUMBA_CPU_NAME`` set) that imports the FMU's own bundle the way an FMU does and
runs every FMU on every built-in scene (:mod:`towcable_fmu.fmu_build.warmup`). The result stays
in the machine cache (below), so the next build of the same code reuses it; the FMU carries it as ``resources/kernels/<target>/towcable-<digest>/``,
and :func:`towcable_fmu.jit.machine_cache.use_carried_kernels` installs it where it runs.

The cache files name the source files they were compiled from (in error messages and
numba's type annotations): the bundle's folder in that cache, the compiling Python's
packages (numba's and numpy's sources) and its standard library. In the FMU's copy each of
those folders is replaced by a relative path of the same length, ``./`` + slashes +
``resources`` (or ``site-packages``, ``stdlib``): the same length keeps numba's pickles and
the string constants of the machine code valid, and the FMU carries no path of the
building machine.

The machine cache is shared by every Python of the user (each venv): the kernels are kept
per bundle and per versions of Python, numba, llvmlite and numpy
(``<cache root>/carried/<target>/py-<versions digest>/<bundle>/``), and the record of a
finished compilation names the compiling Python's folders, so a build by another Python
with the same versions reuses the kernels and rewrites that Python's folders.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from ..jit import machine_cache

#: Script of the compiling Python: argv = resources folder, bundle name.
_COMPILE = """
import json, sys
from importlib import import_module
sys.path.insert(0, sys.argv[1])
import_module(sys.argv[2] + "_activate").import_bundle(sys.argv[2])
warmup = import_module(sys.argv[2] + ".towcable_fmu.fmu_build.warmup")
warmup.compile_kernels(lambda line: print(line, file=sys.stderr, flush=True))
kernel_cache = import_module(sys.argv[2] + ".towcable_fmu.jit.kernel_cache")
print(json.dumps({"folder": kernel_cache.kernel_folder().name}))
"""


class KernelCompileError(RuntimeError):
    """The compiling Python failed or compiled nothing (its messages went to stderr)."""


def carried_root() -> Path:
    """Machine-cache folder of the kernels compiled for FMUs to carry."""
    return (machine_cache.cache_root() / "carried" / machine_cache.CARRIED_TARGET).absolute()


def _compile(package: str, resources: dict[str, bytes], root: Path) -> str:
    """Compile the kernels of bundle ``package`` (the FMU's resources, name -> content)
    into ``root``; return the name of their folder under ``root/kernels``."""
    env = dict(os.environ, TOWCABLE_CACHE_DIR=str(root), NUMBA_CPU_NAME=machine_cache.CARRIED_TARGET,
               NUMBA_CPU_FEATURES="")
    with tempfile.TemporaryDirectory(prefix="towcable_kernels_") as tmp:
        for name, data in resources.items():
            path = Path(tmp, name)
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        print(f"compiling the numerical kernels for {machine_cache.CARRIED_TARGET} to carry in the FMU (first "
              f"build of this code on this machine; kept in {root})...", file=sys.stderr, flush=True)
        proc = subprocess.run([sys.executable, "-c", _COMPILE, tmp, package], env=env, stdout=subprocess.PIPE,
                              text=True, cwd=tmp)  # python -c puts its folder on sys.path: not a checkout
    if proc.returncode != 0:
        raise KernelCompileError(f"compiling the kernels to carry failed (exit status {proc.returncode}); "
                                 "its messages are above")
    return json.loads(proc.stdout.strip().splitlines()[-1])["folder"]


def neutral_paths(data: bytes, folders: dict[Path, str]) -> bytes:
    """``data`` with every occurrence of each folder (folder -> name) replaced by ``./`` +
    slashes + the name, of the same length (see the module docstring)."""
    for folder, name in folders.items():
        old = str(folder).encode()
        new = b"./" + b"/" * (len(old) - len(name) - 2) + name.encode()
        if len(new) != len(old):
            raise ValueError(f"kernel cache folder {folder} is too short to be rewritten as {name}")
        data = data.replace(old, new)
    return data


def python_folders() -> dict[str, str]:
    """The folders of this Python that compiled kernels name (folder -> neutral name): its
    packages (numba's and numpy's sources: ``site-packages``) and its standard library
    (modules named in numba's type annotations: ``stdlib``)."""
    import sysconfig

    import numba
    import numpy

    paths = sysconfig.get_paths()
    folders = {paths[key]: "stdlib" for key in ("stdlib", "platstdlib")}
    folders.update({paths[key]: "site-packages" for key in ("purelib", "platlib")})
    for module in (numba, numpy):
        folders[str(Path(module.__file__).parent.parent)] = "site-packages"
    return folders


def python_versions() -> dict[str, str]:
    """Versions that make compiled kernels differ: Python, numba, llvmlite and numpy."""
    import llvmlite
    import numba
    import numpy

    return {"python": sys.version, "numba": numba.__version__, "llvmlite": llvmlite.__version__,
            "numpy": numpy.__version__}


def source_folders(root: Path, compiled_by: dict[str, str]) -> dict[Path, str]:
    """The folders the carried kernels' messages name (folder -> neutral name): the
    bundle's in the cache ``root`` (``resources``, where the FMU has it) and the folders
    of the Python that compiled them (``compiled_by``, from :func:`python_folders`) and
    of this one."""
    folders = {Path(path): name for path, name in {**python_folders(), **compiled_by}.items()}
    folders[root / "code"] = "resources"
    return dict(sorted(folders.items(), key=lambda item: -len(str(item[0]))))  # a folder before its parents


def _compiled_record(done: Path, root: Path) -> dict | None:
    """The record of the kernels compiled into ``root``, if the compilation finished."""
    try:
        record = json.loads(done.read_text(encoding="utf-8"))
        folder, folders = record["folder"], record["folders"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not isinstance(folders, dict) or not any((root / "kernels" / str(folder)).rglob("*.nbc")):
        return None
    return record


def carried_kernels(package: str, resources: dict[str, bytes]) -> dict[str, bytes]:
    """The FMU entries (``resources/kernels/...`` -> content) of the precompiled kernels of
    bundle ``package``, compiled unless the machine cache has them.

    Parameters
    ----------
    package
        The bundle's package name (``towcable_<digest>``).
    resources
        The FMU's ``resources/`` files needed to import the bundle (the bundle, its
        activation module and ``requirements.txt``), paths relative to ``resources/``.
    """
    versions = hashlib.sha256(json.dumps(python_versions(), sort_keys=True).encode()).hexdigest()[:12]
    root = carried_root() / f"py-{versions}" / package
    done = root / "compiled.json"
    record = _compiled_record(done, root)
    if record is None:  # nothing, or an unfinished compilation (maybe by another Python): start afresh
        shutil.rmtree(root, ignore_errors=True)
        folder = _compile(package, resources, root)
        if not any((root / "kernels" / folder).rglob("*.nbc")):
            raise KernelCompileError(f"compiling the kernels to carry wrote none into {root / 'kernels' / folder}")
        record = {"folder": folder, "versions": python_versions(), "folders": python_folders()}
        done.write_text(json.dumps(record, indent=1), encoding="utf-8")
    folder = record["folder"]
    kernels = root / "kernels" / folder
    folders = source_folders(root, record["folders"])
    return {f"resources/kernels/{machine_cache.CARRIED_TARGET}/{folder}/{path.relative_to(kernels).as_posix()}":
            neutral_paths(path.read_bytes(), folders)
            for path in sorted(kernels.rglob("*")) if path.is_file() and path.suffix in (".nbi", ".nbc")}
