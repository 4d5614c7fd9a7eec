"""Long-term rope damage of a sweep over a scatter diagram: the damage per year of each
case (``SIGNAL.damage``) weighted by the case's probability (``[sweep] probabilities``)."""

from __future__ import annotations

import math
from typing import Iterable

from .spec import SweepSpec
from .statistics import statistic


def long_term_damage(spec: SweepSpec, rows: Iterable[dict[str, str]]) -> dict[str, float]:
    """Probability-weighted sum of each damage statistic over the sweep's cases.

    Parameters
    ----------
    spec
        The sweep (with ``probabilities``).
    rows
        The results table's rows (:func:`~towcable_fmu.sweep.store.read_table`).

    Returns
    -------
    dict
        Damage statistic name -> sum over cases of probability times damage per year
        [1/year]; NaN when a case with a non-zero probability has no value (failed or not
        run yet).

    Raises
    ------
    ValueError
        The sweep gives no probabilities.
    """
    if spec.probabilities is None:
        raise ValueError("sweep.probabilities: absent; a long-term damage needs the probability of each case")
    by_id = {r["case_id"]: r for r in rows}
    names = [n for n in spec.statistics if statistic(n).needs_rope]
    out = {}
    for name in names:
        column = f"{name} [{spec.units[name]}]"
        total = 0.0
        for case, p in zip(spec.cases(), spec.probabilities):
            cell = by_id.get(case.case_id, {}).get(column, "")
            if p > 0.0 and cell == "":
                total = math.nan
                break
            total += p * float(cell) if p > 0.0 else 0.0
        out[name] = total
    return out
