"""The loads of :mod:`towcable_fmu.hydro.cable` in waves, integrated along each ANCF element.

The quadrature of :mod:`.hydro_quadrature` (a scene without waves runs that one, the
code it had before waves existed) with the waves of :mod:`towcable_fmu.hydro.waves`:
the waterline is the instantaneous surface at each grid point of an element that
reaches above the deepest trough, and every point load sees the waves' velocity and
acceleration there.

Once per point and time step. The first residual at a time t (the step's predicted
state) evaluates, at each grid point and each crossing of the waterline, the full sum
of components with its gradients (:func:`~towcable_fmu.hydro.waves.wave_at`; at the
grid points of the wave zone also the elevation and its slopes) and keeps it as the
point's reference; the Newton iterates at the same t (to :data:`SAME_TIME`) take the first-order Taylor
expansion about it in the point's displacement d (:func:`~towcable_fmu.hydro.waves.near`).
Its error is the remainder, at most ``|d|^2 / 2`` times the largest second derivative of
the kinematics (of order ``sum a_i omega_i k_i^2`` for the velocity), with d the
distance of an iterate from the predicted state (millimetres to centimetres in a
0.05 s step): the same references give every iterate's residual, and the converged
state solves the equations with the expanded kinematics. A dry element is one whose
control polygon lies above the surface at the hull's centre plus the steepest slope
``sum a_i k_i`` times the hull's radius and its centre's distance from the reference
(a strict bound, not an expansion). Where the first residual at t happens again after
a restored state, the references are the same (the same predicted state); they are
forgotten when a run starts (``hydrodynamics.Hooks.reset``).

The iteration matrix evaluates the kinematics in full at its own iterate, with their
exact derivatives with respect to the point, and the crossing's motion with the
surface's exact slope: it does not depend on which residuals came before, so a
restored state's Jacobian (:func:`~towcable_fmu.ancf.genalpha.refactorize_from_state`)
is the original one bit for bit. It differs from the derivative of the expanded
residual by the kinematics' change over d (relative order ``k |d|``), which changes the
iterates of the (already modified) Newton method, not its solution.
"""

from __future__ import annotations

import math

import numpy as np

from ...hydro.cable import point_load_in_waves, point_tangent_in_waves, unit_direction
from ...hydro.water import WaterModel
from ...hydro.waves import (ACC, DACC, DVEL, OUT_SIZE, VEL, elevation, near, scratch_size, surface_height,
                            water_waves)
from ...jit.kernel_cache import njit
from ..partial import active_quadrature, add_point_block, crossing_stiffness, hermite, interpolate
from .hydro_quadrature import CableHydro, element_section

#: Layout of a reference (a row of ``CableHydro.wave_ref``): the surface's reference point
#: (x, y) [m], the elevation there above the mean level [m] and its slopes; the
#: kinematics' reference point (x, y, z) [m], then :func:`~towcable_fmu.hydro.waves.wave_at`'s output
SURF_X, SURF_Y, SURF_ETA, SURF_EX, SURF_EY, KIN_X, KIN_Y, KIN_Z, KIN = range(9)
REF_SIZE = KIN + OUT_SIZE
#: Columns of ``CableHydro.wave_stamp``: the generation of the surface's and of the kinematics' reference
SURFACE, KINEMATICS = 0, 1


def wave_cache(elements: int, points: int, waves: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The empty references of ``CableHydro`` (``wave_ref``, ``wave_stamp``, ``wave_clock``)
    for ``elements`` elements of at most ``points`` integration points; no rows without
    ``waves``. Slots per element: the grid points, the crossings of each interval, the hull."""
    rows, slots = (elements, 2 * points) if waves else (0, 0)
    return np.zeros((rows, slots, REF_SIZE)), np.full((rows, slots, 2), -1.0), np.array([math.nan, 0.0])


#: Times closer than this are one time of the references [s] (an output sample at a step's
#: end, its time summed from sample intervals, differs from the step's in the last bits)
SAME_TIME = 1e-9


@njit(cache=True, inline="always")
def _generation(hy: CableHydro, t: float) -> float:
    """The references' generation at time t [s]: a new one when t is not the last call's."""
    if not abs(hy.wave_clock[0] - t) <= SAME_TIME:  # (also when the clock is NaN: no references)
        hy.wave_clock[0] = t
        hy.wave_clock[1] += 1.0
    return hy.wave_clock[1]


@njit(cache=True, inline="always")
def _surface(w: WaterModel, hy: CableHydro, gen: float, e: int, slot: int, x: float, y: float, t: float,
             exact: bool) -> tuple:
    """Height of the surface [m] and its slopes at (x, y) [m], expanded about the slot's
    reference (``exact``: evaluated in full); the first call of a generation sets the reference."""
    ref = hy.wave_ref[e, slot]
    if hy.wave_stamp[e, slot, SURFACE] != gen:
        eta, ex, ey = elevation(w.waves, w.wave_ramp, x, y, t)
        ref[SURF_X] = x
        ref[SURF_Y] = y
        ref[SURF_ETA] = eta
        ref[SURF_EX] = ex
        ref[SURF_EY] = ey
        hy.wave_stamp[e, slot, SURFACE] = gen
    elif exact:
        return surface_height(w, x, y, t)
    return (w.surface_z + ref[SURF_ETA] + ref[SURF_EX] * (x - ref[SURF_X]) + ref[SURF_EY] * (y - ref[SURF_Y]),
            ref[SURF_EX], ref[SURF_EY])


@njit(cache=True, inline="always")
def _reference(w: WaterModel, hy: CableHydro, gen: float, e: int, slot: int, r: tuple, t: float,
               work: np.ndarray) -> np.ndarray:
    """The slot's reference of the kinematics (:func:`~towcable_fmu.hydro.waves.wave_at`'s
    output with gradients), evaluated at the point r if the generation has none yet."""
    ref = hy.wave_ref[e, slot]
    if hy.wave_stamp[e, slot, KINEMATICS] != gen:
        water_waves(w, r[0], r[1], r[2], t, True, work, ref[KIN:])
        ref[KIN_X] = r[0]
        ref[KIN_Y] = r[1]
        ref[KIN_Z] = r[2]
        hy.wave_stamp[e, slot, KINEMATICS] = gen
    return ref


@njit(cache=True, inline="always")
def _kinematics(w: WaterModel, hy: CableHydro, gen: float, e: int, slot: int, r: tuple, t: float,
                work: np.ndarray) -> tuple:
    """The waves' velocity and acceleration at the point r (6-tuple), expanded about the slot's reference."""
    ref = _reference(w, hy, gen, e, slot, r, t, work)
    return near(ref[KIN:], r[0] - ref[KIN_X], r[1] - ref[KIN_Y], r[2] - ref[KIN_Z])


@njit(cache=True, inline="always")
def _hull(x: np.ndarray, base: int, length: float) -> tuple:
    """The element's Bezier control polygon: its lowest and highest control heights [m], the
    horizontal centre (x, y) [m] and radius [m]."""
    z0 = x[base + 2]
    z1 = x[base + 8]
    c0 = z0 + length * x[base + 5] / 3.0
    c1 = z1 - length * x[base + 11] / 3.0
    px = (x[base], x[base] + length * x[base + 3] / 3.0, x[base + 6] - length * x[base + 9] / 3.0, x[base + 6])
    py = (x[base + 1], x[base + 1] + length * x[base + 4] / 3.0, x[base + 7] - length * x[base + 10] / 3.0,
          x[base + 7])
    mx = 0.25 * (px[0] + px[1] + px[2] + px[3])
    my = 0.25 * (py[0] + py[1] + py[2] + py[3])
    radius = 0.0
    for i in range(4):
        radius = max(radius, math.hypot(px[i] - mx, py[i] - my))
    return min(min(z0, z1), min(c0, c1)), max(max(z0, z1), max(c0, c1)), mx, my, radius


@njit(cache=True, inline="always")
def _is_dry(w: WaterModel, hy: CableHydro, gen: float, e: int, low: float, mx: float, my: float, radius: float,
            t: float, cached: bool) -> bool:
    """Convex-hull test: all control points above the highest crest, or above the surface at
    the hull's centre plus the steepest slope times the hull's radius (and, ``cached``, the
    centre's distance from its reference of the step)."""
    if low > w.surface_z + w.wave_crest:
        return True
    if not cached:
        return low > surface_height(w, mx, my, t)[0] + radius * w.wave_slope
    slot = hy.wave_ref.shape[1] - 1
    ref = hy.wave_ref[e, slot]
    if hy.wave_stamp[e, slot, SURFACE] != gen:
        ref[SURF_X] = mx
        ref[SURF_Y] = my
        ref[SURF_ETA] = elevation(w.waves, w.wave_ramp, mx, my, t)[0]
        hy.wave_stamp[e, slot, SURFACE] = gen
    reach = radius + math.hypot(mx - ref[SURF_X], my - ref[SURF_Y])
    return low > w.surface_z + ref[SURF_ETA] + reach * w.wave_slope


@njit(cache=True, inline="always")
def _quadrature(w: WaterModel, hy: CableHydro, gen: float, e: int, x: np.ndarray, base: int, length: float,
                npts: int, high: float, t: float, cached: bool, xi: np.ndarray, wt: np.ndarray, g: np.ndarray,
                dg: np.ndarray, cross: np.ndarray) -> int:
    """Submerged quadrature points of one element (indicator g: depth below the surface,
    its gradient dg with respect to the point); the surface expanded about the step's
    references (``cached``) or evaluated in full (setting the references a generation lacks)."""
    waves = high > w.surface_z - w.wave_crest  # some control point above the deepest trough
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
            px = n0 * x[base] + n1 * x[base + 3] + n2 * x[base + 6] + n3 * x[base + 9]
            py = n0 * x[base + 1] + n1 * x[base + 4] + n2 * x[base + 7] + n3 * x[base + 10]
            surface, sx, sy = _surface(w, hy, gen, e, j, px, py, t, not cached)
            g[j] = surface - z
            dg[j, 0] = sx
            dg[j, 1] = sy
        else:
            g[j] = w.surface_z - z
            dg[j, 0] = 0.0
            dg[j, 1] = 0.0
        dg[j, 2] = -1.0
    return active_quadrature(length, npts, g, xi, wt, cross)


@njit(cache=True)
def add_residual(w: WaterModel, hy: CableHydro, el_len: np.ndarray, q: np.ndarray, v: np.ndarray,
                 a: np.ndarray, t: float, first: int, stop: int, out: np.ndarray) -> None:
    """Subtract the generalised hydrodynamic force in waves (and add the added-mass inertia)
    of the submerged elements ``first`` to ``stop - 1`` from the residual ``out``; the
    waves' kinematics and surface expanded about the references of time t."""
    gen = _generation(hy, t)
    m = 2 * hy.el_npts.max()
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    dg = np.empty((m, 3))
    work = np.empty(scratch_size(w.waves))
    evaluations = 0
    for e in range(first, stop):
        if not hy.el_on[e]:
            continue
        base = 6 * e
        length = el_len[e]
        low, high, mx, my, radius = _hull(q, base, length)
        if _is_dry(w, hy, gen, e, low, mx, my, radius, t, True):
            continue
        npts = hy.el_npts[e]
        count = _quadrature(w, hy, gen, e, q, base, length, npts, high, t, True, xi, wt, g, dg, cross)
        section = element_section(hy, e)
        for p in range(count):
            wp = wt[p]
            if wp == 0.0:
                continue
            n0, n1, n2, n3, d0, d1, d2, d3 = hermite(xi[p], length)
            r = interpolate(q, base, n0, n1, n2, n3)
            wave = _kinematics(w, hy, gen, e, p if p < npts else npts + cross[p], r, t, work)
            fx, fy, fz = point_load_in_waves(w, section, t, r[2], interpolate(q, base, d0, d1, d2, d3),
                                             interpolate(v, base, n0, n1, n2, n3),
                                             interpolate(a, base, n0, n1, n2, n3), wave)
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
    """Every element's hydrodynamic part of ``ca M + cv C + cq K`` in waves, stored as
    :func:`.hydro_quadrature.add_jacobians` does (``blocks[e]``, ``wet[e]``).

    Added mass exactly (W(74)); the exact derivatives of the point load with respect to the
    point velocity, the cable slope and the position (:func:`point_tangent_in_waves`, with
    the waves' gradients evaluated in full at the iterate); the stiffness of the moving
    waterline crossing from the derivative of the wet length (the surface's slope included).
    The first evaluation at a time (the Jacobian of a step's predicted state) is also the
    residuals' reference there. The work arrays are allocated once for all elements.
    """
    gen = _generation(hy, t)
    m = 2 * hy.el_npts.max()
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    fpt = np.empty((m, 3))
    dg = np.empty((m, 3))
    work = np.empty(scratch_size(w.waves))
    kin = np.empty(OUT_SIZE)
    on_point = np.empty((3, 3))  # the load's derivative with respect to the point (added mass, velocity, position)
    on_slope = np.empty((3, 3))
    evaluations = 0
    for e in range(el_len.shape[0]):
        wet[e] = False
        if not hy.el_on[e]:
            continue
        base = 6 * e
        length = el_len[e]
        low, high, mx, my, radius = _hull(q, base, length)
        if _is_dry(w, hy, gen, e, low, mx, my, radius, t, False):
            continue
        wet[e] = True
        ke = blocks[e]
        ke[:, :] = 0.0
        npts = hy.el_npts[e]
        fpt[:2 * npts] = 0.0
        count = _quadrature(w, hy, gen, e, q, base, length, npts, high, t, False, xi, wt, g, dg, cross)
        section = element_section(hy, e)
        rho_a_cm = w.density * section.area * section.cm
        for p in range(count):
            wp = wt[p]
            if wp == 0.0:
                continue
            n = hermite(xi[p], length)
            r = interpolate(q, base, n[0], n[1], n[2], n[3])
            slope = interpolate(q, base, n[4], n[5], n[6], n[7])
            slot = p if p < npts else npts + cross[p]
            if hy.wave_stamp[e, slot, KINEMATICS] != gen:  # the first evaluation at t: the residuals' reference
                kw = _reference(w, hy, gen, e, slot, r, t, work)[KIN:]
            else:
                water_waves(w, r[0], r[1], r[2], t, True, work, kin)
                kw = kin[:]
            wave = (kw[VEL], kw[VEL + 1], kw[VEL + 2], kw[ACC], kw[ACC + 1], kw[ACC + 2])
            dwave = (kw[DVEL], kw[DVEL + 1], kw[DVEL + 2], kw[DVEL + 3], kw[DVEL + 4], kw[DVEL + 5], kw[DVEL + 6],
                     kw[DVEL + 7], kw[DVEL + 8], kw[DACC], kw[DACC + 1], kw[DACC + 2], kw[DACC + 3], kw[DACC + 4],
                     kw[DACC + 5], kw[DACC + 6], kw[DACC + 7], kw[DACC + 8])
            f, dv, dp, dr = point_tangent_in_waves(w, section, t, r[2], slope,
                                                   interpolate(v, base, n[0], n[1], n[2], n[3]), wave, dwave)
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
        evaluations += count
    hy.calls[0] += evaluations
