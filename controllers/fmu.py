"""The ``HeaveCompensation`` FMU slave: the AHC set-point algorithms W(1)-(2) as an FMU.

Parameters are the :class:`~controllers.SetpointConfig` fields (``reference_point`` as
``reference_point.x/.y/.z``; ``max_payout`` and ``max_winch_speed`` 0 mean no limit).
Inputs: the ship position, attitude and their rates (12 ``ship.*`` signals) and the
measured ``sheave_angle``; outputs ``winch.phi_sp`` [rad] and ``winch.phi_sp_rate``
[rad/s].

The algorithm is algebraic, so the FMU has direct feedthrough: the outputs are
recomputed whenever inputs or parameters are set (also in initialisation mode, so that a
master exchanging values before leaving it sees the nominal set-point), and ``do_step`` only checks
that the last inputs were valid. Non-finite ship inputs keep the previous outputs and
make the next step return ``fmi2Discard`` with a message. A missing or non-finite
``sheave_angle`` is "not measured": the rigorous algorithms then use ``theta_nom``
(controllers/README.md) and a warning is logged once.
"""

from __future__ import annotations

from typing import Any

from pythonfmu.enums import Fmi2Status

from towcable_fmu.fmi.slave import ContractSlave, ShipStateReader

from .config import SetpointConfig
from .setpoint import SetpointAlgorithm


def setpoint_config(p: dict[str, Any]) -> SetpointConfig:
    """The set-point configuration from the HeaveCompensation parameters (name -> value)."""
    return SetpointConfig(
        algorithm=p["algorithm"],
        reference_point=(p["reference_point.x"], p["reference_point.y"], p["reference_point.z"]),
        winch_radius=p["winch_radius"], phi_nom=p["phi_nom"], theta_nom=p["theta_nom"],
        waterline_z=p["waterline_z"],
        max_payout=None if p["max_payout"] == 0.0 else p["max_payout"],
        max_winch_speed=None if p["max_winch_speed"] == 0.0 else p["max_winch_speed"])


class HeaveCompensation(ContractSlave):
    """Heave-compensation set-point FMU (see the module docstring)."""

    fmu_name = "HeaveCompensation"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.algorithm: SetpointAlgorithm | None = None
        self.bad_inputs: list[str] = []
        self._warned_fallback = False
        self._ship = ShipStateReader(tuple(v.name for v in self.spec.inputs if v.name.startswith("ship.")))

    def _build(self) -> None:
        self.algorithm = SetpointAlgorithm(setpoint_config({v.name: self.values[v.name]
                                                            for v in self.spec.parameters}))

    def _compute(self) -> None:
        self.bad_inputs = [n for n in self.non_finite_inputs() if n != "sheave_angle"]
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
        if self.bad_inputs:
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
        return True

    def _model_state(self) -> Any:
        return {"bad_inputs": list(self.bad_inputs)}

    def _restore_model_state(self, data: Any) -> None:
        self._build()
        self.bad_inputs = list(data["bad_inputs"])
