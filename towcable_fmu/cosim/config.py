"""What a co-simulation runs (:class:`CosimConfig`), what it returns (:class:`CosimResult`), and
the compensation geometry handed to HeaveCompensation."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np


# ---------------------------------------------------------------------------- configuration
@dataclasses.dataclass
class CosimConfig:
    """What to co-simulate.

    Attributes
    ----------
    scene
        TowCable scene: built-in name or path to a TOML file.
    overrides
        Scene overrides (dotted key -> value), as ``towcable --set``.
    compensation
        HeaveCompensation algorithm (``controllers.ALGORITHMS``); None: the scene's
        ``[compensation]`` algorithm if it has one, else ``"none"``.
    duration, step
        Simulated time and communication step [s].
    start_time
        Start of the simulation [s].
    motion
        Ship motion: None = the scene's own ``[motion]`` if it has one, else the default
        sea (``ship_motion.DEFAULT_SEA``); ``"none"`` = still ship; otherwise a value of
        the ShipMotion parameter ``motion.config`` (TOML file, built-in scene, TOML text).
    ship_parameters, cable_parameters, controller_parameters
        Further FMU parameters by name (win over everything above).
    winch_radius, phi_nom, theta_nom, reference_point
        Compensation geometry; None = the scene's (see :func:`compensation_geometry`);
        theta_nom then is the cable's static departure angle at t0.
    interval
        Recording interval [s] (a multiple of ``step``; None: every step).
    fmu_dir
        Where the FMUs are (built or rebuilt there if missing or stale).
    """

    scene: str = "full_scale"
    overrides: Sequence[tuple[str, Any]] = ()
    compensation: str | None = None
    duration: float = 60.0
    step: float = 0.01
    start_time: float = 0.0
    motion: str | None = None
    ship_parameters: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    cable_parameters: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    controller_parameters: Mapping[str, Any] = dataclasses.field(default_factory=dict)
    winch_radius: float | None = None
    phi_nom: float | None = None
    theta_nom: float | None = None
    reference_point: tuple[float, float, float] | None = None
    interval: float | None = None
    fmu_dir: str | Path = "fmus"


@dataclasses.dataclass
class CosimResult:
    """Outcome of a co-simulation.

    Attributes
    ----------
    series
        Contract name -> samples (``time`` first; ship, set-point and cable outputs).
    parameters
        FMU name -> the parameters the master set.
    geometry
        The compensation geometry used and where each value came from.
    timing
        Wall times [s] and the FMU overhead share (see :func:`run_cosim`).
    """

    series: dict[str, np.ndarray]
    parameters: dict[str, dict[str, Any]]
    geometry: dict[str, Any]
    timing: dict[str, float]


#: HeaveCompensation parameters a scene's ``[compensation]`` may give beyond the geometry
_EXTRA = ("theta_nom", "waterline_z", "max_payout", "max_winch_speed", "max_winch_acceleration", "tension_target",
          "tension_gain")


def compensation_geometry(scene, config: CosimConfig) -> dict[str, Any]:
    """Algorithm, winch radius, nominal winch rotation and reference point for HeaveCompensation.

    The same settings the Simulation uses for its own runs
    (:mod:`towcable_fmu.ancf.compensation_setup`: the cable centreline's winch
    radius, the scene's phi_nom, the sheave centre or the top of the drum), unless
    ``config`` gives a value. ``theta_nom`` is resolved later (the static angle at t0)
    unless the scene's ``[compensation]`` gives it.

    Raises
    ------
    SceneError
        A compensation other than 'none' for a scene without a winch.
    """
    from ..common.errors import SceneError
    from ..ancf.compensation_setup import compensation_config, compensation_table

    # a rigid-link (tug-tow) scene has no [compensation], [winch], [sheave] or [motion]
    table = dict(getattr(scene, "compensation", None) or {})
    winch, sheave = getattr(scene, "winch", None), getattr(scene, "sheave", None)
    algorithm = config.compensation or table.get("algorithm") or "none"
    source = {"algorithm": "given" if config.compensation else "scene [compensation]" if "algorithm" in table
              else "default"}
    if winch is None:
        if algorithm != "none":
            raise SceneError("compensation", algorithm, "'none' for a scene without a [winch] (nothing to drive)")
        return {"algorithm": "none", "extra": {}, "winch_radius": 1.0, "phi_nom": 0.0,
                "reference_point": (0.0, 0.0, 0.0), "has_sheave": sheave is not None,
                "source": {**source, "geometry": "unused (no winch)"}}
    table["algorithm"] = algorithm
    table.update({k: v for k, v in config.controller_parameters.items() if k in _EXTRA and v != 0.0})
    cfg = compensation_config({**compensation_table(scene), **table}, float(table.get("theta_nom", 0.0)))
    geometry = {"winch_radius": cfg.winch_radius, "phi_nom": cfg.phi_nom, "reference_point": cfg.reference_point}
    for key in geometry:
        given = getattr(config, key)
        source[key] = "given" if given is not None else "scene"
        if given is not None:
            geometry[key] = given
    extra = {k: table[k] for k in _EXTRA if k in table}
    extra.setdefault("waterline_z", cfg.waterline_z)
    return {"algorithm": algorithm, "extra": extra, "winch_radius": float(geometry["winch_radius"]),
            "phi_nom": float(geometry["phi_nom"]),
            "reference_point": tuple(float(x) for x in geometry["reference_point"]),
            "has_sheave": sheave is not None, "source": source}


def motion_parameters(config: CosimConfig, scene) -> dict[str, Any]:
    """ShipMotion's parameters: none, the configuration's own ``[motion]``, the scene's
    (its file, or its built-in name; its table as TOML text when the overrides change it),
    or the FMU's default sea (empty)."""
    if config.motion == "none":
        return {"motion.type": "none"}
    if config.motion:
        return {"motion.config": str(config.motion)}
    if getattr(scene, "motion", None):  # (none in a rigid-link scene)
        if any(key.split(".")[0] == "motion" for key, _ in config.overrides):
            from ..scene.sea import motion_config_text

            return {"motion.config": motion_config_text(scene.motion, scene.base_dir)}
        path = Path(config.scene)
        return {"motion.config": str(path.resolve()) if path.suffix == ".toml" or path.exists() else config.scene}
    return {}  # the FMU's defaults: ship_motion.DEFAULT_SEA
