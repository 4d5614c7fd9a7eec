"""The ``ShipMotion`` FMU slave: a ship motion source as an FMI 2.0 Co-Simulation FMU.

Parameters select the source (``motion.type`` and the common numbers, whose defaults are
:data:`ship_motion.DEFAULT_SEA`, or a whole ``[motion]`` table in ``motion.config``);
the 18 outputs ``ship.*`` are :meth:`MotionSource.evaluate` at the start time in
initialisation mode (as soon as the parameters are set) and after it, and at the end of
every step. Variables, units and descriptions come
from ``towcable_fmu/common/contract.toml``; build with ``python build_fmu.py``.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from towcable_fmu.builtin_scenes import builtin_scene_names, scene_document
from towcable_fmu.common.errors import SceneError
from towcable_fmu.fmi.slave import ContractSlave, ship_signal_names

from . import EXAMPLE_CSV, TYPES, motion_from_config
from .irregular import IrregularSea


def motion_table(p: dict[str, Any]) -> tuple[dict, Path | None]:
    """The ``[motion]`` table (and the folder relative paths resolve against) that the
    ShipMotion parameters ``p`` (name -> value) describe."""
    config = str(p.get("motion.config", "")).strip()
    if config:
        return _config_table(config)
    kind = p["motion.type"]
    if kind == "none":
        return {"type": "none"}, None
    if kind == "irregular":
        keys = ("hs", "tp", "gamma", "heading", "speed", "components", "seed", "ramp")
        return {"type": "irregular", **{k: p[f"motion.{k}"] for k in keys}}, None
    if kind == "regular":
        table: dict[str, Any] = {"type": "regular", "ramp": p["motion.ramp"]}
        for dof in ("heave", "roll", "pitch"):
            if p[f"motion.{dof}.amplitude"] != 0.0:
                table[dof] = {"amplitude": p[f"motion.{dof}.amplitude"], "period": p[f"motion.{dof}.period"]}
        return table, None
    if kind == "time_series":
        return {"type": "time_series", "file": p["motion.file"] or str(EXAMPLE_CSV)}, Path.cwd()
    if kind == "manoeuvre":
        table = {"type": "manoeuvre", "speed": p["motion.speed"], "speed_ramp": p["motion.speed_ramp"],
                 "heading": p["motion.heading"], "turn_start": p["motion.turn_start"]}
        if p["motion.turn_angle"] != 0.0 or p["motion.turn_rate"] != 0.0:
            table.update(turn_angle=p["motion.turn_angle"], turn_rate=p["motion.turn_rate"])
        return table, None
    raise SceneError("motion.type", kind, "one of " + ", ".join(TYPES))


def _config_table(config: str) -> tuple[dict, Path | None]:
    """``motion.config``: a TOML file path, a built-in scene name or TOML text."""
    if "\n" not in config and "=" not in config:
        path = Path(config).expanduser()
        if path.suffix == ".toml" or path.exists():
            if not path.is_file():
                raise SceneError("motion.config", config, "an existing TOML file, a built-in scene name or "
                                                          "TOML text of a [motion] table")
            doc, folder = scene_document(path, "motion.config")
            if "motion" not in doc:
                raise SceneError("motion.config", config, "a TOML file with a [motion] table")
            return doc["motion"], folder
        if config in builtin_scene_names():  # (a variant's sea is its base's unless it sets its own)
            motion = scene_document(config, "motion.config")[0].get("motion")
            return (dict(motion) if motion else {"type": "none"}), None
        raise SceneError("motion.config", config, "an existing TOML file, a built-in scene name ("
                         + ", ".join(builtin_scene_names()) + ") or TOML text of a [motion] table")
    try:
        doc = tomllib.loads(config)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError("motion.config", config, f"TOML text of a [motion] table ({exc})") from None
    return (doc["motion"] if isinstance(doc.get("motion"), dict) else doc), Path.cwd()


class ShipMotion(ContractSlave):
    """Ship motion FMU (see the module docstring)."""

    fmu_name = "ShipMotion"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.motion = None
        self._built_from: tuple | None = None
        self._names = ship_signal_names()
        self._step_model: tuple | None = None  # (motion, compiled step, its data)

    def _parameters(self) -> dict[str, Any]:
        return {v.name: self.values[v.name] for v in self.spec.parameters}

    def _build(self) -> None:
        params = self._parameters()
        table, base = motion_table(params)
        self.motion = motion_from_config(table, key="motion", base_dir=base)
        self._built_from = tuple(sorted(params.items()))

    def _ship_state(self, t: float) -> list[float]:
        """The 18 outputs at time ``t`` [s]: position/attitude [m, rad], rates [m/s, rad/s]
        and accelerations [m/s^2, rad/s^2], in the order of the contract."""
        state = self.timed(self.motion.evaluate, t).ravel()
        return state.tolist()

    def _evaluate(self, t: float) -> None:
        self.set_outputs(dict(zip(self._names, self._ship_state(t))))

    def _initialize(self) -> None:
        self._build()
        self.log(f"{self.instance_name}: {self.motion.description}")
        self._evaluate(self.start_time)

    def _inputs_changed(self) -> None:
        # initialisation mode: the outputs follow the parameters set so far (the ship state at
        # the start time), so that masters exchanging values before exit_initialization_mode
        # initialise the cable with it; invalid parameters are reported at exit
        if self.in_initialization and not self.initialized:
            try:
                self._build()
            except Exception:  # noqa: BLE001
                return
            self._evaluate(self.start_time)

    def _step(self, t: float, dt: float) -> bool:
        # the 18 outputs straight into the values (set_outputs' name matching worked out at
        # initialisation: the same 18 names at every step)
        state = self._ship_state(t + dt)
        if not all(map(math.isfinite, state)):
            raise ValueError(f"the ship state at t = {t + dt:.6g} s is not finite")
        self.values.update(zip(self._names, state))
        return True

    def _compiled_functions(self) -> tuple[int, int, np.ndarray] | None:
        # an irregular sea steps in the loader layer (ship_motion/fmu_step.py); the model
        # array is made once per motion
        if not isinstance(self.motion, IrregularSea):
            return None
        if self._step_model is None or self._step_model[0] is not self.motion:
            from .fmu_step import STEP, step_model

            vrs = {var.name: vr for vr, var in self.vars.items()}
            model = step_model(self._buffer_size(), [vrs[name] for name in self._names], *self.motion.harmonic_table)
            self._step_model = (self.motion, STEP, model)
        return self._step_model[1], 0, self._step_model[2]

    def _model_state(self) -> Any:
        return {"time": self._communication_time}

    def _restore_model_state(self, data: Any) -> None:
        if self.motion is None or self._built_from != tuple(sorted(self._parameters().items())):
            self._build()
