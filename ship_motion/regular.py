"""Regular (sinusoidal) ship motion.

Each degree of freedom j is its mean plus a sum of sinusoids, all multiplied by the C2
ramp factor f(t) of :mod:`ship_motion.ramp`:

    q_j(t) = mean_j + f(t) * sum_h A_h sin(2 pi t / T_h + phi_h)

The derivatives are those of this product, exactly.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .base import CONFIG_DOF_NAMES, IS_ANGLE, MotionSource, as_times
from .ramp import modulate, ramp


@dataclass(frozen=True)
class Harmonic:
    """One sinusoid ``amplitude * sin(2 pi t / period + phase)`` on one DOF.

    Parameters
    ----------
    dof
        Column index: 0 x (surge), 1 y (sway), 2 z (heave), 3 roll, 4 pitch, 5 yaw.
    amplitude
        Amplitude [m] (x, y, z) or [rad] (angles), >= 0.
    period
        Period [s], > 0.
    phase
        Phase [rad].
    """

    dof: int
    amplitude: float
    period: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        if self.dof not in range(6):
            raise ValueError(f"dof must be 0..5, got {self.dof}")
        if not (math.isfinite(self.amplitude) and self.amplitude >= 0.0):
            raise ValueError(f"amplitude must be finite and >= 0, got {self.amplitude}")
        if not (math.isfinite(self.period) and self.period > 0.0):
            raise ValueError(f"period must be finite and > 0 s, got {self.period}")
        if not math.isfinite(self.phase):
            raise ValueError(f"phase must be finite, got {self.phase}")


class RegularMotion(MotionSource):
    """Sum of sinusoids about a mean, ramped in smoothly.

    Parameters
    ----------
    harmonics
        The sinusoids (any number per DOF).
    mean
        Mean values of x, y, z [m] and roll, pitch, yaw [rad], shape (6,); default 0.
    ramp
        Ramp time [s] over which the amplitudes rise from 0 (C2 quintic step starting
        at t = 0); 0 means full amplitude from the start.
    """

    def __init__(self, harmonics: Sequence[Harmonic], mean: ArrayLike | None = None,
                 ramp: float = 0.0) -> None:
        self.harmonics = tuple(harmonics)
        self.mean = np.zeros(6) if mean is None else np.asarray(mean, dtype=float).reshape(6)
        if not np.all(np.isfinite(self.mean)):
            raise ValueError("mean values must be finite")
        if not (math.isfinite(ramp) and ramp >= 0.0):
            raise ValueError(f"ramp must be finite and >= 0 s, got {ramp}")
        self.ramp = float(ramp)
        self._omega = np.array([2.0 * math.pi / h.period for h in self.harmonics])
        self._amplitude = np.array([h.amplitude for h in self.harmonics])
        self._phase = np.array([h.phase for h in self.harmonics])
        self._select = np.zeros((len(self.harmonics), 6))
        for i, h in enumerate(self.harmonics):
            self._select[i, h.dof] = 1.0

    def evaluate_many(self, t: ArrayLike) -> np.ndarray:
        times = as_times(t)
        angle = np.outer(times, self._omega) + self._phase
        s = np.sin(angle) * self._amplitude
        c = np.cos(angle) * (self._amplitude * self._omega)
        signal = np.stack([s, c, -s * self._omega ** 2]) @ self._select  # (3, n, 6)
        out = modulate(ramp(times, self.ramp), signal)
        out[0] += self.mean
        return out.transpose(1, 0, 2)

    @property
    def description(self) -> str:
        parts = []
        for h in self.harmonics:
            name = CONFIG_DOF_NAMES[h.dof]
            if IS_ANGLE[h.dof]:
                size = f"{math.degrees(h.amplitude):g} deg"
            else:
                size = f"{h.amplitude:g} m"
            parts.append(f"{name} {size} / {h.period:g} s / phase {math.degrees(h.phase):g} deg")
        means = [f"{CONFIG_DOF_NAMES[j]} {math.degrees(m) if IS_ANGLE[j] else m:g}"
                 f" {'deg' if IS_ANGLE[j] else 'm'}" for j, m in enumerate(self.mean) if m != 0.0]
        text = "regular motion: " + ("; ".join(parts) if parts else "no harmonics")
        if means:
            text += "; mean " + ", ".join(means)
        return text + f"; ramp {self.ramp:g} s"
