"""Drives: how the ship motion and the winch set-point enter one solver call.

A drive is a table of knots: times ``t_k`` [s] and, at each knot, the value, rate and
acceleration of 7 channels (x, y, z [m], roll, pitch, yaw [rad] of the ship, and the
winch set-point phi_sp [rad]) — an array of shape (K, 3, 7). The compiled integrator
evaluates it at any time (:func:`evaluate_drive`):

* with two or more knots, piecewise quintic Hermite interpolation of the ship channels
  (value, rate and acceleration matched at every knot; error O(dt^6)) and cubic
  Hermite interpolation of the set-point (value and rate): used when the motion is
  known ahead (a built-in motion source), with knots as close as the solver's step;
* with one knot, constant-acceleration extrapolation of the ship and a linear
  set-point: used by the FMU, which only knows its inputs at the start of a step.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit.kernel_cache import njit

N_CHANNELS = 7


def knot_times(marks: np.ndarray, spacing: float) -> np.ndarray:
    """Knot times [s] through the increasing ``marks`` [s], no farther apart than ``spacing`` [s].

    Each interval between two marks is cut into equal pieces; the marks themselves are
    knots (the quintic pieces then follow any motion a solver step of ``spacing`` resolves).
    """
    pieces = [marks[:1]]
    for a, b in zip(marks[:-1], marks[1:]):
        n = max(1, math.ceil((b - a) / spacing - 1e-9))
        pieces.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(pieces)


def knot_drive(times: np.ndarray, ships: np.ndarray, setpoints: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drive table from ship states and set-points at knot times.

    Parameters
    ----------
    times
        Increasing knot times [s], shape (K,).
    ships
        Ship states at the knots, shape (K, 3, 6).
    setpoints
        Winch set-point (phi_sp [rad], phi_sp_rate [rad/s]) at the knots, shape (K, 2).

    Returns
    -------
    (times, table)
        Knot times (K,) and channel table (K, 3, 7).
    """
    times = np.ascontiguousarray(times, dtype=float)
    table = np.zeros((times.size, 3, N_CHANNELS))
    table[:, :, :6] = ships
    table[:, 0, 6] = setpoints[:, 0]
    table[:, 1, 6] = setpoints[:, 1]
    return times, table


def taylor_drive(t0: float, ship0: np.ndarray, sp0: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """One-knot drive: constant-acceleration extrapolation of ``ship0`` from ``t0``.

    Parameters
    ----------
    t0
        Time of the knot [s].
    ship0
        Ship state (3, 6) at ``t0``.
    sp0
        Winch set-point (phi_sp [rad], phi_sp_rate [rad/s]) at ``t0``.
    """
    return knot_drive(np.array([t0]), ship0[None], np.array([sp0], dtype=float))


@njit(cache=True)
def evaluate_drive(drive_t: np.ndarray, drive_x: np.ndarray, t: float, ship: np.ndarray) -> tuple:
    """Ship state and winch set-point at time t from a drive table (see the module docstring).

    Parameters
    ----------
    drive_t
        Knot times [s], shape (K,).
    drive_x
        Value, rate and acceleration of the 7 channels at the knots, shape (K, 3, 7).
    t
        Evaluation time [s].
    ship
        Output ship state (3, 6).

    Returns
    -------
    (phi_sp, phi_sp_rate)
        Winch set-point [rad] and its rate [rad/s].
    """
    return evaluate_drive_with(drive_t, drive_x, t, ship, np.empty((6, 3)))


@njit(cache=True)
def evaluate_drive_with(drive_t: np.ndarray, drive_x: np.ndarray, t: float, ship: np.ndarray,
                        basis: np.ndarray) -> tuple:
    """:func:`evaluate_drive` with the scratch ``basis`` (6, 3) for the Hermite basis: nothing
    allocated (the explicit path evaluates the drive at every step)."""
    nk = drive_t.shape[0]
    if nk == 1:
        tau = t - drive_t[0]
        for c in range(6):
            p, v, a = drive_x[0, 0, c], drive_x[0, 1, c], drive_x[0, 2, c]
            ship[0, c] = p + tau * (v + 0.5 * tau * a)
            ship[1, c] = v + tau * a
            ship[2, c] = a
        return drive_x[0, 0, 6] + tau * drive_x[0, 1, 6], drive_x[0, 1, 6]
    # the piece [t_k, t_k+1] with t_k < t <= t_k+1 (the first or last piece outside the table)
    k = min(max(np.searchsorted(drive_t, t) - 1, 0), nk - 2)
    dt = drive_t[k + 1] - drive_t[k]
    s = (t - drive_t[k]) / dt
    s2 = s * s
    s3 = s2 * s
    s4 = s3 * s
    s5 = s4 * s
    # quintic Hermite basis (value, first and second derivative in s) for the ship channels
    h = basis
    h[0, 0] = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5
    h[1, 0] = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5
    h[2, 0] = 0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5
    h[3, 0] = 10.0 * s3 - 15.0 * s4 + 6.0 * s5
    h[4, 0] = -4.0 * s3 + 7.0 * s4 - 3.0 * s5
    h[5, 0] = 0.5 * s3 - s4 + 0.5 * s5
    h[0, 1] = -30.0 * s2 + 60.0 * s3 - 30.0 * s4
    h[1, 1] = 1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4
    h[2, 1] = s - 4.5 * s2 + 6.0 * s3 - 2.5 * s4
    h[3, 1] = 30.0 * s2 - 60.0 * s3 + 30.0 * s4
    h[4, 1] = -12.0 * s2 + 28.0 * s3 - 15.0 * s4
    h[5, 1] = 1.5 * s2 - 4.0 * s3 + 2.5 * s4
    h[0, 2] = -60.0 * s + 180.0 * s2 - 120.0 * s3
    h[1, 2] = -36.0 * s + 96.0 * s2 - 60.0 * s3
    h[2, 2] = 1.0 - 9.0 * s + 18.0 * s2 - 10.0 * s3
    h[3, 2] = 60.0 * s - 180.0 * s2 + 120.0 * s3
    h[4, 2] = -24.0 * s + 84.0 * s2 - 60.0 * s3
    h[5, 2] = 3.0 * s - 12.0 * s2 + 10.0 * s3
    scale = (1.0, 1.0 / dt, 1.0 / (dt * dt))
    for c in range(6):
        a = drive_x[k, :, c]
        b = drive_x[k + 1, :, c]
        for d in range(3):
            val = (h[0, d] * a[0] + h[1, d] * dt * a[1] + h[2, d] * dt * dt * a[2]
                   + h[3, d] * b[0] + h[4, d] * dt * b[1] + h[5, d] * dt * dt * b[2])
            ship[d, c] = val * scale[d]
    # cubic Hermite for the set-point (value and rate only)
    p0, r0, p1, r1 = drive_x[k, 0, 6], drive_x[k, 1, 6], drive_x[k + 1, 0, 6], drive_x[k + 1, 1, 6]
    sp = ((2.0 * s3 - 3.0 * s2 + 1.0) * p0 + (s3 - 2.0 * s2 + s) * dt * r0
          + (-2.0 * s3 + 3.0 * s2) * p1 + (s3 - s2) * dt * r1)
    sp_rate = ((6.0 * s2 - 6.0 * s) * p0 + (3.0 * s2 - 4.0 * s + 1.0) * dt * r0
               + (-6.0 * s2 + 6.0 * s) * p1 + (3.0 * s2 - 2.0 * s) * dt * r1) / dt
    return sp, sp_rate


# The step's helpers are IR-inlined (inline="always") into their only caller: a kernel of
# its own would be a library that every caller links and optimises once more, with the
# whole residual and Jacobian code beneath it.
