"""Helpers of the FMU tests: open an FMU on fmpy's low-level interface by contract names."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from towcable_fmu.common import contract
from towcable_fmu.cosim import FmuInstance

#: Small, fast scene of the FMU tests (eight elements, pinned on the ship, towed body).
SMALL_SCENE = Path(__file__).parent / "data" / "fmu_tow.toml"

SHIP = tuple(n for n in contract.signals() if n.startswith("ship."))


def open_fmu(paths: Mapping[str, Path], name: str, params: Mapping[str, Any] | None = None,
             instance: str | None = None, start: float = 0.0) -> FmuInstance:
    """Instantiate (logging on, messages kept), setup, set parameters, enter initialisation."""
    fmu = FmuInstance(contract.fmu(name), paths[name], instance_name=instance, echo=False)
    fmu.instantiate(start)
    if params:
        fmu.set_parameters(params)
    fmu.fmu.enterInitializationMode()
    return fmu


def set_inputs(fmu: FmuInstance, values: Mapping[str, float]) -> None:
    """Set Real inputs by name in one call."""
    names = list(values)
    fmu.fmu.setReal(fmu.vrs(names), [float(values[n]) for n in names])


def outputs(fmu: FmuInstance) -> dict[str, float]:
    """All outputs by name (Real and Boolean), diagnostics left out."""
    out = dict(zip(fmu.real_outputs, fmu.get_outputs()))
    if fmu.bool_outputs:
        out.update(zip(fmu.bool_outputs, (float(b) for b in fmu.fmu.getBoolean(fmu.bool_output_vrs))))
    return {k: v for k, v in out.items() if not contract.signals()[k].diagnostic}


def ship_inputs(state: np.ndarray) -> dict[str, float]:
    """Ship state (3, 6) as the 18 named inputs."""
    return dict(zip(SHIP, np.asarray(state, dtype=float).ravel()))


def all_finite(values: Mapping[str, float]) -> bool:
    return all(math.isfinite(v) for v in values.values())
