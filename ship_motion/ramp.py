"""The C2 smooth step used to ramp motions in and out, and the product rule.

The step is the quintic ``s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5`` on [0, 1]
(0 before, 1 after). Its first and second derivatives vanish at both ends, so a
quantity multiplied by it, or integrated from it, stays twice continuously
differentiable.
"""

from __future__ import annotations

import numpy as np


def smoothstep(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic smooth step and its derivatives with respect to ``tau``.

    Parameters
    ----------
    tau
        Normalised time [-]; clipped to [0, 1].

    Returns
    -------
    s, ds, d2s : ndarray
        ``s(tau)`` [-], ``s'(tau)`` [-], ``s''(tau)`` [-].
    """
    x = np.clip(tau, 0.0, 1.0)
    s = x ** 3 * (10.0 - 15.0 * x + 6.0 * x * x)
    ds = 30.0 * x * x * (1.0 - x) ** 2
    d2s = 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x)
    return s, ds, d2s


def smoothstep_integral(tau: np.ndarray) -> np.ndarray:
    """Integral of the smooth step from 0 to ``tau`` [-].

    ``tau^4 (5/2 - 3 tau + tau^2)`` on [0, 1], 0 before and ``tau - 1/2`` after.
    """
    x = np.clip(tau, 0.0, 1.0)
    inside = x ** 4 * (2.5 - 3.0 * x + x * x)
    return inside + np.maximum(np.asarray(tau, dtype=float) - 1.0, 0.0)


def ramp(t: np.ndarray, duration: float) -> np.ndarray:
    """Ramp factor rising from 0 at ``t = 0`` to 1 at ``t = duration``.

    Parameters
    ----------
    t
        Times [s], shape (n,).
    duration
        Ramp time [s]; 0 means no ramp (factor 1 at all times).

    Returns
    -------
    ndarray, shape (3, n)
        The factor [-] and its first [1/s] and second [1/s^2] time derivatives.
    """
    t = np.asarray(t, dtype=float)
    if duration <= 0.0:
        return np.stack([np.ones_like(t), np.zeros_like(t), np.zeros_like(t)])
    s, ds, d2s = smoothstep(t / duration)
    return np.stack([s, ds / duration, d2s / duration ** 2])


def modulate(factor: np.ndarray, signal: np.ndarray) -> np.ndarray:
    """Product rule up to the second derivative: ``(f g), (f g)', (f g)''``.

    Parameters
    ----------
    factor
        Shape (3, n): ``f, f', f''``.
    signal
        Shape (3, n, ...): ``g, g', g''``.

    Returns
    -------
    ndarray, same shape as ``signal``
    """
    f = factor.reshape(factor.shape + (1,) * (signal.ndim - 2))
    return np.stack([
        f[0] * signal[0],
        f[1] * signal[0] + f[0] * signal[1],
        f[2] * signal[0] + 2.0 * f[1] * signal[1] + f[0] * signal[2],
    ])
