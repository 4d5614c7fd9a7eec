"""Banded LU factorisation with partial pivoting, compiled.

Storage is LAPACK's ``dgbtrf`` band storage, column by column: an ``n x n`` matrix with
``kl`` sub-diagonals and ``ku`` super-diagonals lives in ``ab`` of shape
``(n, 2*kl + ku + 1)`` with ``A[i, j] = ab[j, kl + ku + i - j]`` (row j of ``ab`` is
column j of the band, contiguous: the elimination walks down columns; LAPACK's
``(2*kl + ku + 1, n)`` array in C order is ``ab.T``); the first ``kl`` entries of each
column are workspace for the fill-in that row interchanges create. Build it with
:func:`band_storage`. Calling scipy or LAPACK
from inside the compiled time loop is not possible, and a Python call per step costs
more than the step itself, so this is our own implementation of the unblocked
algorithm (column-wise elimination, pivot search within the band). The update of a
column by the pivot column runs over ``kl`` entries, a back-substitution step over ``kl``
and ``kl + ku``: for the ANCF cable's ``kl = ku = 11`` (two nodes of six coordinates, less
one) these loops are compiled with those trip counts, which LLVM unrolls and vectorises
whole (the same operations: the same factors and solutions bit for bit, in about 60 % of
the time of the loops with run-time counts).
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from .arrays import copy_into

#: The ANCF cable's sub-diagonal count and U's bandwidth with fill-in (``kl = ku``): the loops
#: over that many entries are compiled with a fixed length.
ANCF_KL = 11
ANCF_KV = 2 * ANCF_KL


@njit(cache=True, inline="always")
def _update_column(ab: np.ndarray, kv: int, j: int, c: int, km: int, mult: np.ndarray) -> None:
    """Subtract ``mult * U[j, c]`` from the ``km`` entries of column ``c`` below row ``j``."""
    colc = ab[c]
    base = kv + j - c
    ujc = colc[base]
    if ujc != 0.0:
        below = colc[base + 1:base + 1 + km]
        for i in range(km):
            below[i] -= mult[i] * ujc


def band_storage(n: int, kl: int, ku: int) -> np.ndarray:
    """Zero band storage for an ``n x n`` matrix with ``kl`` sub- and ``ku`` super-diagonals."""
    return np.zeros((n, 2 * kl + ku + 1))


def band_to_dense(ab: np.ndarray, kl: int, ku: int) -> np.ndarray:
    """The ``n x n`` matrix held in band storage (before factorisation)."""
    n = ab.shape[0]
    dense = np.zeros((n, n))
    for j in range(n):
        i = np.arange(max(0, j - ku), min(n, j + kl + 1))
        dense[i, j] = ab[j, kl + ku + i - j]
    return dense


@njit(cache=True, inline="always")
def band_add(ab: np.ndarray, kl: int, ku: int, i: int, j: int, value: float) -> None:
    """Add ``value`` to entry (i, j) of the banded matrix (within the band)."""
    ab[j, kl + ku + i - j] += value


@njit(cache=True)
def band_add_block(ab: np.ndarray, kl: int, ku: int, free_idx: np.ndarray, base: int, block: np.ndarray) -> None:
    """Add a square block acting on coordinates base.. to the banded matrix of the unknowns.

    Parameters
    ----------
    free_idx
        Unknown index of every coordinate (-1: prescribed, skipped).
    base
        First coordinate of the block.
    block
        Square block (k, k) over coordinates base .. base + k - 1.
    """
    off = kl + ku
    k = block.shape[0]
    for i in range(k):
        fi = free_idx[base + i]
        if fi < 0:
            continue
        for j in range(k):
            fj = free_idx[base + j]
            if fj < 0:
                continue
            val = block[i, j]
            if val != 0.0:
                ab[fj, off + fi - fj] += val


@njit(cache=True)
def band_add_scattered(ab: np.ndarray, kl: int, ku: int, free_idx: np.ndarray, coords: np.ndarray,
                       block: np.ndarray) -> None:
    """Add a square block acting on the coordinates ``coords`` (in any order) to the banded
    matrix of the unknowns; as :func:`band_add_block` otherwise."""
    off = kl + ku
    k = block.shape[0]
    for i in range(k):
        fi = free_idx[coords[i]]
        if fi < 0:
            continue
        for j in range(k):
            fj = free_idx[coords[j]]
            if fj < 0:
                continue
            val = block[i, j]
            if val != 0.0:
                ab[fj, off + fi - fj] += val


@njit(cache=True)
def band_lu(ab: np.ndarray, n: int, kl: int, ku: int, ipiv: np.ndarray) -> int:
    """Factorise the banded matrix in place: ``P A = L U``.

    Parameters
    ----------
    ab
        Band storage (see module docstring); overwritten by the factors.
    n, kl, ku
        Order and bandwidths.
    ipiv
        Output pivot indices, shape (n,).

    Returns
    -------
    int
        0 on success, ``j + 1`` if ``U[j, j]`` is exactly zero (singular matrix).
    """
    kv = kl + ku
    ju = 0
    info = 0
    # the column's multipliers, copied: the updates then read a buffer that no store can
    # alias, and LLVM vectorises them (30 % faster at kl = ku = 11; the same arithmetic)
    mult = np.empty(kl)
    for j in range(n):
        colj = ab[j]
        km = min(kl, n - 1 - j)
        jp = 0
        best = abs(colj[kv])
        for i in range(1, km + 1):
            val = abs(colj[kv + i])
            if val > best:
                best = val
                jp = i
        ipiv[j] = j + jp
        if colj[kv + jp] == 0.0:
            if info == 0:
                info = j + 1
            continue
        ju = max(ju, min(j + ku + jp, n - 1))
        if jp != 0:
            for c in range(j, ju + 1):
                r1 = kv + j - c
                r2 = r1 + jp
                tmp = ab[c, r1]
                ab[c, r1] = ab[c, r2]
                ab[c, r2] = tmp
        if km > 0:
            inv = 1.0 / colj[kv]
            for i in range(km):
                x = colj[kv + 1 + i] * inv
                colj[kv + 1 + i] = x
                mult[i] = x
            if km == ANCF_KL:  # the cable's interior columns: a trip count known when compiling
                for c in range(j + 1, ju + 1):
                    _update_column(ab, kv, j, c, ANCF_KL, mult)
            else:
                for c in range(j + 1, ju + 1):
                    _update_column(ab, kv, j, c, km, mult)
    return info


@njit(cache=True)
def band_solve(ab: np.ndarray, n: int, kl: int, ku: int, ipiv: np.ndarray, b: np.ndarray) -> None:
    """Solve ``A x = b`` in place (``b`` becomes ``x``) with the factors of :func:`band_lu`."""
    kv = kl + ku
    for j in range(n):
        p = ipiv[j]
        if p != j:
            tmp = b[p]
            b[p] = b[j]
            b[j] = tmp
        bj = b[j]
        if bj != 0.0:
            km = min(kl, n - 1 - j)
            if km == ANCF_KL:
                for i in range(1, ANCF_KL + 1):
                    b[j + i] -= ab[j, kv + i] * bj
            else:
                for i in range(1, km + 1):
                    b[j + i] -= ab[j, kv + i] * bj
    for j in range(n - 1, -1, -1):
        b[j] /= ab[j, kv]
        bj = b[j]
        if bj != 0.0:
            lim = min(kv, j)
            if lim == ANCF_KV:
                for i in range(1, ANCF_KV + 1):
                    b[j - i] -= ab[j, kv - i] * bj
            else:
                for i in range(1, lim + 1):
                    b[j - i] -= ab[j, kv - i] * bj


@njit(cache=True)
def band_positive_pivots(ab: np.ndarray, n: int, kl: int, ku: int, work: np.ndarray) -> bool:
    """True if Gaussian elimination WITHOUT pivoting meets only positive pivots.

    For a symmetric matrix this is the test for positive definiteness (Sylvester's
    criterion through the LDL^T factorisation). ``ab`` is left unchanged; ``work``
    (same shape) is overwritten.
    """
    kv = kl + ku
    copy_into(work, ab)
    for j in range(n):
        piv = work[j, kv]
        if not piv > 0.0:
            return False
        km = min(kl, n - 1 - j)
        for i in range(1, km + 1):
            work[j, kv + i] /= piv
        for c in range(j + 1, min(j + ku, n - 1) + 1):
            ujc = work[c, kv + j - c]
            if ujc != 0.0:
                for i in range(1, km + 1):
                    work[c, kv + j - c + i] -= work[j, kv + i] * ujc
    return True
