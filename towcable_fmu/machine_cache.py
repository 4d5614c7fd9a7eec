"""The machine's towcable cache folder, and the FMU code installed into it.

Standard library only and no package-relative import: an FMU carries this file as a
top-level module (``resources/<bundle>_activate.py``, see
:mod:`towcable_fmu.fmi.bundle`) and runs it before its own package can be imported.

The cache folder (:func:`cache_root`) is ``$TOWCABLE_CACHE_DIR``, else
``$NUMBA_CACHE_DIR/towcable``, else ``$XDG_CACHE_HOME/towcable`` or
``~/.cache/towcable``. It holds

* ``code/<bundle>/``: the package an FMU carries (:func:`activate`), installed once per
  bundle digest, so the code has one place per machine whatever folder a host unzips
  the FMU into;
* ``kernels/towcable-<digest>/``: the compiled kernels (:mod:`towcable_fmu.kernel_cache`).

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
import re
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

#: File of a bundle listing ``<sha256>  <relative path>`` for each of its files.
MANIFEST = "MANIFEST.sha256"
#: Our packages (an FMU carries all three, see towcable_fmu/fmi/bundle.py).
PACKAGES = ("towcable_fmu", "ship_motion", "controllers")
#: Files of the packages that are not code: caches and build inputs of the loader.
_SKIP_DIRS = {"__pycache__", "csrc"}
_SKIP_SUFFIXES = {".pyc", ".pyo", ".nbi", ".nbc", ".so", ".c"}
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


def activate(bundle: str, module: str, name: str):
    """The object ``name`` of the module ``module`` (``towcable_fmu.fmu``) of the code
    this FMU carries, the package ``bundle`` beside this file (``resources/<bundle>/``).

    If this Python has the same code installed (:func:`installed_code` equals
    ``bundle``), that is imported. Else the FMU's copy is: the packages of
    ``resources/requirements.txt`` must be importable (:func:`check_requirements`); the
    copy is installed into ``<cache root>/code/<bundle>/`` unless an identical copy is
    there (checked against the FMU's manifest) and imported from there by location (if
    the cache cannot be written, from the FMU's own folder, with a warning: its kernels
    are then compiled in every new folder).
    """
    if bundle not in sys.modules and installed_code() == bundle:
        return getattr(importlib.import_module(module), name)
    import_bundle(bundle)
    return getattr(importlib.import_module(f"{bundle}.{module}"), name)


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
