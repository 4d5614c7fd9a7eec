"""Force term: the loads of the wake oscillators (vortex-induced vibration).

The wake oscillators run outside the compiled step (:mod:`towcable_fmu.ancf.viv_coupling`
advances them and writes their generalised load into ``load`` before every cable step);
in the step the load is a given external force.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...kernel_cache import njit
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion

NAME = "wake"
#: The scene tables this term models (absent in a scene: the term is disabled).
TABLES = ("viv",)


class Data(NamedTuple):
    """The wake load in force."""

    enabled: bool
    load: np.ndarray  #: (nf,) generalised wake load [N] (written by the coupling)


def build(scene: Scene, mesh: Mesh, model: CableModel) -> Data:
    """A zero load over all coordinates for an enabled ``[viv]`` table (disabled without one)."""
    enabled = scene.viv is not None and scene.viv.enabled
    return Data(enabled, np.zeros(model.f_const.shape[0] if enabled else 0))


@njit(cache=True, inline="always")
def residual(term: Data, model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
             out: np.ndarray) -> None:
    """Subtract the wake load (over every row, as the constant load)."""
    for i in range(out.shape[0]):
        out[i] -= term.load[i]


@njit(cache=True, inline="always")
def tangent(term: Data, model: CableModel, motion: Motion, ca: float, cv: float, cq: float,
            ab: np.ndarray) -> None:
    """None: the load is held constant over the step (the staggered coupling)."""

