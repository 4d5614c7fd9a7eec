"""The wake oscillator of Westin 2018 eq. A19 (Bai and Qin; Facchinetti), per node.

As printed, A19 reads ``w'' + a1 w_st [1 - a2 w'^2 / w_st^2] w' + w_st w = (a3 w_st / d) Y'``.
Two corrections, both forced by the equation's own meaning:

* the stiffness term must be ``w_st^2 w``: every other term has units 1/s^2 with w
  dimensionless (``d^2 w'`` is the vortex strength [m^2/s], and A20b then gives N/m), and
  only ``w_st^2`` makes the free oscillator run at the Strouhal frequency A25;
* the damping bracket must be ``[a2 w'^2 / w_st^2 - 1]``: as printed the damping is
  positive at small amplitude, so the wake variable decays to zero (and diverges beyond
  the unstable cycle); a van der Pol/Rayleigh wake oscillator is self-excited, with
  negative damping at small amplitude (Facchinetti: ``eps w_f (q^2 - 1) q'``), which is
  what the thesis's "van der Pol equation" and its stated limit-cycle behaviour need.

So we integrate

    w'' + a1 w_st (a2 w'^2 / w_st^2 - 1) w' + w_st^2 w = (a3 w_st / d) Y'

with ``w_st = 2 pi St U / d`` (A25) and Y' the cable's cross-flow velocity at the node.
Harmonic balance on ``w = A cos(w_st t)`` (the fundamental of sin^3 is 3/4 sin) gives the
limit cycle ``A = 2 / sqrt(3 a2)`` for small a1 (tested in tests/test_viv.py).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..jit.kernel_cache import njit


class WakeParameters(NamedTuple):
    """Constants of A19 for one loaded segment (all nodes alike)."""

    a1: float        #: damping parameter [-]
    a2: float        #: nonlinearity [-]
    a3: float        #: coupling [-]
    omega: float     #: Strouhal frequency w_st [rad/s]
    diameter: float  #: cable diameter d [m]


def strouhal_frequency(strouhal: float, speed: float, diameter: float) -> float:
    """Vortex-shedding angular frequency ``w_st = 2 pi St U / d`` [rad/s], eq. A25.

    Parameters
    ----------
    strouhal
        Strouhal number St [-].
    speed
        Free-stream speed U [m/s].
    diameter
        Cable diameter d [m].
    """
    return 2.0 * math.pi * strouhal * speed / diameter


def limit_cycle_amplitude(a2: float) -> float:
    """Amplitude of w on the free limit cycle, ``2 / sqrt(3 a2)`` [-] (harmonic balance, small a1)."""
    return 2.0 / math.sqrt(3.0 * a2)


@njit(cache=True, inline="always")
def _rhs(w: float, wd: float, yd: float, a1: float, a2: float, k: float, omega: float) -> float:
    """w'' of the corrected A19 for the cross-flow velocity yd; ``k = a3 w_st / d``."""
    return -a1 * omega * (a2 * wd * wd / (omega * omega) - 1.0) * wd - omega * omega * w + k * yd


@njit(cache=True)
def wake_acceleration(w: np.ndarray, wd: np.ndarray, yd: np.ndarray, a1: float, a2: float, a3: float,
                      omega: float, diameter: float, out: np.ndarray) -> None:
    """w'' of every node from A19 (corrected) [1/s^2].

    Parameters
    ----------
    w, wd
        Wake variable [-] and its rate [1/s] per node.
    yd
        Cross-flow velocity of the cable at the node [m/s].
    a1, a2, a3, omega, diameter
        See :class:`WakeParameters`.
    out
        w'' per node [1/s^2].
    """
    k = a3 * omega / diameter
    for i in range(w.shape[0]):
        out[i] = _rhs(w[i], wd[i], yd[i], a1, a2, k, omega)


@njit(cache=True)
def advance_wake(w: np.ndarray, wd: np.ndarray, yd0: np.ndarray, yd1: np.ndarray, h: float, a1: float,
                 a2: float, a3: float, omega: float, diameter: float) -> None:
    """Advance A19 (corrected) over a time ``h`` in place, classical Runge-Kutta.

    The cross-flow velocity varies linearly from ``yd0`` to ``yd1`` over the interval.
    Sub-steps keep ``w_st dt <= 0.05`` (phase error of RK4 below 1e-8 per period).

    Parameters
    ----------
    w, wd
        Wake variable [-] and its rate [1/s] per node, updated in place.
    yd0, yd1
        Cross-flow velocity per node at the start and the end of the interval [m/s].
    h
        Interval [s] (>= 0).
    a1, a2, a3, omega, diameter
        See :class:`WakeParameters`.
    """
    if h <= 0.0:
        return
    n = max(1, int(math.ceil(h * omega / 0.05)))
    dt = h / n
    k = a3 * omega / diameter
    for i in range(w.shape[0]):
        x, v = w[i], wd[i]
        for s in range(n):
            f0 = s / n
            fm = (s + 0.5) / n
            f1 = (s + 1.0) / n
            y0 = yd0[i] + f0 * (yd1[i] - yd0[i])
            ym = yd0[i] + fm * (yd1[i] - yd0[i])
            y1 = yd0[i] + f1 * (yd1[i] - yd0[i])
            k1x = v
            k1v = _rhs(x, v, y0, a1, a2, k, omega)
            k2x = v + 0.5 * dt * k1v
            k2v = _rhs(x + 0.5 * dt * k1x, k2x, ym, a1, a2, k, omega)
            k3x = v + 0.5 * dt * k2v
            k3v = _rhs(x + 0.5 * dt * k2x, k3x, ym, a1, a2, k, omega)
            k4x = v + dt * k3v
            k4v = _rhs(x + dt * k3x, k4x, y1, a1, a2, k, omega)
            x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x)
            v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
        w[i] = x
        wd[i] = v
