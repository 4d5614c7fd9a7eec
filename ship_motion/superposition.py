"""Superposition of a base motion (a manoeuvre) and a wave-induced motion.

The wave-induced motion is expressed about a frame that follows the base motion's
heading: its x, y (surge, sway) are rotated by the base yaw psi(t) before they are
added, ``r = r_base + Rz(psi) r_waves`` (with its first and second time derivatives,
so the rows stay consistent); z and the three angles are added directly. Adding
Euler angles is the usual small-angle superposition of seakeeping: exact for the yaw
of a ship with zero base roll and pitch, and correct to first order in the wave
angles otherwise.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from towcable_fmu.numerics.kinematics import rotation_derivatives

from .base import MotionSource, as_times


class SuperposedMotion(MotionSource):
    """Base motion plus wave-induced motion (see module docstring).

    Parameters
    ----------
    base
        The ship's mean path, for example a :class:`~ship_motion.manoeuvre.Manoeuvre`.
    waves
        The wave-induced motion about the base's heading frame, for example an
        :class:`~ship_motion.irregular.IrregularSea` or a
        :class:`~ship_motion.regular.RegularMotion`.
    """

    def __init__(self, base: MotionSource, waves: MotionSource) -> None:
        self.base = base
        self.waves = waves

    def evaluate_many(self, t: ArrayLike) -> np.ndarray:
        times = as_times(t)
        base = self.base.evaluate_many(times)
        waves = self.waves.evaluate_many(times)
        out = base + waves
        heading = np.zeros((3, 6))
        drift = np.zeros((3, 3))
        for i in range(times.size):
            heading[:, 5] = base[i, :, 5]
            rz, rz1, rz2 = rotation_derivatives(heading)
            drift[:, 0:2] = waves[i, :, 0:2]
            out[i, 0, 0:3] = base[i, 0, 0:3] + rz @ drift[0]
            out[i, 1, 0:3] = base[i, 1, 0:3] + rz1 @ drift[0] + rz @ drift[1]
            out[i, 2, 0:3] = (base[i, 2, 0:3] + rz2 @ drift[0] + 2.0 * rz1 @ drift[1]
                              + rz @ drift[2])
            out[i, :, 2] += waves[i, :, 2]
        return out

    @property
    def description(self) -> str:
        return f"{self.base.description}; plus waves: {self.waves.description}"
