"""The explicit path's force kernel: the lumped-mass cable's nodal forces, masses and outputs.

The forces of :func:`towcable_fmu.nodal.assembly.cable_residual` at zero acceleration (minus
its residual) and the lumped masses, written for a loop that evaluates them once per step:
the model's constants are read out of :class:`~towcable_fmu.nodal.model.NodalModel` once
per call into a :class:`LumpedCable`; the step keeps the nodes' positions, velocities and
accelerations and its per-element results as rows of one array (structure of arrays, rows a
constant apart: LLVM vectorises the element and node loops); nothing is allocated per step.
The physics is that of the implicit path (tests/test_explicit_kernel.py compares the two,
tests/test_explicit.py the stepping with a leapfrog written on cable_residual):

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

from ..jit.kernel_cache import njit
from ..hydro.cable import drag
from ..hydro.loading import NORMAL_TANGENTIAL
from .element import _G0, _G1
from .model import NodalModel

# columns of the element table (one row per element; the outputs' and top reaction's laws)
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

# The step's arrays are structures of arrays: one flat array of rows, row r's entry j at
# r * stride + j (node j, or element j between nodes j and j + 1). With a stride known to
# the compiler (:data:`STRIDE`, a literal where the step is inlined) every access of a loop
# lies at a constant distance from the others in one array, so LLVM vectorises the element
# and node loops with no run-time alias checks (with separate arrays it needs more checks
# than it allows and leaves the loops scalar).
#: rows of the per-element table (:attr:`LumpedCable.table`)
(_T_INV_L0, _T_EA, _T_BA_L0, _T_HALF_WEIGHT, _T_FLOOR, _T_KELVIN_VOIGT, _T_HALF_L0, _T_ADDED, _T_KN, _T_KT,
 _T_BUOYANCY, _T_MASS) = range(12)
_TABLE_ROWS = 12
#: rows of the step's state and scratch (:func:`new_work`): positions [m], velocities [m/s],
#: accelerations [m/s^2] of the nodes; each element's force on its first and on its second node
#: [N], its added masses lumped on them [kg], its unit tangent
_X, _V, _A, _F0, _F1, _K0, _K1, _U = 0, 3, 6, 9, 12, 15, 16, 17
_WORK_ROWS = 20
#: the stride compiled as a constant (nodes per row) for every cable that fits; longer cables
#: use their node count (the same code, not vectorised). LLVM picks the element loop's vector
#: width from the stride (on this AMD EPYC, znver3, and compiled for haswell alike): rows 32
#: apart left the loops scalar, 40 to 64 apart the element loop 2 doubles wide, 72 to 136
#: apart 4 wide, which halves its passes (latency-bound: three square roots and a division
#: per element); 16-element snapping cable, scratch loop: 385 ns per step at 40, 274 at 72,
#: 270 at 104 and 120, 289 at 136 (270 compiled for haswell).
STRIDE = 120
#: the element loop's passes are rounded up to this many elements (its vector width) where the
#: rows have room and the drag has the closed form: a cable of 2 elements takes one vector pass
#: instead of the scalar remainder loop (the extra elements compute from the empty columns
#: beyond the last node and are read by nobody)
_LANES = 4


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
    stride: int              #: entries per row of ``table`` and of the work array (:func:`stride_for`)
    table: np.ndarray        #: (_TABLE_ROWS * stride,) the element constants and node masses by rows


@njit(cache=True)
def stride_for(n_nodes: int) -> int:
    """Entries per row of the step's arrays for a cable of ``n_nodes`` nodes."""
    return STRIDE if n_nodes <= STRIDE else n_nodes


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
    stride = stride_for(m.n_nodes)
    table = np.zeros(_TABLE_ROWS * stride)
    for e in range(ne):
        for row, value in ((_T_INV_L0, elements[e, _INV_L0]), (_T_EA, elements[e, _EA]),
                           (_T_BA_L0, elements[e, _BA_L0]), (_T_HALF_WEIGHT, elements[e, _HALF_WEIGHT]),
                           (_T_KELVIN_VOIGT, elements[e, _KELVIN_VOIGT]), (_T_HALF_L0, elements[e, _HALF_L0]),
                           (_T_ADDED, elements[e, _ADDED]), (_T_KN, hydro[e, _KN]), (_T_KT, hydro[e, _KT]),
                           (_T_BUOYANCY, hydro[e, _BUOYANCY])):
            table[row * stride + e] = value
        # the strain below which the elastic force is kept: 0 tension-only, else none
        table[_T_FLOOR * stride + e] = 0.0 if m.tension_only[e] else -np.inf
    for j in range(m.n_nodes):
        table[_T_MASS * stride + j] = mass[j]
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
                       m.gravity, m.end_mass, elements, hydro, m.kind, flow, body, mass, stride, table)


@njit(cache=True)
def new_work(c: LumpedCable) -> np.ndarray:
    """The step's state and scratch for cable ``c`` (rows of ``c.stride``: :data:`_WORK_ROWS`)."""
    return np.zeros(_WORK_ROWS * c.stride)


@njit(cache=True, inline="always")
def load_state(q: np.ndarray, v: np.ndarray, a: np.ndarray, work: np.ndarray, stride: int) -> None:
    """Positions ``q`` [m], velocities ``v`` [m/s], accelerations ``a`` [m/s^2] (3 n_nodes,
    node by node) into the rows of ``work``."""
    for j in range(q.size // 3):
        for k in range(3):
            work[(_X + k) * stride + j] = q[3 * j + k]
            work[(_V + k) * stride + j] = v[3 * j + k]
            work[(_A + k) * stride + j] = a[3 * j + k]


@njit(cache=True, inline="always")
def store_state(work: np.ndarray, stride: int, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> None:
    """The rows of ``work`` back into ``q``, ``v``, ``a`` (the inverse of :func:`load_state`)."""
    for j in range(q.size // 3):
        for k in range(3):
            q[3 * j + k] = work[(_X + k) * stride + j]
            v[3 * j + k] = work[(_V + k) * stride + j]
            a[3 * j + k] = work[(_A + k) * stride + j]


@njit(cache=True, inline="always")
def set_top(work: np.ndarray, stride: int, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> None:
    """Node 0's position ``q`` [m], velocity ``v`` [m/s] and acceleration ``a`` [m/s^2] (their
    first three entries) into ``work``."""
    for k in range(3):
        work[(_X + k) * stride] = q[k]
        work[(_V + k) * stride] = v[k]
        work[(_A + k) * stride] = a[k]


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
def _point_drag(closed: bool, hydro: np.ndarray, kind: np.ndarray, e: int, rho: float, viscosity: float, rx: float,
                ry: float, rz: float, mx: float, my: float, mz: float, ux: float, uy: float, uz: float, kn: float,
                kt: float) -> tuple:
    """Drag per length [N/m] on element ``e`` at a point with relative flow (rx, ry, rz) and
    mean current (mx, my, mz) [m/s], the element along the unit (ux, uy, uz); ``kn``, ``kt``
    the element's closed-form factors (_KN, _KT). ``closed``: every element has the closed
    form (a constant where the kernel is inlined: the compiled loop then has no call, and
    LLVM vectorises it)."""
    if closed or hydro[e, _CLOSED] != 0.0:
        vt = rx * ux + ry * uy + rz * uz
        nx, ny, nz = rx - vt * ux, ry - vt * uy, rz - vt * uz
        kn = kn * math.sqrt(nx * nx + ny * ny + nz * nz)
        kt = kt * abs(vt) * vt
        return kn * nx + kt * ux, kn * ny + kt * uy, kn * nz + kt * uz
    d, cd, cdt, amp = hydro[e, _D], hydro[e, _CD], hydro[e, _CDT], hydro[e, _AMP]
    fx, fy, fz = drag(rho, viscosity, kind[e], d, cd, cdt, rx, ry, rz, ux, uy, uz)
    if amp != 1.0:  # the amplified mean drag (point_load)
        sx, sy, sz = drag(rho, viscosity, kind[e], d, cd, cdt, mx, my, mz, ux, uy, uz)
        fx, fy, fz = fx + (amp - 1.0) * sx, fy + (amp - 1.0) * sy, fz + (amp - 1.0) * sz
    return fx, fy, fz


@njit(cache=True, inline="always")
def element_forces(stride: int, closed: bool, wet: bool, n_nodes: int, water: tuple, flow: np.ndarray,
                   hydro: np.ndarray, kind: np.ndarray, table: np.ndarray, work: np.ndarray) -> None:
    """Each element's forces [N] on its two nodes and its added masses [kg] lumped on them,
    and its unit tangent, into the rows of ``work`` (_F0, _F1, _K0, _K1, _U) from the
    positions and velocities there (_X, _V): its axial force and half its weight on each
    node, and with ``wet`` at each of its two Gauss points below the surface the drag and
    buoyancy, split by the linear shape functions, and the added mass C_a rho A (I - u u^T)
    lumped by the same weights (the scalars _K0, _K1 times I - u u^T). ``stride``: the rows'
    length (a literal where the step is compiled for it); ``closed``: as :func:`_point_drag`.
    With ``closed`` the loop runs on to a multiple of :data:`_LANES` elements where the rows
    have room.
    The other arguments are the fields of a :class:`LumpedCable` of the same names."""
    surface, rho, viscosity = water[0], water[1], water[2]
    f0, f1, f2, g0, g1, g2 = flow[0], flow[1], flow[2], flow[3], flow[4], flow[5]
    s = stride
    x, y, z, vx, vy, vz = _X * s, (_X + 1) * s, (_X + 2) * s, _V * s, (_V + 1) * s, (_V + 2) * s
    # (padded only with the closed-form drag, which reads no per-element array but the rows)
    count = min((n_nodes + _LANES - 2) // _LANES * _LANES, s - 1) if closed else n_nodes - 1
    for e in range(count):
        dx, dy, dz = work[x + e + 1] - work[x + e], work[y + e + 1] - work[y + e], work[z + e + 1] - work[z + e]
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        inv = 1.0 / length  # a collapsed element: no direction (NaN)
        ux, uy, uz = dx * inv, dy * inv, dz * inv
        ratio = length * table[_T_INV_L0 * s + e]
        rate = (ux * (work[vx + e + 1] - work[vx + e]) + uy * (work[vy + e + 1] - work[vy + e])
                + uz * (work[vz + e + 1] - work[vz + e]))
        n = table[_T_EA * s + e] * max(ratio - 1.0, table[_T_FLOOR * s + e]) + table[_T_BA_L0 * s + e] * rate
        n = n if table[_T_KELVIN_VOIGT * s + e] != 0.0 else ratio * n
        half_weight = table[_T_HALF_WEIGHT * s + e]
        ax, ay, az = n * ux, n * uy, n * uz - half_weight  # on the first node
        bx, by, bz = -n * ux, -n * uy, -n * uz - half_weight  # on the second
        k0, k1 = 0.0, 0.0
        if wet:
            half_l0, added = table[_T_HALF_L0 * s + e], table[_T_ADDED * s + e]
            kn, kt, buoyancy = table[_T_KN * s + e], table[_T_KT * s + e], table[_T_BUOYANCY * s + e]
            for g in range(2):
                xi = _G0 if g == 0 else _G1
                pz = (1.0 - xi) * work[z + e] + xi * work[z + e + 1]
                below = pz - surface
                mx, my, mz = f0 + g0 * below, f1 + g1 * below, f2 + g2 * below
                px, py, pw = _point_drag(closed, hydro, kind, e, rho, viscosity,
                                         mx - ((1.0 - xi) * work[vx + e] + xi * work[vx + e + 1]),
                                         my - ((1.0 - xi) * work[vy + e] + xi * work[vy + e + 1]),
                                         mz - ((1.0 - xi) * work[vz + e] + xi * work[vz + e + 1]), mx, my, mz,
                                         ux, uy, uz, kn, kt)
                pw += buoyancy
                # a point above the surface adds nothing (a select, not a branch: the loop vectorises)
                c0 = half_l0 * (1.0 - xi) if pz < surface else 0.0
                c1 = half_l0 * xi if pz < surface else 0.0
                ax, ay, az = ax + c0 * px, ay + c0 * py, az + c0 * pw
                bx, by, bz = bx + c1 * px, by + c1 * py, bz + c1 * pw
                k0 += 0.5 * (1.0 - xi) * added if pz < surface else 0.0
                k1 += 0.5 * xi * added if pz < surface else 0.0
        work[_F0 * s + e], work[(_F0 + 1) * s + e], work[(_F0 + 2) * s + e] = ax, ay, az
        work[_F1 * s + e], work[(_F1 + 1) * s + e], work[(_F1 + 2) * s + e] = bx, by, bz
        work[_K0 * s + e], work[_K1 * s + e] = k0, k1
        work[_U * s + e], work[(_U + 1) * s + e], work[(_U + 2) * s + e] = ux, uy, uz


@njit(cache=True, inline="always")
def _node_mass(stride: int, table: np.ndarray, work: np.ndarray, j: int, first: bool, last: bool) -> tuple:
    """Node j's 3x3 mass [kg] (xx, yy, zz, xy, xz, yz): its lumped mass and the added masses
    k (I - u u^T) of the elements on either side (none before the first node, after the last)."""
    s = stride
    k0 = 0.0 if last else work[_K0 * s + j]  # element j, of which node j is the first node
    k1 = 0.0 if first else work[_K1 * s + j - 1]  # element j - 1
    ax, ay, az = (0.0, 0.0, 0.0) if last else (work[_U * s + j], work[(_U + 1) * s + j], work[(_U + 2) * s + j])
    bx, by, bz = ((0.0, 0.0, 0.0) if first else
                  (work[_U * s + j - 1], work[(_U + 1) * s + j - 1], work[(_U + 2) * s + j - 1]))
    diagonal = table[_T_MASS * s + j] + k0 + k1
    return (diagonal - k0 * ax * ax - k1 * bx * bx, diagonal - k0 * ay * ay - k1 * by * by,
            diagonal - k0 * az * az - k1 * bz * bz, -k0 * ax * ay - k1 * bx * by, -k0 * ax * az - k1 * bx * bz,
            -k0 * ay * az - k1 * by * bz)


@njit(cache=True, inline="always")
def _solve3(xx: float, yy: float, zz: float, xy: float, xz: float, yz: float, fx: float, fy: float,
            fz: float) -> tuple:
    """The solution of the symmetric 3x3 system (xx, yy, zz, xy, xz, yz) a = f by cofactors
    (positive definite here: a mass plus a semi-definite added mass)."""
    c00, c11, c22 = yy * zz - yz * yz, xx * zz - xz * xz, xx * yy - xy * xy
    c01, c02, c12 = xz * yz - xy * zz, xy * yz - xz * yy, xy * xz - xx * yz
    inv_det = 1.0 / (xx * c00 + xy * c01 + xz * c02)
    return ((c00 * fx + c01 * fy + c02 * fz) * inv_det, (c01 * fx + c11 * fy + c12 * fz) * inv_det,
            (c02 * fx + c12 * fy + c22 * fz) * inv_det)


@njit(cache=True, inline="always")
def _body_load(water: tuple, flow: np.ndarray, body: np.ndarray, z: float, vx: float, vy: float,
               vz: float) -> tuple:
    """The lumped body's hydrodynamic force [N] (no acceleration) at height ``z`` [m] moving
    at (vx, vy, vz) [m/s] and its added mass [kg] per axis, both times its submerged
    fraction (hydro.towbody.submerged): (fx, fy, fz, mx, my, mz)."""
    surface, rho, g = water[0], water[1], water[3]
    height = body[_B_HEIGHT]
    if height > 0.0:
        fraction = min(max((surface - z) / height + 0.5, 0.0), 1.0)
    else:
        fraction = 1.0 if z < surface else 0.0
    if fraction == 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    below = z - surface
    rx = flow[0] + flow[3] * below - vx
    ry = flow[1] + flow[4] * below - vy
    rz = flow[2] + flow[5] * below - vz
    along = rx * body[_B_LIFT_AXIS] + ry * body[_B_LIFT_AXIS + 1] + rz * body[_B_LIFT_AXIS + 2]
    lift = body[_B_LIFT_K] * along * along
    half_rho = 0.5 * rho
    return (fraction * (half_rho * body[_B_CDA] * abs(rx) * rx + lift * body[_B_LIFT_DIR]),
            fraction * (half_rho * body[_B_CDA + 1] * abs(ry) * ry + lift * body[_B_LIFT_DIR + 1]),
            fraction * (rho * body[_B_VOLUME] * g + half_rho * body[_B_CDA + 2] * abs(rz) * rz
                        + lift * body[_B_LIFT_DIR + 2]),
            fraction * body[_B_ADDED], fraction * body[_B_ADDED + 1], fraction * body[_B_ADDED + 2])


@njit(cache=True, inline="always")
def node_accelerations(stride: int, n_nodes: int, body_on: bool, water: tuple, gravity: float, end_mass: float,
                       flow: np.ndarray, body: np.ndarray, table: np.ndarray, work: np.ndarray,
                       kick: float) -> None:
    """The free nodes' accelerations [m/s^2] into row _A of ``work`` from the elements' forces
    and added masses there (:func:`element_forces`), each node's 3x3 mass solved in closed
    form; then the velocities (row _V) kicked by ``kick`` [s] times them. At the last node also
    the end mass's weight and the lumped body's load and added mass (``body_on``)."""
    s = stride
    for j in range(1, n_nodes - 1):
        xx, yy, zz, xy, xz, yz = _node_mass(s, table, work, j, False, False)
        # (the force in locals: stored to row _A and read back before the solve, it kept LLVM
        # from vectorising this loop; 167 -> 61 ns per call at 16 elements)
        fx = work[_F0 * s + j] + work[_F1 * s + j - 1]
        fy = work[(_F0 + 1) * s + j] + work[(_F1 + 1) * s + j - 1]
        fz = work[(_F0 + 2) * s + j] + work[(_F1 + 2) * s + j - 1]
        ax, ay, az = _solve3(xx, yy, zz, xy, xz, yz, fx, fy, fz)
        work[_A * s + j], work[(_A + 1) * s + j], work[(_A + 2) * s + j] = ax, ay, az
        work[_V * s + j] += kick * ax
        work[(_V + 1) * s + j] += kick * ay
        work[(_V + 2) * s + j] += kick * az
    j = n_nodes - 1
    xx, yy, zz, xy, xz, yz = _node_mass(s, table, work, j, False, True)
    fx, fy = work[_F1 * s + j - 1], work[(_F1 + 1) * s + j - 1]
    fz = work[(_F1 + 2) * s + j - 1] - end_mass * gravity
    if body_on:
        bx, by, bz, mx, my, mz = _body_load(water, flow, body, work[(_X + 2) * s + j], work[_V * s + j],
                                            work[(_V + 1) * s + j], work[(_V + 2) * s + j])
        fx, fy, fz = fx + bx, fy + by, fz + bz
        xx, yy, zz = xx + mx, yy + my, zz + mz
    ax, ay, az = _solve3(xx, yy, zz, xy, xz, yz, fx, fy, fz)
    work[_A * s + j], work[(_A + 1) * s + j], work[(_A + 2) * s + j] = ax, ay, az
    work[_V * s + j] += kick * ax
    work[(_V + 1) * s + j] += kick * ay
    work[(_V + 2) * s + j] += kick * az


@njit(cache=True, inline="always")
def update_with(stride: int, closed: bool, n_nodes: int, wet: bool, body_on: bool, water: tuple, gravity: float,
                end_mass: float, flow: np.ndarray, body: np.ndarray, hydro: np.ndarray, kind: np.ndarray,
                table: np.ndarray, work: np.ndarray, h: float) -> None:
    """:func:`leapfrog_update` compiled for ``stride`` and ``closed`` (literals where they can be)."""
    half = 0.5 * h
    for k in range(3):
        x, v, a = (_X + k) * stride, (_V + k) * stride, (_A + k) * stride
        for j in range(1, n_nodes):
            work[v + j] += half * work[a + j]
            work[x + j] += h * work[v + j]
    element_forces(stride, closed, wet, n_nodes, water, flow, hydro, kind, table, work)
    node_accelerations(stride, n_nodes, body_on, water, gravity, end_mass, flow, body, table, work, half)


@njit(cache=True, inline="always")
def leapfrog_update(n_nodes: int, closed: bool, stride: int, wet: bool, body_on: bool, water: tuple, gravity: float,
                    end_mass: float, flow: np.ndarray, body: np.ndarray, hydro: np.ndarray, kind: np.ndarray,
                    table: np.ndarray, work: np.ndarray, h: float) -> None:
    """One leapfrog step of ``h`` [s] of the free nodes in ``work`` (node 0 is set by the
    caller): kick v += h/2 a, drift q += h v, the accelerations at the new positions and
    half-step velocities (:func:`element_forces`, :func:`node_accelerations`), kick
    v += h/2 a. With h = 0 only the accelerations. The other arguments are the fields of a
    :class:`LumpedCable` of the same names (passed one by one: a named tuple of arrays
    passed inside the step loop is reference-counted field by field at every step). The code
    is compiled for the cable's stride (a literal: vectorised) and drag (the closed form
    inline) where it can be."""
    if closed and stride == STRIDE:
        update_with(STRIDE, True, n_nodes, wet, body_on, water, gravity, end_mass, flow, body, hydro, kind, table,
                    work, h)
    else:
        update_with(stride, False, n_nodes, wet, body_on, water, gravity, end_mass, flow, body, hydro, kind, table,
                    work, h)


# fastmath "contract" (fused multiply-adds: round-off only) on every compiled loop of the
# step; tests/test_explicit.py checks the stepping against a reference leapfrog on cable_residual
STEP_FASTMATH = {"contract"}


@njit(cache=True, error_model="numpy", fastmath=STEP_FASTMATH)
def lumped_forces(m: NodalModel, mass: np.ndarray, q: np.ndarray, v: np.ndarray, f: np.ndarray,
                  added: np.ndarray, a: np.ndarray) -> None:
    """The step's loads of model ``m`` with node masses ``mass`` [kg] at positions ``q`` [m] and
    velocities ``v`` [m/s] (3 n_nodes): the force [N] on each node into ``f`` (minus the
    residual of cable_residual at zero acceleration), the added masses [kg] of the nodes
    into ``added`` (n_nodes, 6: xx, yy, zz, xy, xz, yz; the structural mass not included)
    and the free nodes' accelerations [m/s^2] into ``a`` (node 0's entries kept): the
    step's own code (:func:`leapfrog_update` with h = 0), read back out of its rows."""
    c = lumped_cable(m, mass)
    s = c.stride
    work = new_work(c)
    load_state(q, v, a, work, s)
    leapfrog_update(c.n_nodes, c.closed, s, c.wet, c.body_on, c.water, c.gravity, c.end_mass, c.flow, c.body,
                    c.hydro, c.kind, c.table, work, 0.0)
    n = c.n_nodes
    for j in range(n):
        first, last = j == 0, j == n - 1
        for k in range(3):
            f[3 * j + k] = ((0.0 if last else work[(_F0 + k) * s + j])
                            + (0.0 if first else work[(_F1 + k) * s + j - 1]))
            if not first:
                a[3 * j + k] = work[(_A + k) * s + j]
        xx, yy, zz, xy, xz, yz = _node_mass(s, c.table, work, j, first, last)
        added[j, 0], added[j, 1], added[j, 2] = xx - mass[j], yy - mass[j], zz - mass[j]
        added[j, 3], added[j, 4], added[j, 5] = xy, xz, yz
    f[3 * n - 1] -= c.end_mass * c.gravity
    if c.body_on:
        j = n - 1
        bx, by, bz, mx, my, mz = _body_load(c.water, c.flow, c.body, q[3 * j + 2], v[3 * j], v[3 * j + 1],
                                            v[3 * j + 2])
        f[3 * j] += bx
        f[3 * j + 1] += by
        f[3 * j + 2] += bz
        added[j, 0] += mx
        added[j, 1] += my
        added[j, 2] += mz


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
                                 mx, my, mz, ux, uy, uz, hydro[0, _KN], hydro[0, _KT])
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
