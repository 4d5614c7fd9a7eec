"""Keep numba's on-disk cache consistent with the sources.

numba invalidates a cached function when ITS file changes, not when a compiled function
it calls (from another file) changes; an in-place edit of one kernel module could then
leave stale machine code in the callers' caches. At import we hash every source file of
the project's packages that defines compiled kernels and, when the hash differs from
the one recorded last time, delete the packages' cached kernels (``*.nbi``, ``*.nbc``
next to the sources) so they are compiled afresh.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

_PACKAGES = ("towcable_fmu", "ship_motion", "controllers")


def refresh_stale_cache() -> bool:
    """Delete cached kernels if any kernel source changed; True if it did."""
    root = Path(__file__).resolve().parent.parent
    folders = [root / name for name in _PACKAGES if (root / name).is_dir()]
    digest = hashlib.sha256()
    for folder in folders:
        for path in sorted(folder.rglob("*.py")):
            text = path.read_bytes()
            if b"@njit" in text:
                digest.update(path.relative_to(root).as_posix().encode())
                digest.update(text)
    stamp = Path(__file__).parent / "__pycache__" / "kernel_sources.sha256"
    current = digest.hexdigest()
    try:
        if stamp.read_text() == current:
            return False
    except OSError:
        pass
    for folder in folders:
        for cached in list(folder.rglob("*.nbi")) + list(folder.rglob("*.nbc")):
            cached.unlink(missing_ok=True)
    try:
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(current)
    except OSError:  # read-only installation: sources cannot change in place either
        pass
    return True
