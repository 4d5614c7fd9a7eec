"""Slow reference path: the same equations integrated by scipy's Radau/BDF.

Independent of the compiled integrator (no generalised-alpha, no drive polynomials,
no modified Newton): the equations of motion are written as the first-order system
``y = [q_free, v_free]``, ``dq/dt = v``, ``dv/dt = -M_ff^{-1} R(q, v, a = 0, t)``
with the ship motion evaluated exactly at every time, and handed to
``scipy.integrate.solve_ivp``. It is meant for cross-checking the fast path on small
scenes in the tests, not for production runs (its Jacobian is built by finite
differences over the full state).

It also integrates the prescribed ends the reference's way, as constraints held by
Lagrange multipliers with Baumgarte stabilisation W(113)-(118), instead of eliminating
them: all coordinates are states, and for the constraint ``C = q_p - g(t) = 0`` on the
prescribed coordinates (``C_q`` selects them) the augmented system

    [M    C_q^T] [a     ]   [Q                              ]
    [C_q  0    ] [lambda] = [g'' - 2 alpha C' - beta^2 C     ]

gives ``a_p = g'' - 2 alpha (v_p - g') - beta^2 (q_p - g)`` and the free accelerations
from the free rows with that ``a_p``; ``lambda`` is the reaction. The tests show that
this and the exact elimination used everywhere else describe the same motion.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import solve_banded

from .prescribed import apply_prescribed
from .system import iteration_matrix, residual
from ..common.errors import SolverError
from ..numerics.banded import band_storage


def integrate_reference(sim, t_end: float, t_eval: np.ndarray, method: str = "Radau",
                        rtol: float = 1e-8, atol: float = 1e-10, constraints: str = "eliminated",
                        baumgarte: tuple[float, float] = (20.0, 20.0)) -> np.ndarray:
    """Integrate an initialised :class:`~towcable_fmu.ancf.simulation.Simulation` with scipy.

    Parameters
    ----------
    sim
        Simulation after ``initialize()`` (its state is the initial condition; it is
        not modified). The winch rotation is held at its initial value.
    t_end
        End time [s].
    t_eval
        Times at which to return the coordinates [s].
    method
        ``"Radau"`` or ``"BDF"``.
    rtol, atol
        Tolerances of solve_ivp.
    constraints
        ``"eliminated"``: prescribed coordinates follow their motion exactly (as the
        fast path). ``"baumgarte"``: they are states held by the stabilised constraint
        (module docstring), starting from their values in ``sim.state`` (which may
        violate the constraint).
    baumgarte
        (alpha [1/s], beta [1/s]) of the stabilisation.

    Returns
    -------
    ndarray, shape (len(t_eval), nf)
        Full coordinate vectors at ``t_eval``.

    Raises
    ------
    SolverError
        If scipy reports a failure.
    ValueError
        For an unknown ``constraints`` or non-positive Baumgarte parameters.
    """
    if constraints not in ("eliminated", "baumgarte"):
        raise ValueError(f"constraints must be 'eliminated' or 'baumgarte', got {constraints!r}")
    alpha, beta = (float(x) for x in baumgarte)
    if not (alpha > 0.0 and beta > 0.0):
        raise ValueError(f"Baumgarte parameters must be > 0 1/s, got alpha = {alpha}, beta = {beta}")
    model = sim.model
    free = model.free_dofs
    held = np.flatnonzero(model.free_idx < 0)
    n = free.size
    kl, ku = model.kl, model.ku
    phi = sim.state.phi.copy()
    q = sim.state.q.copy()
    v = sim.state.v.copy()
    a = np.zeros_like(q)
    r = np.zeros_like(q)
    ab = band_storage(n, kl, ku)
    goal = (np.zeros_like(q), np.zeros_like(q), np.zeros_like(q))  # g, g', g'' of the prescribed rows
    states = free if constraints == "eliminated" else np.arange(q.size)
    m = states.size

    def full_state(t: float, y: np.ndarray) -> np.ndarray:
        ship = sim.motion.evaluate(t)
        q[states] = y[:m]
        v[states] = y[m:]
        a[:] = 0.0
        if constraints == "eliminated":
            apply_prescribed(model.att_index, model.att_kind, model.att_vec, model.att_radius, ship, phi, q, v, a)
        else:
            apply_prescribed(model.att_index, model.att_kind, model.att_vec, model.att_radius, ship, phi, *goal)
            g, g1, g2 = (x[held] for x in goal)
            a[held] = g2 - 2.0 * alpha * (v[held] - g1) - beta**2 * (q[held] - g)
        return ship

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        ship = full_state(t, y)
        residual(model, q, v, a, t, ship, r)
        iteration_matrix(model, q, v, t, ship, 1.0, 0.0, 0.0, ab)
        acc = a.copy()
        acc[free] = solve_banded((kl, ku), ab[:, kl:].T, -r[free])
        return np.concatenate([y[m:], acc[states]])

    y0 = np.concatenate([sim.state.q[states], sim.state.v[states]])
    t0 = sim.time
    sol = solve_ivp(rhs, (t0, t_end), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol)
    if not sol.success:
        raise SolverError(f"reference integration failed: {sol.message}")
    out = np.empty((len(t_eval), q.size))
    for k, t in enumerate(sol.t):
        full_state(t, sol.y[:, k])
        out[k] = q
    return out
