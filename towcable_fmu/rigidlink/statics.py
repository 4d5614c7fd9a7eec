"""Static equilibrium of the link chain hanging between the two fairleads held in place.

Unknowns: the n link angles and the force ``F = (F_x, F_z)`` [N] the towed vessel's
fairlead exerts on the cable. Equations: stationarity of the potential energy (link
weights, joint springs) against the virtual work of ``F`` on the last node,
``dV/dtheta_k - F . l_k e'_k = 0``, and the closure of the chain on the fairlead. The
tension at the towed vessel is ``F . e_n``; at the tug it follows from the balance of
the whole cable.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.optimize import root

from ..common.errors import SolverError


@dataclasses.dataclass(frozen=True)
class Equilibrium:
    """Static equilibrium of the chain.

    Attributes
    ----------
    theta
        Link angles [rad].
    force_towed
        Force of the towed vessel's fairlead on the cable [N] (x, z).
    tension_tug, tension_towed
        Axial tension at the two fairleads [N].
    sag
        Largest depth of a node below the chord between the fairleads [m].
    iterations
        Function evaluations of the root finder.
    residual
        Largest residual at the solution [N m or m].
    """

    theta: np.ndarray
    force_towed: np.ndarray
    tension_tug: float
    tension_towed: float
    sag: float
    iterations: int
    residual: float


def solve_statics(theta0: np.ndarray, l: np.ndarray, m: np.ndarray, k: np.ndarray, span: float,
                  g: float, force0: tuple[float, float] = (0.0, 0.0)) -> Equilibrium:
    """Equilibrium with the tug's fairlead at ``(span, 0)`` and the towed vessel's at ``(0, 0)``.

    Parameters
    ----------
    theta0
        Initial guess of the link angles [rad] (n).
    l, m
        Link lengths [m] and masses [kg].
    k
        Rotational stiffness of the n - 1 interior joints [N m/rad].
    span
        Horizontal distance between the fairleads [m] (< the cable length).
    g
        Gravity [m/s^2].
    force0
        Initial guess of the towed vessel's force on the cable [N].
    """
    n = l.size
    beyond = np.concatenate((np.cumsum(m[::-1])[::-1][1:], [0.0]))  # link mass beyond link k
    S = beyond + 0.5 * m

    def spring_gradient(theta: np.ndarray) -> np.ndarray:
        torque = k * np.diff(theta)
        out = np.zeros(n)
        out[:-1] -= torque
        out[1:] += torque
        return out

    def residual(u: np.ndarray) -> np.ndarray:
        theta, fx, fz = u[:n], u[n], u[n + 1]
        c, s = np.cos(theta), np.sin(theta)
        r = np.empty(n + 2)
        r[:n] = g * S * l * c + spring_gradient(theta) - (fx * (-l * s) + fz * l * c)
        r[n] = span + np.sum(l * c)
        r[n + 1] = np.sum(l * s)
        return r

    def jacobian(u: np.ndarray) -> np.ndarray:
        theta, fx, fz = u[:n], u[n], u[n + 1]
        c, s = np.cos(theta), np.sin(theta)
        J = np.zeros((n + 2, n + 2))
        idx = np.arange(n)
        J[idx, idx] = -g * S * l * s + fx * l * c + fz * l * s
        J[idx[:-1], idx[:-1]] += k
        J[idx[1:], idx[1:]] += k
        J[idx[:-1], idx[1:]] -= k
        J[idx[1:], idx[:-1]] -= k
        J[:n, n] = l * s
        J[:n, n + 1] = -l * c
        J[n, :n] = -l * s
        J[n + 1, :n] = l * c
        return J

    sol = root(residual, np.concatenate((theta0, force0)), jac=jacobian, method="hybr",
               options={"xtol": 1e-13})
    res = float(np.max(np.abs(residual(sol.x))))
    if not sol.success and res > 1e-8 * max(1.0, g * m.sum() * l.sum()):
        raise SolverError(f"rigid-link statics did not converge: {sol.message} (residual {res:.3g})")
    theta = sol.x[:n]
    F = sol.x[n:]
    e_first = np.array([np.cos(theta[0]), np.sin(theta[0])])
    e_last = np.array([np.cos(theta[-1]), np.sin(theta[-1])])
    force_tug = -F + np.array([0.0, g * m.sum()])  # the tug's fairlead on the cable
    z_nodes = np.concatenate(([0.0], np.cumsum(l * np.sin(theta))))
    return Equilibrium(theta=theta, force_towed=F, tension_tug=float(-force_tug @ e_first),
                       tension_towed=float(F @ e_last), sag=float(-z_nodes.min()),
                       iterations=int(sol.nfev), residual=res)
