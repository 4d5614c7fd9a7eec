"""The loads of :mod:`towcable_fmu.hydro.cable` integrated along each ANCF element, W(78)-(80).

Quadrature: the segment's ``N_I`` equally spaced points with trapezoidal weights; an
interval that crosses the waterline contributes the trapezoid between its submerged
point and the crossing (found by linear interpolation of the height), W(78)-(80),
so the load changes continuously as an element enters or leaves the water. An element
whose Bezier control polygon lies entirely above the surface is dry and skipped.

This is the still-water quadrature (current and turbulence); a scene with waves runs
:mod:`.wave_quadrature` instead, chosen once per call by :mod:`.hydrodynamics`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...hydro.cable import Section, point_load, point_tangent, unit_direction
from ...hydro.water import WaterModel
from ...jit.kernel_cache import njit
from ..partial import active_quadrature, add_point_block, crossing_stiffness, hermite, interpolate


class CableHydro(NamedTuple):
    """Per-element hydrodynamic properties (``enabled`` False: a dry scene)."""

    enabled: bool
    el_on: np.ndarray      #: (ne,) bool: element can carry hydrodynamic loads
    el_kind: np.ndarray    #: (ne,) loading functions (loading.BARE / FAIRED)
    el_d: np.ndarray       #: (ne,) diameter [m]
    el_area: np.ndarray    #: (ne,) pi d^2 / 4 [m^2]
    el_cd: np.ndarray      #: (ne,) constant C_D, or 0 for C_D(Re)
    el_cdt: np.ndarray     #: (ne,) tangential C_Dt on pi d (loading NORMAL_TANGENTIAL; else unused)
    el_g: np.ndarray       #: (ne,) drag amplification G
    el_cm: np.ndarray      #: (ne,) added mass coefficient C_m
    el_npts: np.ndarray    #: (ne,) integration points N_I
    calls: np.ndarray      #: (1,) int64 counter of point evaluations (to verify skipping)
    #: (ne, 2 max N_I, :data:`~.wave_quadrature.REF_SIZE`) the waves' references of a time step
    #: (:mod:`.wave_quadrature`; no rows in still water)
    wave_ref: np.ndarray
    wave_stamp: np.ndarray  #: (ne, 2 max N_I, 2) int64: the generation a reference belongs to
    wave_clock: np.ndarray  #: (2,) the time [s] of the references and their generation


@njit(cache=True, inline="always")
def element_section(hy: CableHydro, e: int) -> Section:
    """Element ``e``'s cross-section."""
    return Section(hy.el_kind[e], hy.el_d[e], hy.el_area[e], hy.el_cd[e], hy.el_g[e], hy.el_cm[e], hy.el_cdt[e])


@njit(cache=True, inline="always")
def _is_dry(w: WaterModel, x: np.ndarray, base: int, length: float) -> bool:
    """Convex-hull test: all Bezier control points of the element above the surface."""
    z0 = x[base + 2]
    z1 = x[base + 8]
    c0 = z0 + length * x[base + 5] / 3.0
    c1 = z1 - length * x[base + 11] / 3.0
    return min(min(z0, z1), min(c0, c1)) > w.surface_z


@njit(cache=True, inline="always")
def _quadrature(w: WaterModel, x: np.ndarray, base: int, length: float, npts: int, xi: np.ndarray,
                wt: np.ndarray, g: np.ndarray, cross: np.ndarray) -> int:
    """Submerged quadrature points of one element (indicator: depth below the surface)."""
    for j in range(npts):
        s = j / (npts - 1)
        s2 = s * s
        s3 = s2 * s
        z = ((1.0 - 3.0 * s2 + 2.0 * s3) * x[base + 2] + length * (s - 2.0 * s2 + s3) * x[base + 5]
             + (3.0 * s2 - 2.0 * s3) * x[base + 8] + length * (s3 - s2) * x[base + 11])
        g[j] = w.surface_z - z
    return active_quadrature(length, npts, g, xi, wt, cross)


@njit(cache=True)
def add_residual(w: WaterModel, hy: CableHydro, el_len: np.ndarray, q: np.ndarray, v: np.ndarray,
                 a: np.ndarray, t: float, first: int, stop: int, out: np.ndarray) -> None:
    """Subtract the generalised hydrodynamic force (and add the added-mass inertia) of the
    submerged elements ``first`` to ``stop - 1`` from the residual ``out``."""
    m = 2 * hy.el_npts.max()
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    evaluations = 0
    for e in range(first, stop):
        if not hy.el_on[e]:
            continue
        base = 6 * e
        length = el_len[e]
        if _is_dry(w, q, base, length):
            continue
        count = _quadrature(w, q, base, length, hy.el_npts[e], xi, wt, g, cross)
        section = element_section(hy, e)
        for p in range(count):
            wp = wt[p]
            if wp == 0.0:
                continue
            n0, n1, n2, n3, d0, d1, d2, d3 = hermite(xi[p], length)
            rz = interpolate(q, base, n0, n1, n2, n3)[2]
            fx, fy, fz = point_load(w, section, t, rz, interpolate(q, base, d0, d1, d2, d3),
                                    interpolate(v, base, n0, n1, n2, n3), interpolate(a, base, n0, n1, n2, n3))
            evaluations += 1
            for i, ni in enumerate((n0, n1, n2, n3)):
                k = wp * ni
                out[base + 3 * i] -= k * fx
                out[base + 3 * i + 1] -= k * fy
                out[base + 3 * i + 2] -= k * fz
    hy.calls[0] += evaluations


@njit(cache=True)
def add_jacobians(w: WaterModel, hy: CableHydro, el_len: np.ndarray, q: np.ndarray, v: np.ndarray, t: float,
                  ca: float, cv: float, cq: float, blocks: np.ndarray, wet: np.ndarray) -> None:
    """Every element's hydrodynamic part of ``ca M + cv C + cq K``: element e's 12x12 block
    in ``blocks[e]`` (ne, 12, 12) and ``wet[e]`` (ne,) True, or ``wet[e]`` False (block
    not written) for a dry element or one without hydrodynamic loads.

    Added mass exactly (W(74)); the exact derivatives of the point load with respect to the
    point velocity, the cable slope and the height (:func:`point_tangent`); the stiffness
    of the moving waterline crossing from the derivative of the wet length. One call per
    matrix: the work arrays are allocated once for all elements.
    """
    npts_max = hy.el_npts.max()
    m = 2 * npts_max
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    fpt = np.empty((m, 3))
    dg = np.zeros((npts_max, 3))
    dg[:, 2] = -1.0  # g = surface - z
    on_point = np.empty((3, 3))  # the load's derivative with respect to the point (added mass, velocity, height)
    on_slope = np.empty((3, 3))
    evaluations = 0
    for e in range(el_len.shape[0]):
        wet[e] = False
        if not hy.el_on[e]:
            continue
        base = 6 * e
        length = el_len[e]
        if _is_dry(w, q, base, length):
            continue
        wet[e] = True
        ke = blocks[e]
        ke[:, :] = 0.0
        npts = hy.el_npts[e]
        fpt[:2 * npts] = 0.0
        count = _quadrature(w, q, base, length, npts, xi, wt, g, cross)
        section = element_section(hy, e)
        rho_a_cm = w.density * section.area * section.cm
        for p in range(count):
            wp = wt[p]
            if wp == 0.0:
                continue
            n = hermite(xi[p], length)
            rz = interpolate(q, base, n[0], n[1], n[2], n[3])[2]
            slope = interpolate(q, base, n[4], n[5], n[6], n[7])
            f, dv, dp, dz = point_tangent(w, section, t, rz, slope, interpolate(v, base, n[0], n[1], n[2], n[3]))
            fpt[p, 0], fpt[p, 1], fpt[p, 2] = f
            u = unit_direction(slope)
            for c in range(3):
                for k in range(3):
                    mass = rho_a_cm * ((1.0 if c == k else 0.0) - u[c] * u[k])
                    on_point[c, k] = ca * mass - cv * dv[3 * c + k]
                    on_slope[c, k] = -cq * dp[3 * c + k]
                on_point[c, 2] -= cq * dz[c]
            add_point_block(ke, wp, n, on_point, on_slope, True)
        if cq != 0.0:
            crossing_stiffness(length, npts, cq, xi, g, dg, cross, fpt, count, ke)
        evaluations += count
    hy.calls[0] += evaluations
