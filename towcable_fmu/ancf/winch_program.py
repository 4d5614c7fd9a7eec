"""A winch's payout program: the set-point of its PD drive from a table of payouts in time.

``[winch] program_times`` [s] and ``program_payout`` [m] give ``winch.payout`` piecewise
linearly in time, held after the last time (and before the first, at the first payout).
The drive's set-point is the rotation with that payout, ``phi_sp = phi_nom - payout / r``,
with the program's rate as the rate set-point (``r = r_w + d/2``: the payout radius), so a
PD drive follows a ramp without a steady lag.
"""

from __future__ import annotations

import numpy as np


def program_setpoints(times: np.ndarray, program_times: np.ndarray, program_payout: np.ndarray,
                      radius: float, phi_nom: float) -> np.ndarray:
    """Set-points at ``times`` [s] of a payout program.

    Parameters
    ----------
    times
        Evaluation times [s], shape (k,).
    program_times, program_payout
        The program: increasing times [s] and payouts [m] there, shape (m,), m >= 1.
    radius
        Payout radius r_w + d/2 [m].
    phi_nom
        Rotation at zero payout [rad].

    Returns
    -------
    ndarray, shape (k, 2)
        ``phi_sp`` [rad] and ``phi_sp_rate`` [rad/s].
    """
    times = np.asarray(times, dtype=float)
    payout = np.interp(times, program_times, program_payout)
    rate = np.zeros_like(times)
    if program_times.size > 1:
        piece = np.clip(np.searchsorted(program_times, times, side="right") - 1, 0, program_times.size - 2)
        slope = np.diff(program_payout) / np.diff(program_times)
        inside = (times >= program_times[0]) & (times < program_times[-1])
        rate[inside] = slope[piece[inside]]
    return np.column_stack([phi_nom - payout / radius, -rate / radius])
