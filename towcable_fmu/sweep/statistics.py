"""Per-case statistics of a sweep, computed on the recorded series after the settling time.

Every statistic is a function of the output series (contract names) on the window
``time >= settle``: a reduction of any one signal (``tension.top.max``,
``tension.towbody.p99``, see :func:`statistic`) or one of the :data:`DERIVED` ones
(``slack.time``, ``ellipsoid.volume``, ...). The sweep's spec refuses a statistic whose
signal the scene does not have; here such a statistic is NaN (an empty cell in the table).
"""

from __future__ import annotations

import dataclasses
import math
import re
from typing import Callable, Mapping

import numpy as np

from ..analysis.ellipsoid import enclosing_ellipsoid
from ..rope_life.extremes import STORM, mpm_from_peaks
from ..rope_life.rope_data import tn_curve
from ..rope_life.tension_fatigue import tension_damage

Series = Mapping[str, np.ndarray]


@dataclasses.dataclass(frozen=True)
class Statistic:
    """One column of the results table.

    Attributes
    ----------
    text
        What it is.
    signals
        Output names it needs.
    compute
        ``compute(series, window, fraction) -> float``; ``series`` restricted to the window
        is passed as the full arrays plus the Boolean mask. A statistic of the rope's life
        (``needs_rope``) is called as ``compute(series, window, fraction, rope)``.
    unit
        Unit of the value; None: the unit of its one signal.
    needs_rope
        It needs the case's rope data (:class:`~towcable_fmu.scene.model.Rope`).
    """

    text: str
    signals: tuple[str, ...]
    compute: Callable[..., float]
    unit: str | None = None
    needs_rope: bool = False


#: Reductions of one signal over the window: ``SIGNAL.<name>``; ``SIGNAL.pNN`` (NN in
#: [0, 100], decimals allowed: ``p99``, ``p99.9``) is the NN-th percentile.
REDUCTIONS: dict[str, tuple[Callable[[np.ndarray], float], str]] = {
    "max": (np.max, "maximum"),
    "min": (np.min, "minimum"),
    "mean": (np.mean, "mean"),
    "std": (np.std, "standard deviation"),
}
_REDUCTION_OF_SIGNAL = re.compile(r"(?P<signal>.+)\.(?:(?P<reduction>max|min|mean|std)|p(?P<percent>\d{1,3}(?:\.\d+)?))")
#: Rope-life statistics of a tension signal (towcable_fmu/rope_life/): ``SIGNAL.damage``, the
#: Miner damage per year of the case's sea all year round [1/year] (rainflow, the rope's T-N
#: curve), and ``SIGNAL.mpm``, its most probable maximum in a 3-hour storm (Weibull fit of
#: the peaks) [unit of the signal].
_ROPE_LIFE_OF_SIGNAL = re.compile(r"(?P<signal>.+)\.(?P<kind>damage|mpm)")


def _damage_per_year(signal: str) -> Callable[..., float]:
    def compute(s: Series, w: np.ndarray, fraction: float, rope) -> float:
        curve = tn_curve(rope.construction)
        return tension_damage(s["time"][w], s[signal][w], rope.breaking_strength, curve).per_year

    return compute


def _mpm(signal: str) -> Callable[..., float]:
    def compute(s: Series, w: np.ndarray, fraction: float) -> float:
        try:
            return mpm_from_peaks(s["time"][w], s[signal][w], STORM).mpm
        except ValueError:  # too few or equal peaks: no distribution to fit
            return math.nan

    return compute


def _time_where(signal: str, predicate: Callable[[np.ndarray], np.ndarray]) -> Callable[[Series, np.ndarray, float], float]:
    """Time [s] during which ``predicate(signal)`` holds: each sample counts for the
    recording interval (samples are equally spaced)."""
    def compute(s: Series, w: np.ndarray, fraction: float) -> float:
        t = s["time"]
        dt = float(t[1] - t[0]) if t.size > 1 else 0.0
        return float(np.count_nonzero(predicate(s[signal][w]))) * dt

    return compute


def _ellipsoid_volume(s: Series, w: np.ndarray, fraction: float) -> float:
    points = np.column_stack([s[f"towbody.{c}"][w] for c in "xyz"])
    return enclosing_ellipsoid(points, fraction).volume


#: Statistics that are not one reduction of one signal, by name.
DERIVED: dict[str, Statistic] = {
    "slack.time": Statistic("time with a slack cable somewhere (tension.min <= 0)", ("tension.min",),
                            _time_where("tension.min", lambda v: v <= 0.0), "s"),
    "contact.detached.time": Statistic("time the cable is out of the sheave groove", ("contact.detached",),
                                       _time_where("contact.detached", lambda v: v != 0.0), "s"),
    "ellipsoid.volume": Statistic("volume of the ellipsoid holding the given share (0.95) of the towed-body "
                                  "positions (Calnan's fit)", ("towbody.x", "towbody.y", "towbody.z"),
                                  _ellipsoid_volume, "m3"),
}


def statistic(name: str) -> Statistic:
    """The statistic of a name: one of :data:`DERIVED`, or ``SIGNAL.REDUCTION`` with a
    reduction of :data:`REDUCTIONS` or a percentile ``pNN``.

    Raises
    ------
    ValueError
        The name is neither (the message says what is allowed).
    """
    if name in DERIVED:
        return DERIVED[name]
    match = _REDUCTION_OF_SIGNAL.fullmatch(name)
    if match and match["reduction"]:
        signal = match["signal"]
        fn, text = REDUCTIONS[match["reduction"]]
        return Statistic(f"{text} of {signal}", (signal,), lambda s, w, f: float(fn(s[signal][w])))
    if match and float(match["percent"]) <= 100.0:
        signal, q = match["signal"], float(match["percent"])
        return Statistic(f"{q:g}th percentile of {signal}", (signal,),
                         lambda s, w, f: float(np.percentile(s[signal][w], q)))
    rope_life = _ROPE_LIFE_OF_SIGNAL.fullmatch(name)
    if rope_life and rope_life["kind"] == "damage":
        signal = rope_life["signal"]
        return Statistic(f"Miner damage per year of {signal} (rainflow, the rope's T-N curve)", (signal,),
                         _damage_per_year(signal), "1/year", needs_rope=True)
    if rope_life:
        signal = rope_life["signal"]
        return Statistic(f"most probable maximum of {signal} in a {STORM / 3600:g} h storm (Weibull fit of its "
                         "peaks)", (signal,), _mpm(signal))
    raise ValueError(f"'{name}' is not a statistic: SIGNAL." + ", SIGNAL.".join(REDUCTIONS)
                     + ", SIGNAL.pNN (a percentile, NN in [0, 100]), SIGNAL.damage, SIGNAL.mpm, or one of "
                     + ", ".join(DERIVED))


#: The statistics of a sweep that names none (those the scene has signals for), in table order.
DEFAULT_STATISTICS = ("tension.sheave.max", "tension.sheave.min", "tension.sheave.mean", "tension.sheave.std",
                      "tension.min.min", "slack.time", "contact.sheave_force.max", "contact.sheave_force.mean",
                      "contact.detached.time", "contact.wrap_angle.mean", "contact.wrap_angle.min", "towbody.z.std",
                      "ellipsoid.volume")

#: Name -> definition of the default statistics.
STATISTICS: dict[str, Statistic] = {name: statistic(name) for name in DEFAULT_STATISTICS}


def compute_statistics(series: Series, names: tuple[str, ...] | list[str], settle: float,
                       fraction: float = 0.95, rope=None) -> dict[str, float]:
    """The named statistics of one case.

    Parameters
    ----------
    series
        Output name -> equally spaced samples, with ``time`` [s].
    names
        Statistic names (see :func:`statistic`).
    settle
        Samples before this time [s] are left out.
    fraction
        Share of the towed-body positions inside the ellipsoid [-].
    rope
        The case's rope data (:class:`~towcable_fmu.scene.model.Rope`), for the statistics
        that need it (None: they are NaN).

    Returns
    -------
    dict
        Name -> value in the statistic's unit; NaN when a needed signal (or the rope) is missing.
    """
    window = series["time"] >= settle - 1e-9 * max(1.0, settle)
    out: dict[str, float] = {}
    for name in names:
        stat = statistic(name)
        if not np.any(window) or any(sig not in series for sig in stat.signals) or (stat.needs_rope and rope is None):
            out[name] = math.nan
        elif stat.needs_rope:
            out[name] = stat.compute(series, window, fraction, rope)
        else:
            out[name] = stat.compute(series, window, fraction)
    return out
