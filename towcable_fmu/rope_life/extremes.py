"""The most probable maximum (MPM) of a tension in a storm of given duration.

Two methods, both stated in the report:

* **Gumbel fit of per-seed maxima** (several runs of the same sea with different seeds):
  the maxima of runs of duration T are fitted with a Gumbel distribution
  F(x) = exp(-exp(-(x - mu) / beta)) by maximum likelihood. The maximum over a storm of
  duration T_s, as that of T_s / T independent runs, is again Gumbel with the same beta
  and mu_s = mu + beta ln(T_s / T); its mode, the MPM, is mu_s.
* **Weibull fit of the peaks of one long run**: the peaks of x - mean (the largest value
  between two up-crossings of the mean) are fitted with a two-parameter Weibull
  distribution P(X > x) = exp(-(x / alpha)^gamma) by maximum likelihood; with n the
  number of peaks a storm of duration T_s has (the run's peak rate times T_s), the
  MPM is the value exceeded once in n peaks: mean + alpha (ln n)^(1 / gamma). For a
  narrow-band Gaussian process the peaks are Rayleigh (gamma = 2, alpha = sigma sqrt 2)
  and this is sigma sqrt(2 ln n).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy import stats

#: the storm duration of a most probable maximum unless given [s] (3 hours)
STORM = 3.0 * 3600.0


class Gumbel(NamedTuple):
    """A Gumbel (largest extreme value) distribution."""

    location: float  #: mu, the mode [unit of the data]
    scale: float     #: beta > 0 [unit of the data]


def fit_gumbel(maxima: np.ndarray) -> Gumbel:
    """Maximum-likelihood Gumbel fit of sample maxima.

    Parameters
    ----------
    maxima
        At least 3 maxima [any unit].

    Raises
    ------
    ValueError
        Fewer than 3 maxima, or non-finite values.
    """
    maxima = np.asarray(maxima, dtype=float)
    if maxima.size < 3 or not np.all(np.isfinite(maxima)):
        raise ValueError(f"a Gumbel fit needs at least 3 finite maxima (got {maxima.size}: {maxima.tolist()})")
    location, scale = stats.gumbel_r.fit(maxima)
    return Gumbel(float(location), float(scale))


def mpm_from_maxima(maxima: np.ndarray, run_duration: float, storm_duration: float) -> float:
    """Most probable maximum over a storm from the maxima of several runs (Gumbel fit).

    Parameters
    ----------
    maxima
        The maximum of each run [any unit].
    run_duration
        Duration T over which each maximum was taken [s].
    storm_duration
        Storm duration T_s [s].
    """
    fit = fit_gumbel(maxima)
    return fit.location + fit.scale * float(np.log(storm_duration / run_duration))


def peaks_above_mean(signal: np.ndarray) -> np.ndarray:
    """The largest excursion above the mean between consecutive up-crossings of the mean.

    Parameters
    ----------
    signal
        Equally spaced samples [any unit].

    Returns
    -------
    numpy.ndarray
        One peak (above the mean) per complete crossing period [unit of the signal].
    """
    x = np.asarray(signal, dtype=float) - float(np.mean(signal))
    up = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0)) + 1
    return np.array([x[a:b].max() for a, b in zip(up[:-1], up[1:])])


class PeakFit(NamedTuple):
    """A Weibull fit of the peaks of one run and the MPM it gives."""

    shape: float       #: gamma [-]
    scale: float       #: alpha [unit of the signal]
    peak_rate: float   #: peaks per second [1/s]
    mpm: float         #: most probable maximum in the storm [unit of the signal]


def mpm_from_peaks(time: np.ndarray, signal: np.ndarray, storm_duration: float) -> PeakFit:
    """Most probable maximum over a storm from one long run (Weibull fit of its peaks).

    Parameters
    ----------
    time
        Sample times [s], equally spaced.
    signal
        The samples [any unit].
    storm_duration
        Storm duration T_s [s].

    Raises
    ------
    ValueError
        Fewer than 10 peaks in the run, or peaks of one height (a periodic signal: no
        distribution to fit).
    """
    peaks = peaks_above_mean(signal)
    if peaks.size < 10:
        raise ValueError(f"a peak fit needs at least 10 mean up-crossing periods (the run has {peaks.size})")
    if np.ptp(peaks) <= 1e-9 * np.max(np.abs(peaks)):
        raise ValueError(f"the {peaks.size} peaks are all {peaks[0]:g} high: a periodic signal, no distribution to fit")
    shape, _, scale = stats.weibull_min.fit(peaks, floc=0.0)
    rate = peaks.size / float(time[-1] - time[0])
    n = rate * storm_duration
    mpm = float(np.mean(signal)) + scale * float(np.log(n)) ** (1.0 / shape)
    return PeakFit(float(shape), float(scale), rate, mpm)
