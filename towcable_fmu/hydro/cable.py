"""Hydrodynamic loads on the cable per unit length at one point, W(56)-(84), for any
formulation (the ANCF element quadrature: :mod:`towcable_fmu.ancf.forces.hydro_quadrature`;
the nodal-position element: :mod:`towcable_fmu.nodal.element`).

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

The iteration matrix differentiates the other loads exactly (:func:`drag_jacobian`,
:func:`point_tangent`), with the mean of the one-sided derivatives where the drag has a
kink (flow along or across the cable).

The point functions take and return scalars (no array slicing or allocation), which is
what keeps a point evaluation cheap in compiled code.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ..jit.kernel_cache import njit
from .loading import NORMAL_TANGENTIAL, drag_coefficient, drag_coefficient_slope, loading_functions, loading_slopes
from .water import CURRENT_LINEAR, WaterModel, mean_flow, turbulence

_TINY = 1e-12
_ZERO3 = (0.0, 0.0, 0.0)
_ZERO9 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


# Scalar arguments only: a plain kernel, compiled once with the loading functions and
# C_D(Re) inlined; its two calls per point cost little next to its work. IR-inlined
# (inline="always") at its call sites, all of it would be expanded and typed again at each.
@njit(cache=True)
def drag(rho: float, mu: float, kind: int, d: float, cd_fixed: float, cdt_fixed: float, vx: float, vy: float,
         vz: float, ux: float, uy: float, uz: float) -> tuple:
    """Drag per unit length W(58) [N/m] for relative flow V [m/s] on a cable along unit u.

    ``cd_fixed`` is the constant C_D (0: C_D(Re)); ``cdt_fixed`` the tangential C_Dt of the
    loading NORMAL_TANGENTIAL (used by that kind only, on the term along the cable)."""
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
        if kind == NORMAL_TANGENTIAL:
            cd = cdt_fixed
        else:
            cd = cd_fixed if cd_fixed > 0.0 else drag_coefficient(rho * d * speed / mu)
        k = qd * cd * ft * (1.0 if vt > 0.0 else -1.0)
        fx += k * ux
        fy += k * uy
        fz += k * uz
    return fx, fy, fz


@njit(cache=True, inline="always")
def _span_matrix(c: float, cuu: float, chu: float, chh: float, cuh: float, ux: float, uy: float, uz: float,
                 hx: float, hy: float, hz: float) -> tuple:
    """The 3x3 matrix ``c I + (cuu u + chu h) u^T + (chh h + cuh u) h^T``, row-major (9-tuple)."""
    rx, ry, rz = cuu * ux + chu * hx, cuu * uy + chu * hy, cuu * uz + chu * hz
    sx, sy, sz = chh * hx + cuh * ux, chh * hy + cuh * uy, chh * hz + cuh * uz
    return (c + rx * ux + sx * hx, rx * uy + sx * hy, rx * uz + sx * hz,
            ry * ux + sy * hx, c + ry * uy + sy * hy, ry * uz + sy * hz,
            rz * ux + sz * hx, rz * uy + sz * hy, c + rz * uz + sz * hz)


@njit(cache=True, inline="always")
def _combine(a: float, x: tuple, b: float, y: tuple) -> tuple:
    """``a x + b y`` for two 3x3 matrices, row-major (9-tuples)."""
    return (a * x[0] + b * y[0], a * x[1] + b * y[1], a * x[2] + b * y[2],
            a * x[3] + b * y[3], a * x[4] + b * y[4], a * x[5] + b * y[5],
            a * x[6] + b * y[6], a * x[7] + b * y[7], a * x[8] + b * y[8])


@njit(cache=True, inline="always")
def _product(x: tuple, y: tuple, offset: int) -> tuple:
    """The 3x3 product ``x Y`` (row-major 9-tuples; Y the 9 entries of ``y`` from ``offset``)."""
    return (x[0] * y[offset] + x[1] * y[offset + 3] + x[2] * y[offset + 6],
            x[0] * y[offset + 1] + x[1] * y[offset + 4] + x[2] * y[offset + 7],
            x[0] * y[offset + 2] + x[1] * y[offset + 5] + x[2] * y[offset + 8],
            x[3] * y[offset] + x[4] * y[offset + 3] + x[5] * y[offset + 6],
            x[3] * y[offset + 1] + x[4] * y[offset + 4] + x[5] * y[offset + 7],
            x[3] * y[offset + 2] + x[4] * y[offset + 5] + x[5] * y[offset + 8],
            x[6] * y[offset] + x[7] * y[offset + 3] + x[8] * y[offset + 6],
            x[6] * y[offset + 1] + x[7] * y[offset + 4] + x[8] * y[offset + 7],
            x[6] * y[offset + 2] + x[7] * y[offset + 5] + x[8] * y[offset + 8])


@njit(cache=True, inline="always")
def _normal_product(ux: float, uy: float, uz: float, y: tuple) -> tuple:
    """``(I - u u^T) Y`` with Y the 3x3 matrix of entries 9 to 17 of ``y`` (row-major)."""
    return _product((1.0 - ux * ux, -ux * uy, -ux * uz, -uy * ux, 1.0 - uy * uy, -uy * uz,
                     -uz * ux, -uz * uy, 1.0 - uz * uz), y, 9)


# A plain kernel as drag (two calls per point).
@njit(cache=True)
def drag_jacobian(rho: float, mu: float, kind: int, d: float, cd_fixed: float, cdt_fixed: float, vx: float,
                  vy: float, vz: float, ux: float, uy: float, uz: float) -> tuple:
    """The drag of :func:`drag` and its exact derivatives.

    With the relative flow ``V = V_t u + V_n h`` (``h`` the unit normal flow direction),
    the drag is ``A V_n h + B u`` with ``A = q C_D(Re_n) f_n / V_n`` and
    ``B = q C_D(Re) f_t sign(V_t)``, ``q = rho d |V|^2 / 2``; f_n, f_t depend on the flow
    angle eta = atan2(V_n, |V_t|). Both derivatives lie in span{I, u u^T, h u^T, h h^T, u h^T}.

    Parameters
    ----------
    rho, mu
        Water density [kg/m^3] and viscosity [Pa s].
    kind, d, cd_fixed, cdt_fixed
        Loading functions, diameter [m], constant C_D (0: C_D(Re)) and tangential C_Dt, as
        :func:`drag`.
    vx, vy, vz
        Relative flow V [m/s].
    ux, uy, uz
        Unit cable direction u.

    Returns
    -------
    tuple
        ``(f, df/dV, df/du)``: the drag per unit length f [N/m] (3-tuple), its derivative
        with respect to V [N s/m^2] and with respect to the direction u on the unit sphere,
        ``df/du (I - u u^T)`` [N/m] (9-tuples, row-major). Divide the latter by |p| for the
        derivative with respect to a slope p of direction u.

    Notes
    -----
    Where the drag is not differentiable, the derivative is the mean of the one-sided
    ones, and always finite:

    * flow across the cable (V_t = 0): f_n has a kink in V_t and the tangential drag
      jumps by ``2 q C_D f_t(90 deg)`` (non-zero for the faired cable): the continuous
      part of the derivative only (the terms with sign(V_t) drop out);
    * flow along the cable (V_n <= 1e-12 |V|, where :func:`drag` drops the normal term):
      the drag is a cone in V_n; the mean over the directions h around the cable drops
      the terms in h, and the normal term's factor is its limit
      ``A = q C_D(Re_n -> 0) f_n'(0) / |V|`` (with C_D(Re), the coefficient held at
      ``RE_MIN``: the exact derivative for V_n below about 1e-7 m/s, and large; the
      faired W(145) has f_n(0) = 9e-6 instead of 0, a jump left out);
    * no flow (V = 0): zero (the drag is quadratic in V there, C_D being held constant
      below ``RE_MIN``).
    """
    speed2 = vx * vx + vy * vy + vz * vz
    if speed2 <= 0.0:
        return _ZERO3, _ZERO9, _ZERO9
    speed = math.sqrt(speed2)
    vt = vx * ux + vy * uy + vz * uz
    nx = vx - vt * ux
    ny = vy - vt * uy
    nz = vz - vt * uz
    vn = math.sqrt(nx * nx + ny * ny + nz * nz)
    cos_eta = min(abs(vt) / speed, 1.0)
    sin_eta = min(vn / speed, 1.0)
    fn, ft = loading_functions(kind, cos_eta, sin_eta)
    dfn, dft = loading_slopes(kind, cos_eta, sin_eta)
    qd = 0.5 * rho * d * speed2
    sign = 0.0 if abs(vt) <= _TINY * speed else (1.0 if vt > 0.0 else -1.0)
    if vn > _TINY * speed:
        re_n = rho * d * vn / mu
        cdn = cd_fixed if cd_fixed > 0.0 else drag_coefficient(re_n)
        # dA = 2 A d|V|/|V| + (A_c - A) dV_n/V_n + q C_D f_n' deta/V_n (A_c from C_D(Re_n)) with
        # deta/dV = (|V_t| h - V_n sign u)/|V|^2, so that V_n h (dA/dV)^T = h (a_u u + a_h h)^T
        a_c = 0.0 if cd_fixed > 0.0 else qd * fn * drag_coefficient_slope(re_n) / vn
        hx = nx / vn
        hy = ny / vn
        hz = nz / vn
        a = qd * cdn * fn / vn
        e = qd * cdn * dfn / speed2
        a_u = 2.0 * a * vn * vt / speed2 - e * vn * sign
        a_h = 2.0 * a * vn * vn / speed2 + a_c - a + e * abs(vt)
        # d/du on the sphere: dV_n = -V_t h.du, deta = -sign h.du
        a_uh = -(a_c - a) * vt - sign * qd * cdn * dfn
    else:
        hx = 0.0
        hy = 0.0
        hz = 0.0
        cdn = cd_fixed if cd_fixed > 0.0 else drag_coefficient(0.0)
        a = qd * cdn * dfn / speed
        a_u = 0.0
        a_h = 0.0
        a_uh = 0.0
    re_t = rho * d * speed / mu
    fixed_t = cd_fixed > 0.0 or kind == NORMAL_TANGENTIAL
    if kind == NORMAL_TANGENTIAL:
        cdt = cdt_fixed
    else:
        cdt = cd_fixed if cd_fixed > 0.0 else drag_coefficient(re_t)
    cdt_slope = 0.0 if fixed_t else drag_coefficient_slope(re_t)
    b = qd * cdt * ft * sign
    b_s = sign * ft * qd * (2.0 * cdt + cdt_slope) / speed2  # dB/dV from |V| and Re: b_s V
    b_eta = qd * cdt * dft  # dB/dV from eta: b_eta (V_t h - V_n u)/|V|^2 (sign^2 = 1: continuous at V_t = 0)
    b_u = b_s * vt - b_eta * vn / speed2
    b_h = b_s * vn + b_eta * vt / speed2
    an = a * vn
    force = (an * hx + b * ux, an * hy + b * uy, an * hz + b * uz)
    dv = _span_matrix(a, b_u - a, a_u, a_h, b_h, ux, uy, uz, hx, hy, hz)
    # d(A n)/du = -A (V_t I + u V^T) and d(B u)/du = B I - b_eta u h^T, projected
    du = _span_matrix(b - a * vt, a * vt - b, 0.0, a_uh, -(an + b_eta), ux, uy, uz, hx, hy, hz)
    return force, dv, du


class Section(NamedTuple):
    """The hydrodynamic properties of one cable element's cross-section."""

    kind: int        #: loading functions (loading.BARE / FAIRED)
    d: float         #: diameter [m]
    area: float      #: pi d^2 / 4 [m^2]
    cd: float        #: constant C_D, or 0 for C_D(Re)
    g_amp: float     #: drag amplification G
    cm: float        #: added mass coefficient C_m
    cdt: float       #: tangential C_Dt on pi d (loading NORMAL_TANGENTIAL only)


@njit(cache=True, inline="always")
def unit_direction(p: tuple) -> tuple:
    """Unit vector (3 floats) along the slope ``p`` (3-tuple, any length) and its length."""
    px, py, pz = p
    lp = max(math.sqrt(px * px + py * py + pz * pz), _TINY)
    return px / lp, py / lp, pz / lp, lp


@njit(cache=True, inline="always")
def _morison(w: WaterModel, section: Section, mean: tuple, flow: tuple, flow_acc: tuple, p: tuple, v: tuple,
             a: tuple) -> tuple:
    """The load of :func:`point_load` in the flow velocity ``flow`` [m/s] and acceleration
    ``flow_acc`` [m/s^2] (3-tuples) with the mean current ``mean`` [m/s] (of the amplified
    drag)."""
    kind, d, area, cd, g_amp, cm, cdt = section
    vx, vy, vz = v
    ax, ay, az = a
    ux, uy, uz, lp = unit_direction(p)
    mx, my, mz = mean
    afx, afy, afz = flow_acc
    fx, fy, fz = drag(w.density, w.viscosity, kind, d, cd, cdt, flow[0] - vx, flow[1] - vy, flow[2] - vz, ux, uy, uz)
    if g_amp != 1.0:
        sx, sy, sz = drag(w.density, w.viscosity, kind, d, cd, cdt, mx, my, mz, ux, uy, uz)
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
def point_load(w: WaterModel, section: Section, t: float, rz: float, p: tuple, v: tuple, a: tuple) -> tuple:
    """Hydrodynamic load per unit length [N/m] at a submerged point of height ``rz`` [m],
    slope ``p`` (3-tuple, any length), velocity ``v`` [m/s] and acceleration ``a`` [m/s^2]
    (3-tuples; pass a = 0 to leave out the added mass) at time ``t`` [s], in still water
    (current and turbulence)."""
    mx, my, mz = mean_flow(w, rz)
    tx, ty, tz, afx, afy, afz = turbulence(w, t)
    return _morison(w, section, (mx, my, mz), (mx + tx, my + ty, mz + tz), (afx, afy, afz), p, v, a)


@njit(cache=True, inline="always")
def point_load_in_waves(w: WaterModel, section: Section, t: float, rz: float, p: tuple, v: tuple, a: tuple,
                        wave: tuple) -> tuple:
    """:func:`point_load` in the waves' particle velocity [m/s] and acceleration [m/s^2]
    ``wave`` (6-tuple), which join the current and the turbulence in the relative flow and
    the fluid's acceleration (not the amplified mean drag, which is the mean current's)."""
    mx, my, mz = mean_flow(w, rz)
    tx, ty, tz, afx, afy, afz = turbulence(w, t)
    wx, wy, wz, wax, way, waz = wave
    return _morison(w, section, (mx, my, mz), (mx + tx + wx, my + ty + wy, mz + tz + wz),
                    (afx + wax, afy + way, afz + waz), p, v, a)


@njit(cache=True, inline="always")
def _morison_tangent(w: WaterModel, section: Section, mean: tuple, flow: tuple, flow_acc: tuple, p: tuple,
                     v: tuple) -> tuple:
    """:func:`point_tangent` in the flow ``flow``, ``flow_acc`` (as :func:`_morison`)."""
    kind, d, area, cd, g_amp, cm, cdt = section
    vx, vy, vz = v
    ux, uy, uz, lp = unit_direction(p)
    mx, my, mz = mean
    afx, afy, afz = flow_acc
    (fx, fy, fz), dv, du = drag_jacobian(w.density, w.viscosity, kind, d, cd, cdt, flow[0] - vx, flow[1] - vy,
                                         flow[2] - vz, ux, uy, uz)
    gm = g_amp - 1.0
    if gm != 0.0:
        (sx, sy, sz), sdv, sdu = drag_jacobian(w.density, w.viscosity, kind, d, cd, cdt, mx, my, mz, ux, uy, uz)
        fx += gm * sx
        fy += gm * sy
        fz += gm * sz
    else:
        sdv = _ZERO9
        sdu = _ZERO9
    dz = _ZERO3
    if w.current_kind == CURRENT_LINEAR:  # the relative and the mean flow change with the height alike
        j = _combine(1.0, dv, gm, sdv)
        gx, gy, gz = w.current_grad[0], w.current_grad[1], w.current_grad[2]
        dz = (j[0] * gx + j[1] * gy + j[2] * gz, j[3] * gx + j[4] * gy + j[5] * gz,
              j[6] * gx + j[7] * gy + j[8] * gz)
    rho_a = w.density * area
    fz += rho_a * w.gravity
    # Froude-Krylov k (a_f - (a_f.u) u): derivative -k ((a_f.u) (I - u u^T) + u a_f,n^T)
    afu = afx * ux + afy * uy + afz * uz
    k_fk = rho_a * (cm + 1.0)
    nfx = afx - afu * ux
    nfy = afy - afu * uy
    nfz = afz - afu * uz
    fx += k_fk * nfx
    fy += k_fk * nfy
    fz += k_fk * nfz
    dfk = _span_matrix(-k_fk * afu, k_fk * afu, 0.0, 0.0, -k_fk, ux, uy, uz, nfx, nfy, nfz)
    dp = _combine(1.0 / lp, _combine(1.0, du, gm, sdu), 1.0 / lp, dfk)
    return (fx, fy, fz), _combine(-1.0, dv, 0.0, _ZERO9), dp, dz  # V = V_f - v


@njit(cache=True, inline="always")
def point_tangent(w: WaterModel, section: Section, t: float, rz: float, p: tuple, v: tuple) -> tuple:
    """The load of :func:`point_load` without the added mass (a = 0) and its exact derivatives.

    Arguments as :func:`point_load`. Returns ``(f, df/dv, df/dp, df/drz)``: the load per unit
    length f [N/m] (3-tuple), its derivatives with respect to the point velocity [N s/m^2]
    and the slope p [N/m] (9-tuples, row-major), and with respect to the height [N/m^2]
    (3-tuple; zero unless the current varies with depth). The drag's derivatives are
    :func:`drag_jacobian`'s; the added-mass term's dependence on the direction is left out
    (the added-mass matrix W(74) is the tangent's inertia part)."""
    mx, my, mz = mean_flow(w, rz)
    tx, ty, tz, afx, afy, afz = turbulence(w, t)
    return _morison_tangent(w, section, (mx, my, mz), (mx + tx, my + ty, mz + tz), (afx, afy, afz), p, v)


@njit(cache=True, inline="always")
def point_tangent_in_waves(w: WaterModel, section: Section, t: float, rz: float, p: tuple, v: tuple, wave: tuple,
                           dwave: tuple) -> tuple:
    """The load of :func:`point_load_in_waves` without the added mass (a = 0) and its exact
    derivatives.

    Arguments as :func:`point_load_in_waves`; ``dwave`` (18-tuple): the derivatives of the
    waves' velocity [1/s] and acceleration [1/s^2] with respect to the point, row-major 3x3
    each (:func:`towcable_fmu.hydro.waves.wave_at`). Returns ``(f, df/dv, df/dp, df/dr)`` as
    :func:`point_tangent`, but the derivative with respect to the point's position [N/m^2]
    a 9-tuple (row-major): the current's gradient with depth and the waves' with the point."""
    mx, my, mz = mean_flow(w, rz)
    tx, ty, tz, afx, afy, afz = turbulence(w, t)
    wx, wy, wz, wax, way, waz = wave
    f, dv, dp, dz = _morison_tangent(w, section, (mx, my, mz), (mx + tx + wx, my + ty + wy, mz + tz + wz),
                                     (afx + wax, afy + way, afz + waz), p, v)
    ux, uy, uz, lp = unit_direction(p)
    k_fk = w.density * section.area * (section.cm + 1.0)
    # dV/dr = du_w/dr in the drag (df/dV = -df/dv), k (I - u u^T) da_w/dr in the Froude-Krylov term
    dr = _combine(-1.0, _product(dv, dwave, 0), k_fk, _normal_product(ux, uy, uz, dwave))
    return f, dv, dp, (dr[0], dr[1], dr[2] + dz[0], dr[3], dr[4], dr[5] + dz[1], dr[6], dr[7], dr[8] + dz[2])
