"""Longitudinal elastic force with the decoupled strain of Yue et al., W(42)-(47).

The element's axial deformation is represented by a one-dimensional Hermite element
with nodal values ``q_delta = [0, |r_p(0)|, s, |r_p(L)|]`` where ``s`` is the arc length
of the deformed element; its Green strain ``eps = (lambda^2 - 1) / 2`` with
``lambda = dr_delta/dp`` does not couple to curvature. The energy is
``U = EA/2 * int eps^2 dp`` and the force its exact gradient: the axial force is
``N = dU/dlambda = EA eps lambda``. The Kelvin-Voigt law of the snapping case and MoorDyn
(segment ``axial_law = "kelvin_voigt"``) uses the engineering strain instead,
``U = EA/2 * int (lambda - 1)^2 dp`` and ``N = EA (lambda - 1)``: the two agree to first
order, but the Green law's tangent ``EA (3 lambda^2 - 1) / 2`` is stiffer by ``3 eps``
(0.2 % at the snapping case's static strain, 1 % in its snaps).

Quadrature: Gauss-Legendre (5 points by default). The integrands of W(46) are
polynomials of degree 8 in xi once the three scalars (|r_p(0)|, s, |r_p(L)|) are
known, so 5 Gauss points integrate them exactly; only the arc length ``s`` itself is
approximated. The reference used trapezoidal weights; this is a quadrature choice,
not a model change, and it is checked by the tests (exact arc length of a circular
arc, energy gradient against finite differences).

All kernels read one element's 12 nodal coordinates ``[r0, r0_p, r1, r1_p]`` from a
coordinate vector ``x`` starting at index ``base``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..jit.kernel_cache import njit

_TINY = 1e-300


@njit(cache=True, inline="always")
def slope_derivatives(gauss_dn: np.ndarray, length: float, d: np.ndarray) -> None:
    """dN_i/dp at the quadrature points for an element of length L.

    Parameters
    ----------
    gauss_dn
        dn_i/dxi of the normalised Hermite functions at the points, shape (ng, 4).
    length
        Element length L [m].
    d
        Output, shape (ng, 4).
    """
    for g in range(gauss_dn.shape[0]):
        d[g, 0] = gauss_dn[g, 0] / length
        d[g, 1] = gauss_dn[g, 1]
        d[g, 2] = gauss_dn[g, 2] / length
        d[g, 3] = gauss_dn[g, 3]


#: columns where the gradients of (a0, s, a1) can be non-zero (from, to)
_GRAD_FROM = (3, 0, 9)
_GRAD_TO = (6, 12, 12)


class AxialWork(NamedTuple):
    """The Gauss quadrature of the axial kernels and their scratch arrays (ng points).

    ``d`` holds the element whose length was last given to :func:`at_length`.
    """

    dn: np.ndarray      #: (ng, 4) dn_i/dxi of the normalised Hermite functions at the points
    gw: np.ndarray      #: (ng,) Gauss weights on [0, 1]
    d: np.ndarray       #: (ng, 4) dN_i/dp at the points (:func:`slope_derivatives`)
    lam: np.ndarray     #: (ng,) slope norms |r_p|
    u: np.ndarray       #: (ng, 3) unit tangents
    grad: np.ndarray    #: (3, 12) gradients of (a0, s, a1), scratch of :func:`axial_tangent`
    first: np.ndarray   #: (3,) first derivatives of U/EA, scratch
    hess: np.ndarray    #: (3, 3) second derivatives of U/EA, scratch
    blocks: np.ndarray  #: (4, 4, 6) symmetric 3x3 blocks (xx, xy, xz, yy, yz, zz) of the arc term, scratch


@njit(cache=True, inline="always")
def axial_work(gauss_dn: np.ndarray, gauss_w: np.ndarray) -> AxialWork:
    """Work arrays for the quadrature ``gauss_dn`` (ng, 4), ``gauss_w`` (ng,)."""
    ng = gauss_w.shape[0]
    return AxialWork(gauss_dn, gauss_w, np.empty((ng, 4)), np.empty(ng), np.empty((ng, 3)), np.empty((3, 12)),
                     np.empty(3), np.empty((3, 3)), np.empty((4, 4, 6)))


@njit(cache=True, inline="always")
def tension_of_strain(ea: float, eps: float, engineering: bool) -> float:
    """Axial force [N] at the Green strain ``eps`` [-]: ``EA eps lambda`` (Green law) or
    ``EA (lambda - 1)`` (``engineering``: the Kelvin-Voigt law's elastic part), with
    ``lambda = sqrt(1 + 2 eps)``."""
    lam = math.sqrt(max(1.0 + 2.0 * eps, 0.0))
    return ea * (lam - 1.0) if engineering else ea * eps * lam


@njit(cache=True, inline="always")
def energy_of_strain(ea: float, eps: float, engineering: bool) -> float:
    """Strain energy per unstretched length [J/m] at the Green strain ``eps`` [-]:
    ``EA eps^2 / 2`` or ``EA (lambda - 1)^2 / 2`` (``engineering``)."""
    if engineering:
        stretch = math.sqrt(max(1.0 + 2.0 * eps, 0.0)) - 1.0
        return 0.5 * ea * stretch * stretch
    return 0.5 * ea * eps * eps


@njit(cache=True, inline="always")
def at_length(work: AxialWork, length: float) -> None:
    """Set ``work.d`` for an element of length ``length`` [m]."""
    slope_derivatives(work.dn, length, work.d)


@njit(cache=True, inline="always")
def _kinematics(x, base, d, length, gw, lam, u):
    """Slope norms at the points and the three decoupled coordinates (a0, s, a1)."""
    ng = d.shape[0]
    s = 0.0
    for g in range(ng):
        n2 = 0.0
        for k in range(3):
            v = (d[g, 0] * x[base + k] + d[g, 1] * x[base + 3 + k] + d[g, 2] * x[base + 6 + k]
                 + d[g, 3] * x[base + 9 + k])
            u[g, k] = v
            n2 += v * v
        lg = math.sqrt(n2)
        lam[g] = lg
        inv = 1.0 / max(lg, _TINY)
        for k in range(3):
            u[g, k] *= inv
        s += gw[g] * length * lg
    a0 = math.sqrt(x[base + 3] ** 2 + x[base + 4] ** 2 + x[base + 5] ** 2)
    a1 = math.sqrt(x[base + 9] ** 2 + x[base + 10] ** 2 + x[base + 11] ** 2)
    return a0, s, a1


@njit(cache=True, inline="always")
def axial_force(x: np.ndarray, base: int, length: float, ea: float, tension_only: bool, engineering: bool,
                work: AxialWork, f: np.ndarray) -> float:
    """Generalised longitudinal elastic force W(46) of one element, added to ``f``.

    Parameters
    ----------
    x, base
        Coordinates [m, -, m, -]; the element's 12 start at ``base``.
    length, ea
        Unstretched length L [m] and axial stiffness EA [N].
    tension_only
        If true, compressive strain carries no force (slack cable).
    engineering
        If true, the engineering-strain law ``N = EA (lambda - 1)`` (module docstring), else
        the Green law ``N = EA eps lambda``.
    work
        The quadrature, set for this element's length (:func:`at_length`), and scratch.
    f
        Output force, shape (12,) [N, N m]: the force is ADDED.

    Returns
    -------
    (float, int)
        Strain energy U of the element [J]; for a tension-only element the bit mask of the
        Gauss points that carry force (bit g: point g is taut), else 0.
    """
    d, gw, u = work.d, work.gw, work.u
    a0, s, a1 = _kinematics(x, base, d, length, gw, work.lam, u)
    ca = 0.0
    cs = 0.0
    c1 = 0.0
    energy = 0.0
    taut = 0
    for g in range(d.shape[0]):
        ld = d[g, 1] * a0 + d[g, 2] * s + d[g, 3] * a1
        eps = 0.5 * (ld * ld - 1.0)
        if tension_only:
            if eps < 0.0:
                continue
            taut |= 1 << g
        wl = gw[g] * length
        if engineering:
            energy += 0.5 * ea * wl * (ld - 1.0) * (ld - 1.0)
            k = wl * (ld - 1.0)
        else:
            energy += 0.5 * ea * wl * eps * eps
            k = wl * eps * ld
        ca += k * d[g, 1]
        cs += k * d[g, 2]
        c1 += k * d[g, 3]
    ca *= ea
    cs *= ea
    c1 *= ea
    inv0 = 1.0 / max(a0, _TINY)
    inv1 = 1.0 / max(a1, _TINY)
    for k in range(3):
        f[3 + k] += ca * x[base + 3 + k] * inv0
        f[9 + k] += c1 * x[base + 9 + k] * inv1
    for g in range(d.shape[0]):
        w = cs * gw[g] * length
        for i in range(4):
            wi = w * d[g, i]
            for k in range(3):
                f[3 * i + k] += wi * u[g, k]
    return energy, taut


@njit(cache=True)
def axial_tangent(x: np.ndarray, base: int, length: float, ea: float, tension_only: bool, engineering: bool,
                  work: AxialWork, scale: float, kmat: np.ndarray) -> int:
    """Tangent stiffness dQ_l/dx of :func:`axial_force`, times ``scale``, added to ``kmat`` (12, 12)
    (arguments as :func:`axial_force`); returns the taut points' bit mask as :func:`axial_force` does."""
    d, gw, lam, u, grad, first, hess = work.d, work.gw, work.lam, work.u, work.grad, work.first, work.hess
    a0, s, a1 = _kinematics(x, base, d, length, gw, lam, u)
    ng = d.shape[0]
    # gradients of the decoupled coordinates (a0, s, a1) with respect to x
    grad[:, :] = 0.0
    inv0 = 1.0 / max(a0, _TINY)
    inv1 = 1.0 / max(a1, _TINY)
    for k in range(3):
        grad[0, 3 + k] = x[base + 3 + k] * inv0
        grad[2, 9 + k] = x[base + 9 + k] * inv1
    for g in range(ng):
        wl = gw[g] * length
        for i in range(4):
            for k in range(3):
                grad[1, 3 * i + k] += wl * d[g, i] * u[g, k]
    # first and second derivatives of U/EA with respect to (a0, s, a1)
    first[:] = 0.0
    hess[:, :] = 0.0
    taut = 0
    for g in range(ng):
        ld = d[g, 1] * a0 + d[g, 2] * s + d[g, 3] * a1
        eps = 0.5 * (ld * ld - 1.0)
        if tension_only:
            if eps < 0.0:
                continue
            taut |= 1 << g
        wl = gw[g] * length
        if engineering:
            k1 = wl * (ld - 1.0)
            k2 = wl
        else:
            k1 = wl * eps * ld
            k2 = wl * (ld * ld + eps)
        for a in range(3):
            first[a] += k1 * d[g, a + 1]
            for b in range(3):
                hess[a, b] += k2 * d[g, a + 1] * d[g, b + 1]
    c = ea * scale
    # grad[0] is non-zero in columns 3-5 only (the slope at node 0), grad[2] in 9-11
    for a in range(3):
        for b in range(3):
            hab = c * hess[a, b]
            if hab != 0.0:
                for i in range(_GRAD_FROM[a], _GRAD_TO[a]):
                    gi = hab * grad[a, i]
                    for j in range(_GRAD_FROM[b], _GRAD_TO[b]):
                        kmat[i, j] += gi * grad[b, j]
    # curvature of the norms: d2|v|/dv2 = (I - u u^T)/|v|
    for k in range(3):
        for m in range(3):
            delta = 1.0 if k == m else 0.0
            kmat[3 + k, 3 + m] += c * first[0] * (delta - x[base + 3 + k] * x[base + 3 + m] * inv0 * inv0) * inv0
            kmat[9 + k, 9 + m] += c * first[2] * (delta - x[base + 9 + k] * x[base + 9 + m] * inv1 * inv1) * inv1
    cs = c * first[1]
    if cs != 0.0:
        # sum_g w_g d_gi d_gj (I - u_g u_g^T): symmetric blocks, symmetric in (i, j); summed
        # over the points first and written once
        blocks = work.blocks
        blocks[:, :, :] = 0.0
        for g in range(ng):
            w = cs * gw[g] * length / max(lam[g], _TINY)
            ux, uy, uz = u[g, 0], u[g, 1], u[g, 2]
            p0, p1, p2, p3, p4, p5 = 1.0 - ux * ux, -ux * uy, -ux * uz, 1.0 - uy * uy, -uy * uz, 1.0 - uz * uz
            for i in range(4):
                wi = w * d[g, i]
                for j in range(i, 4):
                    wij = wi * d[g, j]
                    b = blocks[i, j]
                    b[0] += wij * p0
                    b[1] += wij * p1
                    b[2] += wij * p2
                    b[3] += wij * p3
                    b[4] += wij * p4
                    b[5] += wij * p5
        for i in range(4):
            for j in range(4):
                b = blocks[min(i, j), max(i, j)]
                r = 3 * i
                col = 3 * j
                kmat[r, col] += b[0]
                kmat[r, col + 1] += b[1]
                kmat[r, col + 2] += b[2]
                kmat[r + 1, col] += b[1]
                kmat[r + 1, col + 1] += b[3]
                kmat[r + 1, col + 2] += b[4]
                kmat[r + 2, col] += b[2]
                kmat[r + 2, col + 1] += b[4]
                kmat[r + 2, col + 2] += b[5]
    return taut


@njit(cache=True)
def axial_strains(x: np.ndarray, base: int, length: float, work: AxialWork, dn_at: np.ndarray,
                  out: np.ndarray) -> None:
    """Decoupled Green strain W(45) at points of the element.

    Parameters
    ----------
    x, base, length, work
        As :func:`axial_force`.
    dn_at
        dn_i/dxi of the normalised Hermite functions at the points, shape (k, 4).
    out
        Output strains eps [-], shape (k,).
    """
    a0, s, a1 = _kinematics(x, base, work.d, length, work.gw, work.lam, work.u)
    for k in range(dn_at.shape[0]):
        ld = dn_at[k, 1] * a0 + dn_at[k, 2] / length * s + dn_at[k, 3] * a1
        out[k] = 0.5 * (ld * ld - 1.0)
