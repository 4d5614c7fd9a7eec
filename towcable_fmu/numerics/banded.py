"""Banded LU factorisation, compiled: diagonal pivots where they are safe, partial pivoting elsewhere.

Storage is LAPACK's ``dgbtrf`` band storage, column by column: an ``n x n`` matrix with
``kl`` sub-diagonals and ``ku`` super-diagonals lives in ``ab`` of shape
``(n, 2*kl + ku + 1)`` with ``A[i, j] = ab[j, kl + ku + i - j]`` (row j of ``ab`` is
column j of the band, contiguous: the elimination walks down columns; LAPACK's
``(2*kl + ku + 1, n)`` array in C order is ``ab.T``); the first ``kl`` entries of each
column are workspace for the fill-in that row interchanges create. Build it with
:func:`band_storage`. Calling scipy or LAPACK
from inside the compiled time loop is not possible, and a Python call per step costs
more than the step itself, so this is our own implementation of the unblocked
algorithm (column-wise elimination, pivot search within the band).

Pivoting. The iteration matrices of the cable (``M + c_v C + c_q K``) are nearly symmetric
and positive definite, and elimination without row interchanges is stable on them, but
they are badly scaled (slopes next to positions): partial pivoting swaps rows at about a
third of the columns, which doubles U's bandwidth (fill-in up to ``kl + ku``) and the
cost of the factorisation and of every back-substitution. :func:`band_lu` therefore keeps
the diagonal pivot of column j while the current Schur complement ``S`` satisfies the
scale-invariant test of a positive definite matrix, relaxed by :data:`DIAGONAL_BOUND`:
``S_jj > 0``, ``S_ii > 0`` and ``|S_ij|, |S_ji| <= DIAGONAL_BOUND sqrt(S_ii S_jj)`` for every
``i`` the step updates (a positive definite matrix meets it with bound 1, by Cauchy-Schwarz).
Then no step changes an entry ``S_ik`` by more than ``DIAGONAL_BOUND^2 sqrt(S_ii S_kk)``.
A column that fails the test is pivoted as LAPACK does (largest entry of the column),
so any matrix partial pivoting factorises is factorised; a factorisation that made no
interchange is solved with U's own bandwidth ``ku``.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from .arrays import copy_into

#: Relaxation of the positive-definite test under which :func:`band_lu` keeps a diagonal pivot.
DIAGONAL_BOUND = 2.0


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


@njit(cache=True, inline="always")
def _diagonal_is_safe(ab: np.ndarray, j: int, km: int, kv: int, last: int) -> bool:
    """The module docstring's test of the diagonal pivot of column ``j`` (rows ``j + 1`` to
    ``j + km`` below it, columns ``j + 1`` to ``last`` right of it)."""
    colj = ab[j]
    bound = DIAGONAL_BOUND * DIAGONAL_BOUND * colj[kv]
    if not bound > 0.0:
        return False
    for i in range(1, km + 1):
        sii = ab[j + i, kv]
        x = colj[kv + i]
        if not (sii > 0.0 and x * x <= bound * sii):
            return False
    for c in range(j + 1, last + 1):
        scc = ab[c, kv]
        x = ab[c, kv + j - c]
        if not (scc > 0.0 and x * x <= bound * scc):
            return False
    return True


@njit(cache=True)
def band_lu(ab: np.ndarray, n: int, kl: int, ku: int, ipiv: np.ndarray) -> int:
    """Factorise the banded matrix in place: ``P A = L U`` (pivots: module docstring).

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
        if not _diagonal_is_safe(ab, j, km, kv, max(ju, min(j + ku, n - 1))):
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
            for c in range(j + 1, ju + 1):
                colc = ab[c]
                base = kv + j - c
                ujc = colc[base]
                if ujc != 0.0:
                    below = colc[base + 1:base + 1 + km]
                    for i in range(km):
                        below[i] -= mult[i] * ujc
    return info


@njit(cache=True)
def band_solve(ab: np.ndarray, n: int, kl: int, ku: int, ipiv: np.ndarray, b: np.ndarray) -> None:
    """Solve ``A x = b`` in place (``b`` becomes ``x``) with the factors of :func:`band_lu`."""
    kv = kl + ku
    width = ku  # U's bandwidth: ku without row interchanges (no fill-in), else up to kl + ku
    for j in range(n):
        if ipiv[j] != j:
            width = kv
            break
    for j in range(n):
        p = ipiv[j]
        if p != j:
            tmp = b[p]
            b[p] = b[j]
            b[j] = tmp
        bj = b[j]
        if bj != 0.0:
            km = min(kl, n - 1 - j)
            for i in range(1, km + 1):
                b[j + i] -= ab[j, kv + i] * bj
    for j in range(n - 1, -1, -1):
        b[j] /= ab[j, kv]
        bj = b[j]
        if bj != 0.0:
            lim = min(width, j)
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
