"""The residual of the whole cable and body, and its matrices by coloured differences.

The residual of eq. 27 written for all nodes, ``r = (M + M_a) a + C v + f_int - f_ext``
[N]; at the prescribed top node it is the force the support exerts on the cable (the
reaction). The assembly knows elements and the body, not which forces they carry.

Iteration matrices ``ca M + cv C + cq K`` (M = d r/d a, C = d r/d v, K = d r/d q) are formed by
differences with three node colours: a node's coordinates enter only its own and its
neighbours' residuals, so nodes three apart can be perturbed together and nine residual
evaluations give the whole banded matrix (kl = ku = 5 in the unknowns).

With a rigid towed body (:mod:`.rigid_body`) the last node is the tow point, computed
from the body's six coordinates that follow the free nodes; the cable's residual at
that node goes to the body's rows. Node n_nodes - 2 then couples with the body, so the
band widens to kl = ku = 8 (:func:`bandwidth`), and six more residual evaluations (one
per body coordinate) complete the matrix.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from ..hydro.towbody import body_force
from .element import add_element
from .model import NodalModel
from ..hydro.rigid_body import body_residual, tow_point_state

#: Sub-diagonals (= super-diagonals) of the banded matrices (three coordinates per node).
KL = 5
#: The same with a rigid towed body (its six coordinates couple with the last free node).
KL_RIGID = 8


@njit(cache=True)
def bandwidth(m: NodalModel) -> int:
    """Sub- (= super-) diagonals of the iteration matrices of model ``m``."""
    return KL_RIGID if m.rigid.enabled else KL


@njit(cache=True)
def expand(m: NodalModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, qn: np.ndarray, vn: np.ndarray,
           an: np.ndarray) -> None:
    """Nodal positions, velocities and accelerations of all nodes (3 n_nodes each) from the
    coordinates: a copy, or with a rigid body the free nodes and the tow point."""
    nq = 3 * m.n_nodes
    if not m.rigid.enabled:
        qn[:], vn[:], an[:] = q, v, a
        return
    i = nq - 3
    qn[:i], vn[:i], an[:i] = q[:i], v[:i], a[:i]
    tow_point_state(m.rigid, q[i:i + 6], v[i:i + 6], a[i:i + 6], qn[i:], vn[i:], an[i:])


@njit(cache=True)
def residual(m: NodalModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, r: np.ndarray) -> None:
    """Residual r of all coordinates at positions q, velocities v, accelerations a: [N] on
    the nodes and the body's CG, [N m] on its angles."""
    if m.rigid.enabled:
        _rigid_residual(m, q, v, a, t, r)
    else:
        cable_residual(m, q, v, a, t, r)


@njit(cache=True)
def _rigid_residual(m: NodalModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, r: np.ndarray) -> None:
    """:func:`residual` with a rigid towed body (kept out of the lumped path, which it slows)."""
    nq = 3 * m.n_nodes
    qn, vn, an, rn = np.empty(nq), np.empty(nq), np.empty(nq), np.empty(nq)
    expand(m, q, v, a, qn, vn, an)
    cable_residual(m, qn, vn, an, t, rn)
    i = nq - 3
    r[:i] = rn[:i]
    body_residual(m.water, m.rigid, m.gravity, q[i:i + 6], v[i:i + 6], a[i:i + 6], t, rn[i:], r[i:i + 6])


@njit(cache=True, inline="always")
def cable_residual(m: NodalModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float,
                   r: np.ndarray) -> None:
    """Residual r [N] of all 3 n_nodes nodal coordinates (the lumped end mass and body included)."""
    r[:] = 0.0
    for e in range(m.n_nodes - 1):
        add_element(m, e, q, v, a, t, r)
    i = 3 * (m.n_nodes - 1)
    for k in range(3):
        r[i + k] += m.end_mass * a[i + k]
    r[i + 2] += m.end_mass * m.gravity
    if m.body.enabled:
        f = np.empty(3)
        if body_force(m.water, m.body, q[i:i + 3], v[i:i + 3], a[i:i + 3], t, f):
            for k in range(3):
                r[i + k] -= f[k]


@njit(cache=True)
def iteration_matrix(m: NodalModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, ca: float,
                     cv: float, cq: float, delta: float, r0: np.ndarray, ab: np.ndarray, work: np.ndarray) -> int:
    """Banded ``ca M + cv C + cq K`` of the free coordinates (all but node 0's): the change
    of r when a, v and q move by ``ca``, ``cv`` and ``cq`` times a parameter, into the band
    storage of :mod:`towcable_fmu.numerics.banded`, ``ab`` (q.size - 3, 3 kl + 1) with kl = :func:`bandwidth`.

    Parameters
    ----------
    r0
        Residual at (q, v, a).
    delta
        Perturbation of the parameter; the matrix is exact for the parts linear in it
        (the mass and added mass).
    work
        Scratch, shape (4, q.size): perturbed q, v, a and residual.

    Returns
    -------
    int
        Number of residual evaluations.
    """
    ab[:, :] = 0.0
    rigid = m.rigid.enabled
    nn = m.n_nodes - 1 if rigid else m.n_nodes   # nodes with coordinates of their own
    kl = bandwidth(m)
    qp, vp, ap, rp = work[0], work[1], work[2], work[3]
    off = 2 * kl
    ib = 3 * nn                                  # first body coordinate (rigid)
    for colour in range(3):
        for k in range(3):
            qp[:] = q
            vp[:] = v
            ap[:] = a
            for node in range(1 + colour, nn, 3):
                j = 3 * node + k
                qp[j] += cq * delta
                vp[j] += cv * delta
                ap[j] += ca * delta
            residual(m, qp, vp, ap, t, rp)
            for node in range(1 + colour, nn, 3):
                col = 3 * (node - 1) + k
                for row_node in range(max(node - 1, 1), min(node + 2, nn)):
                    for kk in range(3):
                        row = 3 * (row_node - 1) + kk
                        ab[col, off + row - col] = (rp[3 * row_node + kk] - r0[3 * row_node + kk]) / delta
                if rigid and node == nn - 1:
                    for kk in range(6):
                        row = ib - 3 + kk
                        ab[col, off + row - col] = (rp[ib + kk] - r0[ib + kk]) / delta
    if not rigid:
        return 9
    for k in range(6):
        qp[:] = q
        vp[:] = v
        ap[:] = a
        qp[ib + k] += cq * delta
        vp[ib + k] += cv * delta
        ap[ib + k] += ca * delta
        residual(m, qp, vp, ap, t, rp)
        col = ib - 3 + k
        for j in range(max(ib - 3, 3), ib + 6):
            ab[col, off + j - 3 - col] = (rp[j] - r0[j]) / delta
    return 15
