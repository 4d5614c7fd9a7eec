"""Where the compiled kernels are kept: one cache per machine, keyed by the code's content.

numba's own cache locators key a kernel's cache by the folder of its source file and
check only that file: a copy of the code in a new folder (an FMU unzipped by a host)
finds nothing, and a kernel that calls an edited kernel of another file keeps stale
machine code. :class:`KernelCacheLocator` keys every kernel of our packages by a digest
of all their kernel sources instead::

    <cache root>/kernels/towcable-<digest>/<module path>/<kernel>-<line>.py311.nbi

so the same code finds its kernels from any folder, and any change of a kernel source
compiles everything afresh (old digests are simply never read again).

The cache root is :func:`towcable_fmu.jit.machine_cache.cache_root` (``$TOWCABLE_CACHE_DIR``,
``$NUMBA_CACHE_DIR/towcable`` or ``~/.cache/towcable``). If it cannot be written,
numba's own locators take over (a warning says so once).

Our kernel modules decorate with this module's :func:`njit`, which first calls
:func:`install` (once): that puts the locator in front of numba's (numba picks a
kernel's locator when it is decorated) and registers :data:`WATCH`, which tells when the
kernels compile: the command line prints "compiling the numerical kernels (first run
only)" as it starts, an FMU logs how long it took. Importing ``towcable_fmu`` itself does
no work and does not import numba.
"""

from __future__ import annotations

import functools
import hashlib
import sys
import time
import warnings
from pathlib import Path
from typing import Callable

import numba
from numba.core import caching, event

from .machine_cache import PACKAGES, cache_root

#: numba's cache implementation base, whose ``_locator_classes`` are tried in order
#: (``_CacheImpl`` before numba 0.64).
_CACHE_IMPL = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl")

#: Folder holding the three packages of this copy of the code.
ROOT = Path(__file__).resolve().parents[2]


@functools.cache
def kernel_digest(root: Path = ROOT) -> str:
    """SHA-256 (16 hex digits) of the names and contents of every source file of the
    packages under ``root`` that defines a compiled kernel or a numba overload (a
    formulation's implementation of a protocol a kernel calls, such as
    :mod:`towcable_fmu.numerics.alpha_newton`'s), and of the name the code is
    imported under: numba's cache entries name their module (it is imported again to load
    them), so the copy an FMU carries (``towcable_<digest>.towcable_fmu``) must not share
    the entries of the installed ``towcable_fmu`` even where the sources are the same."""
    h = hashlib.sha256(__name__.encode() + b"\0")
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            text = path.read_bytes()
            if b"@njit" in text or b"@overload" in text:
                h.update(path.relative_to(root).as_posix().encode() + b"\0")
                h.update(hashlib.sha256(text).digest())
    return h.hexdigest()[:16]


def kernel_folder(root: Path = ROOT) -> Path:
    """Folder of this code's kernels in the machine cache."""
    return cache_root() / "kernels" / f"towcable-{kernel_digest(root)}"


class KernelCacheLocator(caching._CacheLocator):
    """numba cache locator for the kernels of our packages (see the module docstring)."""

    def __init__(self, py_func, py_file: str, relative: Path) -> None:
        self._py_file = py_file  # numba's warning about a kernel it cannot cache names it
        self._lineno = py_func.__code__.co_firstlineno
        self._path = kernel_folder() / relative.parent

    @classmethod
    def from_function(cls, py_func, py_file: str):
        try:
            relative = Path(py_file).resolve().relative_to(ROOT)
        except ValueError:
            return None
        if relative.parts[0] not in PACKAGES:
            return None
        self = cls(py_func, py_file, relative)
        try:
            self.ensure_cache_path()
        except OSError as exc:
            _warn_unwritable(exc)
            return None
        return self

    def get_cache_path(self) -> str:
        return str(self._path)

    def get_source_stamp(self) -> str:
        return kernel_digest()

    def get_disambiguator(self) -> str:
        return str(self._lineno)


@functools.cache
def _warn_unwritable(exc: OSError) -> None:
    warnings.warn(f"towcable cannot write its kernel cache ({exc}); set TOWCABLE_CACHE_DIR to a writable "
                  "folder, or the kernels are compiled again in every new folder", stacklevel=3)


class CompileWatch(event.Listener):
    """Watches numba compile our kernels (not load them from the cache).

    ``notice`` is called once, with no argument, when the process starts compiling the
    first of our kernels; ``seconds`` is the wall time spent compiling them so far
    (outermost compilations only: a kernel compiled for its caller is counted once).
    """

    def __init__(self) -> None:
        self.notice: Callable[[], None] | None = None
        self.seconds = 0.0
        self._depth = 0
        self._start = 0.0

    def on_start(self, ev: event.Event) -> None:
        if self._depth == 0:
            module = getattr(ev.data["dispatcher"].py_func, "__module__", "") or ""
            if not any(part in PACKAGES for part in module.split(".")[:2]):  # ours, installed or in an FMU
                return
            self._start = time.perf_counter()
            if self.notice is not None:
                notice, self.notice = self.notice, None
                notice()
        self._depth += 1

    def on_end(self, ev: event.Event) -> None:
        if self._depth == 0:
            return
        self._depth -= 1
        if self._depth == 0:
            self.seconds += time.perf_counter() - self._start


#: The process's watch (registered by :func:`install`).
WATCH = CompileWatch()


def print_compile_notice(processes: int = 1) -> None:
    """The command line's notice, printed to stderr when the first kernel compiles (on
    ``processes`` processes)."""
    where = f" on {processes} processes" if processes > 1 else ""
    print(f"compiling the numerical kernels{where} (first run only; cached in "
          f"{cache_root() / 'kernels'})...", file=sys.stderr, flush=True)


@functools.cache
def install() -> None:
    """Put :class:`KernelCacheLocator` first among numba's locators and register
    :data:`WATCH`. Idempotent."""
    _CACHE_IMPL._locator_classes.insert(0, KernelCacheLocator)
    event.register("numba:compile", WATCH)


def njit(*args, **kwargs):
    """``numba.njit`` for our kernels: :func:`install` first, so that the kernel's cache
    is :class:`KernelCacheLocator`'s."""
    install()
    return numba.njit(*args, **kwargs)
