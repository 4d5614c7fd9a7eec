"""Array copies inside kernels without numpy's slice assignment.

numba compiles ``dst[:] = src`` (and ``dst[:, :] = src``) with an error path that formats
both shapes into its message; that path alone costs about 1 s of compiling per number of
dimensions in every process that compiles kernels (measured, numba 0.68). The copies of
the kernels go element by element instead.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit


@njit(cache=True)
def copy_into(dst: np.ndarray, src: np.ndarray) -> None:
    """``dst[...] = src`` for two arrays of the same shape (element by element, C order)."""
    for i in range(dst.size):
        dst.flat[i] = src.flat[i]
