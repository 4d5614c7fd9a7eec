"""Equations of motion and link forces of the tug - rigid links - towed vessel chain.

Generalised coordinates ``q = [x_t, z_t, theta_1 .. theta_n]`` (n + 2 of them, as in
the reference): the tug's fairlead position [m] and the absolute elevation angle of
each link [rad]; link ``i`` points from node ``i - 1`` to node ``i`` along
``e_i = (cos theta_i, sin theta_i)``, node 0 is the tug's fairlead, node ``n`` the
towed vessel's. Masses: the tug ``M_t`` at node 0, each link's ``m_i`` at its centre,
the towed vessel ``M_b`` at node ``n``.

Instead of symbolic Euler-Lagrange equations per ``n``, the mass matrix and the
generalised forces are assembled by loops from the point-mass Jacobians (the "growth
pattern" of the reference, written once for any ``n``). With ``B_k`` the mass beyond
link ``k`` (links ``k+1..n`` and the towed vessel) and ``S_k = B_k + m_k / 2``::

    M[xz, xz]        = M_total I
    M[xz, theta_k]   = S_k l_k e'_k                       e'_k = (-sin theta_k, cos theta_k)
    M[theta_j, theta_k] = W_jk l_j l_k cos(theta_j - theta_k),
                       W_jk = S_max(j,k) (j != k),  W_kk = B_k + m_k / 4
    h[xz]            = -sum_k S_k l_k e_k thetadot_k^2
    h[theta_j]       = -sum_k W_jk l_j l_k sin(theta_k - theta_j) thetadot_k^2

and ``M qddot + h = Q`` with ``Q`` from gravity, the joint springs and dampers (interior
joints only; the fairleads are free hinges) and the external forces on the two
vessels. The force carried by the chain follows from Newton's law applied link by link
from the towed vessel back to the tug (:func:`link_forces`); it is exact in both the
slack and the taut state, so no switch of method is needed there.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit

#: Layout of a vessel parameter vector: mass [kg], heave kp [N/m], heave kd [N s/m],
#: resistance [N s^2/m^2].
VESSEL_MASS, VESSEL_KP, VESSEL_KD, VESSEL_RESISTANCE = 0, 1, 2, 3


@njit(cache=True)
def node_kinematics(q: np.ndarray, qd: np.ndarray, l: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities of the n + 1 nodes [m, m/s], shape (n + 1, 2) each."""
    n = l.size
    r = np.empty((n + 1, 2))
    v = np.empty((n + 1, 2))
    r[0, 0], r[0, 1] = q[0], q[1]
    v[0, 0], v[0, 1] = qd[0], qd[1]
    for i in range(n):
        c, s = np.cos(q[2 + i]), np.sin(q[2 + i])
        r[i + 1, 0] = r[i, 0] + l[i] * c
        r[i + 1, 1] = r[i, 1] + l[i] * s
        v[i + 1, 0] = v[i, 0] - l[i] * s * qd[2 + i]
        v[i + 1, 1] = v[i, 1] + l[i] * c * qd[2 + i]
    return r, v


@njit(cache=True)
def _vessel_force(p: np.ndarray, z: float, vx: float, vz: float, zref: float, zref_rate: float,
                  g: float) -> tuple[float, float]:
    """Resistance and heave force on a vessel [N]: buoyancy M g plus the PD force about z_ref."""
    fx = -p[VESSEL_RESISTANCE] * abs(vx) * vx
    fz = p[VESSEL_MASS] * g - p[VESSEL_KP] * (z - zref) - p[VESSEL_KD] * (vz - zref_rate)
    return fx, fz


@njit(cache=True)
def external_forces(q: np.ndarray, qd: np.ndarray, l: np.ndarray, tug: np.ndarray, towed: np.ndarray,
                    thrust: float, refs: np.ndarray, g: float) -> tuple[np.ndarray, np.ndarray]:
    """External (non-gravity, non-cable) forces on the tug and the towed vessel [N].

    ``refs = [z_ref_tug, z_ref_rate_tug, z_ref_towed, z_ref_rate_towed]`` [m, m/s].
    """
    r, v = node_kinematics(q, qd, l)
    n = l.size
    ft = np.empty(2)
    fb = np.empty(2)
    ft[0], ft[1] = _vessel_force(tug, r[0, 1], v[0, 0], v[0, 1], refs[0], refs[1], g)
    ft[0] += thrust
    fb[0], fb[1] = _vessel_force(towed, r[n, 1], v[n, 0], v[n, 1], refs[2], refs[3], g)
    return ft, fb


@njit(cache=True)
def equations(q: np.ndarray, qd: np.ndarray, l: np.ndarray, m: np.ndarray, k: np.ndarray, c: np.ndarray,
              m_tug: float, m_towed: float, g: float, ft: np.ndarray, fb: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """Mass matrix ``M`` and right-hand side ``Q - h`` of ``M qddot = Q - h``.

    Parameters
    ----------
    q, qd
        Generalised coordinates and velocities (n + 2) [m, rad, m/s, rad/s].
    l, m
        Link lengths [m] and masses [kg] (n).
    k, c
        Rotational stiffness [N m/rad] and damping [N m s/rad] of the n - 1 interior joints.
    m_tug, m_towed
        Vessel masses [kg].
    g
        Gravity [m/s^2] (along -z).
    ft, fb
        External forces on the tug and the towed vessel [N] (2 each).
    """
    n = l.size
    dim = n + 2
    beyond = np.empty(n)  # B_k
    acc = m_towed
    for kk in range(n - 1, -1, -1):
        beyond[kk] = acc
        acc += m[kk]
    total = acc + m_tug
    S = beyond + 0.5 * m
    cs = np.cos(q[2:])
    sn = np.sin(q[2:])
    w2 = qd[2:] ** 2
    M = np.zeros((dim, dim))
    rhs = np.zeros(dim)
    M[0, 0] = total
    M[1, 1] = total
    rhs[0] = ft[0] + fb[0]
    rhs[1] = ft[1] + fb[1] - total * g
    for kk in range(n):
        M[0, 2 + kk] = M[2 + kk, 0] = -S[kk] * l[kk] * sn[kk]
        M[1, 2 + kk] = M[2 + kk, 1] = S[kk] * l[kk] * cs[kk]
        rhs[0] += S[kk] * l[kk] * cs[kk] * w2[kk]
        rhs[1] += S[kk] * l[kk] * sn[kk] * w2[kk]
        # gravity on everything beyond and half of link kk; towed vessel's force through node n
        rhs[2 + kk] += -S[kk] * g * l[kk] * cs[kk] + l[kk] * (-sn[kk] * fb[0] + cs[kk] * fb[1])
    for j in range(n):
        for kk in range(n):
            if j == kk:
                W = beyond[kk] + 0.25 * m[kk]
            else:
                W = S[max(j, kk)]
            M[2 + j, 2 + kk] = W * l[j] * l[kk] * (cs[j] * cs[kk] + sn[j] * sn[kk])
            # -h_j = sum_k W_jk l_j l_k sin(theta_k - theta_j) thetadot_k^2
            rhs[2 + j] += W * l[j] * l[kk] * (sn[kk] * cs[j] - cs[kk] * sn[j]) * w2[kk]
    for j in range(n - 1):  # interior joint between links j and j + 1
        torque = k[j] * (q[3 + j] - q[2 + j]) + c[j] * (qd[3 + j] - qd[2 + j])
        rhs[2 + j] += torque
        rhs[3 + j] -= torque
    return M, rhs


@njit(cache=True)
def accelerations(q: np.ndarray, qd: np.ndarray, l: np.ndarray, m: np.ndarray, k: np.ndarray, c: np.ndarray,
                  tug: np.ndarray, towed: np.ndarray, thrust: float, refs: np.ndarray, g: float
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Generalised accelerations and the external forces on the tug and the towed vessel.

    Returns
    -------
    qdd, ft, fb
        Accelerations (n + 2) [m/s^2, rad/s^2]; forces on the tug and on the towed vessel [N].
    """
    ft, fb = external_forces(q, qd, l, tug, towed, thrust, refs, g)
    M, rhs = equations(q, qd, l, m, k, c, tug[VESSEL_MASS], towed[VESSEL_MASS], g, ft, fb)
    return np.linalg.solve(M, rhs), ft, fb


@njit(cache=True)
def link_forces(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, l: np.ndarray, m: np.ndarray,
                m_towed: float, fb: np.ndarray, g: float) -> np.ndarray:
    """Force transmitted through each node, from Newton's law link by link [N].

    ``F[i]`` (shape (n + 1, 2)) is the force the chain on the tug's side of node ``i``
    exerts on everything beyond it (towards the towed vessel); ``F[0]`` is the force of
    the tug on the cable, ``F[n]`` the force of the cable on the towed vessel. The
    tension at the two ends of link ``i`` is ``-F[i-1] . e_i`` and ``-F[i] . e_i``
    (negative: compression).
    """
    n = l.size
    F = np.empty((n + 1, 2))
    A = np.empty((n + 1, 2))  # node accelerations
    A[0, 0], A[0, 1] = qdd[0], qdd[1]
    for i in range(n):
        cs, sn = np.cos(q[2 + i]), np.sin(q[2 + i])
        tx = -sn * qdd[2 + i] - cs * qd[2 + i] ** 2
        tz = cs * qdd[2 + i] - sn * qd[2 + i] ** 2
        A[i + 1, 0] = A[i, 0] + l[i] * tx
        A[i + 1, 1] = A[i, 1] + l[i] * tz
    F[n, 0] = m_towed * A[n, 0] - fb[0]
    F[n, 1] = m_towed * (A[n, 1] + g) - fb[1]
    for i in range(n - 1, -1, -1):
        # link i + 1 (0-based i) has its centre halfway between nodes i and i + 1
        F[i, 0] = F[i + 1, 0] + m[i] * 0.5 * (A[i, 0] + A[i + 1, 0])
        F[i, 1] = F[i + 1, 1] + m[i] * (0.5 * (A[i, 1] + A[i + 1, 1]) + g)
    return F


def end_tensions(q: np.ndarray, F: np.ndarray) -> tuple[float, float, float]:
    """Axial tension at the tug, at the towed vessel and the smallest link-end tension [N].

    Parameters
    ----------
    q
        Generalised coordinates (n + 2).
    F
        Node forces from :func:`link_forces`, shape (n + 1, 2).
    """
    e = np.column_stack((np.cos(q[2:]), np.sin(q[2:])))
    t_start = -np.einsum("ij,ij->i", F[:-1], e)
    t_end = -np.einsum("ij,ij->i", F[1:], e)
    return float(t_start[0]), float(t_end[-1]), float(min(t_start.min(), t_end.min()))
