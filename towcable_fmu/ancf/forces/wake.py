"""Force term: the loads of the wake oscillators (vortex-induced vibration).

The wake oscillators run outside the compiled step (:mod:`towcable_fmu.ancf.viv_coupling`
advances them and writes their generalised load into ``load`` before every cable step);
in the step the load is a given external force.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ...common.errors import SceneError
from ...jit.kernel_cache import njit
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from .hooks import TermHooks

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



class Hooks(TermHooks):
    """The wake oscillators (:class:`~towcable_fmu.ancf.viv_coupling.WakeCoupling`) advanced
    around every solver step (the staggered coupling), their state saved and restored."""

    STAGGERED = True

    def __init__(self, name: str, scene: Scene, sim: Any) -> None:
        super().__init__(name, scene, sim)
        #: the wake oscillators of an enabled [viv] table (None: no vortex-induced vibration)
        self.coupling = None
        if scene.viv is not None and scene.viv.enabled:
            from ..viv_coupling import WakeCoupling

            self.coupling = WakeCoupling(scene.viv, sim._mesh, sim.model, scene.water.current.velocity,
                                         scene.water.density)
        self.STAGGERED = self.coupling is not None

    def reset(self) -> None:
        if self.coupling is not None:
            self.coupling.reset()

    def save(self) -> Any:
        return None if self.coupling is None else self.coupling.get_state()

    def restore(self, saved: Any) -> None:
        if self.coupling is not None and saved is not None:
            self.coupling.set_state(saved)

    def before_step(self, h: float) -> None:
        self.coupling.predict(self.sim.state.v, self.sim.state.a, h)

    def after_step(self, h: float) -> None:
        self.coupling.correct(self.sim.state.v, h)

    def remesh(self, key: str) -> None:
        if self.coupling is not None:
            raise SceneError(key, "a scene with wake oscillators", "a scene without them (viv): their states "
                             "belong to the elements")
