"""Wave-induced ship motion in a long-crested irregular sea.

The JONSWAP spectrum is cut into N harmonic components (:mod:`ship_motion.spectrum`),
each passed through the ship's RAOs (:mod:`ship_motion.rao`) at its encounter
frequency ``omega_e = omega - omega^2 U cos(mu) / g`` (speed U, heading mu, 180 deg =
head seas). DOF j is

    q_j(t) = f(t) * Re sum_i a_i H_j(omega_i) exp(i (omega_e,i t + eps_i))

with the C2 ramp factor f(t) of :mod:`ship_motion.ramp` (so the ship starts at rest)
and the derivatives of this product, exactly. The motion is about a frame that moves
with the ship at speed U on a constant heading: the mean of every DOF is zero.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .base import MotionSource, as_times
from .ramp import modulate, ramp
from .rao import GRAVITY, Rao
from .spectrum import Jonswap, discretise

#: Default frequency band, as multiples of the peak frequency 2 pi / Tp.
DEFAULT_BAND: tuple[float, float] = (0.5, 4.0)

_CHUNK = 4096


def _harmonic_sum(phasors: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Real part of ``phasors @ weights``: phasors (..., N), weights (N, m) -> (..., m).

    ``einsum`` instead of ``@``: the products are small (tens of times by a few hundred
    components), and BLAS's threads cost more than they save there; on a busy machine a
    threaded BLAS waiting for a free core made them 50 times slower (measured: 23 ms
    against 0.5 ms for 60 times and 200 components).
    """
    return np.einsum("...n,nj->...j", phasors, weights).real


class IrregularSea(MotionSource):
    """Ship motion in a long-crested JONSWAP sea (module docstring).

    Parameters
    ----------
    spectrum
        The wave spectrum.
    rao
        The ship's response amplitude operators.
    heading
        Wave heading mu relative to the ship [rad] (pi = head seas, 0 = following seas,
        pi/2 = waves travelling towards port).
    speed
        Forward speed U [m/s] for the encounter frequency (and the RAO).
    components
        Number of harmonic components N.
    omega_min, omega_max
        Frequency band [rad/s]; None uses :data:`DEFAULT_BAND` times 2 pi / Tp.
    spacing
        ``"random"`` (frequency drawn within each bin) or ``"equal"`` (bin centres).
    seed
        Seed of the random phases and frequencies (reproducible).
    ramp
        Ramp-in time [s] of the response (C2 quintic step from t = 0); 0 for none.
    """

    def __init__(self, spectrum: Jonswap, rao: Rao, *, heading: float, speed: float = 0.0,
                 components: int = 200, omega_min: float | None = None,
                 omega_max: float | None = None, spacing: str = "random", seed: int = 0,
                 ramp: float = 20.0) -> None:
        if not (math.isfinite(speed) and speed >= 0.0):
            raise ValueError(f"speed must be finite and >= 0 m/s, got {speed}")
        if not (math.isfinite(ramp) and ramp >= 0.0):
            raise ValueError(f"ramp must be finite and >= 0 s, got {ramp}")
        if not math.isfinite(heading):
            raise ValueError(f"heading must be finite, got {heading}")
        peak = spectrum.peak_frequency
        self.spectrum = spectrum
        self.rao = rao
        self.heading = float(heading)
        self.speed = float(speed)
        self.ramp = float(ramp)
        self.seed = int(seed)
        self.spacing = spacing
        self.band = (DEFAULT_BAND[0] * peak if omega_min is None else float(omega_min),
                     DEFAULT_BAND[1] * peak if omega_max is None else float(omega_max))
        self.waves = discretise(spectrum, components=components, omega_min=self.band[0],
                                omega_max=self.band[1], spacing=spacing, seed=seed)
        omega = self.waves.omega
        #: Encounter frequencies [rad/s], shape (N,).
        self.encounter_frequency = omega - omega ** 2 * self.speed * math.cos(self.heading) / GRAVITY
        #: Complex response amplitudes a_i H_j(omega_i), shape (N, 6).
        self.response = self.waves.amplitude[:, None] * rao(omega, self.heading, self.speed)
        we = self.encounter_frequency
        # d^k/dt^k of exp(i omega_e t), k = 0, 1, 2, as factors of the phasor, shape (3, N)
        self._orders = np.stack([np.ones_like(we), 1j * we, -(we ** 2)]).astype(complex)

    def _phasors(self, times: np.ndarray) -> np.ndarray:
        return np.exp(1j * (np.outer(times, self.encounter_frequency) + self.waves.phase))

    def evaluate_many(self, t: ArrayLike) -> np.ndarray:
        times = as_times(t)
        we = self.encounter_frequency
        signal = np.empty((3, times.size, 6))
        for start in range(0, times.size, _CHUNK):
            part = slice(start, start + _CHUNK)
            e = self._phasors(times[part])
            signal[0, part] = _harmonic_sum(e, self.response)
            signal[1, part] = _harmonic_sum(e * (1j * we), self.response)
            signal[2, part] = _harmonic_sum(e * -(we ** 2), self.response)
        return modulate(ramp(times, self.ramp), signal).transpose(1, 0, 2)

    def evaluate(self, t: float) -> np.ndarray:
        """Ship state (3, 6) at one time [s]: the sums of :meth:`evaluate_many` without batching
        (one phasor per component, one product with the responses)."""
        t = float(t)
        if not math.isfinite(t):
            raise ValueError("times must be finite")
        e = np.exp(1j * (t * self.encounter_frequency + self.waves.phase))
        signal = _harmonic_sum(self._orders * e, self.response)
        if self.ramp > 0.0 and t < self.ramp:
            return modulate(ramp(np.array([t]), self.ramp), signal[:, None, :])[:, 0, :]
        return signal

    def wave_elevation(self, t: ArrayLike) -> np.ndarray:
        """Undisturbed wave elevation [m] at the ship's CG (moving with it), not ramped.

        Parameters
        ----------
        t
            Times [s], shape (n,).

        Returns
        -------
        ndarray, shape (n,)
        """
        times = as_times(t)
        out = np.empty(times.size)
        for start in range(0, times.size, _CHUNK):
            part = slice(start, start + _CHUNK)
            out[part] = _harmonic_sum(self._phasors(times[part]), self.waves.amplitude[:, None])[:, 0]
        return out

    def response_std(self) -> np.ndarray:
        """Standard deviations of the six DOFs after the ramp, sqrt(sum |a H|^2 / 2).

        Returns
        -------
        ndarray, shape (6,)
            [m] for x, y, z and [rad] for roll, pitch, yaw.
        """
        return np.sqrt(np.sum(np.abs(self.response) ** 2, axis=0) / 2.0)

    @property
    def description(self) -> str:
        s = self.spectrum
        return (f"irregular sea: JONSWAP Hs {s.hs:g} m, Tp {s.tp:g} s, gamma {s.gamma:g}; "
                f"heading {math.degrees(self.heading):g} deg (180 = head seas), "
                f"speed {self.speed:g} m/s; {self.waves.omega.size} components in "
                f"[{self.band[0]:.3g}, {self.band[1]:.3g}] rad/s ({self.spacing}, seed {self.seed}); "
                f"ramp {self.ramp:g} s; {self.rao.description}")
