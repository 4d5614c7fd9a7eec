"""Drive polynomials: how the ship motion and the winch set-point enter one solver call.

Within one call of the compiled integrator the ship state and the winch set-point are
polynomials in ``tau = t - t0`` (rows: x, y, z, roll, pitch, yaw, phi_sp; see
:func:`towcable_fmu.numerics.genalpha.evaluate_drive`):

* :func:`quintic_drive` matches value, rate and acceleration at both ends of the
  interval: used when the motion is known ahead (a built-in motion source); the
  interpolation error is O(dt^6).
* :func:`taylor_drive` extrapolates from the start of the interval with constant
  acceleration: used by the FMU, which only knows its inputs at the start of a
  communication step.
"""

from __future__ import annotations

import numpy as np

N_COEF = 6


def quintic_drive(dt: float, ship0: np.ndarray, ship1: np.ndarray, sp0: tuple[float, float],
                  sp1: tuple[float, float]) -> np.ndarray:
    """Quintic Hermite coefficients over [0, dt].

    Parameters
    ----------
    dt
        Interval length [s] (> 0).
    ship0, ship1
        Ship states (3, 6) at the start and the end.
    sp0, sp1
        Winch set-point (phi_sp [rad], phi_sp_rate [rad/s]) at the start and the end
        (cubic Hermite in the set-point: its acceleration is not prescribed).

    Returns
    -------
    ndarray, shape (7, 6)
    """
    p0, v0, a0 = ship0
    p1, v1, a1 = ship1
    t = dt
    coef = np.zeros((7, N_COEF))
    coef[:6, 0] = p0
    coef[:6, 1] = v0
    coef[:6, 2] = 0.5 * a0
    coef[:6, 3] = (20.0 * (p1 - p0) - (8.0 * v1 + 12.0 * v0) * t - (3.0 * a0 - a1) * t**2) / (2.0 * t**3)
    coef[:6, 4] = (30.0 * (p0 - p1) + (14.0 * v1 + 16.0 * v0) * t + (3.0 * a0 - 2.0 * a1) * t**2) / (2.0 * t**4)
    coef[:6, 5] = (12.0 * (p1 - p0) - 6.0 * (v1 + v0) * t - (a1 - a0) * t**2) / (2.0 * t**5)
    (s0, r0), (s1, r1) = sp0, sp1
    coef[6, 0] = s0
    coef[6, 1] = r0
    coef[6, 2] = (3.0 * (s1 - s0) - (2.0 * r0 + r1) * t) / t**2
    coef[6, 3] = (2.0 * (s0 - s1) + (r0 + r1) * t) / t**3
    return coef


def taylor_drive(ship0: np.ndarray, sp0: tuple[float, float]) -> np.ndarray:
    """Constant-acceleration extrapolation of the ship state and a linear set-point.

    Parameters
    ----------
    ship0
        Ship state (3, 6) at the start of the interval.
    sp0
        Winch set-point (phi_sp [rad], phi_sp_rate [rad/s]).

    Returns
    -------
    ndarray, shape (7, 6)
    """
    coef = np.zeros((7, N_COEF))
    coef[:6, 0] = ship0[0]
    coef[:6, 1] = ship0[1]
    coef[:6, 2] = 0.5 * ship0[2]
    coef[6, 0] = sp0[0]
    coef[6, 1] = sp0[1]
    return coef
