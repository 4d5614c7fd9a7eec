"""Wave-induced ship motion in an irregular sea, long- or short-crested.

The spectrum (JONSWAP, Ochi-Hubble: :mod:`ship_motion.spectrum`) is cut into N harmonic
components, in a short-crested sea N for each of M directions of a cos-2s spreading
(:mod:`ship_motion.spreading`); each is passed through the ship's RAOs
(:mod:`ship_motion.rao`) at its own heading mu_i and its encounter frequency
``omega_e = omega - omega^2 U cos(mu_i) / g`` (speed U, 180 deg = head seas). DOF j is

    q_j(t) = f(t) * Re sum_i a_i H_j(omega_i) exp(i (omega_e,i t + eps_i))

with the C2 ramp factor f(t) of :mod:`ship_motion.ramp` (so the ship starts at rest)
and the derivatives of this product, exactly. The motion is about a frame that moves
with the ship at speed U on a constant heading: the mean of every DOF is zero.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from towcable_fmu.jit.kernel_cache import njit

from .base import MotionSource, as_times
from .ramp import modulate, ramp
from .rao import GRAVITY, Rao
from .spectrum import Spectrum, WaveComponents, discretise
from .spreading import Cos2s, discretise_directional

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


#: pi/2 in three parts (33, 33 and 53 significant bits): n * part is exact for |n| < 2^20
_PIO2 = (1.57079632673412561417e+00, 6.07710050630396597660e-11, 2.02226624879595063154e-21)
#: the reduction above is exact for arguments below this [rad] (larger ones: math.sin, math.cos)
_REDUCE_MAX = 1.0e5
#: Taylor-like minimax coefficients of sin(x)/x - 1 and cos(x) - 1 + x^2/2 on [-pi/4, pi/4] (fdlibm's)
_SIN = (-1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04,
        2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10)
_COS = (4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05,
        -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11)


@njit(cache=True, inline="always")
def _sincos(x: float) -> tuple:
    """(cos x, sin x) for |x| < _REDUCE_MAX, to about one unit in the last place: x reduced
    by the nearest multiple n of pi/2, polynomials on [-pi/4, pi/4], the quadrant n mod 4.
    Branch-free, so that a loop over many angles vectorises (libm's calls do not)."""
    n = np.floor(x * 0.63661977236758134308 + 0.5)
    r = ((x - n * _PIO2[0]) - n * _PIO2[1]) - n * _PIO2[2]
    z = r * r
    sin_r = r + r * z * (_SIN[0] + z * (_SIN[1] + z * (_SIN[2] + z * (_SIN[3] + z * (_SIN[4] + z * _SIN[5])))))
    cos_r = 1.0 - 0.5 * z + z * z * (_COS[0] + z * (_COS[1] + z * (_COS[2] + z * (_COS[3] + z * (_COS[4]
                                                                                          + z * _COS[5])))))
    q = np.int64(n) & 3  # quadrant: (cos, sin) = (c, s), (-s, c), (-c, -s), (s, -c)
    odd = (q & 1) == 1
    c = (sin_r if odd else cos_r) * float(1 - ((q + 1) & 2))
    s = (cos_r if odd else sin_r) * float(1 - (q & 2))
    return c, s


@njit(cache=True)
def harmonic_state(t: float, table: np.ndarray, dofs: np.ndarray, ramp_time: float) -> np.ndarray:
    """Ship state (3, 6) at one time: the ramped sum of harmonic components.

    ``q_j(t) = f(t) Re sum_i H_ij exp(i (omega_i t + eps_i))`` and its first two time
    derivatives for the columns ``dofs`` (the others are 0), with the ramp factor f of
    :func:`ship_motion.ramp.ramp` applied by the product rule
    (:func:`ship_motion.ramp.modulate`).

    Parameters
    ----------
    t
        Time [s].
    table
        Shape (2 + 2 len(dofs), N), one column per component: its encounter frequency
        omega_i [rad/s], its phase eps_i [rad], then the real and imaginary parts of its
        complex response H_ij [m, rad] for each column j of ``dofs``.
    dofs
        The columns of the state with a response (intp).
    ramp_time
        Ramp-in time [s] (0: none).
    """
    n = table.shape[1]
    cos_e, sin_e = np.empty(n), np.empty(n)
    largest = 0.0
    for i in range(n):
        largest = max(largest, abs(t * table[0, i] + table[1, i]))
    if largest < _REDUCE_MAX:
        for i in range(n):  # (vectorised: no call, no branch)
            cos_e[i], sin_e[i] = _sincos(t * table[0, i] + table[1, i])
    else:
        for i in range(n):
            arg = t * table[0, i] + table[1, i]
            cos_e[i], sin_e[i] = math.cos(arg), math.sin(arg)
    out = np.zeros((3, 6))
    for k in range(dofs.shape[0]):
        s0, s1, s2 = 0.0, 0.0, 0.0
        for i in range(n):
            w, h_re, h_im = table[0, i], table[2 + 2 * k, i], table[3 + 2 * k, i]
            re = cos_e[i] * h_re - sin_e[i] * h_im
            s0 += re
            s1 -= w * (cos_e[i] * h_im + sin_e[i] * h_re)
            s2 -= w * w * re
        j = dofs[k]
        out[0, j], out[1, j], out[2, j] = s0, s1, s2
    if ramp_time > 0.0 and t < ramp_time:
        x = min(max(t / ramp_time, 0.0), 1.0)
        f0 = x ** 3 * (10.0 - 15.0 * x + 6.0 * x * x)
        f1 = 30.0 * x * x * (1.0 - x) ** 2 / ramp_time
        f2 = 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x) / ramp_time ** 2
        for j in range(6):
            g0, g1, g2 = out[0, j], out[1, j], out[2, j]
            out[0, j] = f0 * g0
            out[1, j] = f1 * g0 + f0 * g1
            out[2, j] = f2 * g0 + 2.0 * f1 * g1 + f0 * g2
    return out


class IrregularSea(MotionSource):
    """Ship motion in an irregular sea (module docstring).

    Parameters
    ----------
    spectrum
        The wave spectrum.
    rao
        The ship's response amplitude operators.
    heading
        Wave heading mu relative to the ship [rad] (pi = head seas, 0 = following seas,
        pi/2 = waves travelling towards port); the mean heading of a short-crested sea.
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
    spreading
        Directional spreading of a short-crested sea; None: long-crested.
    directions
        Number M of directions of a short-crested sea (``components`` frequencies each).
    waves
        Wave components with their headings (from a directional spectrum file,
        :mod:`ship_motion.spectrum_file`); then ``spectrum`` only names the sea and
        ``components``, the band, ``spacing``, ``spreading`` and ``directions`` are not used.
    """

    def __init__(self, spectrum: Spectrum, rao: Rao, *, heading: float, speed: float = 0.0,
                 components: int = 200, omega_min: float | None = None,
                 omega_max: float | None = None, spacing: str = "random", seed: int = 0,
                 ramp: float = 20.0, spreading: Cos2s | None = None, directions: int = 1,
                 waves: WaveComponents | None = None) -> None:
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
        #: Frequency components (per direction).
        self.band_components = int(components)
        self.band = (DEFAULT_BAND[0] * peak if omega_min is None else float(omega_min),
                     DEFAULT_BAND[1] * peak if omega_max is None else float(omega_max))
        self.spreading = spreading
        if waves is not None:
            if waves.heading is None:
                raise ValueError("waves given to IrregularSea need their headings")
            self.waves, headings = waves, waves.heading
            self.band = (float(waves.omega.min()), float(waves.omega.max()))
            self.band_components = int(waves.omega.size)
        elif spreading is None:
            self.waves = discretise(spectrum, components=components, omega_min=self.band[0],
                                    omega_max=self.band[1], spacing=spacing, seed=seed)
            headings = np.full(self.waves.omega.size, self.heading)
        else:
            self.waves = discretise_directional(spectrum, spreading, mean_heading=self.heading,
                                                directions=directions, components=components,
                                                omega_min=self.band[0], omega_max=self.band[1],
                                                spacing=spacing, seed=seed)
            headings = self.waves.heading
        omega = self.waves.omega
        #: Encounter frequencies [rad/s], shape (N,).
        self.encounter_frequency = omega - omega ** 2 * self.speed * np.cos(headings) / GRAVITY
        #: Complex response amplitudes a_i H_j(omega_i, mu_i), shape (N, 6).
        self.response = np.zeros((omega.size, 6), dtype=complex)
        for mu in np.unique(headings):
            at = headings == mu
            self.response[at] = self.waves.amplitude[at, None] * rao(omega[at], float(mu), self.speed)
        # the table of harmonic_state: the columns with a response only (the closed-form RAO
        # has no surge, sway and yaw)
        self._dofs = np.flatnonzero(np.any(self.response != 0.0, axis=0)).astype(np.intp)
        parts = [self.encounter_frequency, self.waves.phase]
        for j in self._dofs:
            parts += [self.response[:, j].real, self.response[:, j].imag]
        self._table = np.ascontiguousarray(np.vstack(parts), dtype=np.float64)

    @property
    def harmonic_table(self) -> tuple[np.ndarray, np.ndarray, float]:
        """What :func:`harmonic_state` takes besides the time: the table, the columns with
        a response and the ramp time [s]."""
        return self._table, self._dofs, self.ramp

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
        """Ship state (3, 6) at one time [s]: the sums of :meth:`evaluate_many` in one compiled
        loop over the components (:func:`harmonic_state`)."""
        t = float(t)
        if not math.isfinite(t):
            raise ValueError("times must be finite")
        return harmonic_state(t, self._table, self._dofs, self.ramp)

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
        if self.waves.heading is None:
            sea = "long-crested"
        elif self.spreading is None:
            sea = "short-crested (the file's directions)"
        else:
            sea = (f"short-crested (cos-2s, s {self.spreading.s:g}, {self.waves.omega.size // self.band_components} "
                   "directions)")
        return (f"irregular sea: {self.spectrum.description}, {sea}; "
                f"heading {math.degrees(self.heading):g} deg (180 = head seas), "
                f"speed {self.speed:g} m/s; {self.band_components} components in "
                f"[{self.band[0]:.3g}, {self.band[1]:.3g}] rad/s ({self.spacing}, seed {self.seed}); "
                f"ramp {self.ramp:g} s; {self.rao.description}")
