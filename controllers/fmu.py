"""The ``HeaveCompensation`` FMU slave: the AHC set-point algorithms W(1)-(2) and the
constant-tension winch as an FMU.

Parameters are the :class:`~controllers.SetpointConfig` fields (``reference_point`` as
``reference_point.x/.y/.z``; ``max_payout``, ``max_winch_speed``,
``max_winch_acceleration``, ``tension_target`` and ``tension_gain`` 0 mean "not set").
Inputs: the ship position, attitude and their rates (12 ``ship.*`` signals), the
measured ``sheave_angle`` and the measured ``tension.winch``; outputs ``winch.phi_sp``
[rad] and ``winch.phi_sp_rate`` [rad/s].

The motion algorithms are algebraic, so the FMU has direct feedthrough: the outputs are
recomputed whenever inputs or parameters are set (also in initialisation mode, so that a
master exchanging values before leaving it sees the nominal set-point), and ``do_step`` only checks
that the last inputs were valid. Non-finite ship inputs keep the previous outputs and
make the next step return ``fmi2Discard`` with a message. A missing or non-finite
``sheave_angle`` is "not measured": the rigorous algorithms then use ``theta_nom``
(controllers/README.md) and a warning is logged once.

``constant_tension`` (:class:`~controllers.TensionControl`) has a state: its outputs are
the set-point its state holds (no feedthrough from the tension), and ``do_step`` reads
``tension.winch`` at the step's start and moves the controller to the step's end. A
non-finite tension refuses the step (``fmi2Discard``, state unchanged).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pythonfmu.enums import Fmi2Status

from towcable_fmu.common.errors import SceneError
from towcable_fmu.fmi.slave import ContractSlave, ShipStateReader

from .config import SetpointConfig
from .setpoint import SetpointAlgorithm
from .tension import TensionControl

#: Parameters whose value 0 means "not set" (None in :class:`SetpointConfig`).
_ZERO_IS_UNSET = ("max_payout", "max_winch_speed", "max_winch_acceleration", "tension_target", "tension_gain")


def setpoint_config(p: dict[str, Any]) -> SetpointConfig:
    """The set-point configuration from the HeaveCompensation parameters (name -> value).

    Raises
    ------
    SceneError
        Naming the parameter, its value and what is allowed.
    """
    try:
        return SetpointConfig(
            algorithm=p["algorithm"],
            reference_point=(p["reference_point.x"], p["reference_point.y"], p["reference_point.z"]),
            winch_radius=p["winch_radius"], phi_nom=p["phi_nom"], theta_nom=p["theta_nom"],
            waterline_z=p["waterline_z"], **{name: None if p[name] == 0.0 else p[name] for name in _ZERO_IS_UNSET},
            key="")
    except SceneError as exc:
        if exc.key in _ZERO_IS_UNSET and exc.value is None:  # required and left at 0 (not set)
            raise SceneError(exc.key, 0.0, f"{exc.allowed} for algorithm = {p['algorithm']!r}") from None
        raise


class HeaveCompensation(ContractSlave):
    """Heave-compensation set-point FMU (see the module docstring)."""

    fmu_name = "HeaveCompensation"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.algorithm: SetpointAlgorithm | TensionControl | None = None
        self.bad_inputs: list[str] = []
        self._warned_fallback = False
        self._ship = ShipStateReader(tuple(v.name for v in self.spec.inputs if v.name.startswith("ship.")))

    def _build(self) -> None:
        config = setpoint_config({v.name: self.values[v.name] for v in self.spec.parameters})
        self.algorithm = TensionControl(config) if config.method == "tension" else SetpointAlgorithm(config)

    @property
    def _tension_control(self) -> bool:
        return isinstance(self.algorithm, TensionControl)

    def _compute(self) -> None:
        if self._tension_control:  # the set-point of the controller's state: no feedthrough
            self.bad_inputs = [n for n in self.non_finite_inputs() if n == "tension.winch"]
            sp = self.algorithm.setpoint()
            self.set_outputs({"winch.phi_sp": sp.phi_sp, "winch.phi_sp_rate": sp.phi_sp_rate})
            return
        self.bad_inputs = [n for n in self.non_finite_inputs() if n not in ("sheave_angle", "tension.winch")]
        if self.bad_inputs:
            return
        ship = self._ship(self.values)
        sp = self.timed(self.algorithm.compute, ship, self.values["sheave_angle"])
        if sp.theta_fallback and not self._warned_fallback:
            self._warned_fallback = True
            self.log_error(f"sheave_angle = {self.values['sheave_angle']!r} is not usable; "
                           f"theta_nom = {self.algorithm.config.theta_nom:g} rad is used "
                           "(logged once)", Fmi2Status.warning)
        self.set_outputs({"winch.phi_sp": sp.phi_sp, "winch.phi_sp_rate": sp.phi_sp_rate})

    def _initialize(self) -> None:
        self._build()
        self._compute()
        if self.bad_inputs and not self._tension_control:  # the tension is needed by the first step only
            raise ValueError("non-finite inputs at initialisation: " + ", ".join(self.bad_inputs))

    def _inputs_changed(self) -> None:
        if self.initialized and self.algorithm is not None:
            self._compute()
        elif self.in_initialization:
            # initialisation mode: outputs follow the parameters and inputs set so far, so that
            # masters exchanging values before exit_initialization_mode see the set-point;
            # invalid parameters are reported by exit_initialization_mode
            try:
                self._build()
            except Exception:  # noqa: BLE001
                return
            self._compute()

    def _step(self, t: float, dt: float) -> bool:
        if self.bad_inputs:
            self.log_error("non-finite inputs " + ", ".join(f"{n} = {self.values[n]!r}" for n in self.bad_inputs)
                           + ": the set-point keeps its last value and the step is refused", Fmi2Status.discard)
            return False
        if self._tension_control:
            self.timed(self.algorithm.advance, self.values["tension.winch"], dt)
            self._compute()
        return True

    def _compiled_functions(self) -> tuple[int, int, np.ndarray] | None:
        # the motion algorithms run in the loader layer (controllers/fmu_step.py), the
        # constant-tension controller (a state) in Python; after non-finite inputs the
        # Python step refuses the step
        if not isinstance(self.algorithm, SetpointAlgorithm) or self.bad_inputs:
            return None
        from .fmu_step import OUTPUTS, STEP, law_model

        vrs = {var.name: vr for vr, var in self.vars.items()}
        model = law_model(self._buffer_size(), self._warned_fallback, [vrs[name] for name in self._ship.names],
                          vrs["sheave_angle"], [vrs["winch.phi_sp"], vrs["winch.phi_sp_rate"]],
                          self.algorithm.law)
        return STEP, OUTPUTS, model

    def _model_state(self) -> Any:
        return {"bad_inputs": list(self.bad_inputs),
                "control": self.algorithm.get_state() if self._tension_control else None}

    def _restore_model_state(self, data: Any) -> None:
        self._build()
        self.bad_inputs = list(data["bad_inputs"])
        if data.get("control") is not None and self._tension_control:
            self.algorithm.set_state(data["control"])
            self._compute()
