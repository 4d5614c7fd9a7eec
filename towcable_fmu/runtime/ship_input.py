"""The ship's motion as the cable models take it: the scene's motion source, and the check
of a ship state handed in from outside (an FMU input, a caller of ``step``)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..common.errors import SceneError
from ..scene.model import Scene

if TYPE_CHECKING:
    from ship_motion import MotionSource


def motion_source(scene: Scene) -> "MotionSource":
    """The scene's ``[motion]`` as a ship_motion source (a still ship without one)."""
    from ship_motion import StillShip, motion_from_config

    if scene.motion is None:
        return StillShip()
    base = Path(scene.base_dir) if scene.base_dir else None
    return motion_from_config(scene.motion, key="motion", base_dir=base)


def check_ship_state(ship: np.ndarray) -> None:
    """Raise a SceneError naming the entry unless ``ship`` is a finite (3, 6) array
    (value, rate, acceleration of x, y, z [m], roll, pitch, yaw [rad])."""
    if ship.shape != (3, 6):
        raise SceneError("ship", f"array of shape {ship.shape}", "an array of shape (3, 6)")
    if not np.isfinite(ship).all():
        bad = np.argwhere(~np.isfinite(ship))[0]
        raise SceneError(f"ship[{bad[0]}, {bad[1]}]", float(ship[bad[0], bad[1]]), "a finite number")
