"""Where within a time step a tension-only element goes taut or slack.

A tension-only element (``compression = false``) carries no axial force at Gauss points
in compression; its force switches on when the first of its points goes taut (a slack
cable snapping taut, a dropped load caught) and off when the last goes slack. The
integrator lands its steps on these instants (:func:`crossing_fraction`), so the kink of
the material law falls at a step's end and not inside it, where the scheme would smear
it over the step.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from .axial import at_length, axial_strains, axial_work
from .model import CableModel


@njit(cache=True, inline="always")
def _largest_strain(model: CableModel, q: np.ndarray, e: int, work, eps: np.ndarray) -> float:
    """The largest Green strain over element e's Gauss points [-] (negative: the element is slack)."""
    at_length(work, model.el_len[e])
    axial_strains(q, 6 * e, model.el_len[e], work, model.gauss_dn, eps)
    return eps.max()


@njit(cache=True)
def crossing_fraction(model: CableModel, q0: np.ndarray, q1: np.ndarray, taut0: np.ndarray,
                      taut1: np.ndarray) -> float:
    """The earliest fraction of a step at which a tension-only element went taut or slack.

    Parameters
    ----------
    model
        The cable system.
    q0, q1
        Coordinates at the step's start and end [m, -].
    taut0, taut1
        Taut Gauss points of each element (bit masks, ``CableModel.el_taut``) at the start
        and the end.

    Returns
    -------
    float
        In [0, 1]: where the largest strain of an element that changed between slack (no
        point taut) and taut crosses zero, linearly interpolated between the step's ends;
        1.0 if no element changed.
    """
    first = 1.0
    work = axial_work(model.gauss_dn, model.gauss_w)
    eps = np.empty(model.gauss_w.shape[0])
    for e in range(taut0.shape[0]):
        if (taut0[e] == 0) == (taut1[e] == 0):
            continue
        f0 = _largest_strain(model, q0, e, work, eps)
        f1 = _largest_strain(model, q1, e, work, eps)
        if f0 != f1 and (f0 < 0.0) != (f1 < 0.0):
            first = min(first, max(f0 / (f0 - f1), 0.0))
    return first
