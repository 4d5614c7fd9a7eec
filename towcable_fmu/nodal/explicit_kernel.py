"""The explicit path's force kernel: the lumped-mass cable's nodal forces, masses and outputs.

The forces of :func:`towcable_fmu.nodal.assembly.cable_residual` at zero acceleration (minus
its residual), written for a loop that evaluates them once per step: the model's constants are
read out of :class:`~towcable_fmu.nodal.model.NodalModel` once per call into a
:class:`LumpedCable` (contiguous per-element tables), whose fields the step loop holds in
local variables; the forces go straight into one array of nodal forces; nothing is
allocated per step; the added mass is formed only where the water is. The physics is that of
the implicit path (tests/test_explicit_kernel.py compares the two):

* each element's axial force (:func:`towcable_fmu.nodal.element.axial_force`'s laws: the
  paper's N = (L/L0)(EA eps + BA epsdot), or with ``axial_law = "kelvin_voigt"``
  N = EA eps + BA epsdot; EA eps set to 0 in compression for a tension-only cable), half its
  weight on each node;
* in water, at each of the two Gauss points of an element that is below the surface, the
  load of :func:`towcable_fmu.hydro.cable.point_load` without acceleration: the drag of
  :func:`towcable_fmu.hydro.cable.drag` on the velocity relative to the mean current, and
  the buoyancy rho A g; split between the nodes by the linear shape functions; the added
  mass C_a rho A (I - u u^T) of those points lumped on the nodes by the same weights (the
  row sums of the consistent matrix). For the peers' loading ``normal_tangential`` with a
  constant C_D and no amplification the drag is written in closed form,
  1/2 rho d C_D |V_n| V_n + 1/2 rho pi d C_Dt |V_t| V_t (the same function: its loading
  functions are sin^2 and pi cos^2 of the flow angle); the other loadings call ``drag``.
  Turbulence does not enter (the nodal formulation refuses it), so the flow's inertia is 0;
* at the last node the end mass's weight and the lumped towed body's hydrodynamic force
  (:func:`towcable_fmu.hydro.towbody.body_force` without acceleration: buoyancy, drag per
  axis, lift) and its added mass rho V C_m,b, both times its submerged fraction.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..kernel_cache import njit
from ..hydro.cable import drag
from ..hydro.loading import NORMAL_TANGENTIAL
from .element import _G0, _G1, _add_pair
from .model import NodalModel

# columns of the element table (one row per element)
_INV_L0 = 0      #: 1/L0 [1/m]
_EA = 1          #: EA [N]
_BA_L0 = 2       #: BA/L0 [N s/m]
_HALF_WEIGHT = 3  #: mu L0 g / 2 [N]
_TENSION_ONLY = 4  #: 1.0: no elastic force in compression
_KELVIN_VOIGT = 5  #: 1.0: N = EA eps + BA epsdot (else (L/L0) times it)
_HALF_L0 = 6     #: L0/2 [m] (a Gauss point's weight times the length)
_ADDED = 7       #: C_a rho A L0 [kg] (the element's added mass)
_CONSISTENT = 8  #: mu L0 / 6 [kg] (the consistent mass matrix's unit, for the top reaction)
_ELEMENT_COLUMNS = 9
# columns of the hydrodynamic table (one row per element)
_D = 0           #: diameter [m]
_CD = 1          #: constant C_D, or 0 for C_D(Re)
_CDT = 2         #: tangential C_Dt (normal_tangential)
_AMP = 3         #: drag amplification G
_BUOYANCY = 4    #: rho A g [N/m]
_CLOSED = 5      #: 1.0: the closed-form normal_tangential drag (columns _KN, _KT)
_KN = 6          #: 1/2 rho d C_D [kg/m^2]
_KT = 7          #: 1/2 rho pi d C_Dt [kg/m^2]
_HYDRO_COLUMNS = 8
# entries of the body table
_B_HEIGHT, _B_VOLUME, _B_CDA, _B_ADDED, _B_LIFT_K, _B_LIFT_DIR, _B_LIFT_AXIS = 0, 1, 2, 5, 8, 9, 12
_BODY_ENTRIES = 15


class LumpedCable(NamedTuple):
    """What the explicit step loop reads: the model's constants in contiguous tables."""

    n_nodes: int
    wet: bool                #: water enabled
    body_on: bool            #: a lumped towed body in water
    closed: bool             #: every element's drag has the closed form (normal_tangential, constant C_D)
    water: tuple             #: (surface height [m], density [kg/m^3], viscosity [Pa s], g [m/s^2])
    gravity: float           #: g [m/s^2]
    end_mass: float          #: the last node's lumped mass [kg] (its weight)
    elements: np.ndarray     #: (ne, _ELEMENT_COLUMNS)
    hydro: np.ndarray        #: (ne, _HYDRO_COLUMNS)
    kind: np.ndarray         #: (ne,) loading functions (hydro.loading codes)
    flow: np.ndarray         #: (6,) current at the surface [m/s] and its change per metre of height [1/s]
    body: np.ndarray         #: (_BODY_ENTRIES,)
    mass: np.ndarray         #: (n_nodes,) lumped structural masses [kg]
    inv_mass: np.ndarray     #: (n_nodes,) their inverses [1/kg]


@njit(cache=True)
def lumped_cable(m: NodalModel, mass: np.ndarray) -> LumpedCable:
    """The tables of model ``m`` with the lumped node masses ``mass`` [kg]."""
    ne = m.n_nodes - 1
    w = m.water
    rho = w.density if w.enabled else 0.0
    elements = np.empty((ne, _ELEMENT_COLUMNS))
    hydro = np.zeros((ne, _HYDRO_COLUMNS))
    for e in range(ne):
        l0 = m.L0[e]
        elements[e, _INV_L0] = 1.0 / l0
        elements[e, _EA] = m.EA[e]
        elements[e, _BA_L0] = m.BA[e] / l0
        elements[e, _HALF_WEIGHT] = 0.5 * m.mu[e] * l0 * m.gravity
        elements[e, _TENSION_ONLY] = 1.0 if m.tension_only[e] else 0.0
        elements[e, _KELVIN_VOIGT] = 1.0 if m.kelvin_voigt[e] else 0.0
        elements[e, _HALF_L0] = 0.5 * l0
        elements[e, _ADDED] = m.cm[e] * rho * m.area[e] * l0
        elements[e, _CONSISTENT] = m.mu[e] * l0 / 6.0
        d = m.d[e]
        hydro[e, _D], hydro[e, _CD], hydro[e, _CDT], hydro[e, _AMP] = d, m.cd[e], m.cdt[e], m.g_amp[e]
        hydro[e, _BUOYANCY] = rho * m.area[e] * w.gravity
        closed = m.kind[e] == NORMAL_TANGENTIAL and m.cd[e] > 0.0 and m.g_amp[e] == 1.0
        hydro[e, _CLOSED] = 1.0 if closed else 0.0
        hydro[e, _KN] = 0.5 * rho * d * m.cd[e]
        hydro[e, _KT] = 0.5 * rho * math.pi * d * m.cdt[e]
    flow = np.zeros(6)
    if w.current_kind != 0:  # uniform: no gradient (the mean_flow of hydro.water)
        flow[:3] = w.current_v0
        if w.current_kind == 2:
            flow[3:] = w.current_grad
    b = m.body
    body = np.zeros(_BODY_ENTRIES)
    if b.enabled:
        body[_B_HEIGHT], body[_B_VOLUME], body[_B_LIFT_K] = b.height, b.volume, b.lift_k
        for k in range(3):
            body[_B_CDA + k] = b.cda[k]
            body[_B_ADDED + k] = b.added_mass[k]
            body[_B_LIFT_DIR + k] = b.lift_dir[k]
            body[_B_LIFT_AXIS + k] = b.lift_axis[k]
    closed = bool(np.all(hydro[:, _CLOSED] != 0.0))
    return LumpedCable(m.n_nodes, w.enabled, w.enabled and b.enabled, closed, (w.surface_z, rho, w.viscosity, w.gravity),
                       m.gravity, m.end_mass, elements, hydro, m.kind, flow, body, mass, 1.0 / mass)


@njit(cache=True, inline="always")
def _axial(elements: np.ndarray, e: int, length: float, rate: float) -> float:
    """Axial force [N] of element ``e`` of current length ``length`` [m] that lengthens at
    ``rate`` [m/s]."""
    ratio = length * elements[e, _INV_L0]
    eps = ratio - 1.0
    elastic = elements[e, _EA] * (max(eps, 0.0) if elements[e, _TENSION_ONLY] != 0.0 else eps)
    n = elastic + elements[e, _BA_L0] * rate
    return n if elements[e, _KELVIN_VOIGT] != 0.0 else ratio * n


@njit(cache=True, inline="always")
def _add_normal_mass(added: np.ndarray, node: int, k: float, ux: float, uy: float, uz: float) -> None:
    """Add k (I - u u^T) [kg] (u a unit vector) to the node's symmetric 3x3 (xx, yy, zz, xy, xz, yz)."""
    added[node, 0] += k * (1.0 - ux * ux)
    added[node, 1] += k * (1.0 - uy * uy)
    added[node, 2] += k * (1.0 - uz * uz)
    added[node, 3] -= k * ux * uy
    added[node, 4] -= k * ux * uz
    added[node, 5] -= k * uy * uz


@njit(cache=True, inline="always")
def _point_drag(closed: bool, hydro: np.ndarray, kind: np.ndarray, e: int, rho: float, viscosity: float, rx: float,
                ry: float, rz: float, mx: float, my: float, mz: float, ux: float, uy: float, uz: float) -> tuple:
    """Drag per length [N/m] on element ``e`` at a point with relative flow (rx, ry, rz) and
    mean current (mx, my, mz) [m/s], the element along the unit (ux, uy, uz); ``closed``:
    every element has the closed form (a constant where the kernel is inlined: the compiled
    loop then has no call, which costs a fifth of the wet force loop's time even untaken)."""
    if closed or hydro[e, _CLOSED] != 0.0:
        vt = rx * ux + ry * uy + rz * uz
        nx, ny, nz = rx - vt * ux, ry - vt * uy, rz - vt * uz
        kn = hydro[e, _KN] * math.sqrt(nx * nx + ny * ny + nz * nz)
        kt = hydro[e, _KT] * abs(vt) * vt
        return kn * nx + kt * ux, kn * ny + kt * uy, kn * nz + kt * uz
    d, cd, cdt, amp = hydro[e, _D], hydro[e, _CD], hydro[e, _CDT], hydro[e, _AMP]
    fx, fy, fz = drag(rho, viscosity, kind[e], d, cd, cdt, rx, ry, rz, ux, uy, uz)
    if amp != 1.0:  # the amplified mean drag (point_load)
        sx, sy, sz = drag(rho, viscosity, kind[e], d, cd, cdt, mx, my, mz, ux, uy, uz)
        fx, fy, fz = fx + (amp - 1.0) * sx, fy + (amp - 1.0) * sy, fz + (amp - 1.0) * sz
    return fx, fy, fz


@njit(cache=True, inline="always")
def cable_forces(n_nodes: int, wet: bool, body_on: bool, closed: bool, water: tuple, gravity: float,
                 end_mass: float, elements: np.ndarray, hydro: np.ndarray, kind: np.ndarray, flow: np.ndarray,
                 body: np.ndarray, q: np.ndarray, v: np.ndarray, f: np.ndarray, added: np.ndarray) -> None:
    """Nodal forces [N] on all nodes into ``f`` (3 n_nodes) at positions ``q`` [m] and
    velocities ``v`` [m/s]; with ``wet`` the nodes' added masses [kg] into ``added``
    (n_nodes, 6: xx, yy, zz, xy, xz, yz; not touched in a dry scene). ``closed``: pass
    True (a literal) only where :attr:`LumpedCable.closed` is. The other arguments are the
    fields of a :class:`LumpedCable` of the same names."""
    surface, rho, viscosity = water[0], water[1], water[2]
    for i in range(3 * n_nodes):
        f[i] = 0.0
    if wet:
        for node in range(n_nodes):
            for k in range(6):
                added[node, k] = 0.0
    for e in range(n_nodes - 1):
        i = 3 * e
        dx, dy, dz = q[i + 3] - q[i], q[i + 4] - q[i + 1], q[i + 5] - q[i + 2]
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        inv = 1.0 / length if length > 0.0 else math.nan  # a collapsed element: no direction
        ux, uy, uz = dx * inv, dy * inv, dz * inv
        n = _axial(elements, e, length, ux * (v[i + 3] - v[i]) + uy * (v[i + 4] - v[i + 1]) + uz * (v[i + 5] - v[i + 2]))
        half_weight = elements[e, _HALF_WEIGHT]
        f[i] += n * ux
        f[i + 1] += n * uy
        f[i + 2] += n * uz - half_weight
        f[i + 3] -= n * ux
        f[i + 4] -= n * uy
        f[i + 5] -= n * uz + half_weight
        if not wet:
            continue
        w0, w1 = 0.0, 0.0  # the submerged Gauss points' shares of the element, node by node
        for g in range(2):
            xi = _G0 if g == 0 else _G1
            pz = (1.0 - xi) * q[i + 2] + xi * q[i + 5]
            if pz >= surface:
                continue
            w0 += 0.5 * (1.0 - xi)
            w1 += 0.5 * xi
            below = pz - surface
            mx, my, mz = flow[0] + flow[3] * below, flow[1] + flow[4] * below, flow[2] + flow[5] * below
            px, py, pw = _point_drag(closed, hydro, kind, e, rho, viscosity, mx - ((1.0 - xi) * v[i] + xi * v[i + 3]),
                                     my - ((1.0 - xi) * v[i + 1] + xi * v[i + 4]),
                                     mz - ((1.0 - xi) * v[i + 2] + xi * v[i + 5]), mx, my, mz, ux, uy, uz)
            pw += hydro[e, _BUOYANCY]
            _add_pair(f, i, px, py, pw, elements[e, _HALF_L0] * (1.0 - xi), elements[e, _HALF_L0] * xi)
        if w0 + w1 > 0.0:
            _add_normal_mass(added, e, w0 * elements[e, _ADDED], ux, uy, uz)
            _add_normal_mass(added, e + 1, w1 * elements[e, _ADDED], ux, uy, uz)
    last = 3 * (n_nodes - 1)
    f[last + 2] -= end_mass * gravity
    if body_on:
        _add_body(n_nodes - 1, water, flow, body, q, v, f, added)


@njit(cache=True, inline="always")
def _add_body(node: int, water: tuple, flow: np.ndarray, body: np.ndarray, q: np.ndarray, v: np.ndarray,
              f: np.ndarray, added: np.ndarray) -> None:
    """The lumped body's hydrodynamic force [N] (no acceleration) on ``node`` and its added
    mass [kg], both times its submerged fraction (hydro.towbody.submerged)."""
    surface, rho, g = water[0], water[1], water[3]
    i = 3 * node
    z = q[i + 2]
    height = body[_B_HEIGHT]
    if height > 0.0:
        fraction = min(max((surface - z) / height + 0.5, 0.0), 1.0)
    else:
        fraction = 1.0 if z < surface else 0.0
    if fraction == 0.0:
        return
    below = z - surface
    rx = flow[0] + flow[3] * below - v[i]
    ry = flow[1] + flow[4] * below - v[i + 1]
    rz = flow[2] + flow[5] * below - v[i + 2]
    along = rx * body[_B_LIFT_AXIS] + ry * body[_B_LIFT_AXIS + 1] + rz * body[_B_LIFT_AXIS + 2]
    lift = body[_B_LIFT_K] * along * along
    half_rho = 0.5 * rho
    f[i] += fraction * (half_rho * body[_B_CDA] * abs(rx) * rx + lift * body[_B_LIFT_DIR])
    f[i + 1] += fraction * (half_rho * body[_B_CDA + 1] * abs(ry) * ry + lift * body[_B_LIFT_DIR + 1])
    f[i + 2] += fraction * (rho * body[_B_VOLUME] * g + half_rho * body[_B_CDA + 2] * abs(rz) * rz
                            + lift * body[_B_LIFT_DIR + 2])
    for k in range(3):
        added[node, k] += fraction * body[_B_ADDED + k]


@njit(cache=True, inline="always")
def solve_accelerations(wet: bool, mass: np.ndarray, inv_mass: np.ndarray, f: np.ndarray, added: np.ndarray,
                        a: np.ndarray) -> None:
    """Accelerations [m/s^2] of the free nodes (all but node 0) into ``a``: the forces ``f`` [N]
    through the lumped masses ``mass`` [kg] (``inv_mass`` their inverses), and with ``wet`` the
    nodes' added masses ``added`` [kg] (each node's symmetric 3x3 inverted by cofactors:
    positive definite, a mass plus a semi-definite part)."""
    n_nodes = mass.size
    if not wet:
        for i in range(3, 3 * n_nodes):
            a[i] = f[i] * inv_mass[i // 3]
        return
    for node in range(1, n_nodes):
        i = 3 * node
        xx, yy, zz = mass[node] + added[node, 0], mass[node] + added[node, 1], mass[node] + added[node, 2]
        xy, xz, yz = added[node, 3], added[node, 4], added[node, 5]
        c00, c11, c22 = yy * zz - yz * yz, xx * zz - xz * xz, xx * yy - xy * xy
        c01, c02, c12 = xz * yz - xy * zz, xy * yz - xz * yy, xy * xz - xx * yz
        inv_det = 1.0 / (xx * c00 + xy * c01 + xz * c02)
        fx, fy, fz = f[i], f[i + 1], f[i + 2]
        a[i] = (c00 * fx + c01 * fy + c02 * fz) * inv_det
        a[i + 1] = (c01 * fx + c11 * fy + c12 * fz) * inv_det
        a[i + 2] = (c02 * fx + c12 * fy + c22 * fz) * inv_det


@njit(cache=True, error_model="numpy")
def lumped_forces(m: NodalModel, mass: np.ndarray, q: np.ndarray, v: np.ndarray, f: np.ndarray,
                  added: np.ndarray) -> None:
    """:func:`cable_forces` of model ``m`` with node masses ``mass`` [kg]: forces [N] into
    ``f`` (3 n_nodes) and, in water, added masses [kg] into ``added`` (n_nodes, 6)."""
    c = lumped_cable(m, mass)
    cable_forces(c.n_nodes, c.wet, c.body_on, False, c.water, c.gravity, c.end_mass, c.elements, c.hydro, c.kind,
                 c.flow, c.body, q, v, f, added)


@njit(cache=True, inline="always")
def _top_reaction(wet: bool, water: tuple, flow: np.ndarray, elements: np.ndarray, hydro: np.ndarray,
                  kind: np.ndarray, q: np.ndarray, v: np.ndarray, x: np.ndarray) -> tuple:
    """The force [N] the top support exerts on the cable (the residual of
    :func:`towcable_fmu.nodal.element.add_element` for element 0 at node 0, with its
    consistent inertia and the added mass of its Gauss points) at positions ``q`` [m],
    velocities ``v`` [m/s] and accelerations ``x`` [m/s^2]."""
    dx, dy, dz = q[3] - q[0], q[4] - q[1], q[5] - q[2]
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    ux, uy, uz = dx / length, dy / length, dz / length
    n = _axial(elements, 0, length, ux * (v[3] - v[0]) + uy * (v[4] - v[1]) + uz * (v[5] - v[2]))
    ms = elements[0, _CONSISTENT]
    rx = ms * (2.0 * x[0] + x[3]) - n * ux
    ry = ms * (2.0 * x[1] + x[4]) - n * uy
    rz = ms * (2.0 * x[2] + x[5]) - n * uz + elements[0, _HALF_WEIGHT]
    if not wet:
        return rx, ry, rz
    surface, rho, viscosity = water[0], water[1], water[2]
    for g in range(2):
        xi = _G0 if g == 0 else _G1
        pz = (1.0 - xi) * q[2] + xi * q[5]
        if pz >= surface:
            continue
        below = pz - surface
        mx, my, mz = flow[0] + flow[3] * below, flow[1] + flow[4] * below, flow[2] + flow[5] * below
        px, py, pw = _point_drag(False, hydro, kind, 0, rho, viscosity, mx - ((1.0 - xi) * v[0] + xi * v[3]),
                                 my - ((1.0 - xi) * v[1] + xi * v[4]), mz - ((1.0 - xi) * v[2] + xi * v[5]),
                                 mx, my, mz, ux, uy, uz)
        ax, ay, az = (1.0 - xi) * x[0] + xi * x[3], (1.0 - xi) * x[1] + xi * x[4], (1.0 - xi) * x[2] + xi * x[5]
        au = ax * ux + ay * uy + az * uz
        c = elements[0, _HALF_L0] * (1.0 - xi)
        k = 0.5 * (1.0 - xi) * elements[0, _ADDED]  # c times the added mass per length
        rx += k * (ax - au * ux) - c * px
        ry += k * (ay - au * uy) - c * py
        rz += k * (az - au * uz) - c * (pw + hydro[0, _BUOYANCY])
    return rx, ry, rz


@njit(cache=True, inline="always")
def explicit_outputs(wet: bool, water: tuple, flow: np.ndarray, elements: np.ndarray, hydro: np.ndarray,
                     kind: np.ndarray, q: np.ndarray, v: np.ndarray, x: np.ndarray, out: np.ndarray) -> None:
    """The outputs of :func:`towcable_fmu.nodal.integrators.output_values` for a lumped body
    (its first 10) at one instant into ``out``, nothing allocated: the top reaction's
    magnitude [N] and angle from the vertical [rad] (:func:`_top_reaction`), the largest and
    smallest axial force [N], the last node's position [m] and velocity [m/s]. Arguments:
    the fields of a :class:`LumpedCable` and the state (``x`` the accelerations)."""
    rx, ry, rz = _top_reaction(wet, water, flow, elements, hydro, kind, q, v, x)
    out[0] = math.sqrt(rx * rx + ry * ry + rz * rz)
    out[1] = math.acos(min(max(abs(rz) / max(out[0], 1e-300), 0.0), 1.0))
    hi, lo = -np.inf, np.inf
    for e in range(elements.shape[0]):
        i = 3 * e
        dx, dy, dz = q[i + 3] - q[i], q[i + 4] - q[i + 1], q[i + 5] - q[i + 2]
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        rate = (dx * (v[i + 3] - v[i]) + dy * (v[i + 4] - v[i + 1]) + dz * (v[i + 5] - v[i + 2])) / length
        n = _axial(elements, e, length, rate)
        hi = max(hi, n)
        lo = min(lo, n)
    out[2], out[3] = hi, lo
    i = q.size - 3
    for k in range(3):
        out[4 + k] = q[i + k]
        out[7 + k] = v[i + k]


@njit(cache=True, error_model="numpy")
def lumped_outputs(m: NodalModel, mass: np.ndarray, q: np.ndarray, v: np.ndarray, x: np.ndarray,
                   out: np.ndarray) -> None:
    """:func:`explicit_outputs` of model ``m`` (its tables formed here) into ``out`` (10,)."""
    c = lumped_cable(m, mass)
    explicit_outputs(c.wet, c.water, c.flow, c.elements, c.hydro, c.kind, q, v, x, out)
