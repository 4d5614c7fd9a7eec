"""The loader layer of the FMUs' Linux binary (issue 9; no build paths since issue 17).

pythonfmu 0.7 puts a library into ``binaries/linux64/<model>.so`` that leaves the Python
symbols unresolved (it only loads in a process that already runs Python), drops the log
messages when the host turned logging off and cannot return ``fmi2Error``.
:func:`loader_entries` replaces that binary by a thin C layer
(``towcable_fmu/fmu_build/csrc/fmu_loader.c``, compiled by :func:`compile_loader` with the
machine's C compiler) and keeps pythonfmu's library beside it as
``binaries/linux64/libpythonfmu-export.so``. At the first ``fmi2Instantiate`` the layer
uses the Python already in the process, else the runtime a standalone FMU carries, else
the machine's Python; then it enforces the FMI 2.0 state machine (``csrc/state_machine.c``),
forwards every allowed FMI call, relays error messages to the host whatever its logging
setting, returns the most severe status the model logged, and wraps serialised FMU states
in an envelope with the FMU's name, GUID and a checksum (``csrc/state_bytes.c``).

Linux only: the ``win64`` binary of pythonfmu is left as it is.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sysconfig
import warnings
from pathlib import Path

#: C sources of the loader layer: the layer itself, the state machine it enforces, the
#: variable table it reads from modelDescription.xml, the envelope of serialised states.
LOADER_SOURCE = Path(__file__).with_name("csrc") / "fmu_loader.c"
LOADER_SOURCES = tuple(LOADER_SOURCE.with_name(name) for name in
                       ("fmu_loader.c", "state_machine.c", "model_table.c", "state_bytes.c"))
#: Name of pythonfmu's library inside ``binaries/linux64/``.
REAL_LIBRARY = "libpythonfmu-export.so"


class NativeBuildError(RuntimeError):
    """The loader layer cannot be built on this machine (no C compiler)."""


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
    # no debugging information: it would carry the paths of this machine into the FMU
    cmd = [cc, "-shared", "-fPIC", "-O2", "-g0", "-std=gnu11", "-Wall", "-Wextra", "-Wno-format-truncation",
           "-fvisibility=hidden", "-Wl,-Bsymbolic", f"-I{sysconfig.get_paths()['include']}",
           f"-I{fmi_headers()}", f"-I{LOADER_SOURCE.parent}", *map(str, LOADER_SOURCES), "-o", str(target), "-ldl", "-lpthread"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise NativeBuildError(f"compiling the loader layer failed:\n{' '.join(cmd)}\n{proc.stderr}")
    return target


def loader_or_warning(outdir: str | Path) -> Path | None:
    """:func:`compile_loader`, or None with a warning that the FMUs will need a Python host."""
    try:
        return compile_loader(outdir)
    except NativeBuildError as exc:
        warnings.warn(f"{exc}; building FMUs that load only in Python hosts (fmpy, libcosimpy)", stacklevel=2)
        return None


def loader_entries(files: dict[str, bytes], model_identifier: str, loader: Path) -> dict[str, bytes]:
    """The FMU's files (archive name -> content) with the loader layer installed.

    ``binaries/linux64/<model_identifier>.so`` (pythonfmu's library) moves to
    ``binaries/linux64/libpythonfmu-export.so`` and the loader takes its place.
    """
    binary = f"binaries/linux64/{model_identifier}.so"
    out = dict(files)
    out[f"binaries/linux64/{REAL_LIBRARY}"] = out.pop(binary)
    out[binary] = Path(loader).read_bytes()
    return out
