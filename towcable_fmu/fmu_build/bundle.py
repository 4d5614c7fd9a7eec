"""The code an FMU carries: our packages, copied under a name of their own.

An FMU runs in the host's Python (fmpy, libcosimpy) or in an interpreter it starts
itself; in both a towcable of another version may be installed, or already imported by
the host (``towcable cosim`` imports towcable_fmu and then loads the FMUs). So that an
FMU always runs the code it carries, the build copies ``towcable_fmu``, ``ship_motion``
and ``controllers`` into ``resources/<name>/`` of the FMU, where ``<name>`` is
``towcable_<digest>`` and the digest hashes the copied files: two FMUs built from the
same sources share one package (and one copy in memory); two builds of different
sources never meet. Every absolute import of the three packages is rewritten to import
from that package (as vendoring tools do); relative imports need nothing. Line numbers
are kept (tracebacks, numba's cache names).

At run time the FMU's entry script calls :func:`towcable_fmu.jit.machine_cache.activate`
(copied with the rest as ``resources/<name>_activate.py``). If the Python running the FMU
has these very sources installed, it imports those (one copy of the code and of its
kernels for the command line and the FMUs). Else it installs the package from the
unzipped FMU into the machine's cache folder (once per digest) and imports it from
there, so that the code - and the compiled kernels next to it - have one place per
machine whatever folder the host unzips the FMU into.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

from ..jit import machine_cache
from ..jit.machine_cache import MANIFEST, PACKAGES, bundle_name, manifest_text


class BundleError(RuntimeError):
    """A source file uses an import form the bundle cannot rewrite."""


def source_root() -> Path:
    """The folder holding the three packages (site-packages, or the source checkout)."""
    return Path(__file__).resolve().parents[2]


def package_files(root: Path | None = None) -> dict[str, bytes]:
    """The files of the three packages under ``root`` (default :func:`source_root`): path
    relative to ``root`` (POSIX) -> content."""
    root = source_root() if root is None else Path(root)
    return machine_cache.package_files({package: root / package for package in PACKAGES})


_FROM = re.compile(r"from\s+")


def rewrite_imports(source: str, prefix: str, filename: str = "<source>") -> str:
    """``source`` with every absolute import of :data:`PACKAGES` made to import from ``prefix``.

    ``from towcable_fmu.x import y`` becomes ``from <prefix>.towcable_fmu.x import y`` and
    ``import ship_motion.x as y`` becomes ``import <prefix>.ship_motion.x as y``; the
    rest of the text (and so every line number) is unchanged.

    Raises
    ------
    BundleError
        For ``import towcable_fmu`` or ``import towcable_fmu.x`` without ``as`` (it would
        bind a different name): write ``from towcable_fmu import x`` instead.
    """
    edits: list[tuple[int, int]] = []  # (line, column) where the prefix goes
    for node in ast.walk(ast.parse(source, filename)):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and _ours(node.module):
            line = source.splitlines()[node.lineno - 1]
            match = _FROM.match(line, node.col_offset)
            if match is None or not line.startswith(node.module, match.end()):
                raise BundleError(f"{filename}:{node.lineno}: cannot rewrite this import "
                                  f"(write 'from {node.module} import ...' on one line)")
            edits.append((node.lineno, match.end()))
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if not _ours(alias.name):
                    continue
                if alias.asname is None:
                    raise BundleError(f"{filename}:{node.lineno}: 'import {alias.name}' cannot be bundled; "
                                      f"write 'from ... import' or 'import {alias.name} as ...'")
                edits.append((alias.lineno, alias.col_offset))
    lines = source.splitlines(keepends=True)
    for lineno, col in sorted(edits, reverse=True):
        text = lines[lineno - 1]
        lines[lineno - 1] = text[:col] + prefix + "." + text[col:]
    return "".join(lines)


def _ours(module: str | None) -> bool:
    return module is not None and module.split(".")[0] in PACKAGES


def bundle(files: dict[str, bytes] | None = None) -> tuple[str, dict[str, bytes]]:
    """The package an FMU carries.

    Parameters
    ----------
    files
        The packages' files (default: :func:`package_files` of the running code).

    Returns
    -------
    name, files
        The package name (:func:`bundle_name`) and its files, paths relative to
        ``resources/`` (``<name>/__init__.py``, ``<name>/towcable_fmu/...``), Python
        sources rewritten by :func:`rewrite_imports`.
    """
    files = package_files() if files is None else files
    name = bundle_name(files)
    inner = {"__init__.py": (f'"""towcable code carried by an FMU (bundle {name}, '
                             f'written by towcable_fmu.fmu_build.bundle)."""\n').encode()}
    for rel, data in files.items():
        if rel.endswith(".py"):
            data = rewrite_imports(data.decode("utf-8"), name, rel).encode("utf-8")
        inner[rel] = data
    inner[MANIFEST] = manifest_text(inner).encode()
    return name, {f"{name}/{rel}": data for rel, data in inner.items()}
