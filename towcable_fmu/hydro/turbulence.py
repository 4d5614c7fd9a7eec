"""Turbulent flow fluctuation: filtered white noise (section 4.3 of the reference).

White noise from a seeded generator is passed through a Chebyshev type II low-pass
filter and scaled per axis so that the fluctuation has the requested standard
deviation. The scale uses the filter's own power gain (sum of the squared impulse
response), not the sample statistics, so the series does not depend on how it is
generated in blocks: the generator extends the series block by block, carrying the
filter state and the random stream, and a longer run sees the same beginning.
"""

from __future__ import annotations

import numpy as np
from scipy import signal

from ..scene.model import Turbulence

BLOCK_SECONDS = 600.0


class TurbulenceSeries:
    """A growing table of the turbulent velocity fluctuation, sampled at a fixed rate.

    Parameters
    ----------
    cfg
        The scene's turbulence settings.
    t0
        Time of the first sample [s].
    """

    def __init__(self, cfg: Turbulence, t0: float = 0.0) -> None:
        self.cfg = cfg
        self.t0 = float(t0)
        self.dt = 1.0 / cfg.sample_rate
        self._sos = signal.cheby2(cfg.order, cfg.attenuation, cfg.cutoff, btype="low", fs=cfg.sample_rate,
                                  output="sos")
        impulse = np.zeros(int(60 * cfg.sample_rate / cfg.cutoff) + 1000)
        impulse[0] = 1.0
        gain = float(np.sqrt(np.sum(signal.sosfilt(self._sos, impulse) ** 2)))
        self._scale = np.asarray(cfg.std, dtype=float) / gain
        self._rng = np.random.default_rng(cfg.seed)
        self._zi = np.zeros((3, self._sos.shape[0], 2))
        self.samples = np.zeros((0, 3))

    @property
    def t_end(self) -> float:
        """Time of the last generated sample [s]."""
        return self.t0 + (self.samples.shape[0] - 1) * self.dt

    def extend_to(self, t: float) -> bool:
        """Generate samples until the table covers ``t`` (plus one sample); True if it grew."""
        grew = False
        while self.samples.shape[0] < 4 or self.t_end < t + 2 * self.dt:
            n = int(round(BLOCK_SECONDS * self.cfg.sample_rate))
            noise = self._rng.standard_normal((n, 3))
            block = np.empty((n, 3))
            for k in range(3):
                block[:, k], self._zi[k] = signal.sosfilt(self._sos, noise[:, k], zi=self._zi[k])
            self.samples = np.concatenate([self.samples, block * self._scale])
            grew = True
        return grew
