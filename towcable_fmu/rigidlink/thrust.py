"""The tug's motor thrust: brought from 0 to its maximum with a trapezoidal rate profile.

The reference brings the thrust to 320 kN in 80 s so that "its time derivative obeys a
trapezoidal profile": the rate rises linearly for ``a = rise_fraction * ramp_time``,
stays constant, and falls linearly over the last ``a``; the thrust is its integral.
"""

from __future__ import annotations

from ..scene.rigid_link import Thrust


def thrust_at(t: float, spec: Thrust) -> float:
    """Thrust [N] at time ``t`` [s] (0 before ``t = 0``, the maximum after the ramp).

    Parameters
    ----------
    t
        Time [s].
    spec
        Maximum [N], ramp time [s] and rise fraction [-].
    """
    T = spec.ramp_time
    a = spec.rise_fraction * T
    rate = spec.maximum / (T - a)  # plateau of dF/dt [N/s]: area of the trapezoid = maximum
    if t <= 0.0:
        return 0.0
    if t >= T:
        return spec.maximum
    if t <= a:
        return 0.5 * rate * t * t / a
    if t <= T - a:
        return rate * (0.5 * a + (t - a))
    return spec.maximum - 0.5 * rate * (T - t) ** 2 / a
