"""Hydrodynamic loads on the cable, W(56)-(84), integrated along each element.

Per unit length at a submerged point (relative flow ``V = V_f - rdot``, docs/design.md):

* drag, W(58): ``1/2 rho d C_D |V|^2 (f_n V_n/|V_n| + f_t V_t/|V_t|)`` with the loading
  functions of the segment and C_D(Re). Deviation: W(63) bases Re on the normal
  relative speed, which we keep for the normal term; for the tangential term we use the
  full relative speed. With Re_n, C_D ~ 1/Re_n diverges as the flow turns along the
  cable while f_t(0) stays finite, so a cable moving along itself (a vertical cable
  heaving, a falling body's line) would feel an unbounded skin friction; the tangential
  loading function is calibrated for C_D at the flow's own Reynolds number;
* amplified mean drag, W(64)-(65) as corrected in docs/design.md: ``(G - 1)`` times the
  steady drag of the mean current on the cable at rest, so that the mean drag is G
  times the steady drag;
* buoyancy W(57): ``rho A g`` upwards, ``A = pi d^2 / 4``;
* inertia W(66)-(69) with the Froude-Krylov term counted once (docs/design.md):
  ``rho A (C_m + 1) dV_f,n/dt - rho A C_m a_n``; the added-mass part (normal
  acceleration only) appears in the residual with the point acceleration and in the
  iteration matrix as the added-mass matrix W(74).

Quadrature: the segment's ``N_I`` equally spaced points with trapezoidal weights; an
interval that crosses the waterline contributes the trapezoid between its submerged
point and the crossing (found by linear interpolation of the height), W(78)-(80),
so the load changes continuously as an element enters or leaves the water. An element
whose Bezier control polygon lies entirely above the surface is dry and skipped.

The point functions take and return scalars (no array slicing or allocation), which is
what keeps a point evaluation cheap in compiled code.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..kernel_cache import njit
from ..ancf.partial import active_quadrature, crossing_stiffness, hermite, interpolate
from .loading import drag_coefficient, loading_functions
from .water import CURRENT_LINEAR, WaterModel, mean_flow, turbulence

_TINY = 1e-12


class CableHydro(NamedTuple):
    """Per-element hydrodynamic properties (``enabled`` False: a dry scene)."""

    enabled: bool
    el_on: np.ndarray      #: (ne,) bool: element can carry hydrodynamic loads
    el_kind: np.ndarray    #: (ne,) loading functions (loading.BARE / FAIRED)
    el_d: np.ndarray       #: (ne,) diameter [m]
    el_area: np.ndarray    #: (ne,) pi d^2 / 4 [m^2]
    el_cd: np.ndarray      #: (ne,) constant C_D, or 0 for C_D(Re)
    el_g: np.ndarray       #: (ne,) drag amplification G
    el_cm: np.ndarray      #: (ne,) added mass coefficient C_m
    el_npts: np.ndarray    #: (ne,) integration points N_I
    calls: np.ndarray      #: (1,) int64 counter of point evaluations (to verify skipping)


# Scalar arguments only: a plain kernel, compiled once with the loading functions and
# C_D(Re) inlined; its two calls per point cost little next to its work. IR-inlined
# (inline="always") at its call sites, all of it would be expanded and typed again at each.
@njit(cache=True)
def drag(rho: float, mu: float, kind: int, d: float, cd_fixed: float, vx: float, vy: float, vz: float,
         ux: float, uy: float, uz: float) -> tuple:
    """Drag per unit length W(58) [N/m] for relative flow V [m/s] on a cable along unit u."""
    vt = vx * ux + vy * uy + vz * uz
    nx = vx - vt * ux
    ny = vy - vt * uy
    nz = vz - vt * uz
    vn = math.sqrt(nx * nx + ny * ny + nz * nz)
    speed2 = vx * vx + vy * vy + vz * vz
    if speed2 <= 0.0:
        return 0.0, 0.0, 0.0
    speed = math.sqrt(speed2)
    fn, ft = loading_functions(kind, min(abs(vt) / speed, 1.0), min(vn / speed, 1.0))
    qd = 0.5 * rho * d * speed2
    fx = 0.0
    fy = 0.0
    fz = 0.0
    if vn > _TINY * speed:
        cd = cd_fixed if cd_fixed > 0.0 else drag_coefficient(rho * d * vn / mu)
        k = qd * cd * fn / vn
        fx += k * nx
        fy += k * ny
        fz += k * nz
    if abs(vt) > _TINY * speed:
        cd = cd_fixed if cd_fixed > 0.0 else drag_coefficient(rho * d * speed / mu)
        k = qd * cd * ft * (1.0 if vt > 0.0 else -1.0)
        fx += k * ux
        fy += k * uy
        fz += k * uz
    return fx, fy, fz


class Section(NamedTuple):
    """The hydrodynamic properties of one cable element's cross-section."""

    kind: int        #: loading functions (loading.BARE / FAIRED)
    d: float         #: diameter [m]
    area: float      #: pi d^2 / 4 [m^2]
    cd: float        #: constant C_D, or 0 for C_D(Re)
    g_amp: float     #: drag amplification G
    cm: float        #: added mass coefficient C_m


@njit(cache=True, inline="always")
def element_section(hy: CableHydro, e: int) -> Section:
    """Element ``e``'s cross-section."""
    return Section(hy.el_kind[e], hy.el_d[e], hy.el_area[e], hy.el_cd[e], hy.el_g[e], hy.el_cm[e])


@njit(cache=True, inline="always")
def point_load(w: WaterModel, section: Section, t: float, rz: float, p: tuple, v: tuple, a: tuple) -> tuple:
    """Hydrodynamic load per unit length [N/m] at a submerged point of height ``rz`` [m],
    slope ``p`` (3-tuple, any length), velocity ``v`` [m/s] and acceleration ``a`` [m/s^2]
    (3-tuples; pass a = 0 to leave out the added mass) at time ``t`` [s]."""
    kind, d, area, cd, g_amp, cm = section
    px, py, pz = p
    vx, vy, vz = v
    ax, ay, az = a
    lp = max(math.sqrt(px * px + py * py + pz * pz), _TINY)
    ux = px / lp
    uy = py / lp
    uz = pz / lp
    mx, my, mz = mean_flow(w, rz)
    tx, ty, tz, afx, afy, afz = turbulence(w, t)
    fx, fy, fz = drag(w.density, w.viscosity, kind, d, cd, mx + tx - vx, my + ty - vy, mz + tz - vz, ux, uy, uz)
    if g_amp != 1.0:
        sx, sy, sz = drag(w.density, w.viscosity, kind, d, cd, mx, my, mz, ux, uy, uz)
        fx += (g_amp - 1.0) * sx
        fy += (g_amp - 1.0) * sy
        fz += (g_amp - 1.0) * sz
    rho_a = w.density * area
    fz += rho_a * w.gravity
    afu = afx * ux + afy * uy + afz * uz
    au = ax * ux + ay * uy + az * uz
    k_fk = rho_a * (cm + 1.0)
    k_am = rho_a * cm
    fx += k_fk * (afx - afu * ux) - k_am * (ax - au * ux)
    fy += k_fk * (afy - afu * uy) - k_am * (ay - au * uy)
    fz += k_fk * (afz - afu * uz) - k_am * (az - au * uz)
    return fx, fy, fz


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
def add_jacobian(w: WaterModel, hy: CableHydro, el_len: np.ndarray, q: np.ndarray, v: np.ndarray, t: float,
                 e: int, ca: float, cv: float, cq: float, ke: np.ndarray) -> bool:
    """Add element e's hydrodynamic part of ``ca M + cv C + cq K`` to the 12x12 block ``ke``;
    False (nothing added) for a dry element or one without hydrodynamic loads.

    Added mass exactly (W(74)); derivatives of the point load with respect to the point
    velocity, the cable direction and the depth (depth-dependent current) by finite
    differences; the stiffness of the moving waterline crossing from the derivative of
    the wet length.
    """
    if not hy.el_on[e]:
        return False
    base = 6 * e
    length = el_len[e]
    if _is_dry(w, q, base, length):
        return False
    npts = hy.el_npts[e]
    m = 2 * npts
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    fpt = np.zeros((m, 3))
    count = _quadrature(w, q, base, length, npts, xi, wt, g, cross)
    section = element_section(hy, e)
    rho_a_cm = w.density * section.area * section.cm
    jac = np.zeros((3, 7))  # columns: d/dv (3), d/dp (3), d/dz (zero unless the current varies with depth)
    depth_varies = w.current_kind == CURRENT_LINEAR
    pert = np.empty(7)
    for p in range(count):
        wp = wt[p]
        if wp == 0.0:
            continue
        n = hermite(xi[p], length)
        rx, ry, rz = interpolate(q, base, n[0], n[1], n[2], n[3])
        px, py, pz = interpolate(q, base, n[4], n[5], n[6], n[7])
        vx, vy, vz = interpolate(v, base, n[0], n[1], n[2], n[3])
        state = (vx, vy, vz, px, py, pz, rz)
        # k = -1: the load at the point itself, then one perturbed state per column (a single
        # call site of the inlined point_load: each site is typed and compiled on its own)
        for k in range(-1, 7 if depth_varies else 6):
            for j in range(7):
                pert[j] = state[j]
            h = 0.0
            if k >= 0:
                h = 1e-7 * max(1.0, abs(state[k]))
                pert[k] += h
            f = point_load(w, section, t, pert[6], (pert[3], pert[4], pert[5]), (pert[0], pert[1], pert[2]),
                           (0.0, 0.0, 0.0))
            if k < 0:
                fpt[p, 0], fpt[p, 1], fpt[p, 2] = f
            else:
                for c in range(3):
                    jac[c, k] = (f[c] - fpt[p, c]) / h
        lp = max(math.sqrt(px * px + py * py + pz * pz), _TINY)
        u = (px / lp, py / lp, pz / lp)
        for i in range(4):
            for j in range(4):
                nn = wp * n[i] * n[j]
                nd = wp * n[i] * n[4 + j]
                for c in range(3):
                    for k in range(3):
                        mass = rho_a_cm * ((1.0 if c == k else 0.0) - u[c] * u[k])
                        ke[3 * i + c, 3 * j + k] += ca * nn * mass - cv * nn * jac[c, k] - cq * nd * jac[c, 3 + k]
                    ke[3 * i + c, 3 * j + 2] -= cq * nn * jac[c, 6]
    if cq != 0.0:
        dg = np.zeros((npts, 3))
        dg[:, 2] = -1.0  # g = surface - z
        crossing_stiffness(length, npts, cq, xi, g, dg, cross, fpt, count, ke)
    hy.calls[0] += 8 * count
    return True
