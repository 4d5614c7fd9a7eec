"""The ``TowCable`` FMU slave: any towcable scene as an FMI 2.0 Co-Simulation FMU.

The scene decides the model (:func:`towcable_fmu.models.simulation_for`): the ANCF
cable (:class:`~towcable_fmu.ancf.simulation.Simulation`), the nodal-position cable
(:class:`~towcable_fmu.nodal.simulation.NodalSimulation`; the winch inputs are not used)
or the rigid-link tug-tow model
(:class:`~towcable_fmu.rigidlink.simulation.RigidLinkSimulation`; the tug follows its own
thrust and heave references, the ship and winch inputs are not used). "Simulation" below
is whichever of them the scene asks for.

Parameters: ``scene`` (a built-in scene name or a path to a scene TOML file),
``overrides`` (``KEY=VALUE`` items as for ``towcable --set``, separated by ``;``; the
item ``motion = {...}`` sets the sea of the waves in the water, the TOML text ShipMotion's
``motion.config`` takes: give both FMUs the same text; with waves in the water the ship
inputs are checked once, after the sea's ramp, against the motion that sea gives the
ship, and a difference is a warning) and a few common overrides named by their scene
keys (``solver.time_step``, ``solver.rho_inf``, ``towbody.mass``; their sentinel values
0 / -1 keep the scene's).
Inputs: the 18 ``ship.*`` signals and ``winch.phi_sp``, ``winch.phi_sp_rate``.

* ``exit_initialization_mode`` loads the scene, builds the Simulation and initialises it
  (statics) at the start time with the ship state and set-point inputs present then.
* ``do_step(t, dt)`` calls ``Simulation.step_row(dt, ship, (phi_sp, phi_sp_rate))`` with
  the inputs at ``t`` (the ship state is extrapolated with constant acceleration over the
  step) and copies the outputs (an array: no dict per step).
* Outputs the Simulation does not produce for the scene (for instance ``tension.sheave``,
  ``contact.*`` and ``sheave_angle`` without a sheave, ``winch.*`` without a winch, or
  ``towbody.*`` without a towed body) are 0 (false); the list is logged at initialisation.
* Bad inputs or parameters: see :mod:`towcable_fmu.fmi.slave` (message, then
  ``fmi2Discard`` for the step; outputs never NaN).
* FMU state: the variable values plus ``Simulation.get_state()`` (JSON-able); restoring
  it continues bit-identically, also in a fresh instance (the Simulation is rebuilt from
  the parameters stored in the state).
"""

from __future__ import annotations

import operator
import time
from typing import Any

import numpy as np
from pythonfmu.enums import Fmi2Status

from .common.errors import SceneError
from .hydro.waves import sea_of
from .models import model_kind, simulation_for
from .fmi.slave import ContractSlave, ShipStateReader, ship_signal_names
from .scene import load_scene, parse_overrides

#: Numeric parameters that override a scene key, with the value that means "keep the scene's".
OVERRIDE_PARAMETERS = {"solver.time_step": 0.0, "solver.rho_inf": -1.0, "towbody.mass": 0.0}


def scene_overrides(p: dict[str, Any]) -> list[tuple[str, Any]]:
    """Scene overrides from the TowCable parameters (name -> value)."""
    items = parse_overrides(str(p.get("overrides", "")))
    for key, keep in OVERRIDE_PARAMETERS.items():
        if key in p and p[key] != keep:
            items.append((key, p[key]))
    return items


class TowCable(ContractSlave):
    """Towed-cable FMU (see the module docstring)."""

    fmu_name = "TowCable"

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        self.sim = None
        self.missing: list[str] = []
        self._row_copy: _RowCopy | None = None
        self._plan = None  # the Simulation's step on the shared values (Simulation.buffer_plan)
        self._native: np.ndarray | None = None  # the data of the loader's compiled step (Simulation.native_step)
        self._built_from: tuple | None = None
        self._ship = ShipStateReader()
        self._sea_watch: tuple | None = None  # (the sea of the waves, when to check the ship inputs [s])

    def _parameters(self) -> dict[str, Any]:
        return {v.name: self.values[v.name] for v in self.spec.parameters}

    def _build(self) -> None:
        params = self._parameters()
        self.sim = simulation_for(load_scene(params["scene"], scene_overrides(params)))
        self._built_from = tuple(sorted(params.items()))

    def _inputs(self):
        bad = self.non_finite_inputs()
        if bad:
            raise SceneError(bad[0], self.values[bad[0]], "a finite number (input "
                             + ", ".join(f"{n} = {self.values[n]!r}" for n in bad) + ")")
        return self._ship(self.values), (self.values["winch.phi_sp"], self.values["winch.phi_sp_rate"])

    def _initialize(self) -> None:
        ship, setpoint = self._inputs()
        self._build()
        out = self.timed(self.sim.initialize, self.start_time, ship, setpoint)
        self.missing = self.set_outputs(out)
        self._use_row_copy()
        kind = model_kind(self.sim.scene)
        parts = {"ancf": "ANCF elements", "nodal_position": "nodal-position elements", "rigid_link": "rigid links"}
        self.log(f"{self.instance_name}: scene '{self.values['scene']}' ({self.sim.scene.title}); "
                 f"{self.sim.n_elements} {parts[kind]}; initialised")
        self._watch_the_sea(ship)
        if kind == "rigid_link":
            self.log(f"{self.instance_name}: the rigid-link tug is driven by the scene's thrust and heave "
                     "references; the ship.* and winch inputs are not used")
        if self.missing:
            self.log(f"{self.instance_name}: outputs this scene does not model, held at 0: "
                     + ", ".join(self.missing))

    def _step(self, t: float, dt: float) -> bool:
        now = self.sim.time  # t, to 1e-9 (ContractSlave.do_step)
        try:
            ship, setpoint = self._inputs()
            if self._sea_watch is not None and t >= self._sea_watch[1]:
                self._check_sea(t, ship)
            # step to t + dt exactly: the model time follows the master's clock; the row's
            # outputs are finite (else the step fails and the state is unchanged)
            row = self.timed(self.sim.step_row, (t + dt) - now, ship, setpoint)
        except (SceneError, ArithmeticError, ValueError) as exc:
            self.log_error(f"step from t = {t:.6g} s by {dt:.6g} s refused: {exc}", Fmi2Status.discard)
            return False
        except Exception as exc:  # SolverError and anything unexpected: the state is unchanged
            self.log_error(f"step from t = {t:.6g} s by {dt:.6g} s failed: {exc}", Fmi2Status.discard)
            return False
        self._row_copy(row, self.values)
        return True

    def _step_values(self, t: float, dt: float, values: np.ndarray) -> bool:
        # the step of _step on the shared values: the inputs read from them, the outputs
        # written into them; a non-finite input or a failed step is left to _step, which
        # refuses it with the reason (a failed step leaves the Simulation as it was)
        if self._sea_watch is not None and t >= self._sea_watch[1]:
            self._check_sea(t, values[self._row_copy.input_vrs[:18]])
        plan = self._plan
        if plan is not None:  # the whole step in one compiled call
            start = time.perf_counter()
            done = self.sim.step_on_values(t + dt, values, plan)
            self._model_time += time.perf_counter() - start
            values[self._row_copy.timer_vr] = self._model_time
            return done
        copy = self._row_copy
        inputs = values[copy.input_vrs]
        if not np.isfinite(inputs).all():
            return False
        now = self.sim.time
        try:
            row = self.timed(self.sim.step_row, (t + dt) - now, inputs[:18].reshape(3, 6), (inputs[18], inputs[19]))
        except Exception:  # noqa: BLE001 - _step makes the step again and reports it
            return False
        copy.into_buffer(row, values)
        values[copy.timer_vr] = self._model_time
        return True

    def _compiled_functions(self) -> tuple[int, int, np.ndarray] | None:
        # the loader layer steps with the Simulation's step on the shared values as a C
        # function (Simulation.native_step); what it did is taken over in _take_back. Not
        # while the ship inputs are still to be checked against the sea (_check_sea, Python)
        make = getattr(self.sim, "native_step", None)
        native = (None if self._plan is None or make is None or self._sea_watch is not None
                  else make(self._buffer_size(), self._plan))
        self._native = None if native is None else native[1]
        return None if native is None else (native[0], 0, native[1])

    def _take_back(self) -> None:
        super()._take_back()
        if self._native is not None:
            self.sim.native_steps_made(self._native)

    def _watch_the_sea(self, ship: np.ndarray) -> None:
        """With waves in the water: log the sea, and check the ship inputs against the
        motion that sea gives the ship (the scene's RAOs) at the first time after its ramp
        (:meth:`_check_sea`): TowCable cannot see ShipMotion's parameters, but a ship that
        moves by another sea is seen in its inputs."""
        water = getattr(self.sim.scene, "water", None)
        self._sea_watch = None
        if water is None or water.waves == "off":
            return
        sea = sea_of(self.sim.scene)
        self.log(f"{self.instance_name}: waves in the water from the sea of the scene's [motion]: {sea.description}; "
                 "ShipMotion must have the same sea (its motion.config the 'motion = {...}' item of overrides)")
        self._sea_watch = (sea, max(sea.ramp, self.start_time))
        if self.start_time >= self._sea_watch[1]:
            self._check_sea(self.start_time, ship)

    def _check_sea(self, t: float, ship: np.ndarray) -> None:
        """Warn (once) if the ship inputs at ``t`` [s] are not the motion the sea of the
        waves gives the ship: ShipMotion then has another sea (or other RAOs)."""
        sea = self._sea_watch[0]
        self._sea_watch = None
        expected = sea.evaluate(t)[0]
        given = np.asarray(ship, dtype=float).reshape(3, 6)[0]
        error = np.abs(given - expected)
        if np.all(error <= 1e-6 * (1.0 + np.abs(expected))):
            return
        k = int(np.argmax(error))
        name = ship_signal_names()[k]
        self.log(f"{self.instance_name}: at t = {t:.6g} s the ship input {name} = {given[k]:.6g} is not the motion "
                 f"the sea of TowCable's waves gives the ship, {expected[k]:.6g} ({sea.description}): ShipMotion's "
                 "sea (or its RAOs) is not TowCable's; give ShipMotion's motion.config as the 'motion = {...}' item of "
                 "TowCable's overrides", Fmi2Status.warning)

    def _model_state(self) -> Any:
        return {"simulation": self.sim.get_state(), "missing": list(self.missing)}

    def _restore_model_state(self, data: Any) -> None:
        if self.sim is None or self._built_from != tuple(sorted(self._parameters().items())):
            self._build()
        self.sim.set_state(data["simulation"])
        self.missing = list(data["missing"])
        self._use_row_copy()

    def _use_row_copy(self) -> None:
        """Work out the copy of the Simulation's outputs, and its step on the shared values
        in one compiled call if it has one (``Simulation.buffer_plan``); the Simulation
        computes only the outputs the FMU reports (``only_outputs``)."""
        self.sim.only_outputs(name for name, _, _ in self._output_slots)
        self._row_copy = copy = _RowCopy(self.sim.names, self._output_slots, self._value_references())
        plan = getattr(self.sim, "buffer_plan", None)
        self._plan = None if plan is None or copy.casts_other_than_bool else plan(*copy.buffer_layout())

    def _value_references(self) -> dict[str, int]:
        return {var.name: vr for vr, var in self.vars.items()}


class _RowCopy:
    """Copies a step's outputs (:meth:`~towcable_fmu.runtime.driver.SimulationDriver.step_row`,
    in the order of the Simulation's ``names``) into the FMU's values, as
    :meth:`~towcable_fmu.fmi.slave.ContractSlave.set_outputs` copies the named outputs
    (worked out once per model; the outputs the scene does not model keep the zeros set at
    initialisation).

    Parameters
    ----------
    names
        The Simulation's output names (the row's order).
    slots
        The FMU's outputs: (name, cast, is Real).
    vrs
        Value reference of every variable (name -> vr), for the copy into the values the
        loader layer shares (:meth:`into_buffer`).
    """

    def __init__(self, names: tuple[str, ...], slots: list[tuple[str, Any, bool]], vrs: dict[str, int]) -> None:
        position = {name: k for k, name in enumerate(names)}
        reals = [(name, position[name]) for name, _, real in slots if real and name in position]
        self._real_names = tuple(name for name, _ in reals)
        self._pick = values_getter_at(tuple(k for _, k in reals))
        self._others = tuple((name, cast, position[name]) for name, cast, real in slots
                             if not real and name in position)
        self._real_vrs = np.array([vrs[name] for name, _ in reals], dtype=np.intp)
        self._real_positions = np.array([k for _, k in reals], dtype=np.intp)
        self._other_vrs = tuple((vrs[name], cast, k) for name, cast, k in self._others)
        #: the shared values of the inputs: the 18 ship signals (ship-state order), the set-point and its rate
        self.input_vrs = np.array([vrs[name] for name in (*ship_signal_names(), "winch.phi_sp",
                                                          "winch.phi_sp_rate")], dtype=np.intp)
        #: the shared value of the model wall time [s]
        self.timer_vr = vrs["model_wall_time"]
        #: an output other than Real is not a Boolean (:meth:`buffer_layout` has no cast for it)
        self.casts_other_than_bool = any(cast is not bool for _, cast, _ in self._other_vrs)

    def buffer_layout(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The copy for a compiled step on the shared values: the inputs' value references
        (:attr:`input_vrs`), and per output its value reference, its position in the row
        and whether it is a Boolean."""
        items = [(int(vr), int(k), False) for vr, k in zip(self._real_vrs, self._real_positions)]
        items += [(vr, k, True) for vr, _, k in self._other_vrs]
        vrs, positions, booleans = (np.array(column) for column in zip(*items))
        return self.input_vrs, vrs, positions, booleans.astype(bool)

    def __call__(self, row: np.ndarray, values: dict[str, Any]) -> None:
        """Copy ``row`` into ``values`` (name -> value)."""
        items = row.tolist()
        values.update(zip(self._real_names, self._pick(items)))
        for name, cast, k in self._others:
            values[name] = cast(items[k])

    def into_buffer(self, row: np.ndarray, buffer: np.ndarray) -> None:
        """Copy ``row`` into the shared values ``buffer`` (by value reference) as
        :meth:`__call__` copies it into the values."""
        buffer[self._real_vrs] = row[self._real_positions]
        for vr, cast, k in self._other_vrs:
            buffer[vr] = float(cast(row[k]))


def values_getter_at(positions: tuple[int, ...]):
    """A function returning the items at ``positions`` of a list as a tuple (one C-level
    ``itemgetter`` for two or more)."""
    if len(positions) >= 2:
        return operator.itemgetter(*positions)
    return lambda items: tuple(items[k] for k in positions)
