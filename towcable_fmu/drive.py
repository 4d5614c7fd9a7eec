"""Drives: how the ship motion and the winch set-point enter one solver call.

A drive is a table of knots: times ``t_k`` [s] and, at each knot, the value, rate and
acceleration of 7 channels (x, y, z [m], roll, pitch, yaw [rad] of the ship, and the
winch set-point phi_sp [rad]) — an array of shape (K, 3, 7). The compiled integrator
evaluates it at any time (:func:`towcable_fmu.numerics.genalpha.evaluate_drive`):

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
