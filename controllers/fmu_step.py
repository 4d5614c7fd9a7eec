"""HeaveCompensation's set-point law compiled for the FMU's loader layer
(``fmu_build/csrc/shared_values.h``): the loader calls :data:`OUTPUTS` when a host gets
an output after setting inputs (direct feedthrough) and before a step, and :data:`STEP`
for ``fmi2DoStep``, without entering Python.

:data:`OUTPUTS` evaluates :func:`controllers.setpoint.setpoint_law` on the inputs in the
shared values, as the slave's Python does for the motion algorithms (``constant_tension``
has a state and stays in Python), and writes ``winch.phi_sp`` and ``winch.phi_sp_rate``.
It declines (returns 1, nothing written) where the slave has something to say: a
non-finite ship input (the step is then refused by the slave) or an unusable sheave
angle before the slave warned of it. The algorithms have no state: :data:`STEP` has
nothing to do once the outputs are those of the inputs. The data (one float64 array,
:func:`law_model`)::

    [count, warned, ship_vr (12), sheave_angle_vr, phi_sp_vr, phi_sp_rate_vr, law (11)]

``count`` is the number of shared values (value references 0 .. count - 1); the 12 ship
inputs are the position, attitude and their rates in ship-state order.
"""

from __future__ import annotations

import math

import numpy as np
from numba import carray, cfunc, types

from towcable_fmu.jit.kernel_cache import install, njit

from .setpoint import setpoint_law

_HEAD = 2
_SHIP = 12
_LAW = _HEAD + _SHIP + 3
#: the length of :meth:`SetpointAlgorithm.law`
LAW_SIZE = 11
MODEL_SIZE = _LAW + LAW_SIZE
#: ``int32 outputs(double *values, const double *model)``
OUTPUTS_SIGNATURE = types.int32(types.CPointer(types.float64), types.CPointer(types.float64))
#: ``int32 step(double *values, const double *model, double t, double h)``
STEP_SIGNATURE = types.int32(types.CPointer(types.float64), types.CPointer(types.float64), types.float64,
                             types.float64)


def law_model(count: int, warned: bool, ship_vrs: list[int], sheave_vr: int, output_vrs: list[int],
              law: np.ndarray) -> np.ndarray:
    """The data of :data:`OUTPUTS` and :data:`STEP` (module docstring)."""
    if len(ship_vrs) != _SHIP or len(output_vrs) != 2 or law.size != LAW_SIZE:
        raise ValueError("the compiled set-point takes 12 ship inputs, 2 outputs and a law of 11 numbers")
    return np.concatenate([[count, float(warned)], np.asarray(ship_vrs, dtype=float), [sheave_vr],
                           np.asarray(output_vrs, dtype=float), law]).astype(np.float64)


@njit(cache=True)
def setpoint_outputs(values: np.ndarray, model: np.ndarray) -> int:
    """Write the set-point of the inputs in ``values``; 1 (nothing written) if the slave
    must see them (module docstring)."""
    ship = np.zeros((3, 6))
    for k in range(_SHIP):
        x = values[int(model[_HEAD + k])]
        if not math.isfinite(x):
            return 1
        ship[k // 6, k % 6] = x
    angle = values[int(model[_HEAD + _SHIP])]
    phi_sp, phi_sp_rate, _, _, _, fallback, _, _ = setpoint_law(ship, model[_LAW:_LAW + LAW_SIZE], angle)
    if fallback and model[1] == 0.0:
        return 1
    values[int(model[_HEAD + _SHIP + 1])] = phi_sp
    values[int(model[_HEAD + _SHIP + 2])] = phi_sp_rate
    return 0


install()


@cfunc(OUTPUTS_SIGNATURE, cache=True)
def _outputs(values_ptr, model_ptr):
    model = carray(model_ptr, MODEL_SIZE)
    return setpoint_outputs(carray(values_ptr, int(model[0])), model)


@cfunc(STEP_SIGNATURE, cache=True)
def _step(values_ptr, model_ptr, t, h):
    return 0


#: The addresses of the compiled functions (C).
OUTPUTS = _outputs.address
STEP = _step.address
