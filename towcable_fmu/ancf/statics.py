"""Static equilibrium by pseudo-transient continuation (PTC) with Newton.

Solves ``F(q) = 0`` (the residual with zero velocity and acceleration) from a rough
initial shape. Each iteration solves ``(K + M/tau) dq = -F`` with the tangent
stiffness K and the mass matrix M as regulariser: for small pseudo time step ``tau``
this is a heavily damped implicit dynamic step (robust far from equilibrium, e.g. a
slack initial shape), for large ``tau`` it is Newton's method (quadratic convergence
near equilibrium). ``tau`` is kept small enough that ``K + M/tau`` is positive
definite (checked by elimination without pivoting), so that every step goes
downhill and the iteration cannot settle on a saddle such as a straight cable in
compression. After an accepted step ``tau`` grows by the factor the residual
fell (switched evolution relaxation, Mulder & van Leer 1985; Kelley & Keyes 1998),
and at least twofold; a step that increases the residual tenfold, or produces
non-finite values, is rejected and ``tau`` shrinks fourfold. A node moves at most
half the length of its elements per iteration.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from .feed import apply_feed
from .prescribed import apply_prescribed
from .model import CableModel
from .system import iteration_matrix, residual
from ..common.errors import SolverError
from ..numerics.banded import band_lu, band_positive_pivots, band_solve, band_storage


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


def _ptc(model: CableModel, q: np.ndarray, ship: np.ndarray, t: float, tolerance: float, max_iterations: int,
         tau0: float, move_limit: float) -> tuple[np.ndarray, int, float, float, bool]:
    """PTC iterations; returns (q, iterations, residual norm, load scale, converged)."""
    v = np.zeros_like(q)
    a = np.zeros_like(q)
    n = model.free_dofs.size
    free = model.free_dofs
    position_dof = (free % 6) < 3
    # the move limit in element lengths (free_scale is stricter at a rigid body's link: Newton's measure)
    move_scale = np.minimum(model.free_scale, 1.0 / model.el_len.min())[position_dof]
    ab = band_storage(n, model.kl, model.ku)
    work = np.zeros_like(ab)
    ipiv = np.zeros(n, dtype=np.int64)
    r = np.zeros(q.size)

    def out_of_balance(x: np.ndarray) -> tuple[float, float]:
        residual(model, x, v, a, t, ship, r)
        reaction = np.abs(np.delete(r, free)).max(initial=0.0)
        return float(np.abs(r[free]).max(initial=0.0)), reaction

    norm, reaction = out_of_balance(q)
    weight = float(np.abs(model.f_const).sum())
    tau = tau0
    it = 0
    while True:
        scale = max(weight, reaction, 1e-9)
        if math.isfinite(norm) and norm <= tolerance * scale:
            return q, it, norm, scale, True
        if it == max_iterations:
            return q, it, norm, scale, False
        it += 1
        residual(model, q, v, a, t, ship, r)
        rhs = -r[free]
        iteration_matrix(model, q, v, t, ship, 1.0 / tau, 0.0, 1.0, ab)
        if not band_positive_pivots(ab, n, model.kl, model.ku, work) or band_lu(ab, n, model.kl, model.ku, ipiv):
            tau *= 0.25  # keep K + M/tau positive definite: descend, never climb to a saddle
            continue
        band_solve(ab, n, model.kl, model.ku, ipiv, rhs)
        biggest = np.abs(rhs[position_dof] * move_scale).max(initial=0.0)
        if biggest > move_limit:
            rhs *= move_limit / biggest
        trial = q.copy()
        trial[free] += rhs
        new_norm, new_reaction = out_of_balance(trial)
        if not math.isfinite(new_norm) or new_norm > 10.0 * norm:
            tau *= 0.25
            continue
        tau = min(tau * max(norm / max(new_norm, 1e-300), 2.0), 1e12)
        q, norm, reaction = trial, new_norm, new_reaction


def solve_statics(model: CableModel, q0: np.ndarray, ship: np.ndarray, phi: np.ndarray, t: float,
                  tolerance: float = 1e-8, max_iterations: int = 400, tau0: float = 1e-3,
                  max_move: float | None = None) -> StaticsResult:
    """Bring the cable to rest.

    Two phases: first the cable is treated as unable to carry compression (a rough
    initial shape laid too short or folded then holds no spurious compressive energy
    and simply falls into shape), to a loose tolerance; then the scene's own material
    law takes over from that shape to the requested tolerance.

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
        Iteration limit of each phase.
    tau0
        Initial pseudo time step [s^2].
    max_move
        Largest position change of a node per iteration, relative to the length of its
        elements (default 0.5).

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
    apply_feed(model, phi_static)
    move_limit = 0.5 if max_move is None else max_move
    slack_model = model._replace(el_tension_only=np.ones_like(model.el_tension_only))
    q, it1, _, _, _ = _ptc(slack_model, q, ship_static, t, max(tolerance, 1e-4), max_iterations, tau0, move_limit)
    q, it2, norm, scale, converged = _ptc(model, q, ship_static, t, tolerance, max_iterations, tau0, move_limit)
    if not converged:
        raise SolverError(f"statics did not converge in {max_iterations} iterations: largest out-of-balance "
                          f"force {norm:.3g} N (tolerance {tolerance:g} x load scale {scale:.3g} N)")
    return StaticsResult(q, it1 + it2, norm, scale, time.perf_counter() - start)
