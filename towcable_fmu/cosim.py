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
with all its Real outputs (and one getBoolean for TowCable's Boolean output).

Initialisation: ShipMotion leaves initialisation first (ship state at t0); TowCable is
initialised (statics) with that ship state and the nominal set-point; then
HeaveCompensation, whose ``theta_nom`` defaults to the cable's departure angle at t0
(``sheave_angle``: from the sheave, or from the drum in a scene without a sheave; the
static angle, as Westin 2018 used for the simplified algorithms).

Overhead: each FMU reports ``model_wall_time``, the wall time spent in its own model
(Simulation.step, MotionSource.evaluate, SetpointAlgorithm.compute). The FMU overhead
is the rest of the loop's wall time (pythonfmu's C/Python layer, ctypes, the master's
bookkeeping) as a share of the loop's wall time.
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

from . import contract
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
            raise CosimError(f"{self.name}: initialisation failed: " + "\n".join(errors))

    def get_outputs(self) -> np.ndarray:
        """All Real outputs (contract order) in one fmi2GetReal."""
        return np.array(self.fmu.getReal(self.real_output_vrs))

    def real_block(self, vrs: Sequence[int]) -> "ValueBlock":
        """Buffers for reading or writing the same Real variables at every step."""
        return ValueBlock(self.fmu, vrs, "Real")

    def boolean_block(self, vrs: Sequence[int]) -> "ValueBlock":
        """Buffers for reading the same Boolean variables at every step."""
        return ValueBlock(self.fmu, vrs, "Boolean")

    def do_step(self, t: float, dt: float) -> None:
        """fmi2DoStep from ``t`` by ``dt`` [s]; raises fmpy's ``FMICallException`` above warning."""
        _checked("fmi2DoStep", self.fmu.dll.fmi2DoStep(self.fmu.component, t, dt, 1))

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


def _checked(function: str, status: int) -> None:
    """Raise fmpy's ``FMICallException`` for a status above fmi2Warning, as fmpy's own calls do."""
    if status > 1:
        from fmpy.fmi1 import FMICallException

        raise FMICallException(function=function, status=status)


class ValueBlock:
    """Preallocated value-reference and value arrays for one repeated get/set of Real or
    Boolean variables.

    ``values`` is a numpy view of the value buffer: :meth:`read` fills it, :meth:`write`
    sends it. The calls go straight to the ctypes functions fmpy configured on the FMU's
    library (``fmu.dll``), without fmpy's Python wrappers or building ctypes arrays each
    time; a status above warning raises ``FMICallException`` as fmpy does. (fmpy's call
    logger, which this master does not use, does not see these calls.)
    """

    def __init__(self, fmu, vrs: Sequence[int], kind: str = "Real") -> None:
        from fmpy.fmi2 import fmi2Boolean, fmi2Real, fmi2ValueReference

        ctype, dtype = {"Real": (fmi2Real, np.float64), "Boolean": (fmi2Boolean, np.int32)}[kind]
        self._fmu = fmu
        self._n = len(vrs)
        self._vr = (fmi2ValueReference * self._n)(*vrs)
        self._buffer = (ctype * self._n)()
        self._get = getattr(fmu.dll, f"fmi2Get{kind}")
        self._set = getattr(fmu.dll, f"fmi2Set{kind}")
        self._names = (f"fmi2Get{kind}", f"fmi2Set{kind}")
        self.values = np.frombuffer(self._buffer, dtype=dtype) if self._n else np.empty(0, dtype=dtype)

    def read(self) -> np.ndarray:
        """Get the variables into :attr:`values` (returned; overwritten by the next read)."""
        if self._n:
            _checked(self._names[0], self._get(self._fmu.component, self._vr, self._n, self._buffer))
        return self.values

    def write(self) -> None:
        """Set the variables to :attr:`values`."""
        if self._n:
            _checked(self._names[1], self._set(self._fmu.component, self._vr, self._n, self._buffer))


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
        ``do_step.<FMU>``, ``model.<FMU>``, ``get_set`` (all getReal/setReal/getBoolean),
        ``initialisation`` and ``realtime_factor`` (simulated / wall seconds).

    Raises
    ------
    CosimError
        An FMU failed to initialise or refused a step (message with the FMU's log).
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
    """The connections of the system as block copies between preallocated buffers.

    ``outputs[name]`` holds the FMU's Real outputs as last read; :meth:`feed` gathers a
    target's inputs from them and sends them in one fmi2SetReal.
    """

    def __init__(self, inst: Mapping[str, FmuInstance], order: Sequence[str]) -> None:
        self.outputs = {name: inst[name].real_block(inst[name].real_output_vrs) for name in order}
        self.inputs: dict[str, ValueBlock] = {}
        self.gathers: dict[str, list[tuple[str, np.ndarray, np.ndarray]]] = {}
        for name in order:
            vrs, sources = _routes(inst, name)
            self.inputs[name] = inst[name].real_block(vrs)
            by_source: dict[str, tuple[list[int], list[int]]] = {}
            for k, (src, index) in enumerate(sources):
                src_idx, dst_idx = by_source.setdefault(src, ([], []))
                src_idx.append(index)
                dst_idx.append(k)
            self.gathers[name] = [(self.outputs[src].values, _as_slice(a), _as_slice(b))
                                  for src, (a, b) in by_source.items()]

    def feed(self, target: str) -> None:
        """Copy the connected outputs into the target's inputs and set them (one fmi2SetReal)."""
        block = self.inputs[target]
        values = block.values
        for source, src_idx, dst_idx in self.gathers[target]:
            values[dst_idx] = source[src_idx]
        block.write()


def _as_slice(index: list[int]) -> slice | np.ndarray:
    """A run of consecutive indices as a slice (a view, cheaper than fancy indexing), else an index array."""
    if index and index == list(range(index[0], index[0] + len(index))):
        return slice(index[0], index[0] + len(index))
    return np.array(index, dtype=np.intp)


def _run(config: CosimConfig, inst: dict[str, FmuInstance], order: list[str], params: dict, geometry: dict,
         n_steps: int, stride: int, progress, t_init: float) -> CosimResult:
    t0, h = config.start_time, config.step
    ship, ctrl, cable = inst["ShipMotion"], inst["HeaveCompensation"], inst["TowCable"]
    io = _Exchange(inst, order)
    out = io.outputs

    # ---- initialisation (see the module docstring)
    ship.exit_initialization()
    out["ShipMotion"].read()
    phi_sp_index = ctrl.real_outputs.index("winch.phi_sp")
    out["HeaveCompensation"].values[:] = 0.0  # the nominal set-point until the controller runs
    out["HeaveCompensation"].values[phi_sp_index] = geometry["phi_nom"]
    io.feed("TowCable")
    cable.exit_initialization()
    out["TowCable"].read()
    theta_source = "given"
    if "theta_nom" not in params["HeaveCompensation"]:
        values = dict(zip(cable.real_outputs, out["TowCable"].values))
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
    init_wall = time.perf_counter() - t_init

    # ---- the loop
    n_rows = n_steps // stride + 1
    rec_time = np.empty(n_rows)
    rec_index = {name: np.array([i for i, n in enumerate(inst[name].real_outputs)
                                 if not contract.signals()[n].diagnostic], dtype=np.intp) for name in order}
    rec = {name: np.empty((n_rows, out[name].values.size)) for name in order}  # all columns; picked at the end
    rec_bool = np.empty((n_rows, len(cable.bool_outputs)))
    bool_block = cable.boolean_block(cable.bool_output_vrs)
    model_index = {name: inst[name].real_outputs.index("model_wall_time") for name in order}
    model_start = {name: float(out[name].values[model_index[name]]) for name in ("ShipMotion", "TowCable")}
    model_start["HeaveCompensation"] = float(np.asarray(ctrl.fmu.getReal([ctrl.variables["model_wall_time"]
                                                                          .valueReference]))[0])
    step_time = {name: 0.0 for name in order}
    io_time = 0.0
    row = 0

    def record(t: float) -> None:
        nonlocal row
        rec_time[row] = t
        for name in order:
            rec[name][row] = out[name].values
        if cable.bool_outputs:
            rec_bool[row] = bool_block.read()
        row += 1

    def control() -> None:
        nonlocal io_time
        a = time.perf_counter()
        io.feed("HeaveCompensation")
        out["HeaveCompensation"].read()
        io_time += time.perf_counter() - a

    from fmpy.fmi1 import FMICallException

    def do_step(fmu: FmuInstance, t: float, dt: float) -> None:
        mark = len(fmu.messages)
        a = time.perf_counter()
        try:
            fmu.do_step(t, dt)
        except FMICallException as exc:
            raise CosimError(f"{fmu.name} refused the step from t = {t:.6g} s by {dt:.6g} s ({exc}): "
                             + (fmu.log_text(mark) or "(no message)")) from None
        step_time[fmu.name] += time.perf_counter() - a

    loop_start = time.perf_counter()
    t = t0
    for k in range(n_steps):
        t = t0 + k * h
        t_next = t0 + (k + 1) * h
        dt = t_next - t
        control()
        if k % stride == 0:
            record(t)
        a = time.perf_counter()
        io.feed("TowCable")
        io_time += time.perf_counter() - a
        for name in order:
            do_step(inst[name], t, dt)
        a = time.perf_counter()
        out["ShipMotion"].read()
        out["TowCable"].read()
        io_time += time.perf_counter() - a
        if progress is not None:
            progress(t_next, t0 + n_steps * h)
    t_end = t0 + n_steps * h
    control()
    if n_steps % stride == 0:
        record(t_end)
    wall = time.perf_counter() - loop_start

    model = {name: float(out[name].values[model_index[name]]) - model_start[name] for name in order}
    timing = {"wall": wall, "initialisation": init_wall, "get_set": io_time, "model": sum(model.values()),
              "overhead_share": 1.0 - sum(model.values()) / wall if wall > 0 else float("nan"),
              "realtime_factor": (t_end - t0) / wall if wall > 0 else float("inf"),
              "steps": n_steps, "communication_step": h}
    for name in order:
        timing[f"do_step.{name}"] = step_time[name]
        timing[f"model.{name}"] = model[name]
    series = {"time": rec_time[:row].copy()}
    for name in order:
        columns = dict(zip((inst[name].real_outputs[i] for i in rec_index[name]), rec[name][:row, rec_index[name]].T))
        if name == "TowCable":
            columns.update(zip(cable.bool_outputs, rec_bool[:row].T))
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
