"""The loads of :mod:`towcable_fmu.hydro.cable` integrated along each ANCF element, W(78)-(80).

Quadrature: the segment's ``N_I`` equally spaced points with trapezoidal weights; an
interval that crosses the waterline contributes the trapezoid between its submerged
point and the crossing (found by linear interpolation of the depth below the surface),
W(78)-(80), so the load changes continuously as an element enters or leaves the water.
An element whose Bezier control polygon lies entirely above the highest crest is dry
and skipped.

In waves (:mod:`towcable_fmu.hydro.waves`) the waterline is the instantaneous surface
at each grid point of an element that reaches above the deepest trough, and every
point load sees the waves' velocity and acceleration there, evaluated at the iterate
(not frozen within the step: the residual is the exact one at every Newton iterate).
The iteration matrix differentiates both: the kinematics with respect to the point
(:func:`towcable_fmu.hydro.waves.wave_at`'s gradients) and the crossing's motion with
the surface's slope.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...hydro.cable import NO_WAVE, NO_WAVE_GRADIENT, Section, point_load, point_tangent, unit_direction
from ...hydro.water import WaterModel
from ...hydro.waves import DACC, DVEL, OUT_SIZE, VEL, ACC, scratch_size, surface_height, water_waves
from ...kernel_cache import njit
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


@njit(cache=True, inline="always")
def element_section(hy: CableHydro, e: int) -> Section:
    """Element ``e``'s cross-section."""
    return Section(hy.el_kind[e], hy.el_d[e], hy.el_area[e], hy.el_cd[e], hy.el_g[e], hy.el_cm[e], hy.el_cdt[e])


@njit(cache=True, inline="always")
def _is_dry(w: WaterModel, x: np.ndarray, base: int, length: float, t: float) -> bool:
    """Convex-hull test: all Bezier control points of the element above the highest crest,
    or in waves above the surface at the hull's centre plus its horizontal radius times
    the surface's steepest slope (a bound of the surface over the hull)."""
    z0 = x[base + 2]
    z1 = x[base + 8]
    c0 = z0 + length * x[base + 5] / 3.0
    c1 = z1 - length * x[base + 11] / 3.0
    low = min(min(z0, z1), min(c0, c1))
    if low > w.surface_z + w.wave_crest:
        return True
    if w.waves.shape[0] == 0:
        return False
    px = (x[base], x[base] + length * x[base + 3] / 3.0, x[base + 6] - length * x[base + 9] / 3.0, x[base + 6])
    py = (x[base + 1], x[base + 1] + length * x[base + 4] / 3.0, x[base + 7] - length * x[base + 10] / 3.0,
          x[base + 7])
    mx = 0.25 * (px[0] + px[1] + px[2] + px[3])
    my = 0.25 * (py[0] + py[1] + py[2] + py[3])
    radius = 0.0
    for i in range(4):
        radius = max(radius, math.hypot(px[i] - mx, py[i] - my))
    return low > surface_height(w, mx, my, t)[0] + radius * w.wave_slope


@njit(cache=True, inline="always")
def _in_waves(w: WaterModel, x: np.ndarray, base: int, length: float) -> bool:
    """Convex-hull test: some Bezier control point of the element above the deepest trough
    (its waterline is the instantaneous surface); False in still water."""
    if w.waves.shape[0] == 0:
        return False
    z0 = x[base + 2]
    z1 = x[base + 8]
    c0 = z0 + length * x[base + 5] / 3.0
    c1 = z1 - length * x[base + 11] / 3.0
    return max(max(z0, z1), max(c0, c1)) > w.surface_z - w.wave_crest


@njit(cache=True, inline="always")
def _quadrature(w: WaterModel, x: np.ndarray, base: int, length: float, npts: int, t: float, xi: np.ndarray,
                wt: np.ndarray, g: np.ndarray, dg: np.ndarray, cross: np.ndarray) -> int:
    """Submerged quadrature points of one element (indicator g: depth below the surface,
    its gradient dg with respect to the point)."""
    waves = _in_waves(w, x, base, length)
    for j in range(npts):
        s = j / (npts - 1)
        s2 = s * s
        s3 = s2 * s
        n0 = 1.0 - 3.0 * s2 + 2.0 * s3
        n1 = length * (s - 2.0 * s2 + s3)
        n2 = 3.0 * s2 - 2.0 * s3
        n3 = length * (s3 - s2)
        z = n0 * x[base + 2] + n1 * x[base + 5] + n2 * x[base + 8] + n3 * x[base + 11]
        if waves:
            surface, sx, sy = surface_height(w, n0 * x[base] + n1 * x[base + 3] + n2 * x[base + 6] + n3 * x[base + 9],
                                             n0 * x[base + 1] + n1 * x[base + 4] + n2 * x[base + 7]
                                             + n3 * x[base + 10], t)
            g[j] = surface - z
            dg[j, 0] = sx
            dg[j, 1] = sy
        else:
            g[j] = w.surface_z - z
            dg[j, 0] = 0.0
            dg[j, 1] = 0.0
        dg[j, 2] = -1.0
    return active_quadrature(length, npts, g, xi, wt, cross)


@njit(cache=True, inline="always")
def _point_waves(w: WaterModel, r: tuple, t: float, work: np.ndarray, out: np.ndarray) -> tuple:
    """The waves' velocity and acceleration at the point r (6-tuple; zeros in still water)."""
    if w.waves.shape[0] == 0:
        return NO_WAVE
    water_waves(w, r[0], r[1], r[2], t, False, work, out)
    return out[VEL], out[VEL + 1], out[VEL + 2], out[ACC], out[ACC + 1], out[ACC + 2]


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
    dg = np.empty((m, 3))
    work = np.empty(scratch_size(w.waves))
    kin = np.empty(OUT_SIZE)
    evaluations = 0
    for e in range(first, stop):
        if not hy.el_on[e]:
            continue
        base = 6 * e
        length = el_len[e]
        if _is_dry(w, q, base, length, t):
            continue
        count = _quadrature(w, q, base, length, hy.el_npts[e], t, xi, wt, g, dg, cross)
        section = element_section(hy, e)
        for p in range(count):
            wp = wt[p]
            if wp == 0.0:
                continue
            n0, n1, n2, n3, d0, d1, d2, d3 = hermite(xi[p], length)
            r = interpolate(q, base, n0, n1, n2, n3)
            fx, fy, fz = point_load(w, section, t, r[2], interpolate(q, base, d0, d1, d2, d3),
                                    interpolate(v, base, n0, n1, n2, n3), interpolate(a, base, n0, n1, n2, n3),
                                    _point_waves(w, r, t, work, kin))
            evaluations += 1
            for i, ni in enumerate((n0, n1, n2, n3)):
                k = wp * ni
                out[base + 3 * i] -= k * fx
                out[base + 3 * i + 1] -= k * fy
                out[base + 3 * i + 2] -= k * fz
    hy.calls[0] += evaluations


@njit(cache=True)
def add_jacobian(w: WaterModel, hy: CableHydro, el_len: np.ndarray, q: np.ndarray, v: np.ndarray, t: float,
                 e: int, ca: float, cv: float, cq: float, ke: np.ndarray) -> bool:
    """Add element e's hydrodynamic part of ``ca M + cv C + cq K`` to the 12x12 block ``ke``;
    False (nothing added) for a dry element or one without hydrodynamic loads.

    Added mass exactly (W(74)); the exact derivatives of the point load with respect to the
    point velocity, the cable slope and the position (:func:`point_tangent`, with the
    waves' gradients); the stiffness of the moving waterline crossing from the derivative
    of the wet length (the surface's slope included).
    """
    if not hy.el_on[e]:
        return False
    base = 6 * e
    length = el_len[e]
    if _is_dry(w, q, base, length, t):
        return False
    npts = hy.el_npts[e]
    m = 2 * npts
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    fpt = np.zeros((m, 3))
    dg = np.empty((m, 3))
    waves = w.waves.shape[0] > 0
    work = np.empty(scratch_size(w.waves))
    kin = np.empty(OUT_SIZE)
    count = _quadrature(w, q, base, length, npts, t, xi, wt, g, dg, cross)
    section = element_section(hy, e)
    rho_a_cm = w.density * section.area * section.cm
    on_point = np.empty((3, 3))  # the load's derivative with respect to the point (added mass, velocity, height)
    on_slope = np.empty((3, 3))
    for p in range(count):
        wp = wt[p]
        if wp == 0.0:
            continue
        n = hermite(xi[p], length)
        r = interpolate(q, base, n[0], n[1], n[2], n[3])
        slope = interpolate(q, base, n[4], n[5], n[6], n[7])
        wave = NO_WAVE
        dwave = NO_WAVE_GRADIENT
        if waves and water_waves(w, r[0], r[1], r[2], t, True, work, kin) > 0:
            wave = (kin[VEL], kin[VEL + 1], kin[VEL + 2], kin[ACC], kin[ACC + 1], kin[ACC + 2])
            dwave = (kin[DVEL], kin[DVEL + 1], kin[DVEL + 2], kin[DVEL + 3], kin[DVEL + 4], kin[DVEL + 5],
                     kin[DVEL + 6], kin[DVEL + 7], kin[DVEL + 8], kin[DACC], kin[DACC + 1], kin[DACC + 2],
                     kin[DACC + 3], kin[DACC + 4], kin[DACC + 5], kin[DACC + 6], kin[DACC + 7], kin[DACC + 8])
        f, dv, dp, dr = point_tangent(w, section, t, r[2], slope, interpolate(v, base, n[0], n[1], n[2], n[3]), wave,
                                      dwave)
        fpt[p, 0], fpt[p, 1], fpt[p, 2] = f
        u = unit_direction(slope)
        for c in range(3):
            for k in range(3):
                mass = rho_a_cm * ((1.0 if c == k else 0.0) - u[c] * u[k])
                on_point[c, k] = ca * mass - cv * dv[3 * c + k] - cq * dr[3 * c + k]
                on_slope[c, k] = -cq * dp[3 * c + k]
        add_point_block(ke, wp, n, on_point, on_slope, True)
    if cq != 0.0:
        crossing_stiffness(length, npts, cq, xi, g, dg, cross, fpt, count, ke)
    hy.calls[0] += count
    return True
