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
"""

from __future__ import annotations

import hashlib
import os
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

#: File of a bundle listing ``<sha256>  <relative path>`` for each of its files.
MANIFEST = "MANIFEST.sha256"


def cache_root() -> Path:
    """The machine's towcable cache folder (see the module docstring)."""
    if os.environ.get("TOWCABLE_CACHE_DIR"):
        return Path(os.environ["TOWCABLE_CACHE_DIR"])
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"]) / "towcable"
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "towcable"


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


def activate(bundle: str) -> Path:
    """Make the package ``bundle`` that this FMU carries importable; return its folder.

    The package is ``resources/<bundle>/`` beside this file. It is installed into
    ``<cache root>/code/<bundle>/`` unless an identical copy is there (checked against
    the FMU's manifest), and that folder's parent goes first on ``sys.path``. If the cache
    cannot be written the package is imported from the FMU's own folder (with a
    warning: its kernels are then compiled in every new folder). Idempotent.
    """
    source = Path(__file__).resolve().parent / bundle
    if bundle in sys.modules:
        return Path(sys.modules[bundle].__file__).parent
    target = cache_root() / "code" / bundle
    try:
        if not is_copy_of(target, source):
            _install(source, target)
        folder = target
    except OSError as exc:
        warnings.warn(f"cannot install the FMU's code into {target} ({exc}); running it from {source} "
                      "(set TOWCABLE_CACHE_DIR to a writable folder)", stacklevel=2)
        folder = source
    if str(folder.parent) not in sys.path:
        sys.path.insert(0, str(folder.parent))
    return folder
