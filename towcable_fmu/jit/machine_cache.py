"""The machine's towcable cache folder, and the FMU code installed into it.

Standard library only and no package-relative import: an FMU carries this file as a
top-level module (``resources/<bundle>_activate.py``, see
:mod:`towcable_fmu.fmu_build.bundle`) and runs it before its own package can be imported.

The cache folder (:func:`cache_root`) is ``$TOWCABLE_CACHE_DIR``, else
``$NUMBA_CACHE_DIR/towcable``, else ``$XDG_CACHE_HOME/towcable`` or
``~/.cache/towcable``. It holds

* ``code/<bundle>/``: the package an FMU carries (:func:`activate`), installed once per
  bundle digest, so the code has one place per machine whatever folder a host unzips
  the FMU into;
* ``kernels/towcable-<digest>/``: the compiled kernels (:mod:`towcable_fmu.jit.kernel_cache`),
  compiled on this machine or installed from the precompiled kernels an FMU carries
  (:func:`use_carried_kernels`).

An FMU built from the very sources this Python has installed (same files, byte for
byte: :func:`installed_code`) runs the installed modules instead of its copy: the same
code, imported once, and the same compiled kernels as the command line and any other
FMU of that version (``towcable run`` and ``towcable cosim`` compile once between them).
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
import platform
import re
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

#: File of a bundle listing ``<sha256>  <relative path>`` for each of its files.
MANIFEST = "MANIFEST.sha256"
#: Our packages (an FMU carries all three, see towcable_fmu/fmu_build/bundle.py).
PACKAGES = ("towcable_fmu", "ship_motion", "controllers")
#: Files of the packages that are not code: caches and build inputs of the loader.
_SKIP_DIRS = {"__pycache__", "csrc"}
_SKIP_SUFFIXES = {".pyc", ".pyo", ".nbi", ".nbc", ".so", ".c"}
#: CPU target of the kernels an FMU carries precompiled (``resources/kernels/<target>/``):
#: x86-64 with AVX2 and FMA, every Intel CPU since Haswell (2013) and AMD since Zen (2017).
CARRIED_TARGET = "x86-64-v3"
#: The /proc/cpuinfo flags a CPU needs to run x86-64-v3 code (``abm``: lzcnt).
_TARGET_FLAGS = frozenset("cx16 lahf_lm popcnt sse4_1 sse4_2 ssse3 avx avx2 bmi1 bmi2 f16c fma abm movbe xsave".split())
#: File that marks a kernel folder of the machine cache as installed from an FMU.
CARRIED_MARK = "CARRIED"
#: Bump when the bundle's layout or its rewriting changes (the digest then changes too).
BUNDLE_FORMAT = "1"


def cache_root() -> Path:
    """The machine's towcable cache folder (see the module docstring)."""
    if os.environ.get("TOWCABLE_CACHE_DIR"):
        return Path(os.environ["TOWCABLE_CACHE_DIR"])
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"]) / "towcable"
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "towcable"


def package_files(folders: dict[str, Path]) -> dict[str, bytes]:
    """The files of our packages (package name -> its folder): path relative to the
    package's parent (POSIX, ``towcable_fmu/...``) -> content."""
    files: dict[str, bytes] = {}
    for package in PACKAGES:
        root = Path(folders[package]).parent
        for path in sorted(Path(folders[package]).rglob("*")):
            rel = path.relative_to(root)
            if path.is_file() and not _SKIP_DIRS.intersection(rel.parts) and path.suffix not in _SKIP_SUFFIXES:
                files[rel.as_posix()] = path.read_bytes()
    return files


def code_digest(files: dict[str, bytes]) -> str:
    """Hex SHA-256 of the packages' file names and contents (and the bundle format): the
    bundle an FMU carries is named ``towcable_`` + its first 16 digits."""
    h = hashlib.sha256(BUNDLE_FORMAT.encode())
    for name in sorted(files):
        h.update(name.encode() + b"\0" + hashlib.sha256(files[name]).digest())
    return h.hexdigest()


def bundle_name(files: dict[str, bytes]) -> str:
    """The package name an FMU's copy of ``files`` is imported as: ``towcable_`` + the
    first 16 digits of :func:`code_digest`."""
    return f"towcable_{code_digest(files)[:16]}"


@functools.cache
def installed_code() -> str | None:
    """The bundle name (``towcable_<16 hex digits>``) of the three packages as this Python
    would import them (found on ``sys.path`` without importing them), or None if one is
    missing."""
    folders = {}
    for package in PACKAGES:
        try:
            spec = importlib.util.find_spec(package)
        except (ImportError, ValueError):
            return None
        if spec is None or not spec.submodule_search_locations:
            return None
        folders[package] = Path(list(spec.submodule_search_locations)[0])
    try:
        return bundle_name(package_files(folders))
    except OSError:
        return None


def manifest_text(files: dict[str, bytes]) -> str:
    """The manifest of a bundle's files (relative path -> content)."""
    return "".join(f"{hashlib.sha256(data).hexdigest()}  {name}\n" for name, data in sorted(files.items()))


def is_copy_of(folder: Path, source: Path) -> bool:
    """True if ``folder`` holds every file of ``source``'s manifest with the listed content."""
    try:
        text = (source / MANIFEST).read_text(encoding="utf-8")
        if (folder / MANIFEST).read_text(encoding="utf-8") != text:
            return False
        return all(hashlib.sha256((folder / name).read_bytes()).hexdigest() == sha
                   for sha, name in (line.split("  ", 1) for line in text.splitlines()))
    except (OSError, ValueError):
        return False


def _install(source: Path, target: Path) -> None:
    """Copy ``source`` to ``target`` atomically (another process may do the same)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    try:
        shutil.copytree(source, staging / "copy", ignore=shutil.ignore_patterns("__pycache__"))
        if target.exists() and not is_copy_of(target, source):
            shutil.rmtree(target, ignore_errors=True)  # a damaged or altered copy
        try:
            os.rename(staging / "copy", target)
        except OSError:
            if not is_copy_of(target, source):  # not another process's finished copy
                raise
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def check_requirements(path: Path) -> None:
    """Raise ImportError naming every package of a requirements file (``name>=version``
    lines) that the running Python cannot import."""
    names = [re.split(r"[<>=!~;\[ ]", line.strip(), maxsplit=1)[0]
             for line in path.read_text(encoding="utf-8").splitlines() if line.strip() and not line.startswith("#")]
    missing = [name for name in names if importlib.util.find_spec(name) is None]
    if missing:
        raise ImportError(f"this FMU needs the Python packages {', '.join(missing)} ({path.name} in the FMU's "
                          f"resources) in the Python that runs it ({sys.executable or sys.prefix}): install them "
                          f"with 'pythonfmu deploy <FMU>' or 'pip install -r resources/{path.name}', or use the "
                          "standalone FMU (build_fmu.py --standalone), which carries its own Python")


def activate(bundle: str, module: str, name: str, entry: str):
    """The object ``name`` of the module ``module`` (``towcable_fmu.fmu``) of the code
    this FMU carries, the package ``bundle`` in the FMU's ``resources/`` (the folder of its
    entry script ``entry``; FMUs of one build share this module, each passes its own).

    If this Python has the same code installed (:func:`installed_code` equals
    ``bundle``), that is imported. Else the FMU's copy is: the packages of
    ``resources/requirements.txt`` must be importable (:func:`check_requirements`); the
    copy is installed into ``<cache root>/code/<bundle>/`` unless an identical copy is
    there (checked against the FMU's manifest) and imported from there by location (if
    the cache cannot be written, from the FMU's own folder, with a warning: its kernels
    are then compiled in every new folder). The build's precompiled kernels are used where
    they can be (:func:`use_carried_kernels`).
    """
    if bundle not in sys.modules and installed_code() == bundle:
        return getattr(importlib.import_module(module), name)
    CARRIED_KERNELS[bundle] = use_carried_kernels(Path(entry).resolve().parent / "kernels")
    import_bundle(bundle)
    return getattr(importlib.import_module(f"{bundle}.{module}"), name)


def cpu_runs_carried_kernels(cpuinfo: str = "/proc/cpuinfo") -> bool:
    """True if this machine is x86-64 and its CPU has every feature of :data:`CARRIED_TARGET`."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return False
    try:
        with open(cpuinfo, encoding="utf-8", errors="replace") as f:
            flags = next((line.split(":", 1)[1].split() for line in f if line.startswith("flags")), [])
    except OSError:
        return False
    return _TARGET_FLAGS.issubset(flags)


def _install_kernels(source: Path, target: Path) -> None:
    """Copy one kernel folder an FMU carries into the machine cache (atomically), marked."""
    target.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    try:
        shutil.copytree(source, staging / "copy")
        (staging / "copy" / CARRIED_MARK).write_text(CARRIED_TARGET + "\n", encoding="utf-8")
        if target.is_dir() and not any(target.rglob("*.nbi")):
            shutil.rmtree(target, ignore_errors=True)  # made by an import that compiled nothing
        try:
            os.rename(staging / "copy", target)
        except OSError:
            if not (target / CARRIED_MARK).is_file():  # not another process's finished copy
                raise
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def use_carried_kernels(folder: Path) -> str | None:
    """Let the precompiled kernels of an FMU's build (``folder``: its ``resources/kernels``)
    serve this process, where they can; return None if they do, else why not.

    numba finds a cached kernel only for the CPU target it was compiled for. Every FMU of a
    build with precompiled kernels names their target in ``kernels/TARGET``; the FMU that
    carries them (TowCable) has them in ``kernels/<target>/towcable-<digest>/``. They are
    installed into the machine cache (``kernels/towcable-<digest>/``, marked
    :data:`CARRIED_MARK`) unless that folder already holds kernels compiled on this
    machine, and numba's target is set to :data:`CARRIED_TARGET` (``NUMBA_CPU_NAME``,
    ``NUMBA_CPU_FEATURES``) for this process, whichever FMU of the build is instantiated
    first. That needs a CPU that runs x86-64-v3 code and a numba not yet imported (or
    imported for that target, by an earlier FMU); otherwise the kernels are compiled on
    this machine as usual.
    """
    try:
        target = (folder / "TARGET").read_text(encoding="utf-8").strip()
    except OSError:
        return "the FMU carries no precompiled kernels"
    if target != CARRIED_TARGET:
        return f"they are compiled for {target}, this code runs {CARRIED_TARGET} kernels"
    if not cpu_runs_carried_kernels():
        return f"this CPU cannot run {CARRIED_TARGET} code"
    if "numba" in sys.modules:
        config = sys.modules["numba"].core.config
        if (config.CPU_NAME, config.CPU_FEATURES) != (CARRIED_TARGET, ""):
            return f"numba was imported before the FMU, for the CPU target {config.CPU_NAME or 'of this machine'}"
    elif (os.environ.get("NUMBA_CPU_NAME", CARRIED_TARGET), os.environ.get("NUMBA_CPU_FEATURES", "")) != (CARRIED_TARGET, ""):
        return "NUMBA_CPU_NAME / NUMBA_CPU_FEATURES ask for another CPU target"
    carried = folder / CARRIED_TARGET
    for source in sorted(p for p in carried.iterdir() if p.is_dir()) if carried.is_dir() else []:
        installed = cache_root() / "kernels" / source.name
        if (installed / CARRIED_MARK).is_file():
            continue
        if installed.is_dir() and any(installed.rglob("*.nbi")):
            return f"{installed} holds kernels compiled on this machine"
        try:
            _install_kernels(source, installed)
        except OSError as exc:
            return f"cannot install them into {installed} ({exc})"
    os.environ["NUMBA_CPU_NAME"] = CARRIED_TARGET
    os.environ["NUMBA_CPU_FEATURES"] = ""
    return None


#: Bundle -> None if its build's precompiled kernels serve this process, else why not
#: (:func:`activate`, the last FMU of the bundle activated).
CARRIED_KERNELS: dict[str, str | None] = {}


def import_bundle(bundle: str) -> Path:
    """Import the package ``bundle`` that this FMU carries (``sys.modules[bundle]``) from
    the machine cache (see :func:`activate`); return its folder. Idempotent."""
    source = Path(__file__).resolve().parent / bundle
    if bundle in sys.modules:
        return Path(sys.modules[bundle].__file__).parent
    check_requirements(source.parent / "requirements.txt")
    target = cache_root() / "code" / bundle
    try:
        if not is_copy_of(target, source):
            _install(source, target)
        folder = target
    except OSError as exc:
        warnings.warn(f"cannot install the FMU's code into {target} ({exc}); running it from {source} "
                      "(set TOWCABLE_CACHE_DIR to a writable folder)", stacklevel=2)
        folder = source
    # imported from that folder by location: whatever else is on sys.path (pythonfmu puts
    # the unzipped resources/ first, where the same package lies) cannot shadow it
    spec = importlib.util.spec_from_file_location(bundle, folder / "__init__.py",
                                                  submodule_search_locations=[str(folder)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[bundle] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[bundle]
        raise
    return folder
