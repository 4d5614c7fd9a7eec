"""Cubic Hermite interpolation inside a time step, from values and rates at both ends."""

from __future__ import annotations

from ..jit.kernel_cache import njit


@njit(cache=True, inline="always")
def step_weights(s: float, h: float) -> tuple:
    """Weights of the cubic Hermite interpolant at the fraction ``s`` of a step of ``h`` [s].

    Returns
    -------
    tuple
        ``(h00, h10, h01, h11, d00, d10, d01, d11)``: the value is
        ``h00 x0 + h10 h v0 + h01 x1 + h11 h v1`` and its rate
        ``d00 x0 + d10 v0 + d01 x1 + d11 v1`` (x, v: value and rate at the step's start
        0 and end 1). Exact for cubics in time.
    """
    s2, s3 = s * s, s * s * s
    return (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, 3.0 * s2 - 2.0 * s3, s3 - s2,
            (6.0 * s2 - 6.0 * s) / h, 3.0 * s2 - 4.0 * s + 1.0, (6.0 * s - 6.0 * s2) / h, 3.0 * s2 - 2.0 * s)
