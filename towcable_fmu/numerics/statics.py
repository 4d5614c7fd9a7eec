"""Static equilibrium by pseudo-transient continuation (PTC) with Newton.

Solves ``F(q) = 0`` (the residual with zero velocity and acceleration) from a rough
initial shape. Each iteration solves ``(K + M/tau) dq = -F`` with the tangent
stiffness K and the mass matrix M as regulariser: for small pseudo time step ``tau``
this is a heavily damped implicit dynamic step (robust far from equilibrium, e.g. a
slack initial shape), for large ``tau`` it is Newton's method (quadratic convergence
near equilibrium). ``tau`` grows as the residual falls (switched evolution
relaxation, Mulder & van Leer 1985; Kelley & Keyes 1998); a step that increases the
residual a lot, or produces non-finite values, is rejected and ``tau`` shrinks.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from ..ancf.prescribed import apply_prescribed
from ..ancf.system import CableModel, iteration_matrix, residual
from ..errors import SolverError
from .banded import band_lu, band_solve


@dataclasses.dataclass
class StaticsResult:
    """Outcome of a static solve.

    Attributes
    ----------
    q
        Equilibrium coordinates (full vector).
    iterations
        Iterations used.
    residual_norm
        Largest out-of-balance generalised force at the end [N].
    load_scale
        Force scale the tolerance was relative to [N].
    wall_time
        Wall-clock time [s].
    """

    q: np.ndarray
    iterations: int
    residual_norm: float
    load_scale: float
    wall_time: float


def solve_statics(model: CableModel, q0: np.ndarray, ship: np.ndarray, phi: np.ndarray, t: float,
                  tolerance: float = 1e-8, max_iterations: int = 400, tau0: float = 1e-3,
                  max_move: float | None = None) -> StaticsResult:
    """Bring the cable to rest.

    Parameters
    ----------
    model
        The cable system.
    q0
        Initial coordinates (full vector; prescribed entries are overwritten).
    ship
        Ship state (3, 6) at which to solve (its velocities are ignored).
    phi
        Winch rotation [rad] (rates ignored), shape (4,) as in the integrator state.
    t
        Time [s] (for time-dependent loads such as the current).
    tolerance
        Converged when the largest out-of-balance force is below ``tolerance`` times
        the load scale.
    max_iterations
        Iteration limit.
    tau0
        Initial pseudo time step [s^2].
    max_move
        Largest position change per iteration [m] (default: half the shortest element).

    Returns
    -------
    StaticsResult

    Raises
    ------
    SolverError
        If the iteration does not converge within ``max_iterations``.
    """
    start = time.perf_counter()
    ship_static = ship.copy()
    ship_static[1:] = 0.0
    phi_static = np.array([phi[0], 0.0, 0.0, 0.0])
    q = q0.copy()
    v = np.zeros_like(q)
    a = np.zeros_like(q)
    apply_prescribed(model.att_index, model.att_kind, model.att_vec, model.att_radius, ship_static, phi_static,
                     q, v, a)
    v[:] = 0.0
    a[:] = 0.0
    n = model.free_dofs.size
    free = model.free_dofs
    position_dof = (free % 6) < 3
    move_limit = 0.5 * float(model.el_len.min()) if max_move is None else max_move
    ab = np.zeros((2 * model.kl + model.ku + 1, n))
    ipiv = np.zeros(n, dtype=np.int64)
    r = np.zeros(q.size)

    def out_of_balance(x: np.ndarray) -> tuple[float, float]:
        residual(model, x, v, a, t, ship_static, r)
        fr = r[free]
        reaction = np.abs(np.delete(r, free)).max(initial=0.0)
        return float(np.abs(fr).max(initial=0.0)), reaction

    norm, reaction = out_of_balance(q)
    weight = float(np.abs(model.f_const).sum())
    tau = tau0
    for it in range(1, max_iterations + 1):
        scale = max(weight, reaction, 1e-9)
        if math.isfinite(norm) and norm <= tolerance * scale:
            return StaticsResult(q, it - 1, norm, scale, time.perf_counter() - start)
        residual(model, q, v, a, t, ship_static, r)
        rhs = -r[free]
        iteration_matrix(model, q, v, t, ship_static, 1.0 / tau, 0.0, 1.0, ab)
        if band_lu(ab, n, model.kl, model.ku, ipiv) != 0:
            tau *= 0.1
            continue
        band_solve(ab, n, model.kl, model.ku, ipiv, rhs)
        biggest = np.abs(rhs[position_dof]).max(initial=0.0)
        if biggest > move_limit:
            rhs *= move_limit / biggest
        trial = q.copy()
        trial[free] += rhs
        new_norm, new_reaction = out_of_balance(trial)
        if not math.isfinite(new_norm) or new_norm > 10.0 * norm:
            tau *= 0.25
            continue
        tau = min(tau * max(norm / max(new_norm, 1e-300), 0.5), 1e12)
        q, norm, reaction = trial, new_norm, new_reaction
    raise SolverError(f"statics did not converge in {max_iterations} iterations: largest out-of-balance "
                      f"force {norm:.3g} N (tolerance {tolerance:g} x load scale {max(weight, reaction):.3g} N)")
