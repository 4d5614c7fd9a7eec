"""Co-simulation master: ShipMotion -> HeaveCompensation -> TowCable on fmpy's low-level API.

The three FMUs (built by ``build_fmu.py`` / :func:`towcable_fmu.fmi.build.ensure_fmus`)
are driven with ``fmpy.fmi2.FMU2Slave`` at a fixed communication step ``h``. Which
output feeds which input comes from the contract (``[system]`` in
``towcable_fmu/contract.toml``); nothing here names a signal except for plotting.

Order at each communication point t_k (documented contract, tested):

1. ``HeaveCompensation`` gets the ship state at t_k and the sheave angle the cable
   reported at t_k (the end of its previous step: the measured angle reaches the
   controller with one step of delay, which the rigorous algorithms need because the
   cable has not computed its angle for the new step yet); its outputs follow at once
   (direct feedthrough) and are read: the set-point u(t_k).
2. The row at t_k is recorded (ship, set-point, cable outputs: one consistent time).
3. ``TowCable`` gets the ship state at t_k and u(t_k). (Its Simulation extrapolates
   the ship with constant acceleration over the step: it needs the state at the start.)
4. All three step from t_k to t_{k+1} (ShipMotion, HeaveCompensation, TowCable).
5. ShipMotion's and TowCable's outputs at t_{k+1} are read.

Values move in blocks: per step one setReal per FMU with inputs, one getReal per FMU
with all its Real outputs (and one getBoolean for TowCable's Boolean output). The
stepping loop is compiled (:mod:`towcable_fmu.cosim_loop`): it makes these calls
through the FMI functions' addresses, without ctypes' per-call conversions, and returns
to Python about every 0.2 s of wall time for the progress report.

Initialisation: ShipMotion leaves initialisation first (ship state at t0); TowCable is
initialised (statics) with that ship state and the nominal set-point; then
HeaveCompensation, whose ``theta_nom`` defaults to the cable's departure angle at t0
(``sheave_angle``: from the sheave, or from the drum in a scene without a sheave; the
static angle, as Westin 2018 used for the simplified algorithms).

Overhead: each FMU reports ``model_wall_time``, the wall time spent in its own model
(Simulation.step, MotionSource.evaluate, SetpointAlgorithm.compute). The FMU overhead
is the rest of the loop's wall time (the slaves' Python glue around their models,
pythonfmu's C layer, the master's loop) as a share of the loop's wall time.
"""

from __future__ import annotations

import ctypes
import dataclasses
import itertools
import json
import math
import shutil
import sys
import time
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from . import contract, cosim_loop
from .errors import TowcableError

class CosimError(TowcableError, RuntimeError):
    """An FMU refused to initialise or to step; the message carries the FMU's log."""


# ---------------------------------------------------------------------------- one FMU
#: Instances by the component environment their FMU passes back to the logger.
_LOG_TARGETS: dict[int, "FmuInstance"] = {}
_ENVIRONMENT_IDS = itertools.count(1)
#: The one ctypes logger of this process (kept alive here; see ``FmuInstance.instantiate``).
_LOG_ROUTER = None


def _route_log_message(env, instance, status, category, message) -> None:
    """Hand an FMU's log message to the :class:`FmuInstance` whose environment id ``env`` is."""
    target = _LOG_TARGETS.get(int(env or 0))
    if target is not None:
        target._logger(env, instance, status, category, message)


class FmuInstance:
    """One FMU instance on fmpy's low-level FMI 2.0 interface, addressed by contract names.

    Parameters
    ----------
    spec
        The FMU's contract entry.
    path
        The ``.fmu`` file.
    instance_name
        Instance name (default: the FMU name).
    echo
        Print the FMU's warnings and errors on stderr as they arrive.
    """

    def __init__(self, spec: contract.FmuSpec, path: str | Path, instance_name: str | None = None,
                 echo: bool = True) -> None:
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.spec = spec
        self.name = instance_name or spec.name
        self.md = read_model_description(str(path))
        self.unzipdir = extract(str(path))
        self.variables = {v.name: v for v in self.md.modelVariables}
        missing = [v.name for v in spec.variables if v.name not in self.variables]
        if missing:
            raise CosimError(f"{path} lacks the contract variables {', '.join(missing)}: rebuild the FMUs")
        self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzipdir,
                             modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=self.name)
        self.messages: list[tuple[int, str]] = []
        self.echo = echo
        self.real_outputs = [v.name for v in spec.outputs if v.type == "Real"]
        self.bool_outputs = [v.name for v in spec.outputs if v.type == "Boolean"]
        self.real_output_vrs = self.vrs(self.real_outputs)
        self.bool_output_vrs = self.vrs(self.bool_outputs)
        self._callbacks = None
        self.active = False

    def vrs(self, names: Iterable[str]) -> list[int]:
        """Value references of variables by name."""
        return [self.variables[n].valueReference for n in names]

    # -------------------------------------------------------------- lifecycle
    def _logger(self, env, instance, status, category, message) -> None:
        text = message.decode("utf-8", "replace") if isinstance(message, bytes) else str(message)
        self.messages.append((int(status), text))
        if self.echo and status >= 1:
            label = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "PENDING"][min(int(status), 5)]
            print(f"[{self.name}] {label}: {text}", file=sys.stderr)

    def instantiate(self, start_time: float = 0.0, logging_on: bool = True) -> None:
        """fmi2Instantiate (with a logger that keeps the messages) and fmi2SetupExperiment."""
        from fmpy import calloc, free
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE, fmi2CallbackFunctions,
                               fmi2CallbackLoggerTYPE)

        callbacks = fmi2CallbackFunctions()
        # fmpy's logger proxy keeps ONE process-wide logger: the same router for every
        # instance, which hands each message to the instance named by its environment
        global _LOG_ROUTER
        if _LOG_ROUTER is None:
            _LOG_ROUTER = fmi2CallbackLoggerTYPE(_route_log_message)
        self._environment = next(_ENVIRONMENT_IDS)
        _LOG_TARGETS[self._environment] = self
        callbacks.logger = _LOG_ROUTER
        callbacks.componentEnvironment = self._environment
        callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        try:
            from fmpy.logging import addLoggerProxy

            addLoggerProxy(ctypes.byref(callbacks))
        except Exception:  # noqa: BLE001 - without the proxy messages arrive unformatted
            pass
        self._callbacks = callbacks
        self.fmu.instantiate(callbacks=callbacks, loggingOn=logging_on)
        self.active = True
        self.fmu.setupExperiment(startTime=start_time)

    def set_parameters(self, values: Mapping[str, Any]) -> None:
        """Set parameters by name, one call per FMI type."""
        by_type: dict[str, tuple[list[int], list[Any]]] = {}
        for name, value in values.items():
            var = self.variables[name]
            vrs, vals = by_type.setdefault(var.type, ([], []))
            vrs.append(var.valueReference)
            vals.append(value)
        for kind, (vrs, vals) in by_type.items():
            setter = {"Real": self.fmu.setReal, "Integer": self.fmu.setInteger, "Boolean": self.fmu.setBoolean,
                      "String": self.fmu.setString}[kind]
            cast = {"Real": float, "Integer": int, "Boolean": bool, "String": str}[kind]
            setter(vrs, [cast(v) for v in vals])

    def errors_since(self, mark: int) -> list[str]:
        """Messages with status error or worse logged after message number ``mark``."""
        return [text for status, text in self.messages[mark:] if status >= 3]

    def log_text(self, mark: int = 0, least: int = 1) -> str:
        """The messages since ``mark`` with status >= ``least``, one per line."""
        return "\n".join(text for status, text in self.messages[mark:] if status >= least)

    def call(self, what: str, fn: Callable[..., Any], *args) -> Any:
        """Call an FMI function; turn a failure status into :class:`CosimError` with the FMU's log."""
        from fmpy.fmi1 import FMICallException

        mark = len(self.messages)
        try:
            return fn(*args)
        except FMICallException as exc:
            log = self.log_text(mark) or "(no message)"
            raise CosimError(f"{self.name}: {what} failed ({exc}): {log}") from None

    def exit_initialization(self) -> None:
        """fmi2ExitInitializationMode; raises CosimError if the FMU logged an error."""
        mark = len(self.messages)
        self.call("exitInitializationMode", self.fmu.exitInitializationMode)
        errors = self.errors_since(mark)
        if errors:
            prefix, text = f"{self.name}: initialisation failed", "\n".join(errors)
            raise CosimError(text if text.startswith(prefix) else f"{prefix}: {text}")  # our slaves say it

    def get_outputs(self) -> np.ndarray:
        """All Real outputs (contract order) in one fmi2GetReal."""
        return np.array(self.fmu.getReal(self.real_output_vrs))

    def free(self) -> None:
        """fmi2Terminate, fmi2FreeInstance, remove the extracted files."""
        if self.active:
            self.active = False
            try:
                self.fmu.terminate()
            except Exception:  # noqa: BLE001 - a failed FMU may refuse to terminate
                pass
            self.fmu.freeInstance()
            _LOG_TARGETS.pop(self._environment, None)
        shutil.rmtree(self.unzipdir, ignore_errors=True)


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


def compensation_geometry(scene, config: CosimConfig) -> dict[str, Any]:
    """Algorithm, winch radius, nominal winch rotation and reference point for HeaveCompensation.

    The same settings the Simulation uses for its own runs
    (:func:`towcable_fmu.simulation.compensation_config`: the cable centreline's winch
    radius, the scene's phi_nom, the sheave centre or the top of the drum), unless
    ``config`` gives a value. ``theta_nom`` is resolved later (the static angle at t0)
    unless the scene's ``[compensation]`` gives it.

    Raises
    ------
    SceneError
        A compensation other than 'none' for a scene without a winch.
    """
    from .errors import SceneError
    from .simulation import compensation_config

    table = dict(scene.compensation or {})
    algorithm = config.compensation or table.get("algorithm") or "none"
    source = {"algorithm": "given" if config.compensation else "scene [compensation]" if "algorithm" in table
              else "default"}
    if scene.winch is None:
        if algorithm != "none":
            raise SceneError("compensation", algorithm, "'none' for a scene without a [winch] (nothing to drive)")
        return {"algorithm": "none", "extra": {}, "winch_radius": 1.0, "phi_nom": 0.0,
                "reference_point": (0.0, 0.0, 0.0), "has_sheave": scene.sheave is not None,
                "source": {**source, "geometry": "unused (no winch)"}}
    table["algorithm"] = algorithm
    cfg = compensation_config(dataclasses.replace(scene, compensation=table), float(table.get("theta_nom", 0.0)))
    geometry = {"winch_radius": cfg.winch_radius, "phi_nom": cfg.phi_nom, "reference_point": cfg.reference_point}
    for key in geometry:
        given = getattr(config, key)
        source[key] = "given" if given is not None else "scene"
        if given is not None:
            geometry[key] = given
    extra = {k: table[k] for k in ("theta_nom", "waterline_z", "max_payout", "max_winch_speed") if k in table}
    extra.setdefault("waterline_z", cfg.waterline_z)
    return {"algorithm": algorithm, "extra": extra, "winch_radius": float(geometry["winch_radius"]),
            "phi_nom": float(geometry["phi_nom"]),
            "reference_point": tuple(float(x) for x in geometry["reference_point"]),
            "has_sheave": scene.sheave is not None, "source": source}


def _motion_parameters(config: CosimConfig, scene) -> dict[str, Any]:
    if config.motion == "none":
        return {"motion.type": "none"}
    if config.motion:
        return {"motion.config": str(config.motion)}
    if scene.motion:
        path = Path(config.scene)
        return {"motion.config": str(path.resolve()) if path.suffix == ".toml" or path.exists() else config.scene}
    return {}  # the FMU's defaults: ship_motion.DEFAULT_SEA


def format_overrides(items: Iterable[tuple[str, Any]]) -> str:
    """Overrides as the TowCable parameter ``overrides`` (``key=value; ...`` in TOML syntax)."""
    def toml(value: Any) -> str:
        if isinstance(value, bool):
            return "true" if value else "false"
        if isinstance(value, (int, float)):
            return repr(value)
        if isinstance(value, str):
            return json.dumps(value)
        if isinstance(value, (list, tuple)):
            return "[" + ", ".join(toml(v) for v in value) + "]"
        if isinstance(value, Mapping):
            return "{" + ", ".join(f"{k} = {toml(v)}" for k, v in value.items()) + "}"
        raise TypeError(f"cannot write {value!r} as TOML")

    return "; ".join(f"{key}={toml(value)}" for key, value in items)


# ---------------------------------------------------------------------------- the master
def run_cosim(config: CosimConfig, progress: Callable[[float, float], None] | None = None,
              echo: bool = True, fmus: Mapping[str, Path] | None = None) -> CosimResult:
    """Run the three-FMU co-simulation (see the module docstring for the order).

    Parameters
    ----------
    config
        What to run.
    progress
        Called as ``progress(t, t_end)`` after every step (e.g. :class:`towcable_fmu.cli.Progress`).
    echo
        Print the FMUs' warnings and errors on stderr.
    fmus
        FMU name -> ``.fmu`` file; default: :func:`~towcable_fmu.fmi.build.ensure_fmus` in ``config.fmu_dir``.

    Returns
    -------
    CosimResult
        ``timing`` holds ``wall`` (the stepping loop), ``model`` (sum of the FMUs' own
        model time in the loop), ``overhead_share`` = 1 - model / wall, per-FMU
        ``model.<FMU>``, ``initialisation``, ``steps``, ``communication_step`` and
        ``realtime_factor`` (simulated / wall seconds).

    Raises
    ------
    CosimError
        An FMU failed to initialise or refused a call (message: the FMU, the call, the
        time and the FMU's log).
    SceneError
        Invalid configuration.
    """
    from .errors import SceneError
    from .fmi.build import ensure_fmus
    from .scene import load_scene

    for name, value in (("duration", config.duration), ("step", config.step)):
        if not (math.isfinite(value) and value > 0):
            raise SceneError(name, value, "a finite time > 0 s")
    n_steps = max(1, int(round(config.duration / config.step)))
    if abs(n_steps * config.step - config.duration) > 1e-9 * max(1.0, config.duration):
        raise SceneError("duration", config.duration, f"a multiple of the step {config.step:g} s")
    stride = 1
    if config.interval is not None:
        stride = int(round(config.interval / config.step))
        if stride < 1 or abs(stride * config.step - config.interval) > 1e-9 * config.interval:
            raise SceneError("interval", config.interval, f"a multiple of the step {config.step:g} s")

    scene = load_scene(config.scene, config.overrides)
    geometry = compensation_geometry(scene, config)
    paths = dict(fmus) if fmus is not None else ensure_fmus(config.fmu_dir)
    specs = contract.fmus()
    order = contract.system()["components"]
    scene_param = str(Path(config.scene).resolve()) if (Path(config.scene).suffix == ".toml"
                                                         or Path(config.scene).exists()) else config.scene
    params = {
        "ShipMotion": {**_motion_parameters(config, scene), **config.ship_parameters},
        "TowCable": {"scene": scene_param, "overrides": format_overrides(config.overrides), **config.cable_parameters},
        "HeaveCompensation": {"algorithm": geometry["algorithm"], "winch_radius": geometry["winch_radius"],
                              "phi_nom": geometry["phi_nom"],
                              **{f"reference_point.{c}": v for c, v in zip("xyz", geometry["reference_point"])}},
    }
    for key, value in geometry["extra"].items():  # from the scene's [compensation]
        params["HeaveCompensation"][key] = 0.0 if value is None else float(value)
    if config.theta_nom is not None:
        params["HeaveCompensation"]["theta_nom"] = float(config.theta_nom)
    params["HeaveCompensation"].update(config.controller_parameters)

    inst: dict[str, FmuInstance] = {}
    t_init = time.perf_counter()
    try:
        for name in order:
            inst[name] = FmuInstance(specs[name], paths[name], echo=echo)
            inst[name].instantiate(config.start_time)
        for name in order:
            inst[name].set_parameters({k: v for k, v in params[name].items()
                                       if specs[name].variable(k).causality == "parameter"})
            inst[name].call("enterInitializationMode", inst[name].fmu.enterInitializationMode)
        return _run(config, inst, order, params, geometry, n_steps, stride, progress, t_init)
    finally:
        for fmu in inst.values():
            fmu.free()


def _routes(inst: Mapping[str, FmuInstance], target: str) -> tuple[list[int], list[tuple[str, int]]]:
    """Value references of the target's connected Real inputs and where each value comes from
    (source FMU, index in its Real outputs)."""
    vrs, sources = [], []
    for c in contract.connections():
        if c.target == target:
            vrs.append(inst[target].variables[c.signal].valueReference)
            sources.append((c.source, inst[c.source].real_outputs.index(c.signal)))
    return vrs, sources


class _Exchange:
    """The connections of the system as flat buffers, and the compiled loop that moves them.

    ``outputs`` holds every FMU's Real outputs as last read (:meth:`outputs_of` gives one
    FMU's part, a view), ``inputs`` every FMU's connected Real inputs; the layout is that
    of :mod:`towcable_fmu.cosim_loop`. :meth:`feed` and :meth:`read` make single
    exchanges (initialisation), :meth:`advance` runs communication steps.
    """

    def __init__(self, inst: Mapping[str, FmuInstance], order: Sequence[str], feedthrough: Sequence[str],
                 bool_fmu: str) -> None:
        self.inst = inst
        self.order = list(order)
        self.index = {name: i for i, name in enumerate(order)}
        functions = [cosim_loop.fmi_functions(inst[name].fmu.dll, inst[name].fmu.component) for name in order]
        self.components = np.array([f.component for f in functions], dtype=np.intp)
        self.do_steps = tuple(f.do_step for f in functions)
        self.get_reals = tuple(f.get_real for f in functions)
        self.set_reals = tuple(f.set_real for f in functions)
        self.get_boolean = functions[self.index[bool_fmu]].get_boolean
        self.bool_fmu = self.index[bool_fmu]
        self.bool_vr = np.ascontiguousarray(inst[bool_fmu].bool_output_vrs, dtype=np.uint32)
        self.booleans = np.zeros(self.bool_vr.size, dtype=np.int32)
        self.out_off = np.cumsum([0] + [len(inst[n].real_outputs) for n in order], dtype=np.intp)
        self.out_vr = np.ascontiguousarray([vr for n in order for vr in inst[n].real_output_vrs], dtype=np.uint32)
        self.outputs = np.zeros(self.out_vr.size)
        in_vr, in_src, sizes = [], [], []
        for name in order:
            vrs, sources = _routes(inst, name)
            in_vr += vrs
            in_src += [self.out_off[self.index[src]] + k for src, k in sources]
            sizes.append(len(vrs))
        self.in_off = np.cumsum([0] + sizes, dtype=np.intp)
        self.in_vr = np.ascontiguousarray(in_vr, dtype=np.uint32)
        self.in_src = np.ascontiguousarray(in_src, dtype=np.intp)
        self.inputs = np.zeros(self.in_vr.size)
        self.feedthrough = np.array([name in feedthrough for name in order])

    def outputs_of(self, name: str) -> np.ndarray:
        """FMU ``name``'s Real outputs as last read (a view of :attr:`outputs`, contract order)."""
        i = self.index[name]
        return self.outputs[self.out_off[i]:self.out_off[i + 1]]

    def _status(self, call: int, status: int, mark: Mapping[str, int], what: str) -> None:
        if status > 1:
            fmu = self.inst[self.order[call % 100]]
            raise CosimError(f"{fmu.name}: {cosim_loop.CALL_NAMES[call // 100]} {what}failed (status {status}): "
                             + (fmu.log_text(mark[fmu.name]) or "(no message)"))

    def _marks(self) -> dict[str, int]:
        return {name: len(fmu.messages) for name, fmu in self.inst.items()}

    def feed(self, target: str) -> None:
        """Copy the connected outputs into the target's inputs and set them (one fmi2SetReal)."""
        i, mark = self.index[target], self._marks()
        status = cosim_loop.feed(i, self.components, self.set_reals, self.in_vr, self.in_off, self.in_src,
                                 self.inputs, self.outputs)
        self._status(cosim_loop.SET_REAL * 100 + i, status, mark, "")

    def read(self, name: str) -> np.ndarray:
        """Get FMU ``name``'s Real outputs (one fmi2GetReal); returns :meth:`outputs_of`."""
        i, mark = self.index[name], self._marks()
        status = cosim_loop.read(i, self.components, self.get_reals, self.out_vr, self.out_off, self.outputs)
        self._status(cosim_loop.GET_REAL * 100 + i, status, mark, "")
        return self.outputs_of(name)

    def advance(self, k_start: int, k_stop: int, finish: bool, t0: float, h: float, stride: int, row: int,
                rec_time: np.ndarray, rec_outputs: np.ndarray, rec_booleans: np.ndarray) -> int:
        """Communication steps ``k_start`` to ``k_stop - 1`` (see :func:`towcable_fmu.cosim_loop.advance`);
        returns the next free row.

        Raises
        ------
        CosimError
            An FMU refused a call; the message names the call and carries the FMU's log.
        """
        mark = self._marks()
        k, row, call, status = cosim_loop.advance(
            k_start, k_stop, finish, t0, h, stride, row, self.components, self.do_steps, self.get_reals,
            self.set_reals, self.get_boolean, self.out_vr, self.out_off, self.outputs, self.in_vr, self.in_off,
            self.in_src, self.inputs, self.feedthrough, self.bool_fmu, self.bool_vr, self.booleans, rec_time,
            rec_outputs, rec_booleans)
        if call:
            t = t0 + k * h
            what = f"from t = {t:.6g} s by {t0 + (k + 1) * h - t:.6g} s " if call // 100 == cosim_loop.DO_STEP \
                else f"at t = {t:.6g} s "
            self._status(call, status, mark, what)
        return row


def _run(config: CosimConfig, inst: dict[str, FmuInstance], order: list[str], params: dict, geometry: dict,
         n_steps: int, stride: int, progress, t_init: float) -> CosimResult:
    t0, h = config.start_time, config.step
    ctrl, cable = inst["HeaveCompensation"], inst["TowCable"]
    io = _Exchange(inst, order, feedthrough=("HeaveCompensation",), bool_fmu="TowCable")

    # ---- initialisation (see the module docstring)
    inst["ShipMotion"].exit_initialization()
    io.read("ShipMotion")
    setpoint = io.outputs_of("HeaveCompensation")
    setpoint[:] = 0.0  # the nominal set-point until the controller runs
    setpoint[ctrl.real_outputs.index("winch.phi_sp")] = geometry["phi_nom"]
    io.feed("TowCable")
    cable.exit_initialization()
    io.read("TowCable")
    theta_source = "given"
    if "theta_nom" not in params["HeaveCompensation"]:
        values = dict(zip(cable.real_outputs, io.outputs_of("TowCable")))
        angle_name = "sheave_angle"  # departure from the sheave, or the drum without a sheave
        theta = float(values[angle_name])
        if not (0.0 <= theta < 0.5 * math.pi):
            theta = min(max(theta, 0.0), 0.5 * math.pi - 1e-6)
        ctrl.set_parameters({"theta_nom": theta})
        params["HeaveCompensation"]["theta_nom"] = theta
        theta_source = f"static {angle_name} of the cable at t0"
    geometry = {**geometry, "theta_nom": params["HeaveCompensation"]["theta_nom"],
                "source": {**geometry["source"], "theta_nom": theta_source}}
    io.feed("HeaveCompensation")
    ctrl.exit_initialization()
    io.read("HeaveCompensation")
    init_wall = time.perf_counter() - t_init

    # ---- the loop: compiled (towcable_fmu.cosim_loop), in chunks of about 0.2 s wall for the progress
    n_rows = n_steps // stride + 1
    rec_time = np.empty(n_rows)
    rec_outputs = np.empty((n_rows, io.outputs.size))  # all columns; picked at the end
    rec_bool = np.empty((n_rows, io.booleans.size), dtype=np.int32)
    model_slot = {name: io.out_off[io.index[name]] + inst[name].real_outputs.index("model_wall_time")
                  for name in order}
    model_start = {name: float(io.outputs[slot]) for name, slot in model_slot.items()}
    loop_start = time.perf_counter()
    k, row, chunk = 0, 0, 1
    if progress is not None:
        progress(t0, t0 + n_steps * h)
    while k < n_steps:
        stop = min(n_steps, k + chunk)
        a = time.perf_counter()
        row = io.advance(k, stop, stop == n_steps, t0, h, stride, row, rec_time, rec_outputs, rec_bool)
        per_step = (time.perf_counter() - a) / (stop - k)
        chunk = int(min(max(1, 0.2 / per_step if per_step > 0 else 1000), 1000))
        k = stop
        if progress is not None:
            progress(t0 + k * h, t0 + n_steps * h)
    wall = time.perf_counter() - loop_start
    t_end = t0 + n_steps * h

    model = {name: float(io.outputs[slot]) - model_start[name] for name, slot in model_slot.items()}
    timing = {"wall": wall, "initialisation": init_wall, "model": sum(model.values()),
              "overhead_share": 1.0 - sum(model.values()) / wall if wall > 0 else float("nan"),
              "realtime_factor": (t_end - t0) / wall if wall > 0 else float("inf"),
              "steps": n_steps, "communication_step": h}
    for name in order:
        timing[f"model.{name}"] = model[name]
    series = {"time": rec_time[:row].copy()}
    for name in order:
        i = io.index[name]
        columns = dict(zip(inst[name].real_outputs, rec_outputs[:row, io.out_off[i]:io.out_off[i + 1]].T))
        if i == io.bool_fmu:
            columns.update(zip(inst[name].bool_outputs, rec_bool[:row].T.astype(float)))
        for var in inst[name].spec.outputs:
            if not var.diagnostic:
                series[var.name] = np.ascontiguousarray(columns[var.name])
    return CosimResult(series=series, parameters={k: dict(v) for k, v in params.items()}, geometry=geometry,
                       timing=timing)


# ---------------------------------------------------------------------------- results
def write_results(result: CosimResult, outdir: str | Path, plot: bool = True, title: str = "") -> dict[str, Path]:
    """Write ``cosim.csv`` (columns = contract names), ``summary.json`` (parameters,
    geometry, timing) and ``cosim.png`` (plots) into ``outdir``."""
    from .cli import write_csv

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    files = {"csv": outdir / "cosim.csv", "summary": outdir / "summary.json"}
    write_csv(files["csv"], result.series)
    summary = {"parameters": result.parameters, "geometry": result.geometry, "timing": result.timing,
               "units": {name: contract.unit_of(name) for name in result.series}}
    files["summary"].write_text(json.dumps(summary, indent=2, default=str), encoding="utf-8")
    if plot:
        from .plots import plot_cosim

        files["plot"] = outdir / "cosim.png"
        plot_cosim(result.series, files["plot"], title=title)
    return files
