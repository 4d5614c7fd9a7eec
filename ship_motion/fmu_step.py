"""ShipMotion's step compiled for the FMU's loader layer (``fmu_build/csrc/shared_values.h``):
the loader calls :data:`STEP` (a C function) for ``fmi2DoStep`` without entering Python.

It evaluates :func:`ship_motion.irregular.harmonic_state` at the step's end, as the
slave's Python step does, and writes the 18 ``ship.*`` outputs into the shared values.
Its data (one float64 array, :func:`step_model`)::

    [count, n_dofs, n_components, ramp, out_vr (18), dofs (n_dofs), table (2 + 2 n_dofs, n)]

``count`` is the number of shared values (value references 0 .. count - 1).
"""

from __future__ import annotations

import math

import numpy as np
from numba import carray, cfunc, types

from towcable_fmu.jit.kernel_cache import install, njit

from .irregular import harmonic_state

_HEAD = 4
#: ``int32 step(double *values, const double *model, double t, double h)``
STEP_SIGNATURE = types.int32(types.CPointer(types.float64), types.CPointer(types.float64), types.float64,
                             types.float64)


def step_model(count: int, out_vrs: list[int], table: np.ndarray, dofs: np.ndarray, ramp: float) -> np.ndarray:
    """The data of :data:`STEP` (module docstring) for a buffer of ``count`` values, the
    value references of the 18 outputs (ship-state order) and :attr:`IrregularSea.harmonic_table`."""
    return np.concatenate([[count, dofs.size, table.shape[1], ramp], np.asarray(out_vrs, dtype=float),
                           np.asarray(dofs, dtype=float), np.ascontiguousarray(table, dtype=float).ravel()])


@njit(cache=True)
def irregular_step(values: np.ndarray, model: np.ndarray, t: float, h: float) -> int:
    """Write the ship state at ``t + h`` [s] into ``values``; 1 (nothing written) if it is
    not finite."""
    n_dofs, n = int(model[1]), int(model[2])
    dofs = model[_HEAD + 18:_HEAD + 18 + n_dofs].astype(np.intp)
    table = model[_HEAD + 18 + n_dofs:_HEAD + 18 + n_dofs + (2 + 2 * n_dofs) * n].reshape(2 + 2 * n_dofs, n)
    state = harmonic_state(t + h, table, dofs, model[3])
    for k in range(18):
        if not math.isfinite(state[k // 6, k % 6]):
            return 1
    for k in range(18):
        values[int(model[_HEAD + k])] = state[k // 6, k % 6]
    return 0


install()


@cfunc(STEP_SIGNATURE, cache=True)
def _step(values_ptr, model_ptr, t, h):
    head = carray(model_ptr, _HEAD)
    n_dofs, n = int(head[1]), int(head[2])
    model = carray(model_ptr, _HEAD + 18 + n_dofs + (2 + 2 * n_dofs) * n)
    return irregular_step(carray(values_ptr, int(head[0])), model, t, h)


#: The address of the compiled step (C).
STEP = _step.address
