"""The residual of the whole cable and body, and its matrices by coloured differences.

The residual of eq. 27 written for all nodes, ``r = (M + M_a) a + C v + f_int - f_ext``
[N]; at the prescribed top node it is the force the support exerts on the cable (the
reaction). The assembly knows elements and the body, not which forces they carry.

Iteration matrices ``ca M + cv C + cq K`` (M = d r/d a, C = d r/d v, K = d r/d q) are formed by
differences with three node colours: a node's coordinates enter only its own and its
neighbours' residuals, so nodes three apart can be perturbed together and nine residual
evaluations give the whole banded matrix (kl = ku = 5 in the unknowns).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..hydro.towbody import body_force
from .element import add_element
from .model import NodalModel

#: Sub- and super-diagonals of the banded matrices (three coordinates per node).
KL = 5
KU = 5


@njit(cache=True)
def residual(m: NodalModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, r: np.ndarray) -> None:
    """Residual r [N] of all 3 n_nodes coordinates at positions q, velocities v, accelerations a."""
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
    """Banded ``ca M + cv C + cq K`` of the free coordinates (nodes 1..): the change of r when
    a, v and q move by ``ca``, ``cv`` and ``cq`` times a parameter, into LAPACK band storage
    ``ab`` (2 KL + KU + 1, 3 (n_nodes - 1)).

    Parameters
    ----------
    r0
        Residual at (q, v, a).
    delta
        Perturbation of the parameter; the matrix is exact for the parts linear in it
        (the mass and added mass).
    work
        Scratch, shape (4, 3 n_nodes): perturbed q, v, a and residual.

    Returns
    -------
    int
        Number of residual evaluations.
    """
    ab[:, :] = 0.0
    nn = m.n_nodes
    qp, vp, ap, rp = work[0], work[1], work[2], work[3]
    off = KL + KU
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
                        ab[off + row - col, col] = (rp[3 * row_node + kk] - r0[3 * row_node + kk]) / delta
    return 9
