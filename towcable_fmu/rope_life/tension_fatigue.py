"""Tension fatigue of a run: rainflow counting (ASTM E1049-85, rainflow counting of
section 5.4.4, by the ``rainflow`` package) and Palmgren-Miner damage on a T-N curve.

The ``rainflow`` package was chosen over ``fatpack`` by measurement (docs/design.md,
"Rope life"): it counts the exact ranges of the signal (fatpack first sorts the reversals
into k classes: 0.3 % of Miner sum off at its default k = 64) and counts the residue's
half cycles as ASTM E1049 does; it is one pure-Python module without dependencies.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .rope_data import TNCurve, cycles_to_failure

#: seconds in a year (365.25 days) [s]
YEAR = 365.25 * 24.0 * 3600.0


class Cycles(NamedTuple):
    """Rainflow cycles of a signal."""

    ranges: np.ndarray   #: peak-to-trough ranges [signal's unit]
    means: np.ndarray    #: mean of each cycle [signal's unit]
    counts: np.ndarray   #: 1.0 for a full cycle, 0.5 for a half cycle [-]


def rainflow_cycles(signal: np.ndarray) -> Cycles:
    """Rainflow cycles (ASTM E1049-85, 5.4.4) of a signal, residue as half cycles.

    Parameters
    ----------
    signal
        Samples of the load [any unit], in time order.

    Raises
    ------
    ImportError
        The ``rainflow`` package is missing (the message says how to install it).
    """
    try:
        import rainflow
    except ImportError as exc:  # a core dependency; a broken install says so plainly
        raise ImportError("rope life needs the 'rainflow' package: pip install rainflow") from exc
    rows = [(rng, mean, count) for rng, mean, count, _, _ in rainflow.extract_cycles(np.asarray(signal, dtype=float))]
    if not rows:
        empty = np.zeros(0)
        return Cycles(empty, empty, empty)
    ranges, means, counts = (np.array(c, dtype=float) for c in zip(*rows))
    return Cycles(ranges, means, counts)


def miner_damage(cycles: Cycles, breaking_strength: float, curve: TNCurve) -> float:
    """Palmgren-Miner damage sum of counted cycles, D = sum n_i / N(R_i).

    Parameters
    ----------
    cycles
        Tension cycles (ranges in N).
    breaking_strength
        Minimum breaking strength [N].
    curve
        The rope's T-N curve.

    Returns
    -------
    float
        Damage [-] (1: failure).
    """
    return float(np.sum(cycles.counts / cycles_to_failure(cycles.ranges, breaking_strength, curve)))


class TensionDamage(NamedTuple):
    """Miner damage of one tension signal over a run."""

    damage: float      #: over the run [-]
    duration: float    #: the run's duration [s]
    per_hour: float    #: damage per hour of the same sea [1/h]
    per_year: float    #: damage per year of the same sea, all year round [1/year]
    cycles: Cycles     #: the rainflow cycles [N]


def tension_damage(time: np.ndarray, tension: np.ndarray, breaking_strength: float, curve: TNCurve) -> TensionDamage:
    """Rainflow and Miner damage of a tension history, scaled to an hour and a year.

    Parameters
    ----------
    time
        Sample times [s], increasing.
    tension
        Tension [N] at those times.
    breaking_strength
        Minimum breaking strength [N].
    curve
        The rope's T-N curve.
    """
    time = np.asarray(time, dtype=float)
    duration = float(time[-1] - time[0]) if time.size > 1 else 0.0
    if not duration > 0.0:
        raise ValueError(f"a tension history needs a positive duration (got {duration} s)")
    cycles = rainflow_cycles(tension)
    damage = miner_damage(cycles, breaking_strength, curve)
    return TensionDamage(damage, duration, damage * 3600.0 / duration, damage * YEAR / duration, cycles)
