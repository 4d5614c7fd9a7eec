"""Quadrature over the part of an element where a load acts (W(78)-(80), W(103)-(106)).

A distributed load acts where an indicator ``g(p) > 0`` (submerged: depth below the
surface; contact: penetration, and height below the groove top). The element carries
``N_I`` equally spaced points with trapezoidal weights; an interval whose end points
disagree on the sign of ``g`` contributes the trapezoid between its active point and the
crossing, located by linear interpolation of ``g``. The integrated load then changes
continuously as the active part grows or shrinks: no impulse when an element enters
the water or touches a surface.

The crossing moves with the element's coordinates, so the integral has a stiffness
of its own: :func:`crossing_stiffness` adds it to the iteration matrix (without it,
Newton stalls on a cable resting across the waterline).
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit


# Scalars only: a plain kernel (LLVM inlines it), not IR-inlined at each of its many call sites.
@njit(cache=True)
def hermite(xi: float, length: float) -> tuple:
    """(N_0..N_3, dN_0/dp..dN_3/dp) at xi for an element of length L."""
    xi2 = xi * xi
    xi3 = xi2 * xi
    return (1.0 - 3.0 * xi2 + 2.0 * xi3, length * (xi - 2.0 * xi2 + xi3), 3.0 * xi2 - 2.0 * xi3,
            length * (xi3 - xi2), (-6.0 * xi + 6.0 * xi2) / length, 1.0 - 4.0 * xi + 3.0 * xi2,
            (6.0 * xi - 6.0 * xi2) / length, 3.0 * xi2 - 2.0 * xi)


@njit(cache=True, inline="always")
def interpolate(x: np.ndarray, base: int, n0: float, n1: float, n2: float, n3: float) -> tuple:
    """sum_i n_i x[base + 3 i : base + 3 i + 3] as a 3-tuple."""
    return (n0 * x[base] + n1 * x[base + 3] + n2 * x[base + 6] + n3 * x[base + 9],
            n0 * x[base + 1] + n1 * x[base + 4] + n2 * x[base + 7] + n3 * x[base + 10],
            n0 * x[base + 2] + n1 * x[base + 5] + n2 * x[base + 8] + n3 * x[base + 11])


@njit(cache=True, inline="always")
def add_point_block(ke: np.ndarray, wp: float, n: tuple, a: np.ndarray, b: np.ndarray, slope: bool) -> None:
    """Add one quadrature point's tangent to the element block ``ke`` (12x12):
    ``ke[3i+c, 3j+k] += wp N_i (N_j a[c, k] + N_j' b[c, k])``.

    ``n`` is :func:`hermite`'s tuple at the point, ``wp`` its weight [m]; ``a`` (3, 3) is
    the derivative of the point load with respect to the point's position (and velocity,
    acceleration: scaled by the caller), ``b`` (3, 3) with respect to its slope, used only
    with ``slope``. The 3x3 blocks are combined once per point, not once per node pair.
    """
    for i in range(4):
        wi = wp * n[i]
        for j in range(4):
            nn = wi * n[j]
            nd = wi * n[4 + j]
            for c in range(3):
                for k in range(3):
                    if slope:
                        ke[3 * i + c, 3 * j + k] += nn * a[c, k] + nd * b[c, k]
                    else:
                        ke[3 * i + c, 3 * j + k] += nn * a[c, k]


@njit(cache=True)
def active_quadrature(length: float, npts: int, g: np.ndarray, xi: np.ndarray, wt: np.ndarray,
                      cross: np.ndarray) -> int:
    """Quadrature points (xi, weight [m]) of the active part of an element.

    Parameters
    ----------
    length
        Element length L [m].
    npts
        Number of equally spaced points N_I (>= 2).
    g
        Indicator at the points, shape (>= npts,); active where g > 0.
    xi, wt
        Output normalised positions and weights, shape (>= 2 npts,): the first ``npts``
        entries are the grid points (weight 0 where inactive), then the crossings.
    cross
        Output: for each crossing point (index >= npts), the interval it lies in.

    Returns
    -------
    int
        Number of points written (npts plus the crossings).
    """
    step = length / (npts - 1)
    for j in range(npts):
        xi[j] = j / (npts - 1)
        wt[j] = 0.0
    count = npts
    for j in range(npts - 1):
        ga, gb = g[j], g[j + 1]
        if ga > 0.0 and gb > 0.0:
            wt[j] += 0.5 * step
            wt[j + 1] += 0.5 * step
        elif ga > 0.0 or gb > 0.0:
            xi_c = (j + ga / (ga - gb)) / (npts - 1)
            act = j if ga > 0.0 else j + 1
            half = 0.5 * abs(xi_c - xi[act]) * length
            wt[act] += half
            xi[count] = xi_c
            wt[count] = half
            cross[count] = j
            count += 1
    return count


@njit(cache=True)
def crossing_stiffness(length: float, npts: int, scale: float, xi: np.ndarray, g: np.ndarray,
                       dg: np.ndarray, cross: np.ndarray, fpt: np.ndarray, count: int, ke: np.ndarray) -> None:
    """Add ``-scale * dQ/dx`` of the moving crossings to the element block ``ke`` (12x12).

    Parameters
    ----------
    g, dg
        Indicator at the grid points and its gradient with respect to the point position,
        shapes (npts,) and (npts, 3).
    fpt
        Load per unit length at every quadrature point, shape (count, 3) [N/m].
    Other parameters as in :func:`active_quadrature` (its outputs).
    """
    for p in range(npts, count):
        j = cross[p]
        ga, gb = g[j], g[j + 1]
        act = j if ga > 0.0 else j + 1
        dl = length if act == j else -length  # d(active length) / d(xi_c)
        denom = (ga - gb) ** 2 * (npts - 1)
        na = hermite(j / (npts - 1), length)
        nb = hermite((j + 1) / (npts - 1), length)
        nw = hermite(xi[act], length)
        nc = hermite(xi[p], length)
        for i in range(4):
            for m in range(3):
                # d xi_c / d x_(i,m) from xi_c = (j + ga / (ga - gb)) / (N_I - 1)
                dxi = (ga * nb[i] * dg[j + 1, m] - gb * na[i] * dg[j, m]) / denom
                if dxi == 0.0:
                    continue
                for k in range(4):
                    for c in range(3):
                        dq = 0.5 * dl * (nw[k] * fpt[act, c] + nc[k] * fpt[p, c])
                        ke[3 * k + c, 3 * i + m] -= scale * dq * dxi
