"""The master loop: instantiate and initialise the three FMUs, step them, collect the series."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Callable, Mapping, Sequence

import numpy as np

from ..common import contract
from . import loop
from ..scene import format_overrides
from .config import CosimConfig, CosimResult, compensation_geometry, motion_parameters
from .instance import CosimError, FmuInstance


# ---------------------------------------------------------------------------- the master
def run_cosim(config: CosimConfig, progress: Callable[[float, float], None] | None = None,
              echo: bool = True, fmus: Mapping[str, Path] | None = None) -> CosimResult:
    """Run the three-FMU co-simulation (see the module docstring for the order).

    Parameters
    ----------
    config
        What to run.
    progress
        Called as ``progress(t, t_end)`` after every step (e.g. :class:`towcable_fmu.common.run_io.Progress`).
    echo
        Print the FMUs' warnings and errors on stderr.
    fmus
        FMU name -> ``.fmu`` file; default: :func:`~towcable_fmu.fmu_build.build.ensure_fmus` in ``config.fmu_dir``.

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
    from ..common.errors import SceneError
    from ..fmu_build.build import ensure_fmus
    from ..scene import load_scene

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
        "ShipMotion": {**motion_parameters(config, scene), **config.ship_parameters},
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
    _share_the_sea(config, scene, params["ShipMotion"], params["TowCable"])

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


def _share_the_sea(config: CosimConfig, scene, ship: dict, cable: dict) -> None:
    """A scene with waves in the water: one sea for ShipMotion and TowCable. ShipMotion's
    sea (:func:`~towcable_fmu.cosim.sea.shared_motion_config`) as TOML text ``motion = {...}``
    becomes ShipMotion's ``motion.config`` and the last item of TowCable's ``overrides``
    (the same text), unless the configuration gives TowCable its own ``overrides``, whose
    sea must then be ShipMotion's.

    Raises
    ------
    SceneError
        TowCable's sea differs from ShipMotion's (the message names both).
    """
    water = getattr(scene, "water", None)
    if water is None or water.waves == "off":
        return
    from ..scene import load_scene, parse_overrides
    from ..scene.sea import motion_config_table, motion_config_text
    from .sea import check_same_sea, shared_motion_config

    ship["motion.config"] = motion_config_text(motion_config_table(shared_motion_config(ship)))
    if "overrides" not in config.cable_parameters:
        cable["overrides"] = "; ".join(item for item in (cable["overrides"], ship["motion.config"]) if item)
    check_same_sea(ship, cable, load_scene(cable["scene"], parse_overrides(cable["overrides"])))


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
    of :mod:`towcable_fmu.cosim.loop`. :meth:`feed` and :meth:`read` make single
    exchanges (initialisation), :meth:`advance` runs communication steps.
    """

    def __init__(self, inst: Mapping[str, FmuInstance], order: Sequence[str], feedthrough: Sequence[str],
                 bool_fmu: str) -> None:
        self.inst = inst
        self.order = list(order)
        self.index = {name: i for i, name in enumerate(order)}
        functions = [loop.fmi_functions(inst[name].fmu.dll, inst[name].fmu.component) for name in order]
        self.calls = loop.Calls(np.array([f.component for f in functions], dtype=np.intp),
                                tuple(f.do_step for f in functions), tuple(f.get_real for f in functions),
                                tuple(f.set_real for f in functions))
        bool_vr = np.ascontiguousarray(inst[bool_fmu].bool_output_vrs, dtype=np.uint32)
        self.bools = loop.BooleanOutputs(functions[self.index[bool_fmu]].get_boolean, self.index[bool_fmu], bool_vr,
                                         np.zeros(bool_vr.size, dtype=np.int32))
        out_off = np.cumsum([0] + [len(inst[n].real_outputs) for n in order], dtype=np.intp)
        out_vr = np.ascontiguousarray([vr for n in order for vr in inst[n].real_output_vrs], dtype=np.uint32)
        in_vr, in_src, sizes = [], [], []
        for name in order:
            vrs, sources = _routes(inst, name)
            in_vr += vrs
            in_src += [out_off[self.index[src]] + k for src, k in sources]
            sizes.append(len(vrs))
        self.buffers = loop.Buffers(out_vr, out_off, np.zeros(out_vr.size),
                                    np.ascontiguousarray(in_vr, dtype=np.uint32), np.cumsum([0] + sizes, dtype=np.intp),
                                    np.ascontiguousarray(in_src, dtype=np.intp), np.zeros(len(in_vr)),
                                    np.array([name in feedthrough for name in order]))
        #: every FMU's Real outputs as last read
        self.outputs = self.buffers.outputs

    def outputs_of(self, name: str) -> np.ndarray:
        """FMU ``name``'s Real outputs as last read (a view of :attr:`outputs`, contract order)."""
        i = self.index[name]
        return self.outputs[self.buffers.out_off[i]:self.buffers.out_off[i + 1]]

    def _status(self, call: int, status: int, mark: Mapping[str, int], what: str) -> None:
        if status > 1:
            fmu = self.inst[self.order[call % 100]]
            raise CosimError(f"{fmu.name}: {loop.CALL_NAMES[call // 100]} {what}failed (status {status}): "
                             + (fmu.log_text(mark[fmu.name]) or "(no message)"))

    def _marks(self) -> dict[str, int]:
        return {name: len(fmu.messages) for name, fmu in self.inst.items()}

    def feed(self, target: str) -> None:
        """Copy the connected outputs into the target's inputs and set them (one fmi2SetReal)."""
        i, mark = self.index[target], self._marks()
        status = loop.feed(i, self.calls, self.buffers)
        self._status(loop.SET_REAL * 100 + i, status, mark, "")

    def read(self, name: str) -> np.ndarray:
        """Get FMU ``name``'s Real outputs (one fmi2GetReal); returns :meth:`outputs_of`."""
        i, mark = self.index[name], self._marks()
        status = loop.read(i, self.calls, self.buffers)
        self._status(loop.GET_REAL * 100 + i, status, mark, "")
        return self.outputs_of(name)

    def advance(self, k_start: int, k_stop: int, finish: bool, t0: float, h: float, stride: int, row: int,
                rec_time: np.ndarray, rec_outputs: np.ndarray, rec_booleans: np.ndarray) -> int:
        """Communication steps ``k_start`` to ``k_stop - 1`` (see :func:`towcable_fmu.cosim.loop.advance`);
        returns the next free row.

        Raises
        ------
        CosimError
            An FMU refused a call; the message names the call and carries the FMU's log.
        """
        mark = self._marks()
        k, row, call, status = loop.advance(k_start, k_stop, finish, t0, h, stride, row, self.calls, self.buffers,
                                            self.bools, loop.Record(rec_time, rec_outputs, rec_booleans))
        if call:
            t = t0 + k * h
            what = f"from t = {t:.6g} s by {t0 + (k + 1) * h - t:.6g} s " if call // 100 == loop.DO_STEP \
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

    # ---- the loop: compiled (towcable_fmu.cosim.loop), in chunks of about 0.2 s wall for the progress
    n_rows = n_steps // stride + 1
    rec_time = np.empty(n_rows)
    rec_outputs = np.empty((n_rows, io.outputs.size))  # all columns; picked at the end
    rec_bool = np.empty((n_rows, io.bools.values.size), dtype=np.int32)
    model_slot = {name: io.buffers.out_off[io.index[name]] + inst[name].real_outputs.index("model_wall_time")
                  for name in order}
    model_start = {name: float(io.outputs[slot]) for name, slot in model_slot.items()}
    # no step (0 to 0, no last row): the loop's kernel loaded, or compiled if not cached,
    # before the clock starts
    io.advance(0, 0, False, t0, h, stride, 0, rec_time, rec_outputs, rec_bool)
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
        columns = dict(zip(inst[name].real_outputs, rec_outputs[:row, io.buffers.out_off[i]:io.buffers.out_off[i + 1]].T))
        if i == io.bools.fmu:
            columns.update(zip(inst[name].bool_outputs, rec_bool[:row].T.astype(float)))
        for var in inst[name].spec.outputs:
            if not var.diagnostic:
                series[var.name] = np.ascontiguousarray(columns[var.name])
    return CosimResult(series=series, parameters={k: dict(v) for k, v in params.items()}, geometry=geometry,
                       timing=timing)
