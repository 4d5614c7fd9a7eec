"""Directional spreading of a short-crested sea: the cos-2s distribution and its discretisation.

The energy of frequency omega travelling in direction theta is ``S(omega) D(theta)``
with (Longuet-Higgins et al. 1963; DNV-RP-C205 section 3.5.8.7)::

    D(theta) = Gamma(s + 1) / (2 sqrt(pi) Gamma(s + 1/2)) cos^(2s)((theta - theta_0) / 2),  |theta - theta_0| <= pi

which integrates to 1 over the circle; s is the spreading exponent (larger: narrower;
wind seas about 1 to 10, swell 15 to 75), theta_0 the mean direction. Its first circular
moment is ``int D cos(theta - theta_0) dtheta = s / (s + 1)``, so the circular spread
is ``sigma = sqrt(2 (1 - s / (s + 1))) = sqrt(2 / (s + 1))`` [rad].

Discretisation (:func:`discretise_directional`): the circle centred on theta_0 is cut
into M equal bins, each represented by its centre direction with the weight
``int_bin D dtheta``; each direction gets its own N frequency components of the
spectrum (amplitude ``sqrt(2 w_m int_bin S domega)``), with frequencies and phases
drawn independently for each direction (no two components share a frequency, so the
sea is ergodic).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .spectrum import Spectrum, WaveComponents, check_band

_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(24)


@dataclass(frozen=True)
class Cos2s:
    """The cos-2s spreading function (module docstring).

    Parameters
    ----------
    s
        Spreading exponent [-], > 0.
    """

    s: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.s) and self.s > 0.0):
            raise ValueError(f"spreading exponent s must be finite and > 0, got {self.s}")

    def density(self, relative: np.ndarray) -> np.ndarray:
        """D [1/rad] at directions ``relative`` [rad] from the mean, within [-pi, pi]."""
        norm = math.exp(math.lgamma(self.s + 1.0) - math.lgamma(self.s + 0.5)) / (2.0 * math.sqrt(math.pi))
        return norm * np.cos(0.5 * np.asarray(relative, dtype=float)) ** (2.0 * self.s)

    @property
    def circular_spread(self) -> float:
        """sqrt(2 / (s + 1)) [rad]."""
        return math.sqrt(2.0 / (self.s + 1.0))

    def bin_weights(self, directions: int) -> tuple[np.ndarray, np.ndarray]:
        """Centres [rad, relative to the mean] and weights [-] (summing to 1) of M equal bins."""
        if directions < 1:
            raise ValueError(f"directions must be >= 1, got {directions}")
        edges = np.linspace(-math.pi, math.pi, directions + 1)
        lo, hi = edges[:-1, None], edges[1:, None]
        theta = 0.5 * (lo + hi) + 0.5 * (hi - lo) * _GAUSS_NODES
        weights = 0.5 * (hi[:, 0] - lo[:, 0]) * (self.density(theta) @ _GAUSS_WEIGHTS)
        return 0.5 * (edges[:-1] + edges[1:]), weights / weights.sum()


def discretise_directional(spectrum: Spectrum, spreading: Cos2s, *, mean_heading: float, directions: int,
                           components: int, omega_min: float, omega_max: float, spacing: str = "random",
                           seed: int = 0) -> WaveComponents:
    """N x M wave components of a short-crested sea (module docstring).

    Parameters
    ----------
    spectrum
        The frequency spectrum.
    spreading
        The directional distribution.
    mean_heading
        Mean direction of travel theta_0 [rad] (relative to the ship).
    directions
        Number M of directions.
    components
        Number N of frequency components per direction.
    omega_min, omega_max
        Frequency band [rad/s], 0 < omega_min < omega_max.
    spacing
        ``"random"`` (uniform within each bin, drawn for each direction) or ``"equal"``.
    seed
        Seed of the phases (and frequencies).

    Returns
    -------
    WaveComponents
        Direction m's components are entries m N to (m + 1) N - 1; ``heading`` is set.
    """
    check_band(components, omega_min, omega_max, spacing)
    centres, weights = spreading.bin_weights(directions)
    edges = np.linspace(omega_min, omega_max, components + 1)
    rng = np.random.default_rng(seed)
    phase = rng.uniform(0.0, 2.0 * math.pi, (directions, components))
    offset = (rng.uniform(0.0, 1.0, (directions, components)) if spacing == "random"
              else np.full((directions, components), 0.5))
    omega = edges[:-1] + offset * np.diff(edges)
    energy = spectrum.band_energy(edges[:-1], edges[1:])
    amplitude = np.sqrt(2.0 * weights[:, None] * energy[None, :])
    heading = np.broadcast_to((mean_heading + centres)[:, None], omega.shape)
    return WaveComponents(omega=omega.ravel(), amplitude=amplitude.ravel(), phase=phase.ravel(),
                          heading=np.mod(heading, 2.0 * math.pi).ravel())
