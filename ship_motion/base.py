"""The interface shared by all ship motion sources, and the still ship.

A ship state is a (3, 6) array (see :mod:`towcable_fmu.numerics.kinematics`): row k is the
k-th time derivative (0 value, 1 rate, 2 acceleration); the columns are x, y, z [m]
of the ship's centre of gravity in the inertial frame (z up, origin at the mean
waterline) and roll, pitch, yaw [rad] (R = Rz(yaw) Ry(pitch) Rx(roll); the rates are
Euler-angle time derivatives).
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np
from numpy.typing import ArrayLike

from towcable_fmu.numerics.kinematics import SHIP_DOF_NAMES

#: Column order of a ship state (x, y, z, roll, pitch, yaw).
DOF_NAMES: tuple[str, ...] = SHIP_DOF_NAMES

#: Configuration names of the six columns (surge = x, sway = y, heave = z).
CONFIG_DOF_NAMES: tuple[str, ...] = ("surge", "sway", "heave", "roll", "pitch", "yaw")

#: True for the angular columns (roll, pitch, yaw).
IS_ANGLE: tuple[bool, ...] = (False, False, False, True, True, True)


def as_times(t: ArrayLike) -> np.ndarray:
    """Times [s] as a finite 1-D float array (a scalar becomes one element).

    Raises
    ------
    ValueError
        If ``t`` has more than one dimension or a non-finite entry.
    """
    times = np.atleast_1d(np.asarray(t, dtype=float))
    if times.ndim != 1:
        raise ValueError(f"times must be a scalar or a 1-D array, got shape {times.shape}")
    if not np.all(np.isfinite(times)):
        raise ValueError("times must be finite")
    return times


class MotionSource(ABC):
    """A prescribed 6-DOF ship motion with consistent first and second derivatives."""

    @abstractmethod
    def evaluate_many(self, t: ArrayLike) -> np.ndarray:
        """Ship states at many times.

        Parameters
        ----------
        t
            Times [s], shape (n,).

        Returns
        -------
        ndarray, shape (n, 3, 6)
            ``out[i]`` is the ship state at ``t[i]``.
        """

    def evaluate(self, t: float) -> np.ndarray:
        """Ship state at time ``t`` [s] as a (3, 6) array."""
        return self.evaluate_many(np.array([float(t)]))[0]

    @property
    @abstractmethod
    def description(self) -> str:
        """One human-readable line with the parameters and their units."""

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {self.description}>"


class StillShip(MotionSource):
    """The ship at rest: every position, angle and derivative is zero."""

    def evaluate_many(self, t: ArrayLike) -> np.ndarray:
        return np.zeros((as_times(t).size, 3, 6))

    @property
    def description(self) -> str:
        return "still ship: CG at the origin, zero angles, no motion"
