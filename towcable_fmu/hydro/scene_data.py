"""A scene's water and lumped towed body as the data the kernels read (both cable
formulations build theirs here)."""

from __future__ import annotations

import numpy as np

from ..scene.model import Scene
from .towbody import BodyHydro, no_body
from .water import CURRENT_KINDS, WaterModel, dry_water
from .waves import A, K, crest_bound, scene_waves


def build_water(scene: Scene) -> WaterModel:
    """Water data for the kernels (no turbulence table yet: the simulation attaches it), with
    the waves of the motion's sea when ``waves = "motion"`` (:mod:`.waves`)."""
    w = scene.water
    if w is None:
        return dry_water()
    table, depth, stretch, ramp = scene_waves(scene)
    return WaterModel(True, w.density, w.viscosity, w.surface_z, scene.environment.gravity,
                      CURRENT_KINDS[w.current.type], np.array(w.current.velocity, dtype=float),
                      np.array(w.current.gradient, dtype=float), 0.0, 1.0, np.zeros((0, 3)), table, depth, stretch,
                      ramp, crest_bound(table), float(np.sum(np.abs(table[:, A]) * table[:, K])))


def build_body(scene: Scene, index: int) -> BodyHydro:
    """Towed-body data (disabled without a body or without water)."""
    body, w = scene.towbody, scene.water
    if body is None or w is None or body.model == "rigid":  # a rigid body has its own kernel
        return no_body()
    volume = scene.towbody_volume()
    cm = np.array(body.added_mass_coefficient, dtype=float)
    cda = np.zeros(3)
    for part in body.parts:
        cda += np.array(part.area) * np.array(part.drag_coefficient)
    lift_k, lift_dir, lift_axis = 0.0, np.zeros(3), np.array([1.0, 0.0, 0.0])
    if body.lift is not None:
        lift_k = 0.5 * w.density * body.lift.area * body.lift.coefficient
        lift_dir = np.array(body.lift.direction, dtype=float) / np.linalg.norm(body.lift.direction)
        lift_axis = np.array(body.lift.axis, dtype=float) / np.linalg.norm(body.lift.axis)
    return BodyHydro(True, index, volume, float(body.height), w.density * volume * cm, w.density * volume * (cm + 1.0), cda,
                     lift_k, lift_dir, lift_axis, np.zeros(1, dtype=np.int64))
