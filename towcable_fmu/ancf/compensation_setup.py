"""A scene's heave-compensation settings: its ``[compensation]`` table over the defaults the
scene's geometry gives, and the set-point algorithm's configuration from them.

The defaults: the winch radius to the cable centreline (r_w + d/2), the winch's phi_nom, the
reference point (the sheave centre, or the top of the drum without a sheave) and the
waterline. ``theta_nom`` is the caller's (the model's own steady departure angle) unless
the table gives it.
"""

from __future__ import annotations

from typing import Any, Mapping

from .mesh import winch_radius
from ..scene.model import Scene


def compensation_table(scene: Scene) -> dict[str, Any]:
    """The scene's ``[compensation]`` table (empty if none) over its geometry's defaults.

    Parameters
    ----------
    scene
        A validated scene with a ``[winch]``.
    """
    winch = scene.winch
    if scene.sheave is not None:
        reference = list(scene.sheave.position)
    else:
        reference = [winch.position[0], winch.position[1], winch.position[2] + winch.radius]
    return {"reference_point": reference, "winch_radius": winch_radius(scene),
            "phi_nom": winch.phi_nom, "waterline_z": 0.0 if scene.water is None else scene.water.surface_z,
            **(scene.compensation or {})}


def compensation_config(table: Mapping[str, Any], theta_nom: float):
    """The set-point algorithm's configuration (``controllers.SetpointConfig``) of ``table``
    (from :func:`compensation_table`), ``theta_nom`` [rad] unless the table gives it.

    Raises
    ------
    SceneError
        Naming the ``compensation.*`` key whose value cannot be used.
    """
    from controllers import setpoint_config_from_table

    return setpoint_config_from_table({"theta_nom": theta_nom, **table}, key="compensation")
