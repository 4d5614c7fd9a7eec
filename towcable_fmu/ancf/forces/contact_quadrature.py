"""Contact forces on the cable, integrated along each element, W(103)-(106).

Each face has its own partial quadrature (W(105): "each contact surface has a distinct
set of quadrature weights"), with the crossing of the contact boundary located by
linear interpolation of the face indicator (:mod:`towcable_fmu.ancf.partial`). Only
elements that can reach a surface are evaluated: the Bezier control points of an element
bound it, and an element whose bounding sphere stays outside the groove top (or the
drum) is skipped.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...jit.kernel_cache import njit
from ..partial import active_quadrature, add_point_block, crossing_stiffness, hermite, interpolate
from ...numerics.kinematics import rotation_derivatives
from ...contact.surfaces import CYLINDER, ContactModel, face_force, face_tangent, groove_exit

_MARGIN = 1e-3  # [m] added to the reach of a surface when culling elements


@njit(cache=True, inline="always")
def _ship_offset(rot: np.ndarray, ship: np.ndarray, px: float, py: float, pz: float) -> tuple:
    """Inertial point -> ship frame, relative to the ship's origin [m] (each face subtracts
    its own centre: the transform is made once for all faces)."""
    dx, dy, dz = px - ship[0, 0], py - ship[0, 1], pz - ship[0, 2]
    return (rot[0, 0] * dx + rot[1, 0] * dy + rot[2, 0] * dz,
            rot[0, 1] * dx + rot[1, 1] * dy + rot[2, 1] * dz,
            rot[0, 2] * dx + rot[1, 2] * dy + rot[2, 2] * dz)


@njit(cache=True, inline="always")
def _control_points(x: np.ndarray, base: int, length: float, rot: np.ndarray, ship: np.ndarray) -> tuple:
    """The element's (coordinates at base) four Bezier control points in the ship frame,
    relative to the ship's origin (:func:`_ship_offset`)."""
    k = length / 3.0
    return (_ship_offset(rot, ship, x[base], x[base + 1], x[base + 2]),
            _ship_offset(rot, ship, x[base] + k * x[base + 3], x[base + 1] + k * x[base + 4],
                         x[base + 2] + k * x[base + 5]),
            _ship_offset(rot, ship, x[base + 6] - k * x[base + 9], x[base + 7] - k * x[base + 10],
                         x[base + 8] - k * x[base + 11]),
            _ship_offset(rot, ship, x[base + 6], x[base + 7], x[base + 8]))


@njit(cache=True, inline="always")
def _reaches(c: ContactModel, f: int, half_d: float, ctrl: tuple) -> bool:
    """Can an element touch face f? Bounding sphere of its Bezier polygon (``ctrl``:
    :func:`_control_points`)."""
    (ax, ay, az), (bx, by, bz), (cx, cy, cz), (dx, dy, dz) = ctrl
    ox, oy, oz = c.face_center[f, 0], c.face_center[f, 1], c.face_center[f, 2]
    ax, ay, az, bx, by, bz = ax - ox, ay - oy, az - oz, bx - ox, by - oy, bz - oz
    cx, cy, cz, dx, dy, dz = cx - ox, cy - oy, cz - oz, dx - ox, dy - oy, dz - oz
    mx = 0.25 * (ax + bx + cx + dx)
    my = 0.25 * (ay + by + cy + dy)
    mz = 0.25 * (az + bz + cz + dz)
    radius = math.sqrt(max(max((ax - mx) ** 2 + (ay - my) ** 2 + (az - mz) ** 2,
                               (bx - mx) ** 2 + (by - my) ** 2 + (bz - mz) ** 2),
                           max((cx - mx) ** 2 + (cy - my) ** 2 + (cz - mz) ** 2,
                               (dx - mx) ** 2 + (dy - my) ** 2 + (dz - mz) ** 2)))
    reach = c.face_radius[f] + half_d + c.face_depth[f] + _MARGIN
    return math.sqrt(mx * mx + mz * mz) - radius <= reach


@njit(cache=True, inline="always")
def _ship_point(rot: np.ndarray, rot1: np.ndarray, ship: np.ndarray, rx: float, ry: float, rz: float, vx: float,
                vy: float, vz: float) -> tuple:
    """Ship-frame position relative to the ship's origin and velocity relative to the ship."""
    dx, dy, dz = rx - ship[0, 0], ry - ship[0, 1], rz - ship[0, 2]
    ux, uy, uz = vx - ship[1, 0], vy - ship[1, 1], vz - ship[1, 2]
    sx = rot[0, 0] * dx + rot[1, 0] * dy + rot[2, 0] * dz
    sy = rot[0, 1] * dx + rot[1, 1] * dy + rot[2, 1] * dz
    sz = rot[0, 2] * dx + rot[1, 2] * dy + rot[2, 2] * dz
    wx = rot[0, 0] * ux + rot[1, 0] * uy + rot[2, 0] * uz + rot1[0, 0] * dx + rot1[1, 0] * dy + rot1[2, 0] * dz
    wy = rot[0, 1] * ux + rot[1, 1] * uy + rot[2, 1] * uz + rot1[0, 1] * dx + rot1[1, 1] * dy + rot1[2, 1] * dz
    wz = rot[0, 2] * ux + rot[1, 2] * uy + rot[2, 2] * uz + rot1[0, 2] * dx + rot1[1, 2] * dy + rot1[2, 2] * dz
    return sx, sy, sz, wx, wy, wz


@njit(cache=True, inline="always")
def _face_point(c: ContactModel, f: int, spts: np.ndarray, p: int) -> tuple:
    """Point p of ``spts`` (:func:`_ship_points`) relative to face f's centre, and its velocity."""
    return (spts[p, 0] - c.face_center[f, 0], spts[p, 1] - c.face_center[f, 1], spts[p, 2] - c.face_center[f, 2],
            spts[p, 3], spts[p, 4], spts[p, 5])


@njit(cache=True, inline="always")
def _inertial_force(c: ContactModel, f: int, half_d: float, rot: np.ndarray, spts: np.ndarray, p: int) -> tuple:
    """Face force per unit length at point p of ``spts`` in the inertial frame, W(102), the
    indicator, the stored energy and the point in the ship frame relative to the face's centre."""
    sx, sy, sz, wx, wy, wz = _face_point(c, f, spts, p)
    fx, fy, fz, g, energy = face_force(c, f, half_d, sx, sy, sz, wx, wy, wz)
    return (rot[0, 0] * fx + rot[0, 1] * fy + rot[0, 2] * fz, rot[1, 0] * fx + rot[1, 1] * fy + rot[1, 2] * fz,
            rot[2, 0] * fx + rot[2, 1] * fy + rot[2, 2] * fz, g, energy, sx, sy, sz)


@njit(cache=True, inline="always")
def _inertial_tangent(c: ContactModel, f: int, half_d: float, rot: np.ndarray, rot1: np.ndarray, spts: np.ndarray,
                      p: int, jac: np.ndarray, dg: np.ndarray) -> None:
    """Derivatives of :func:`_inertial_force`'s force with respect to the inertial position
    and velocity into ``jac`` (3, 6) [N/m^2, N s/m^2], and the indicator's gradient into
    ``dg`` (3,).

    With the ship-frame point ``s = R^T (r - r_0) - c`` and velocity
    ``w = R^T (v - v_0) + Rdot^T (r - r_0)`` and the inertial force ``R f(s, w)``:
    ``df/dr = R (F_s R^T + F_w Rdot^T)``, ``df/dv = R F_w R^T``, ``dg/dr = R dg/ds``.
    """
    sx, sy, sz, wx, wy, wz = _face_point(c, f, spts, p)
    _, _, fs, fw, gs = face_tangent(c, f, half_d, sx, sy, sz, wx, wy, wz)
    for i in range(3):
        dg[i] = rot[i, 0] * gs[0] + rot[i, 1] * gs[1] + rot[i, 2] * gs[2]
    for a in range(3):
        for k in range(3):
            # (F_s R^T + F_w Rdot^T)[a, k] and (F_w R^T)[a, k]
            pos = 0.0
            vel = 0.0
            for b in range(3):
                pos += fs[3 * a + b] * rot[k, b] + fw[3 * a + b] * rot1[k, b]
                vel += fw[3 * a + b] * rot[k, b]
            jac[a, k] = pos
            jac[a, 3 + k] = vel
    # rotate the rows: jac <- R jac
    for k in range(6):
        c0, c1, c2 = jac[0, k], jac[1, k], jac[2, k]
        for i in range(3):
            jac[i, k] = rot[i, 0] * c0 + rot[i, 1] * c1 + rot[i, 2] * c2


class Elements(NamedTuple):
    """The cable's elements as the contact sees them (fields of the cable model)."""

    length: np.ndarray     #: (ne,) element lengths [m]
    diameter: np.ndarray   #: (ne,) cable diameters [m]
    points: np.ndarray     #: (ne,) int64 integration grid points N_I


class SurfaceSummary(NamedTuple):
    """What touches what, per surface s = WINCH, SHEAVE (see :func:`surface_summary`)."""

    force: np.ndarray    #: (2, 3) total contact force on the cable, inertial frame [N]
    span: np.ndarray     #: (2, 2) smallest and largest angle psi = atan2(X, Z) of an active point [rad]
    ends: np.ndarray     #: (2, 4) element index and xi of the first and last touching point
    lowest: np.ndarray   #: (2,) how far the cable is from its seat over the upper half [m]
    energy: np.ndarray   #: (2,) elastic energy stored in the contact [J]
    dist: np.ndarray     #: (k, 3) rows (surface, psi [rad], force per unit length [N/m]) of active points


# _element_points, _ship_points, _face_points and _touching_faces are IR-inlined into the
# three contact kernels: called as kernels of their own, once per element and face, their
# calls cost a fifth of the contact residual (full_scale: 26.4 us of CPU time instead of
# 20.8 us, the same results; typing them three times costs compile time). They take their
# arrays one by one, not bundled: a named tuple of arrays read field by field inside a loop
# costs reference counting on every array at every call; bundled, the contact residual of
# full_scale took 100 us instead of 28 us (measured).
@njit(cache=True, inline="always")
def _element_points(q, v, base, length, npts, pts):
    """Positions and velocities (inertial) of the element's grid points into pts (npts, 6)."""
    for j in range(npts):
        n = hermite(j / (npts - 1), length)
        pts[j, 0], pts[j, 1], pts[j, 2] = interpolate(q, base, n[0], n[1], n[2], n[3])
        pts[j, 3], pts[j, 4], pts[j, 5] = interpolate(v, base, n[0], n[1], n[2], n[3])


@njit(cache=True, inline="always")
def _ship_points(rot, rot1, ship, pts, start, stop, spts):
    """The points ``start`` to ``stop - 1`` of ``pts`` in the ship frame into ``spts``
    (columns X, Y, Z [m] relative to the ship's origin, velocity relative to the ship
    [m/s]): made once per point for all faces, which differ only by their centre."""
    for p in range(start, stop):
        (spts[p, 0], spts[p, 1], spts[p, 2], spts[p, 3], spts[p, 4], spts[p, 5]) = _ship_point(
            rot, rot1, ship, pts[p, 0], pts[p, 1], pts[p, 2], pts[p, 3], pts[p, 4], pts[p, 5])


@njit(cache=True, inline="always")
def _face_points(c, f, half_d, rot, rot1, ship, q, v, base, length, npts, pts, spts, xi, wt, g, cross, fpt):
    """Active quadrature of face f on one element (grid points in ``pts``, inertial, and
    ``spts``, :func:`_ship_points`); forces, stored energy density and ship-frame position
    at all its points into ``fpt`` (columns fx, fy, fz [N/m], energy [J/m], X, Y, Z [m]
    relative to the face's centre). The crossing points are appended to ``pts`` and ``spts``."""
    count = npts
    start = 0
    for stage in range(2):  # the grid, then the crossings its indicator gives (one inlined force call)
        for p in range(start, count):
            fpt[p, 0], fpt[p, 1], fpt[p, 2], gp, fpt[p, 3], fpt[p, 4], fpt[p, 5], fpt[p, 6] = _inertial_force(
                c, f, half_d, rot, spts, p)
            if stage == 0:
                g[p] = gp
        if stage == 0:
            count = active_quadrature(length, npts, g, xi, wt, cross)
            for p in range(npts, count):
                n = hermite(xi[p], length)
                pts[p, 0], pts[p, 1], pts[p, 2] = interpolate(q, base, n[0], n[1], n[2], n[3])
                pts[p, 3], pts[p, 4], pts[p, 5] = interpolate(v, base, n[0], n[1], n[2], n[3])
            _ship_points(rot, rot1, ship, pts, npts, count, spts)
            start = npts
    return count


@njit(cache=True)
def _face_quadrature(c, f, half_d, rot, rot1, ship, q, v, base, length, npts, pts, xi, wt, g, cross, fpt):
    """:func:`_face_points` of one face alone, from the inertial grid points ``pts``
    (:func:`_element_points`; the kernels below share the ship-frame points among faces)."""
    spts = np.empty_like(pts)
    _ship_points(rot, rot1, ship, pts, 0, npts, spts)
    return _face_points(c, f, half_d, rot, rot1, ship, q, v, base, length, npts, pts, spts, xi, wt, g, cross, fpt)


@njit(cache=True, inline="always")
def _touching_faces(c, half_d, q, base, length, rot, ship, faces) -> int:
    """Faces element (at base) can touch, into ``faces``; the bounding test runs once per surface
    (its control points are put in the ship frame once)."""
    ctrl = _control_points(q, base, length, rot, ship)
    count = 0
    surface = -1
    reach = False
    for f in range(c.face_kind.shape[0]):
        if c.face_surface[f] != surface:
            surface = c.face_surface[f]
            reach = _reaches(c, f, half_d, ctrl)
        if reach:
            faces[count] = f
            count += 1
    return count


@njit(cache=True)
def add_residual(c: ContactModel, cable: Elements, q: np.ndarray, v: np.ndarray, ship: np.ndarray, first: int,
                 stop: int, out: np.ndarray) -> None:
    """Subtract the generalised contact forces of the elements ``first`` to ``stop - 1`` that touch a face."""
    el_len, el_d, el_npts = cable
    rot, rot1, _ = rotation_derivatives(ship)
    m = 2 * el_npts.max()
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    fpt = np.empty((m, 7))
    pts = np.empty((m, 6))
    spts = np.empty((m, 6))
    faces = np.empty(c.face_kind.shape[0], dtype=np.int64)
    evaluations = 0
    for e in range(first, stop):
        base = 6 * e
        length = el_len[e]
        half_d = 0.5 * el_d[e]
        npts = el_npts[e]
        nfaces = _touching_faces(c, half_d, q, base, length, rot, ship, faces)
        if nfaces:
            _element_points(q, v, base, length, npts, pts)
            _ship_points(rot, rot1, ship, pts, 0, npts, spts)
        for k in range(nfaces):
            f = faces[k]
            count = _face_points(c, f, half_d, rot, rot1, ship, q, v, base, length, npts, pts, spts, xi, wt, g,
                                 cross, fpt)
            evaluations += count
            for p in range(count):
                wp = wt[p]
                if wp == 0.0:
                    continue
                n = hermite(xi[p], length)
                for i in range(4):
                    k = wp * n[i]
                    out[base + 3 * i] -= k * fpt[p, 0]
                    out[base + 3 * i + 1] -= k * fpt[p, 1]
                    out[base + 3 * i + 2] -= k * fpt[p, 2]
    c.calls[0] += evaluations


@njit(cache=True)
def add_jacobian(c: ContactModel, cable: Elements, q: np.ndarray, v: np.ndarray, ship: np.ndarray, cv: float,
                 cq: float, blocks: np.ndarray, touched: np.ndarray) -> None:
    """The contact part of ``cv C + cq K``, element by element: the 12x12 block of element
    ``e`` into ``blocks[e]`` (ne, 12, 12) and ``touched[e]`` True where a face acts on it
    (``blocks[e]`` is written only there; ``touched`` is overwritten).

    The exact derivatives of the point force with respect to the point position and
    velocity (:func:`_inertial_tangent`); the stiffness of the moving contact boundary
    from the derivative of the active length (:func:`towcable_fmu.ancf.partial.crossing_stiffness`).
    """
    el_len, el_d, el_npts = cable
    rot, rot1, _ = rotation_derivatives(ship)
    m = 2 * el_npts.max()
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    fpt = np.zeros((m, 7))
    dg = np.zeros((m, 3))
    jac = np.empty((3, 6))
    on_point = np.empty((3, 3))
    gradient = np.empty(3)
    pts = np.empty((m, 6))
    spts = np.empty((m, 6))
    faces = np.empty(c.face_kind.shape[0], dtype=np.int64)
    for e in range(el_len.shape[0]):
        base = 6 * e
        length = el_len[e]
        half_d = 0.5 * el_d[e]
        npts = el_npts[e]
        touched[e] = False
        ke = blocks[e]
        nfaces = _touching_faces(c, half_d, q, base, length, rot, ship, faces)
        if nfaces:
            _element_points(q, v, base, length, npts, pts)
            _ship_points(rot, rot1, ship, pts, 0, npts, spts)
        for kf in range(nfaces):
            f = faces[kf]
            count = _face_points(c, f, half_d, rot, rot1, ship, q, v, base, length, npts, pts, spts, xi, wt, g,
                                 cross, fpt)
            active = False
            for p in range(npts):
                active = active or wt[p] > 0.0
            if not active:
                continue
            if not touched[e]:
                ke[:, :] = 0.0
                touched[e] = True
            for p in range(count):
                wp = wt[p]
                # derivatives where the load acts, and the indicator gradient where a crossing needs it
                needs_dg = p < npts and ((p > 0 and (g[p - 1] > 0.0) != (g[p] > 0.0))
                                         or (p < npts - 1 and (g[p + 1] > 0.0) != (g[p] > 0.0)))
                if wp == 0.0 and not needs_dg:
                    continue
                _inertial_tangent(c, f, half_d, rot, rot1, spts, p, jac, gradient)
                for k in range(3):
                    dg[p, k] = gradient[k]
                if wp == 0.0:
                    continue
                for d in range(3):
                    for k in range(3):
                        on_point[d, k] = -(cq * jac[d, k] + cv * jac[d, 3 + k])
                add_point_block(ke, wp, hermite(xi[p], length), on_point, on_point, False)
            if cq != 0.0:
                crossing_stiffness(length, npts, cq, xi, g, dg, cross, fpt, count, ke)


@njit(cache=True)
def surface_summary(c: ContactModel, cable: Elements, q: np.ndarray, v: np.ndarray, ship: np.ndarray,
                    out: SurfaceSummary) -> int:
    """What touches what: totals and the force distribution, for the outputs.

    Idlers (surfaces beyond SHEAVE) are left out.

    Parameters
    ----------
    out
        Filled per surface s = WINCH, SHEAVE: ``force``; ``span`` (NaN when nothing
        touches; none when it has no rows, :func:`new_summary`); ``ends``: element index and xi of the first and of the last touching
        point along the cable (element -1 when nothing touches), where the cable meets and
        leaves the surface; ``lowest`` (inf when no point is on the upper half, Z >= 0): for
        a plain drum or pulley the height h above the surface, for a groove how far the
        point is out of it (:func:`~towcable_fmu.contact.surfaces.groove_exit`: above the
        groove top, or its contact point on the wall of its side above the top), positive
        when out; ``energy``; ``dist`` as many rows as fit.

    Returns
    -------
    int
        Number of rows written to ``out.dist``.
    """
    el_len, el_d, el_npts = cable
    force, span, ends, lowest, energy, dist = out
    rot, rot1, _ = rotation_derivatives(ship)
    force[:, :] = 0.0
    span[:, 0] = np.inf
    span[:, 1] = -np.inf
    ends[:, 0] = -1.0
    ends[:, 2] = -1.0
    lowest[:] = np.inf
    energy[:] = 0.0
    m = 2 * el_npts.max()
    xi = np.empty(m)
    wt = np.empty(m)
    g = np.empty(m)
    cross = np.empty(m, dtype=np.int64)
    fpt = np.empty((m, 7))
    pts = np.empty((m, 6))
    spts = np.empty((m, 6))
    faces = np.empty(c.face_kind.shape[0], dtype=np.int64)
    rows = 0
    spans = span.shape[0] > 0
    angles = spans or dist.shape[0] > 0  # the angles psi are wanted (an atan2 per active point)
    for e in range(el_len.shape[0]):
        base = 6 * e
        length = el_len[e]
        half_d = 0.5 * el_d[e]
        npts = el_npts[e]
        nfaces = _touching_faces(c, half_d, q, base, length, rot, ship, faces)
        if nfaces:
            _element_points(q, v, base, length, npts, pts)
            _ship_points(rot, rot1, ship, pts, 0, npts, spts)
        for kf in range(nfaces):
            f = faces[kf]
            s = c.face_surface[f]
            if s >= force.shape[0]:  # an idler (surface 2, 3, ...): not summarised
                continue
            count = _face_points(c, f, half_d, rot, rot1, ship, q, v, base, length, npts, pts, spts, xi, wt, g,
                                 cross, fpt)
            for p in range(count):
                sx, sy, sz = fpt[p, 4], fpt[p, 5], fpt[p, 6]
                if p < npts and sz >= 0.0:
                    h = math.sqrt(sx * sx + sz * sz) - (c.face_radius[f] + half_d)
                    if c.face_kind[f] != CYLINDER:  # out of a groove: above its top, or climbed out
                        h = groove_exit(c, f, h, sy)
                    lowest[s] = min(lowest[s], h)
                wp = wt[p]
                if wp == 0.0:
                    continue
                fx, fy, fz = fpt[p, 0], fpt[p, 1], fpt[p, 2]
                energy[s] += wp * fpt[p, 3]
                force[s, 0] += wp * fx
                force[s, 1] += wp * fy
                force[s, 2] += wp * fz
                psi = math.atan2(sx, sz) if angles else np.nan
                if spans:
                    span[s, 0] = min(span[s, 0], psi)
                    span[s, 1] = max(span[s, 1], psi)
                if ends[s, 0] < 0 or e < ends[s, 0] or (e == ends[s, 0] and xi[p] < ends[s, 1]):
                    ends[s, 0] = e
                    ends[s, 1] = xi[p]
                if e > ends[s, 2] or (e == ends[s, 2] and xi[p] > ends[s, 3]):
                    ends[s, 2] = e
                    ends[s, 3] = xi[p]
                if rows < dist.shape[0]:
                    dist[rows, 0] = s
                    dist[rows, 1] = psi
                    dist[rows, 2] = math.sqrt(fx * fx + fy * fy + fz * fz)
                    rows += 1
    for s in range(span.shape[0]):
        if span[s, 0] > span[s, 1]:
            span[s, 0] = np.nan
            span[s, 1] = np.nan
    return rows


@njit(cache=True, inline="always")
def new_summary(distribution_rows: int, spans: bool = True) -> SurfaceSummary:
    """Output arrays for :func:`surface_summary` with room for ``distribution_rows`` points;
    without ``spans`` no angular span (``span`` has no rows, and no angle is computed when
    there is no distribution either)."""
    return SurfaceSummary(np.zeros((2, 3)), np.zeros((2 if spans else 0, 2)), np.zeros((2, 4)), np.zeros(2),
                          np.zeros(2), np.zeros((distribution_rows, 3)))
