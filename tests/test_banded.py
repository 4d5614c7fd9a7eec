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
