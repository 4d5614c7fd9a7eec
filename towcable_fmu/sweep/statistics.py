"""Per-case statistics of a sweep, computed on the recorded series after the settling time.

Every statistic is a function of the output series (contract names) on the window
``time >= settle``; a statistic whose signal the scene does not have is NaN (an empty
cell in the table).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable, Mapping

import numpy as np

from ..analysis.ellipsoid import enclosing_ellipsoid

Series = Mapping[str, np.ndarray]


@dataclasses.dataclass(frozen=True)
class Statistic:
    """One column of the results table.

    Attributes
    ----------
    unit
        Unit of the value.
    text
        What it is.
    signals
        Output names it needs.
    compute
        ``compute(series, window, fraction) -> float``; ``series`` restricted to the window
        is passed as the full arrays plus the Boolean mask.
    """

    unit: str
    text: str
    signals: tuple[str, ...]
    compute: Callable[[Series, np.ndarray, float], float]


def _reduce(signal: str, fn: Callable[[np.ndarray], float], text: str, unit: str = "N") -> Statistic:
    return Statistic(unit, text, (signal,), lambda s, w, f: float(fn(s[signal][w])))


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


#: Statistic name -> definition, in table order.
STATISTICS: dict[str, Statistic] = {
    "tension.sheave.max": _reduce("tension.sheave", np.max, "maximum tension leaving the sheave"),
    "tension.sheave.min": _reduce("tension.sheave", np.min, "minimum tension leaving the sheave"),
    "tension.sheave.mean": _reduce("tension.sheave", np.mean, "mean tension leaving the sheave"),
    "tension.sheave.std": _reduce("tension.sheave", np.std, "standard deviation of the tension leaving the sheave"),
    "tension.min.min": _reduce("tension.min", np.min, "lowest tension anywhere in the cable (<= 0: slack)"),
    "slack.time": Statistic("s", "time with a slack cable somewhere (tension.min <= 0)", ("tension.min",),
                            _time_where("tension.min", lambda v: v <= 0.0)),
    "contact.sheave_force.max": _reduce("contact.sheave_force", np.max, "peak sheave contact force"),
    "contact.sheave_force.mean": _reduce("contact.sheave_force", np.mean, "mean sheave contact force"),
    "contact.detached.time": Statistic("s", "time the cable is out of the sheave groove", ("contact.detached",),
                                       _time_where("contact.detached", lambda v: v != 0.0)),
    "contact.wrap_angle.mean": _reduce("contact.wrap_angle", np.mean, "mean wrap angle on the sheave", "rad"),
    "contact.wrap_angle.min": _reduce("contact.wrap_angle", np.min, "smallest wrap angle on the sheave", "rad"),
    "towbody.z.std": _reduce("towbody.z", np.std, "standard deviation of the towed-body depth", "m"),
    "ellipsoid.volume": Statistic("m3", "volume of the ellipsoid holding the given share (0.95) of the "
                                        "towed-body positions (Calnan's fit)",
                                  ("towbody.x", "towbody.y", "towbody.z"), _ellipsoid_volume),
}


def compute_statistics(series: Series, names: tuple[str, ...] | list[str], settle: float,
                       fraction: float = 0.95) -> dict[str, float]:
    """The named statistics of one case.

    Parameters
    ----------
    series
        Output name -> equally spaced samples, with ``time`` [s].
    names
        Statistic names (keys of :data:`STATISTICS`).
    settle
        Samples before this time [s] are left out.
    fraction
        Share of the towed-body positions inside the ellipsoid [-].

    Returns
    -------
    dict
        Name -> value in the statistic's unit; NaN when a needed signal is missing.
    """
    window = series["time"] >= settle - 1e-9 * max(1.0, settle)
    out: dict[str, float] = {}
    for name in names:
        stat = STATISTICS[name]
        if not np.any(window) or any(sig not in series for sig in stat.signals):
            out[name] = math.nan
        else:
            out[name] = stat.compute(series, window, fraction)
    return out
