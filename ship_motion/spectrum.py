"""Wave spectra (JONSWAP, Ochi-Hubble, Torsethaugen) and their discretisation into harmonic wave components.

Spectrum (DNV-RP-C205 section 3.5.5, omega in rad/s)::

    S(omega) = C(gamma) S_PM(omega) gamma ** exp(-(omega - omega_p)^2 / (2 sigma^2 omega_p^2))
    S_PM(omega) = 5/16 Hs^2 omega_p^4 omega^-5 exp(-5/4 (omega_p / omega)^4)

with omega_p = 2 pi / Tp, sigma = 0.07 for omega <= omega_p and 0.09 above. The
Pierson-Moskowitz part alone integrates to Hs^2 / 16. The normalising factor C(gamma)
is computed by numerical quadrature so that the zeroth moment is exactly Hs^2 / 16
(the common closed-form approximation 1 - 0.287 ln(gamma) is within 2 % of it
for gamma <= 7).

Ochi-Hubble two-peak spectrum (DNV-RP-C205 section 3.5.7; Ochi & Hubble 1976), the sum
of two generalised Pierson-Moskowitz spectra j = 1, 2 (wind sea, swell) of significant
heights H_j, peak frequencies omega_j = 2 pi / T_j and shape lambda_j::

    S_j(omega) = 1/4 ((4 lambda_j + 1) / 4 omega_j^4)^lambda_j / Gamma(lambda_j) H_j^2 omega^-(4 lambda_j + 1)
                 exp(-(4 lambda_j + 1) / 4 (omega_j / omega)^4)

each with zeroth moment H_j^2 / 16 (lambda = 1: Pierson-Moskowitz), so the sea's
Hs = sqrt(H_1^2 + H_2^2).

Torsethaugen two-peak spectrum (wind sea + swell fitted to Northern North Sea data), the
simplified 2004 version: Torsethaugen & Haver (2004), "Simplified double peak spectral model
for ocean waves", ISOPE, as given in DNV-RP-C205 (2010) section 3.5.7 (two-peak spectra) and its
Appendix A (section 3.5.6 of that edition is the TMA spectrum; not the 1996 SINTEF
model of MSS's torsetSpectrum.m, whose tail exponent 0.5 Hs^(1/2) + 3.2 and gamma factor
1 + 3.5 exp(-Hs) depend on Hs). From Hs [m] and the
primary peak period Tp [s], with the fully developed peak period Tpf = 6.6 Hs^(1/3) [s]
(Hs in m), T_l = 2 Hs^(1/2) [s] and T_u = 25 s:

- wind-dominated sea, Tp <= Tpf: epsilon_l = (Tpf - Tp) / (Tpf - T_l),
  R_w = 0.7 + 0.3 exp(-(epsilon_l / 0.5)^2); primary (wind sea) H_1 = R_w Hs at Tp with
  gamma = 35 (2 pi H_1 / (g Tp^2))^0.857; secondary (swell) H_2 = sqrt(1 - R_w^2) Hs at
  T_p2 = Tpf + 2 s with gamma = 1;
- swell-dominated sea, Tp > Tpf: epsilon_u = (Tp - Tpf) / (T_u - Tpf),
  R_s = 0.6 + 0.4 exp(-(epsilon_u / 0.3)^2); primary (swell) H_1 = R_s Hs at Tp with
  gamma = 35 (2 pi Hs / (g Tpf^2))^0.857 (1 + 6 epsilon_u) (the whole sea's Hs at Tpf, as in
  Torsethaugen & Haver 2004 and DNV-RP-C205, not the primary height H_1 that some
  implementations use); secondary (wind sea) H_2 = sqrt(1 - R_s^2) Hs at
  T_p2 = 6.6 H_2^(1/3) with gamma = 1.

Each peak j has the normalised shape of N = M = 4 (the 2004 simplification: an omega^-4 tail)::

    S_j(omega) = H_j^2 / 16 * T_pj / (2 pi) * G_0 A_gamma x^-4 exp(-x^-4) gamma^exp(-(x - 1)^2 / (2 sigma^2)),
    x = omega T_pj / (2 pi)

with sigma = 0.07 (x <= 1) or 0.09 and G_0 = 4 / Gamma(3/4) = 3.26; so each part's zeroth
moment is H_j^2 / 16 and the sea's is Hs^2 / 16 (H_1^2 + H_2^2 = Hs^2), and each part peaks at
its own T_pj. The source's A_gamma = (1 + 1.1 (ln gamma)^1.19) / gamma is a fit to the exact
normalisation; as for JONSWAP it is replaced here by the exact value (quadrature), which it
matches within 3.5 % for 1 <= gamma <= 40 (1.7 % in Hs). gamma is kept >= 1 (the steepness law
gives less than 1 near Tpf for Hs below ~2 m, where A_gamma is undefined). The model's range is
T_l <= Tp <= T_u (epsilon_l, epsilon_u in [0, 1]). At Tp = Tpf both branches give R = 1: a
single peak of Hs at Tpf with gamma = 35 (2 pi Hs / (g Tpf^2))^0.857.

Discretisation: [omega_min, omega_max] is cut into N bins of equal width. Each
component takes the energy of its bin, amplitude ``a_i = sqrt(2 int_bin S domega)``
(Gauss-Legendre quadrature per bin), so the variance of the sum is exactly the
spectrum's energy in the band; its frequency is either the bin centre (``"equal"``)
or drawn uniformly within the bin (``"random"``, the default, which avoids the
repetition period 2 pi / d_omega of equal spacing). Phases are uniform in [0, 2 pi).
Both come from ``numpy.random.default_rng(seed)``: the phases are drawn first, then
the frequency offsets, so a seed gives the same phases in both spacings.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import quad

from .rao import GRAVITY

#: Values of ``[motion] spectrum``.
SPECTRA: tuple[str, ...] = ("jonswap", "ochi_hubble", "torsethaugen", "file")

#: Torsethaugen's period constants: T_pf = 6.6 Hs^(1/3) [s], T_l = 2 Hs^(1/2) [s], T_u = 25 [s].
TORSETHAUGEN_FULLY_DEVELOPED = 6.6
TORSETHAUGEN_LOWER = 2.0
TORSETHAUGEN_UPPER = 25.0

#: Ways of placing component frequencies within their bins.
SPACINGS: tuple[str, ...] = ("random", "equal")

_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(16)


def _shape(x: np.ndarray, gamma: float, tail: int = 5) -> np.ndarray:
    """Unnormalised peak-enhanced shape ``x^-n exp(-n/4 x^-4) gamma^r`` in x = omega / omega_p, n = ``tail``
    (5: JONSWAP, 4: Torsethaugen); it peaks at x = 1 for gamma = 1."""
    x = np.asarray(x, dtype=float)
    safe = np.where(x > 0.05, x, 1.0)  # below 0.05 omega_p the spectrum is exp(-1.6e5) = 0
    sigma = np.where(safe <= 1.0, 0.07, 0.09)
    peak = gamma ** np.exp(-((safe - 1.0) ** 2) / (2.0 * sigma ** 2))
    value = safe ** -tail * np.exp(-0.25 * tail * safe ** -4) * peak
    return np.where(x > 0.05, value, 0.0)


@lru_cache(maxsize=64)
def normalisation(gamma: float, tail: int = 5) -> float:
    """Factor [-] that makes the zeroth moment of ``Hs^2 / omega_p * factor * _shape`` Hs^2 / 16 (JONSWAP:
    C(gamma) times 5/16)."""
    integral = sum(quad(lambda x: float(_shape(x, gamma, tail)), a, b, limit=200)[0]
                   for a, b in ((0.0, 0.9), (0.9, 1.1), (1.1, 3.0), (3.0, np.inf)))
    return 1.0 / (16.0 * integral)


def _peak_density(omega: ArrayLike, hs: float, tp: float, gamma: float, tail: int = 5) -> np.ndarray:
    """S(omega) [m^2 s/rad] of one normalised peak of height ``hs`` [m] and period ``tp`` [s] (``_shape``)."""
    wp = 2.0 * math.pi / tp
    x = np.asarray(omega, dtype=float) / wp
    return hs ** 2 / wp * normalisation(gamma, tail) * _shape(x, gamma, tail)


class Spectrum:
    """A wave spectrum: :meth:`density` S(omega) [m^2 s/rad], :attr:`peak_frequency` [rad/s]."""

    def density(self, omega: ArrayLike) -> np.ndarray:
        """Spectral density S(omega) [m^2 s/rad] at wave frequencies ``omega`` [rad/s]."""
        raise NotImplementedError

    @property
    def peak_frequency(self) -> float:
        """The frequency [rad/s] the default wave band is scaled by."""
        raise NotImplementedError

    def band_energy(self, lower: ArrayLike, upper: ArrayLike) -> np.ndarray:
        """Integral of S over each [lower, upper] [m^2] (16-point Gauss-Legendre)."""
        lo = np.asarray(lower, dtype=float)[..., None]
        hi = np.asarray(upper, dtype=float)[..., None]
        omega = 0.5 * (lo + hi) + 0.5 * (hi - lo) * _GAUSS_NODES
        return 0.5 * (hi[..., 0] - lo[..., 0]) * (self.density(omega) @ _GAUSS_WEIGHTS)


@dataclass(frozen=True)
class Jonswap(Spectrum):
    """JONSWAP spectrum (module docstring).

    Parameters
    ----------
    hs
        Significant wave height [m], >= 0.
    tp
        Peak period [s], > 0.
    gamma
        Peak enhancement factor [-], >= 1 (1 gives Pierson-Moskowitz).
    """

    hs: float
    tp: float
    gamma: float = 3.3

    def __post_init__(self) -> None:
        if not (math.isfinite(self.hs) and self.hs >= 0.0):
            raise ValueError(f"hs must be finite and >= 0 m, got {self.hs}")
        if not (math.isfinite(self.tp) and self.tp > 0.0):
            raise ValueError(f"tp must be finite and > 0 s, got {self.tp}")
        if not (math.isfinite(self.gamma) and self.gamma >= 1.0):
            raise ValueError(f"gamma must be finite and >= 1, got {self.gamma}")

    @property
    def peak_frequency(self) -> float:
        """omega_p = 2 pi / Tp [rad/s]."""
        return 2.0 * math.pi / self.tp

    def density(self, omega: ArrayLike) -> np.ndarray:
        """Spectral density S(omega) [m^2 s/rad] at wave frequencies ``omega`` [rad/s]."""
        return _peak_density(omega, self.hs, self.tp, self.gamma)

    @property
    def description(self) -> str:
        """One line naming the spectrum and its parameters."""
        return f"JONSWAP Hs {self.hs:g} m, Tp {self.tp:g} s, gamma {self.gamma:g}"


@dataclass(frozen=True)
class OchiHubble(Spectrum):
    """Ochi-Hubble two-peak spectrum (module docstring).

    Parameters
    ----------
    hs, tp, shape
        Significant height [m] (>= 0), peak period [s] (> 0) and shape lambda [-] (> 0) of the
        first part (the wind sea).
    swell_hs, swell_tp, swell_shape
        The same of the second part (the swell).
    """

    hs: float
    tp: float
    shape: float
    swell_hs: float
    swell_tp: float
    swell_shape: float

    def __post_init__(self) -> None:
        for name, low in (("hs", -1.0), ("tp", 0.0), ("shape", 0.0), ("swell_hs", -1.0), ("swell_tp", 0.0),
                          ("swell_shape", 0.0)):
            value = getattr(self, name)
            if not (math.isfinite(value) and (value >= 0.0 if low < 0.0 else value > 0.0)):
                raise ValueError(f"{name} must be finite and {'>= 0' if low < 0.0 else '> 0'}, got {value}")

    @property
    def peak_frequency(self) -> float:
        """The lower of the two peak frequencies [rad/s]."""
        return 2.0 * math.pi / max(self.tp, self.swell_tp)

    @property
    def significant_height(self) -> float:
        """Hs = sqrt(H_1^2 + H_2^2) [m]."""
        return math.hypot(self.hs, self.swell_hs)

    def density(self, omega: ArrayLike) -> np.ndarray:
        w = np.asarray(omega, dtype=float)
        safe = np.where(w > 0.0, w, 1.0)
        total = np.zeros_like(safe)
        for h, tp, lam in ((self.hs, self.tp, self.shape), (self.swell_hs, self.swell_tp, self.swell_shape)):
            c = (4.0 * lam + 1.0) / 4.0
            x = 2.0 * math.pi / tp / safe
            # the power law and exponential in logarithms: no overflow at small omega
            log_part = lam * math.log(c) - math.lgamma(lam) + (4.0 * lam + 1.0) * np.log(x) - c * x ** 4
            total += 0.25 * h * h * (tp / (2.0 * math.pi)) * np.exp(log_part)
        return np.where(w > 0.0, total, 0.0)

    @property
    def description(self) -> str:
        """One line naming the spectrum and its parameters."""
        return (f"Ochi-Hubble wind sea Hs {self.hs:g} m, Tp {self.tp:g} s, lambda {self.shape:g}; swell Hs "
                f"{self.swell_hs:g} m, Tp {self.swell_tp:g} s, lambda {self.swell_shape:g}")


@dataclass(frozen=True)
class Torsethaugen(Spectrum):
    """Torsethaugen two-peak spectrum, the simplified 2004 version (module docstring).

    Parameters
    ----------
    hs
        Significant wave height [m] of the whole sea, > 0.
    tp
        Primary peak period [s], in the model's range [2 sqrt(hs), 25] s.
    """

    hs: float
    tp: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.hs) and self.hs > 0.0):
            raise ValueError(f"hs must be finite and > 0 m, got {self.hs}")
        lower, upper = self.period_range(self.hs)
        if not (math.isfinite(self.tp) and lower <= self.tp <= upper):
            raise ValueError(f"tp must lie in [{lower:.4g}, {upper:g}] s (2 sqrt(hs) to 25 s), got {self.tp}")

    @staticmethod
    def period_range(hs: float) -> tuple[float, float]:
        """The model's range of primary peak periods [s], (T_l, T_u) = (2 sqrt(hs), 25) for hs [m]."""
        return TORSETHAUGEN_LOWER * math.sqrt(hs), TORSETHAUGEN_UPPER

    @property
    def fully_developed_period(self) -> float:
        """T_pf = 6.6 Hs^(1/3) [s], the peak period of a fully developed sea."""
        return TORSETHAUGEN_FULLY_DEVELOPED * self.hs ** (1.0 / 3.0)

    @property
    def wind_dominated(self) -> bool:
        """True when Tp <= T_pf: the primary peak is the wind sea."""
        return self.tp <= self.fully_developed_period

    @property
    def parts(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """(height [m], peak period [s], gamma [-]) of the primary and the secondary peak."""
        hs, tp, tpf = self.hs, self.tp, self.fully_developed_period
        if self.wind_dominated:
            eps = (tpf - tp) / (tpf - self.period_range(hs)[0])
            ratio = 0.3 * math.exp(-((eps / 0.5) ** 2)) + 0.7
            h1 = ratio * hs
            h2 = math.sqrt(1.0 - ratio ** 2) * hs
            return (h1, tp, max(1.0, _steepness_gamma(h1, tp))), (h2, tpf + 2.0, 1.0)
        eps = (tp - tpf) / (TORSETHAUGEN_UPPER - tpf)
        ratio = 0.4 * math.exp(-((eps / 0.3) ** 2)) + 0.6
        h1 = ratio * hs
        h2 = math.sqrt(1.0 - ratio ** 2) * hs
        gamma = max(1.0, _steepness_gamma(hs, tpf) * (1.0 + 6.0 * eps))
        return (h1, tp, gamma), (h2, TORSETHAUGEN_FULLY_DEVELOPED * h2 ** (1.0 / 3.0), 1.0)

    @property
    def peak_periods(self) -> tuple[float, ...]:
        """The peak periods [s] of the parts that carry energy (one at Tp = Tpf)."""
        return tuple(tp for h, tp, _ in self.parts if h > 0.0)

    @property
    def peak_frequency(self) -> float:
        """The lower of the two peak frequencies [rad/s]."""
        return 2.0 * math.pi / max(self.peak_periods)

    def density(self, omega: ArrayLike) -> np.ndarray:
        """Spectral density S(omega) [m^2 s/rad] at wave frequencies ``omega`` [rad/s]."""
        total = np.zeros(np.shape(omega))
        for h, tp, gamma in self.parts:
            if h > 0.0:
                total = total + _peak_density(omega, h, tp, gamma, tail=4)
        return total

    @property
    def description(self) -> str:
        """One line naming the spectrum and its parameters."""
        (h1, _, gamma), (h2, tp2, _) = self.parts
        kind = "wind-dominated" if self.wind_dominated else "swell-dominated"
        return (f"Torsethaugen Hs {self.hs:g} m, Tp {self.tp:g} s ({kind}: primary Hs {h1:.3g} m, gamma "
                f"{gamma:.3g}; secondary Hs {h2:.3g} m, Tp {tp2:.3g} s)")


def _steepness_gamma(height: float, period: float) -> float:
    """Torsethaugen's peak enhancement law 35 (2 pi H / (g T^2))^0.857 [-] of a height [m] and a period [s]."""
    return 35.0 * (2.0 * math.pi * height / (GRAVITY * period ** 2)) ** 0.857


@dataclass(frozen=True)
class WaveComponents:
    """Harmonic components of an irregular sea.

    The elevation is ``eta(t) = sum_i amplitude_i cos(omega_i t + phase_i)`` (at a point
    fixed in space, the reference point of the phases).

    Parameters
    ----------
    omega
        Wave frequencies [rad/s], shape (N,).
    amplitude
        Amplitudes [m], shape (N,).
    phase
        Phases [rad], shape (N,).
    heading
        Direction of travel of each component [rad] relative to the ship, shape (N,);
        None: a long-crested sea (all travel in the sea's heading).
    """

    omega: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    heading: np.ndarray | None = None

    @property
    def variance(self) -> float:
        """Variance of the elevation, sum a_i^2 / 2 [m^2]."""
        return float(np.sum(self.amplitude ** 2) / 2.0)


def check_band(components: int, omega_min: float, omega_max: float, spacing: str) -> None:
    """Raise ValueError unless components >= 1, 0 < omega_min < omega_max [rad/s] and spacing is one of
    :data:`SPACINGS`."""
    if components < 1:
        raise ValueError(f"components must be >= 1, got {components}")
    if not 0.0 < omega_min < omega_max:
        raise ValueError(f"need 0 < omega_min < omega_max, got {omega_min}, {omega_max}")
    if spacing not in SPACINGS:
        raise ValueError(f"spacing must be one of {SPACINGS}, got {spacing!r}")


def discretise(spectrum: Spectrum, *, components: int, omega_min: float, omega_max: float,
               spacing: str = "random", seed: int = 0) -> WaveComponents:
    """Cut the spectrum into harmonic components (module docstring).

    Parameters
    ----------
    spectrum
        The wave spectrum.
    components
        Number N of components (bins), >= 1.
    omega_min, omega_max
        Frequency band [rad/s], 0 < omega_min < omega_max.
    spacing
        ``"random"`` (uniform within each bin) or ``"equal"`` (bin centres).
    seed
        Seed of the random phases (and frequencies).

    Returns
    -------
    WaveComponents
    """
    check_band(components, omega_min, omega_max, spacing)
    edges = np.linspace(omega_min, omega_max, components + 1)
    rng = np.random.default_rng(seed)
    phase = rng.uniform(0.0, 2.0 * math.pi, components)
    offset = rng.uniform(0.0, 1.0, components) if spacing == "random" else np.full(components, 0.5)
    omega = edges[:-1] + offset * np.diff(edges)
    amplitude = np.sqrt(2.0 * spectrum.band_energy(edges[:-1], edges[1:]))
    return WaveComponents(omega=omega, amplitude=amplitude, phase=phase)
