"""Published tension-tension fatigue curves of steel wire rope.

API RP 2SK (3rd edition, 2005, section 6.5; the same curves are in ISO 19901-7) gives
the number of cycles to failure of a rope under a tension range as

    N R^M = K,    R = tension range / minimum breaking strength (MBS),

with, for wire rope, K depending on the mean tension through the 2nd edition's
(1996) fit K = 10^(a - b L_m), L_m the mean tension over the MBS; the 3rd edition
tabulates K at L_m = 0.3:

=====================  ======  ==============================  ==========
construction           M       K(L_m) (API RP 2SK 2nd ed.)     K (3rd ed.)
=====================  ======  ==============================  ==========
six- / multi-strand    4.09    10^(3.20 - 2.79 L_m)            231
spiral strand          5.05    10^(3.25 - 3.43 L_m)            166
=====================  ======  ==============================  ==========

API TR 2FC-2 (2020) advises against these curves for tension ranges above 0.5 MBS (fretting
shortens the life there); :func:`cycles_to_failure` uses them as published.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class TNCurve(NamedTuple):
    """A tension-tension fatigue curve N R^M = K."""

    M: float        #: slope [-]
    K: float        #: intercept [-] (cycles at R = 1)
    a: float        #: K = 10^(a - b L_m) as a function of the mean load ratio L_m [-]
    b: float        #: see ``a`` [-]
    source: str     #: where the numbers come from


#: The curves by ``cable.segments[].rope.construction``.
TN_CURVES: dict[str, TNCurve] = {
    "six_strand": TNCurve(4.09, 231.0, 3.20, 2.79, "API RP 2SK 3rd ed. (2005), six/multi-strand wire rope"),
    "spiral_strand": TNCurve(5.05, 166.0, 3.25, 3.43, "API RP 2SK 3rd ed. (2005), spiral strand wire rope"),
}


def tn_curve(construction: str) -> TNCurve:
    """The T-N curve of a rope construction.

    Raises
    ------
    ValueError
        An unknown construction (the message names the known ones).
    """
    try:
        return TN_CURVES[construction]
    except KeyError:
        raise ValueError(f"rope construction {construction!r} has no T-N curve: one of "
                         + ", ".join(repr(c) for c in TN_CURVES)) from None


def intercept_at_mean_load(curve: TNCurve, mean_ratio: float) -> float:
    """K of the 2nd edition's mean-load fit, 10^(a - b L_m).

    Parameters
    ----------
    curve
        The rope's curve.
    mean_ratio
        L_m, the mean tension over the minimum breaking strength [-].
    """
    return float(10.0 ** (curve.a - curve.b * mean_ratio))


def cycles_to_failure(tension_range: np.ndarray | float, breaking_strength: float, curve: TNCurve) -> np.ndarray:
    """Cycles to failure N = K R^-M of tension ranges.

    Parameters
    ----------
    tension_range
        Tension ranges (peak to trough) [N].
    breaking_strength
        Minimum breaking strength [N].
    curve
        The T-N curve.

    Returns
    -------
    numpy.ndarray
        N [-]; infinite for a zero range.
    """
    ratio = np.abs(np.asarray(tension_range, dtype=float)) / breaking_strength
    with np.errstate(divide="ignore"):
        return curve.K * ratio ** (-curve.M)


def bending_cycles_to_discard(tension: np.ndarray | float, cycles0: float, tension0: float,
                              exponent: float) -> np.ndarray:
    """Simple bending cycles to discard at a tension, N = N_0 (S_0 / S)^p.

    The endurance of a rope bent over a sheave falls with its tension as a power law
    locally (K. Feyrer, *Wire Ropes: Tension, Endurance, Reliability*, the collective
    method, eqs. 3.93-3.93b: the working cycles at two tensions are in the ratio of the
    tensions to the power p); N_0 at S_0 and p are the rope's (scene keys
    ``rope.bending_cycles``, ``bending_tension``, ``bending_exponent``).

    Parameters
    ----------
    tension
        Tension S at the bending [N].
    cycles0
        N_0, bending cycles to discard at S_0 [-].
    tension0
        S_0 [N].
    exponent
        p [-].

    Returns
    -------
    numpy.ndarray
        N [-]; infinite at zero tension (a slack rope is not counted as bent under load).
    """
    s = np.maximum(np.asarray(tension, dtype=float), 0.0)
    with np.errstate(divide="ignore"):
        return cycles0 * (tension0 / s) ** exponent
