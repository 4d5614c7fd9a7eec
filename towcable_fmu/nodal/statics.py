"""Static equilibrium of the nodal-position cable: pseudo-transient continuation.

Newton's method on the static residual r(X, 0, 0) = 0 of the free nodes, regularised
by the mass matrix: (K + lambda M) dX = -r with lambda = 1/tau^2 of a pseudo time step
tau that grows as the residual falls (switched evolution relaxation; with a rigid body
at least by sqrt(2) per iteration that lowers the residual), so that a slack
start (a tension-only cable laid out unstretched has no lateral stiffness) settles
like a damped motion and the last iterations are plain Newton steps.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from ..numerics.banded import band_lu, band_solve
from .assembly import bandwidth, iteration_matrix, residual
from .model import NodalModel

#: Initial pseudo time step tau [s].
TAU0 = 0.01
#: Smallest lambda [1/s^2] with a rigid body (a pseudo time step of 1000 s).
LAMBDA_MIN_RIGID = 1e-6
#: Extra factor on lambda after an iteration that lowered the residual (rigid body only;
#: the lumped body keeps the plain switched evolution relaxation).
SHRINK_RIGID = 0.5


@njit(cache=True)
def solve_statics(m: NodalModel, q: np.ndarray, t: float, tolerance: float, max_iterations: int) -> tuple:
    """Move the free nodes of ``q`` [m] (node 0 prescribed, kept) to equilibrium.

    Parameters
    ----------
    tolerance
        Converged when the largest out-of-balance force is below tolerance times the
        load scale (total weight of cable, end mass and rigid body; a rigid body's
        out-of-balance moments [N m] are held to the same number).

    Returns
    -------
    (converged, iterations, residual)
        The largest out-of-balance force [N] at the end.
    """
    n = q.size
    zero = np.zeros(n)
    r = np.empty(n)
    kl = bandwidth(m)
    ab = np.empty((n - 3, 3 * kl + 1))
    mass = np.empty_like(ab)
    ipiv = np.empty(n - 3, dtype=np.int64)
    work = np.empty((4, n))
    scale = tolerance * m.gravity * max((m.mu * m.L0).sum() + m.end_mass + m.rigid.mass, 1e-300)
    residual(m, q, zero, zero, t, r)
    iteration_matrix(m, q, zero, zero, t, 1.0, 0.0, 0.0, 1.0, r, mass, work)
    lam = 1.0 / (TAU0 * TAU0)
    norm = np.abs(r[3:]).max()
    for it in range(max_iterations):
        if norm < scale:
            return True, it, norm
        iteration_matrix(m, q, zero, zero, t, 0.0, 0.0, 1.0, 1e-7 * m.L0.min(), r, ab, work)
        ab += lam * mass
        if band_lu(ab, n - 3, kl, kl, ipiv) != 0:
            return False, it, norm
        d = -r[3:]
        band_solve(ab, n - 3, kl, kl, ipiv, d)
        q[3:] += d
        residual(m, q, zero, zero, t, r)
        new = np.abs(r[3:]).max()
        lam *= min(max(new / norm, 1e-3), 10.0)
        if m.rigid.enabled:
            # a heavy body on a slack or lightly loaded cable creeps at a small pseudo
            # step while the residual hardly falls: grow the step anyway while the
            # residual falls; a free yaw (no current) has no stiffness: keep a little mass
            if new < norm:
                lam *= SHRINK_RIGID
            lam = max(lam, LAMBDA_MIN_RIGID)
        norm = new
    return norm < scale, max_iterations, norm
