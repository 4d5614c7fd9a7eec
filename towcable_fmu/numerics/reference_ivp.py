"""Slow reference path: the same equations integrated by scipy's Radau/BDF.

Independent of the compiled integrator (no generalised-alpha, no drive polynomials,
no modified Newton): the equations of motion are written as the first-order system
``y = [q_free, v_free]``, ``dq/dt = v``, ``dv/dt = -M_ff^{-1} R(q, v, a = 0, t)``
with the ship motion evaluated exactly at every time, and handed to
``scipy.integrate.solve_ivp``. It is meant for cross-checking the fast path on small
scenes in the tests, not for production runs (its Jacobian is built by finite
differences over the full state).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import solve_banded

from ..ancf.prescribed import apply_prescribed
from ..ancf.system import iteration_matrix, residual
from ..errors import SolverError


def integrate_reference(sim, t_end: float, t_eval: np.ndarray, method: str = "Radau",
                        rtol: float = 1e-8, atol: float = 1e-10) -> np.ndarray:
    """Integrate an initialised :class:`~towcable_fmu.simulation.Simulation` with scipy.

    Parameters
    ----------
    sim
        Simulation after ``initialize()`` (its state is the initial condition; it is
        not modified).
    t_end
        End time [s].
    t_eval
        Times at which to return the coordinates [s].
    method
        ``"Radau"`` or ``"BDF"``.
    rtol, atol
        Tolerances of solve_ivp.

    Returns
    -------
    ndarray, shape (len(t_eval), nf)
        Full coordinate vectors at ``t_eval``.

    Raises
    ------
    SolverError
        If scipy reports a failure.
    """
    model = sim.model
    free = model.free_dofs
    n = free.size
    kl, ku = model.kl, model.ku
    phi = sim.state.phi.copy()
    q = sim.state.q.copy()
    v = sim.state.v.copy()
    a = np.zeros_like(q)
    r = np.zeros_like(q)
    ab = np.zeros((2 * kl + ku + 1, n))

    def full_state(t: float, y: np.ndarray) -> np.ndarray:
        ship = sim.motion.evaluate(t)
        q[free] = y[:n]
        v[free] = y[n:]
        apply_prescribed(model.att_index, model.att_kind, model.att_vec, model.att_radius, ship, phi, q, v, a)
        a[free] = 0.0
        return ship

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        ship = full_state(t, y)
        residual(model, q, v, a, t, ship, r)
        iteration_matrix(model, q, v, t, ship, 1.0, 0.0, 0.0, ab)
        acc = solve_banded((kl, ku), ab[kl:], -r[free])
        return np.concatenate([y[n:], acc])

    y0 = np.concatenate([sim.state.q[free], sim.state.v[free]])
    t0 = sim.time
    sol = solve_ivp(rhs, (t0, t_end), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol)
    if not sol.success:
        raise SolverError(f"reference integration failed: {sol.message}")
    out = np.empty((len(t_eval), q.size))
    for k, t in enumerate(sol.t):
        full_state(t, sol.y[:, k])
        out[k] = q
    return out
