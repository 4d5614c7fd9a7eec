"""Assembly of the cable system: residual and banded iteration matrix.

Global coordinates: node ``n`` owns ``x[6n:6n+3] = r`` and ``x[6n+3:6n+6] = r_p``
(shared nodal coordinates embed position and slope continuity, W(123)-(132): 6N+6
coordinates for N elements). Element ``e`` uses ``x[6e:6e+12]``.

The equations of motion are written as the residual

    R(q, v, a, t) = M a + C v + K_b q + Q_l(q) - Q_g - Q_ext(q, v, t) = 0

over all coordinates; rows of free coordinates are the equations, rows of prescribed
coordinates are the reaction forces. Constant element matrices are Kronecker products
``m (x) I_3`` of 4x4 factors and are applied as such.

Extra coordinates follow the cable's: a rigid load's centre of inertia (3, W(138)-(139)),
or a rigid 6-DOF towed body's CG and roll, pitch, yaw (6, the kernel of
:mod:`towcable_fmu.rigid_body`). The body hangs from the last node by a stiff
spring-damper link to its tow point (the ANCF node keeps its slope coordinates free:
the joint is spherical); see :func:`_rigid_rows` and ``RIGID_LINK_FACTOR`` in
:mod:`towcable_fmu.ancf.mesh`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from ..contact import cable as cable_contact
from ..contact.surfaces import ContactModel
from ..hydro import cable as cable_hydro
from ..hydro import towbody as body_hydro
from ..hydro.cable import CableHydro
from ..hydro.towbody import BodyHydro
from ..hydro.water import WaterModel
from ..rigid_body import RigidBodyModel, attitude_ok, body_residual, tow_point_state
from ..numerics.banded import band_add_block
from .axial import axial_force, axial_tangent, slope_derivatives


class CableModel(NamedTuple):
    """Everything the compiled kernels need about one cable system (arrays only).

    Sizes: ``ne`` elements, ``nn = ne + 1`` nodes, ``nf = 6 nn`` coordinates.
    """

    el_len: np.ndarray          #: (ne,) unstretched element lengths [m]
    el_ea: np.ndarray           #: (ne,) axial stiffness EA [N]
    el_tension_only: np.ndarray  #: (ne,) bool: no axial force in compression
    el_mass: np.ndarray         #: (ne, 4, 4) mass factor [kg...]
    el_bend: np.ndarray         #: (ne, 4, 4) bending stiffness factor
    el_damp: np.ndarray         #: (ne, 4, 4) internal damping factor
    f_const: np.ndarray         #: (nf,) constant generalised load (gravity of cable and point masses) [N]
    node_mass: np.ndarray       #: (nn, 3) lumped mass at node positions, per axis [kg]
    gauss_dn: np.ndarray        #: (ng, 4) dn/dxi of the normalised Hermite functions at Gauss points
    gauss_w: np.ndarray         #: (ng,) Gauss weights on [0, 1]
    free_idx: np.ndarray        #: (nf,) unknown index of each coordinate, -1 if prescribed
    free_dofs: np.ndarray       #: (n,) coordinate index of each unknown
    free_scale: np.ndarray      #: (n,) 1/length of the adjacent elements for positions, 1 for slopes [1/m, -]
    kl: int                     #: sub-diagonals of the iteration matrix
    ku: int                     #: super-diagonals of the iteration matrix
    att_index: np.ndarray       #: (na,) first coordinate of each prescribed triple
    att_kind: np.ndarray        #: (na,) attachment kind (see prescribed.py)
    att_vec: np.ndarray         #: (na, 3) attachment vector
    att_radius: np.ndarray      #: (na,) winch radius for winch attachments [m]
    water: WaterModel           #: water, current and turbulence (``enabled`` False: dry scene)
    hydro: CableHydro           #: per-element hydrodynamic properties
    body: BodyHydro             #: towed body in water
    contact: ContactModel       #: winch drum and sheave faces (``enabled`` False: none)
    load_on: bool               #: a rigid load hangs from the last node (W(138)-(139))
    load_index: int             #: first coordinate of the load's centre of inertia I
    load_mass: np.ndarray       #: (3,) entries m_PP, m_PI, m_II of the load mass matrix W(138) [kg]
    load_k: float               #: k_L, stiffness of the link P-I [N]
    load_length: float          #: L_PI, rest length of the link [m]
    rigid: RigidBodyModel       #: rigid 6-DOF towed body (``enabled`` False: none), see towcable_fmu/rigid_body.py
    rigid_index: int            #: first of the body's six coordinates (CG [m], roll, pitch, yaw [rad])
    rigid_k: float              #: stiffness of the link last node - tow point [N/m]
    rigid_c: float              #: damping of that link [N s/m]
    gravity: float              #: g [m/s^2] (the rigid body's weight; the cable's is in f_const)


@njit(cache=True, inline="always")
def _linear_forces(mass: np.ndarray, damp: np.ndarray, bend: np.ndarray, e: int, q: np.ndarray, v: np.ndarray,
                   a: np.ndarray, base: int, out: np.ndarray) -> None:
    """out[base:base+12] += (M (x) I3) a + (C (x) I3) v + (K_b (x) I3) q for element e."""
    for i in range(4):
        for c in range(3):
            acc = 0.0
            for j in range(4):
                k = base + 3 * j + c
                acc += mass[e, i, j] * a[k] + damp[e, i, j] * v[k] + bend[e, i, j] * q[k]
            out[base + 3 * i + c] += acc


@njit(cache=True)
def residual(model: CableModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, ship: np.ndarray,
             out: np.ndarray) -> float:
    """Residual of the equations of motion over all coordinates.

    Parameters
    ----------
    model
        The cable system.
    q, v, a
        Full coordinates [m, -], velocities and accelerations (prescribed entries set).
    t
        Time [s].
    ship
        Ship state (3, 6) at time t (moves the winch and sheave surfaces).
    out
        Output residual, shape (nf,) [N, N m].

    Returns
    -------
    float
        Total axial strain energy [J] (a by-product, used for energy outputs).
    """
    return residual_span(model, q, v, a, t, ship, np.intp(0), model.el_len.shape[0], out)


@njit(cache=True)
def residual_span(model: CableModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, ship: np.ndarray,
                  first: int, stop: int, out: np.ndarray) -> float:
    """The residual with the contributions of elements ``first`` to ``stop - 1`` only.

    The rows of a node are complete when all elements it belongs to are in the span:
    ``(0, 1)`` gives the top node's rows (its support reaction) at the cost of one
    element. Node masses of the span's nodes are included; the rigid load and the towed
    body's hydrodynamics when the span ends at the last element. Arguments as
    :func:`residual`; returns the axial strain energy of the span [J].
    """
    ng = model.gauss_w.shape[0]
    d = np.empty((ng, 4))
    lam = np.empty(ng)
    u = np.empty((ng, 3))
    fe = np.empty(12)
    for i in range(out.shape[0]):
        out[i] = -model.f_const[i]
    energy = 0.0
    for e in range(first, stop):
        base = 6 * e
        _linear_forces(model.el_mass, model.el_damp, model.el_bend, e, q, v, a, base, out)
        length = model.el_len[e]
        slope_derivatives(model.gauss_dn, length, d)
        fe[:] = 0.0
        energy += axial_force(q, base, length, model.el_ea[e], model.el_tension_only[e],
                              d, model.gauss_w, lam, u, fe)
        for i in range(12):
            out[base + i] += fe[i]
    for n in range(first, stop + 1):
        for c in range(3):
            out[6 * n + c] += model.node_mass[n, c] * a[6 * n + c]
    to_end = stop == model.el_len.shape[0]
    if model.load_on and to_end:
        _load_residual(model, q, a, out)
    if model.rigid.enabled and to_end:
        _rigid_residual(model, q, v, a, t, out)
    if model.contact.enabled:
        cable_contact.add_residual(model.contact, model.el_len, model.hydro.el_d, model.hydro.el_npts, q, v, ship,
                                   first, stop, out)
    if model.water.enabled:
        cable_hydro.add_residual(model.water, model.hydro, model.el_len, q, v, a, t, first, stop, out)
        if model.body.enabled and to_end:
            body_hydro.add_residual(model.water, model.body, q, v, a, t, out)
    return energy


@njit(cache=True)
def _rigid_rows(model: CableModel, zq: np.ndarray, zv: np.ndarray, za: np.ndarray, t: float,
                rows: np.ndarray) -> None:
    """The residual rows of the rigid towed body and its link to the cable end.

    Parameters
    ----------
    model
        The cable system (``model.rigid.enabled``).
    zq, zv, za
        Local coordinates, rates and accelerations (9 each): the last node's position
        [m], then the body's CG [m] and roll, pitch, yaw [rad].
    t
        Time [s].
    rows
        Output (9,): the link force on the last node's position rows [N], then the six
        body residuals of :func:`~towcable_fmu.rigid_body.body_residual` [N, N m].

    Notes
    -----
    The link is a stiff spring-damper between the last node X_N and the tow point
    p = r + R p_b: the cable end feels ``-f``, the body ``+f`` at its tow point, with
    ``f = k (X_N - p) + c (V_N - dp/dt)``. ``body_residual`` takes the force the body
    exerts on the cable end, ``-f``.
    """
    xt = np.empty(3)
    vt = np.empty(3)
    at = np.empty(3)
    tow_point_state(model.rigid, zq[3:9], zv[3:9], za[3:9], xt, vt, at)
    f = np.empty(3)
    for c in range(3):
        f[c] = model.rigid_k * (zq[c] - xt[c]) + model.rigid_c * (zv[c] - vt[c])
        rows[c] = f[c]
    body_residual(model.water, model.rigid, model.gravity, zq[3:9], zv[3:9], za[3:9], t, -f, rows[3:9])


@njit(cache=True, inline="always")
def _rigid_local(model: CableModel, x: np.ndarray, z: np.ndarray) -> None:
    """Gather the 9 local entries (last node position, body coordinates) of ``x`` into ``z``."""
    p = model.rigid_index - 6
    i = model.rigid_index
    for c in range(3):
        z[c] = x[p + c]
    for c in range(6):
        z[3 + c] = x[i + c]


# IR-inlined into its only caller: a kernel of its own would be one more library for the
# caller to link and optimise again, with all the code beneath it.
@njit(cache=True, inline="always")
def _rigid_residual(model: CableModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float,
                    out: np.ndarray) -> None:
    """Add the rigid body's rows and its link force on the last node to ``out``."""
    zq, zv, za, rows = np.empty(9), np.empty(9), np.empty(9), np.empty(9)
    _rigid_local(model, q, zq)
    _rigid_local(model, v, zv)
    _rigid_local(model, a, za)
    _rigid_rows(model, zq, zv, za, t, rows)
    if not attitude_ok(zq[3:9]) or abs(zq[7]) > 0.5 * np.pi:
        # Euler angles singular (pitch +-pi/2): no residual, the step fails (the nodal
        # cable's integrators stop there too; Simulation names the cause)
        rows[:] = np.nan
    p = model.rigid_index - 6
    i = model.rigid_index
    for c in range(3):
        out[p + c] += rows[c]
    for c in range(6):
        out[i + c] += rows[3 + c]


@njit(cache=True, inline="always")  # (as _rigid_residual)
def rigid_block(model: CableModel, q: np.ndarray, v: np.ndarray, t: float, ca: float, cv: float,
                cq: float) -> np.ndarray:
    """``ca M + cv C + cq K`` of the rigid body and its link over the 9 local coordinates.

    The body's equations are nonlinear in its angles and in the relative flow; their
    derivatives are taken by differences of :func:`_rigid_rows` (central for q and v,
    one-sided for a, in which the rows are linear), at zero acceleration: the change of
    the inertia forces with the attitude (terms in the body's acceleration) is left
    out, as modified Newton allows. Rows and columns: the last node's position, then the
    body's coordinates.
    """
    zq, zv, za = np.empty(9), np.empty(9), np.zeros(9)
    _rigid_local(model, q, zq)
    _rigid_local(model, v, zv)
    r0, rp, rm = np.empty(9), np.empty(9), np.empty(9)
    block = np.zeros((9, 9))
    _rigid_rows(model, zq, zv, za, t, r0)
    for j in range(9):
        if ca != 0.0:
            za[j] = 1.0
            _rigid_rows(model, zq, zv, za, t, rp)
            za[j] = 0.0
            for r in range(9):
                block[r, j] += ca * (rp[r] - r0[r])
        for kind in range(2):
            weight = cq if kind == 0 else cv
            if weight == 0.0:
                continue
            z = zq if kind == 0 else zv
            keep = z[j]
            h = 1e-6 * max(1.0, abs(keep))
            z[j] = keep + h
            _rigid_rows(model, zq, zv, za, t, rp)
            z[j] = keep - h
            _rigid_rows(model, zq, zv, za, t, rm)
            z[j] = keep
            for r in range(9):
                block[r, j] += weight * (rp[r] - rm[r]) / (2.0 * h)
    return block


@njit(cache=True, inline="always")  # (as _rigid_residual)
def _rigid_jacobian(model: CableModel, q: np.ndarray, v: np.ndarray, t: float, ca: float, cv: float, cq: float,
                    ab: np.ndarray) -> None:
    """Add :func:`rigid_block` to the band storage ``ab``."""
    block = rigid_block(model, q, v, t, ca, cv, cq)
    off = model.kl + model.ku
    p = model.rigid_index - 6
    i = model.rigid_index
    for r in range(9):
        fr = model.free_idx[p + r if r < 3 else i + r - 3]
        if fr < 0:
            continue
        for c in range(9):
            fc = model.free_idx[p + c if c < 3 else i + c - 3]
            if fc >= 0:
                ab[off + fr - fc, fc] += block[r, c]


@njit(cache=True, inline="always")  # (as _rigid_residual; small, two callers)
def _load_link(model: CableModel, q: np.ndarray) -> tuple:
    """Separation d = r_P - r_I, its length and the link strain of the rigid load."""
    i = model.load_index
    p = i - 6
    dx, dy, dz = q[p] - q[i], q[p + 1] - q[i + 1], q[p + 2] - q[i + 2]
    length = np.sqrt(dx * dx + dy * dy + dz * dz)
    return dx, dy, dz, length, (length - model.load_length) / model.load_length


@njit(cache=True, inline="always")  # (as _rigid_residual)
def _load_residual(model: CableModel, q: np.ndarray, a: np.ndarray, out: np.ndarray) -> None:
    """Inertia W(138) and link force W(139) of the rigid load (P = last node, I = extra point)."""
    i = model.load_index
    p = i - 6
    m_pp, m_pi, m_ii = model.load_mass[0], model.load_mass[1], model.load_mass[2]
    dx, dy, dz, _, eps = _load_link(model, q)
    k = model.load_k * eps
    for c, dc in enumerate((dx, dy, dz)):
        out[p + c] += m_pp * a[p + c] + m_pi * a[i + c] + k * dc
        out[i + c] += m_pi * a[p + c] + m_ii * a[i + c] - k * dc


@njit(cache=True, inline="always")  # (as _rigid_residual)
def _load_jacobian(model: CableModel, q: np.ndarray, ca: float, cq: float, ab: np.ndarray) -> None:
    i = model.load_index
    p = i - 6
    dx, dy, dz, length, eps = _load_link(model, q)
    d = (dx, dy, dz)
    block = np.zeros((6, 6))
    mass = model.load_mass
    for r in range(3):
        block[r, r] += ca * mass[0]
        block[r, 3 + r] += ca * mass[1]
        block[3 + r, r] += ca * mass[1]
        block[3 + r, 3 + r] += ca * mass[2]
        for c in range(3):
            kk = cq * model.load_k * ((eps if r == c else 0.0) + d[r] * d[c] / (model.load_length * length))
            block[r, c] += kk
            block[r, 3 + c] -= kk
            block[3 + r, c] -= kk
            block[3 + r, 3 + c] += kk
    off = model.kl + model.ku
    for r in range(6):
        fr = model.free_idx[(p if r < 3 else i) + r % 3]
        for c in range(6):
            fc = model.free_idx[(p if c < 3 else i) + c % 3]
            if fr >= 0 and fc >= 0:
                ab[off + fr - fc, fc] += block[r, c]


@njit(cache=True)
def iteration_matrix(model: CableModel, q: np.ndarray, v: np.ndarray, t: float, ship: np.ndarray,
                     ca: float, cv: float, cq: float, ab: np.ndarray) -> None:
    """Banded iteration matrix ``ca M + cv C + cq K`` over the free coordinates.

    Parameters
    ----------
    model
        The cable system.
    q, v
        Full coordinates and velocities at which the tangents are evaluated.
    t, ship
        Time [s] and ship state (3, 6).
    ca, cv, cq
        Weights of the mass, damping and stiffness parts.
    ab
        Output band storage, shape (2 kl + ku + 1, n); overwritten.
    """
    ab[:, :] = 0.0
    ne = model.el_len.shape[0]
    ng = model.gauss_w.shape[0]
    d = np.empty((ng, 4))
    lam = np.empty(ng)
    u = np.empty((ng, 3))
    ke = np.empty((12, 12))
    grad = np.empty((3, 12))
    first = np.empty(3)
    hess = np.empty((3, 3))
    wet = model.water.enabled
    for e in range(ne):
        base = 6 * e
        ke[:, :] = 0.0
        for i in range(4):
            for j in range(4):
                val = ca * model.el_mass[e, i, j] + cv * model.el_damp[e, i, j] + cq * model.el_bend[e, i, j]
                for c in range(3):
                    ke[3 * i + c, 3 * j + c] = val
        length = model.el_len[e]
        slope_derivatives(model.gauss_dn, length, d)
        axial_tangent(q, base, length, model.el_ea[e], model.el_tension_only[e],
                      d, model.gauss_w, lam, u, cq, ke, grad, first, hess)
        if wet:
            cable_hydro.add_jacobian(model.water, model.hydro, model.el_len, q, v, t, e, ca, cv, cq, ke)
        band_add_block(ab, model.kl, model.ku, model.free_idx, base, ke)
    off = model.kl + model.ku
    nn = model.node_mass.shape[0]
    for n in range(nn):
        for c in range(3):
            fi = model.free_idx[6 * n + c]
            if fi >= 0:
                ab[off, fi] += ca * model.node_mass[n, c]
    if model.load_on:
        _load_jacobian(model, q, ca, cq, ab)
    if model.rigid.enabled:
        _rigid_jacobian(model, q, v, t, ca, cv, cq, ab)
    if model.contact.enabled:
        cable_contact.add_jacobian(model.contact, model.el_len, model.hydro.el_d, model.hydro.el_npts, q, v, ship,
                                   model.free_idx, model.kl, model.ku, cv, cq, ab)
    if wet and model.body.enabled:
        block = np.zeros((3, 3))
        if body_hydro.add_jacobian(model.water, model.body, q, v, t, ca, cv, block):
            i0 = model.body.index
            for k in range(3):
                fk = model.free_idx[i0 + k]
                for m in range(3):
                    fm = model.free_idx[i0 + m]
                    if fk >= 0 and fm >= 0:
                        ab[off + fk - fm, fm] += block[k, m]
