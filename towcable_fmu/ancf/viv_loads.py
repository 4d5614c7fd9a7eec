"""Oscillating drag and lift of the wake, eq. A20, as generalised forces on the cable.

Per unit length at a node with wake rate w' and acceleration w'' (free stream U, fluid
density rho, diameter d, Strouhal number St):

    f_SW = -(C_D0 rho d^4 / (32 pi^3 St^3 U)) w' w''   along the flow (stream-wise)
    f_CF =  (C_L0 rho U d^2 / (8 pi St)) w'            along the cross-flow direction

Both are dimensionally N/m with w dimensionless (A20 as printed; no correction). On the
limit cycle ``w = A cos(w_st t)`` they are ``C_L0 (A/2) (rho U^2 d / 2)`` in amplitude
across the flow (at w_st) and ``C_D0 (A^2/4) (rho U^2 d / 2)`` along it (at 2 w_st), i.e.
lift and drag coefficients C_L0 and C_D0 for the van der Pol amplitude A = 2.

As the thesis says, the nodal values are interpolated linearly along each element; the
element load is then integrated with the segment's N_I equally spaced trapezoidal points
(weights L/(N_I - 1), as for the other distributed loads, W(78)). The load depends on
the wake only, not on the cable coordinates, so the map from nodal forces to
generalised forces is a constant (k, 4, 2) table built once.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit.kernel_cache import njit
from . import element


def force_factors(rho: float, speed: float, diameter: float, strouhal: float, cd0: float,
                  cl0: float) -> tuple[float, float]:
    """Factors of A20: ``f_SW = -k_sw w' w''`` and ``f_CF = k_cf w'``.

    Returns
    -------
    k_sw, k_cf
        [kg s] and [kg/s] (so that the forces are N/m).
    """
    k_sw = cd0 * rho * diameter**4 / (32.0 * math.pi**3 * strouhal**3 * speed)
    k_cf = cl0 * rho * speed * diameter**2 / (8.0 * math.pi * strouhal)
    return k_sw, k_cf


def interpolation_table(lengths: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Generalised-force weights of linearly interpolated nodal loads, per element.

    Parameters
    ----------
    lengths
        Element lengths [m], shape (k,).
    points
        Integration points N_I per element, shape (k,).

    Returns
    -------
    ndarray, shape (k, 4, 2)
        ``B[e, i, j]``: generalised force on shape function i (position, slope, position,
        slope) per unit nodal force per length at the element's node j (start, end)
        [m, m^2 for slopes].
    """
    out = np.zeros((lengths.size, 4, 2))
    for e, (length, npts) in enumerate(zip(lengths, points)):
        xi = np.linspace(0.0, 1.0, int(npts))
        wt = np.full(xi.size, length / (xi.size - 1))
        wt[[0, -1]] *= 0.5
        n = element.shape_functions(xi, length)  # (npts, 4)
        out[e, :, 0] = (wt * (1.0 - xi)) @ n
        out[e, :, 1] = (wt * xi) @ n
    return out


@njit(cache=True)
def nodal_forces(wd: np.ndarray, wdd: np.ndarray, k_sw: float, k_cf: float, e_sw: np.ndarray,
                 e_cf: np.ndarray, out: np.ndarray) -> None:
    """Force per unit length of A20 at each wake node, inertial frame [N/m], into ``out`` (m, 3)."""
    for i in range(wd.shape[0]):
        sw = -k_sw * wd[i] * wdd[i]
        cf = k_cf * wd[i]
        for c in range(3):
            out[i, c] = sw * e_sw[c] + cf * e_cf[c]


@njit(cache=True)
def add_generalised(fnode: np.ndarray, elements: np.ndarray, node_a: np.ndarray, node_b: np.ndarray,
                    table: np.ndarray, out: np.ndarray) -> None:
    """Add the generalised forces of the interpolated nodal loads to ``out`` (full coordinates) [N].

    Parameters
    ----------
    fnode
        Force per unit length at the wake nodes [N/m], shape (m, 3).
    elements
        Loaded element indices, shape (k,).
    node_a, node_b
        Wake-node index of each loaded element's start and end node, shape (k,).
    table
        :func:`interpolation_table` of the loaded elements, shape (k, 4, 2).
    out
        Generalised force vector over all coordinates, added to.
    """
    for k in range(elements.shape[0]):
        base = 6 * elements[k]
        a, b = node_a[k], node_b[k]
        for i in range(4):
            for c in range(3):
                out[base + 3 * i + c] += table[k, i, 0] * fnode[a, c] + table[k, i, 1] * fnode[b, c]
