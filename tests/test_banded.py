"""Banded LU factorisation against a dense solve."""

from __future__ import annotations

import numpy as np
import pytest

from towcable_fmu.numerics.banded import band_add, band_lu, band_solve, band_storage, band_to_dense


@pytest.mark.parametrize("n,kl,ku", [(40, 11, 11), (25, 3, 5), (9, 0, 0), (30, 6, 1)])
def test_band_lu_solves_random_banded_systems(n, kl, ku):
    rng = np.random.default_rng(n + kl)
    a = np.zeros((n, n))
    ab = band_storage(n, kl, ku)
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            a[i, j] = rng.normal()
            band_add(ab, kl, ku, i, j, a[i, j])
    np.testing.assert_array_equal(band_to_dense(ab, kl, ku), a)
    b = rng.normal(size=n)
    x = b.copy()
    ipiv = np.zeros(n, dtype=np.int64)
    assert band_lu(ab, n, kl, ku, ipiv) == 0
    band_solve(ab, n, kl, ku, ipiv, x)
    np.testing.assert_allclose(x, np.linalg.solve(a, b), rtol=1e-9, atol=1e-9)


def test_band_lu_reports_singular_matrix():
    n, kl, ku = 5, 1, 1
    ab = band_storage(n, kl, ku)
    ab[:, kl + ku] = [1, 1, 0, 1, 1]  # the diagonal: a zero pivot in column 2 with nothing to swap in
    assert band_lu(ab, n, kl, ku, np.zeros(n, dtype=np.int64)) == 3


def _banded(a, kl, ku):
    n = a.shape[0]
    ab = band_storage(n, kl, ku)
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            band_add(ab, kl, ku, i, j, a[i, j])
    return ab


def _scaled_positive_definite(n, k, seed):
    """D S D with S symmetric, positive definite and banded (k), D spanning six decades."""
    rng = np.random.default_rng(seed)
    s = np.zeros((n, n))
    for i in range(n):
        for j in range(max(0, i - k), i):
            s[i, j] = s[j, i] = rng.normal()
    s += np.diag(np.abs(s).sum(axis=1) + 0.1)
    d = 10.0 ** rng.uniform(-3.0, 3.0, n)
    return d[:, None] * s * d[None, :]


def test_band_lu_keeps_the_diagonal_of_a_badly_scaled_positive_definite_matrix():
    n, k = 60, 11
    a = _scaled_positive_definite(n, k, 1)
    col_max = np.abs(a).max(axis=0)
    assert np.any(np.abs(np.diag(a)) < 0.01 * col_max)  # partial pivoting would swap rows here
    ab = _banded(a, k, k)
    ipiv = np.zeros(n, dtype=np.int64)
    assert band_lu(ab, n, k, k, ipiv) == 0
    np.testing.assert_array_equal(ipiv, np.arange(n))  # no interchange: U keeps bandwidth k
    assert not ab[:, :k].any()  # and no fill-in
    b = np.random.default_rng(2).normal(size=n)
    x = b.copy()
    band_solve(ab, n, k, k, ipiv, x)
    np.testing.assert_allclose(a @ x, b, rtol=0, atol=1e-10 * np.abs(a).max() * np.abs(x).max())


def test_band_lu_pivots_the_columns_whose_diagonal_fails_the_test():
    n, k = 60, 11
    a = _scaled_positive_definite(n, k, 3)
    a[20, 20] = 0.0  # no diagonal pivot possible in column 20
    a[41, 41] *= -1.0  # nor a positive one in 41
    ab = _banded(a, k, k)
    ipiv = np.zeros(n, dtype=np.int64)
    assert band_lu(ab, n, k, k, ipiv) == 0
    # columns 0-8 see neither bad row and keep their diagonal; the test sends the others to partial pivoting
    np.testing.assert_array_equal(ipiv[:9], np.arange(9))
    assert np.any(ipiv != np.arange(n))
    b = np.random.default_rng(4).normal(size=n)
    x = b.copy()
    band_solve(ab, n, k, k, ipiv, x)
    np.testing.assert_allclose(x, np.linalg.solve(a, b), rtol=1e-8, atol=1e-8 * np.abs(np.linalg.solve(a, b)).max())
