"""FMI Cross-Check artefacts of the three FMUs (``python build_fmu.py --crosscheck DIR``).

Laid out as the FMI Cross-Check rules (version 4.1, section 9.1) ask for exported FMUs::

    DIR/fmus/2.0/cs/linux64/towcable/<version>/<Model>/
        <Model>.fmu
        <Model>_ref.csv    reference solution (fmpy), at most 10 variables
        <Model>_in.csv     input signals (HeaveCompensation, TowCable)
        <Model>_ref.opt    StartTime, StopTime, StepSize, RelTol

Every FMU runs with its default parameters (as the rules ask). The inputs chain the
models as the co-simulation does, without the feedback loop: ShipMotion's ship signals
drive HeaveCompensation (with a prescribed sheave angle) and TowCable, whose winch
set-point is HeaveCompensation's output. CSV files follow the rules' appendix B: quoted
names in the header, unquoted numbers (``repr``: read back bit-exactly), Booleans 0/1.

The reference runs are fmpy's ``simulate_fmu`` on the communication grid of
``StepSize``; inputs are given on the same grid, so no interpolation takes place.
"""

from __future__ import annotations

import math
import shutil
from dataclasses import dataclass
from importlib.metadata import version
from pathlib import Path
from typing import Mapping

import numpy as np

from ..common import contract

TOOL = "towcable"
PLATFORM_PATH = ("fmus", "2.0", "cs", "linux64")


@dataclass(frozen=True)
class Experiment:
    """One cross-check run: grid [s], relative tolerance (unused by the FMUs), reference outputs."""

    start: float
    stop: float
    step: float
    rel_tol: float
    outputs: tuple[str, ...]

    def times(self) -> np.ndarray:
        """The communication points t_k = start + k step [s] (as the hosts compute them)."""
        n = round((self.stop - self.start) / self.step)
        return np.array([self.start + k * self.step for k in range(n + 1)])


EXPERIMENTS: dict[str, Experiment] = {
    "ShipMotion": Experiment(0.0, 10.0, 0.01, 1e-4, ("ship.x", "ship.y", "ship.z", "ship.roll", "ship.pitch",
                                                     "ship.yaw", "ship.vz", "ship.az")),
    "HeaveCompensation": Experiment(0.0, 10.0, 0.01, 1e-4, ("winch.phi_sp", "winch.phi_sp_rate")),
    "TowCable": Experiment(0.0, 10.0, 0.01, 1e-4, (
        "tension.sheave", "tension.winch", "tension.towbody", "sheave_angle", "contact.sheave_force",
        "contact.wrap_angle", "towbody.x", "towbody.z", "winch.phi", "winch.payout")),
}


def sheave_angle_signal(t: np.ndarray) -> np.ndarray:
    """Prescribed sheave angle input of HeaveCompensation [rad]: 0.3 + 0.05 sin(0.2 pi t)."""
    return 0.3 + 0.05 * np.sin(0.2 * math.pi * t)


def tension_signal(t: np.ndarray) -> np.ndarray:
    """Prescribed winch tension input of HeaveCompensation [N]: 4000 + 200 sin(0.4 pi t)
    (read by its constant_tension algorithm only)."""
    return 4000.0 + 200.0 * np.sin(0.4 * math.pi * t)


def model_folder(root: str | Path, model: str) -> Path:
    """``root/fmus/2.0/cs/linux64/towcable/<version>/<model>``."""
    return Path(root).joinpath(*PLATFORM_PATH, TOOL, version("towcable"), model)


def write_csv(path: str | Path, columns: Mapping[str, np.ndarray]) -> Path:
    """Write ``columns`` (first one: ``time``) as cross-check CSV."""
    names = list(columns)
    with open(path, "w", newline="", encoding="utf-8") as f:
        f.write(",".join(f'"{n}"' for n in names) + "\n")
        for row in zip(*(np.asarray(columns[n], dtype=float) for n in names)):
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    return Path(path)


def write_opt(path: str | Path, exp: Experiment) -> Path:
    """The ``_ref.opt`` file."""
    text = (f"StartTime, {exp.start!r}\nStopTime, {exp.stop!r}\nStepSize, {exp.step!r}\n"
            f"RelTol, {exp.rel_tol!r}\n")
    Path(path).write_text(text, encoding="utf-8")
    return Path(path)


def read_opt(path: str | Path) -> Experiment:
    """An ``_ref.opt`` file as an :class:`Experiment` (without outputs)."""
    values = {}
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        key, _, value = line.partition(",")
        values[key.strip()] = float(value.split("//")[0])
    return Experiment(values["StartTime"], values["StopTime"], values["StepSize"], values["RelTol"], ())


def simulate(fmu: str | Path, exp: Experiment, inputs: Mapping[str, np.ndarray] | None,
             outputs: tuple[str, ...], start_values: Mapping[str, object] | None = None) -> dict[str, np.ndarray]:
    """Run ``fmu`` with fmpy on the grid of ``exp``; outputs by name, ``time`` first.

    ``inputs``: ``time`` [s] and the input signals by name (None: no inputs);
    ``start_values``: parameters by name (None: the defaults, as the cross-check runs).
    """
    from fmpy import simulate_fmu

    signals = None
    if inputs:
        names = list(inputs)
        signals = np.array(list(zip(*(np.asarray(inputs[n], dtype=float) for n in names))),
                           dtype=[(n, float) for n in names])
    result = simulate_fmu(str(fmu), start_time=exp.start, stop_time=exp.stop, step_size=exp.step,
                          output_interval=exp.step, relative_tolerance=exp.rel_tol, input=signals,
                          output=list(outputs), start_values=dict(start_values or {}))
    return {name: np.asarray(result[name], dtype=float) for name in ("time",) + tuple(outputs)}


def write_crosscheck(fmus: Mapping[str, str | Path], root: str | Path) -> dict[str, Path]:
    """Run the three FMUs and write the cross-check folders under ``root``.

    Parameters
    ----------
    fmus
        FMU name -> ``.fmu`` file (ShipMotion, HeaveCompensation, TowCable).
    root
        Folder that receives ``fmus/2.0/cs/linux64/towcable/<version>/...``.

    Returns
    -------
    dict
        FMU name -> its cross-check folder.
    """
    specs = contract.fmus()
    ship_names = specs["ShipMotion"].names("output")
    ship_names = tuple(n for n in ship_names if not contract.signals()[n].diagnostic)
    folders = {}
    signals: dict[str, np.ndarray] = {}
    for model in ("ShipMotion", "HeaveCompensation", "TowCable"):
        exp = EXPERIMENTS[model]
        folder = model_folder(root, model)
        folder.mkdir(parents=True, exist_ok=True)
        t = exp.times()
        signals["sheave_angle"] = sheave_angle_signal(t)
        signals["tension.winch"] = tension_signal(t)
        input_names = specs[model].names("input")
        inputs = {"time": t, **{n: signals[n] for n in input_names}} if input_names else None
        extra = ship_names if model == "ShipMotion" else tuple(n for n in specs[model].names("output")
                                                               if n.startswith("winch.phi_sp"))
        wanted = tuple(dict.fromkeys(exp.outputs + extra))
        result = simulate(fmus[model], exp, inputs, wanted)
        if not np.array_equal(result["time"], t):
            raise RuntimeError(f"{model}: fmpy's output times are not the grid of the experiment")
        signals.update({n: result[n] for n in wanted})
        shutil.copy2(fmus[model], folder / f"{model}.fmu")
        write_csv(folder / f"{model}_ref.csv", {"time": t, **{n: result[n] for n in exp.outputs}})
        write_opt(folder / f"{model}_ref.opt", exp)
        if inputs:
            write_csv(folder / f"{model}_in.csv", inputs)
        folders[model] = folder
    return folders
