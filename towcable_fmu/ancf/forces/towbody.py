"""Force term: hydrodynamics of a lumped towed body on the cable's last node.

Drag, lift, Froude-Krylov and added-mass forces of :mod:`towcable_fmu.hydro.towbody`
at the last node (the body's mass is in the node's lumped mass).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...jit.kernel_cache import njit
from ...hydro import towbody as body_hydro
from ...hydro.scene_data import build_body
from ...hydro.towbody import BodyHydro
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from .hooks import TermHooks
from .term import add_block

NAME = "towbody"
#: The scene tables this term models (absent in a scene: the term is disabled).
TABLES = ("towbody", "towbody.lift")
Data = BodyHydro


def build(scene: Scene, mesh: Mesh, model: CableModel) -> BodyHydro:
    """The lumped body in water (disabled without a body, without water or for a rigid body)."""
    return build_body(scene, 6 * (mesh.n_nodes - 1))


@njit(cache=True, inline="always")
def residual(term: BodyHydro, model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
             out: np.ndarray) -> None:
    """Subtract the body's hydrodynamic force from the last node's rows (none while the
    model's water is disabled)."""
    if stop == model.el_len.shape[0] and model.water.enabled:
        body_hydro.add_residual(model.water, term, motion.q, motion.v, a, motion.t, out)


@njit(cache=True, inline="always")
def tangent(term: BodyHydro, model: CableModel, motion: Motion, ca: float, cv: float, cq: float,
            ab: np.ndarray) -> None:
    """The body's added mass and drag tangent over the last node's position."""
    if not model.water.enabled:
        return
    block = np.zeros((3, 3))
    if body_hydro.add_jacobian(model.water, term, motion.q, motion.v, motion.t, ca, cv, block):
        add_block(model, np.arange(term.index, term.index + 3), block, ab)



class Hooks(TermHooks):
    """The lumped body's outputs (in the compiled output kernel; also without water)."""

    OUTPUTS = ("tension.towbody", "towbody.x", "towbody.y", "towbody.z", "towbody.vx", "towbody.vy", "towbody.vz")

    def __init__(self, name: str, scene: Scene, sim: Any) -> None:
        super().__init__(name, scene, sim)
        if scene.towbody is not None and scene.towbody.model != "rigid":
            self.outputs = self.OUTPUTS
            self.output_scene = {"body_mass": float(scene.towbody.mass)}
