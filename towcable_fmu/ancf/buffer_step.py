"""An FMU's communication step of the ANCF cable on a buffer of values, in one compiled call.

The FMU's loader layer shares the slave's values in a float64 buffer indexed by value
reference (:mod:`towcable_fmu.fmi.shared_values`). :func:`step_on_values` makes the
whole step there: it reads the 18 ship signals and the winch set-point from the buffer,
saves the rollback point, steps (:func:`towcable_fmu.ancf.stepper.step_to`), checks the
outputs and writes them into the buffer. It refuses what the Python step must report
(non-finite inputs: nothing changed; a failed step, non-finite outputs, a payout beyond
the drum: the state is left for the caller to roll back from ``stepper.saved``), so the
Python around one step is one call (:meth:`towcable_fmu.ancf.simulation.Simulation.step_on_values`); the layout of the buffer
is one array (:func:`buffer_plan`), so that the call passes five arguments (numba's
dispatch costs about half a microsecond per argument).
"""

from __future__ import annotations

import math
import numpy as np

from ..jit.kernel_cache import njit
from .feed import feed_event
from .genalpha import CLOCK_TIME
from .output_kernel import OUTPUT_FIELDS
from .stepper import save_state, step_to

#: :func:`step_on_values`' results: the step is made; an input is not finite (nothing
#: changed); the step failed or its outputs are refused (roll back from ``stepper.saved``)
DONE, BAD_INPUT, ROLL_BACK = 0, 1, 2
#: the output field of ``winch.payout`` (NaN without a winch)
_PAYOUT = OUTPUT_FIELDS.index("winch.payout")


def buffer_plan(inputs: np.ndarray, checked: np.ndarray, outputs: np.ndarray, fields: np.ndarray,
                booleans: np.ndarray) -> np.ndarray:
    """Where an FMU keeps a simulation's inputs and outputs in its buffer of values, as the
    one array :func:`step_on_values` takes (one argument to pass instead of five).

    Parameters
    ----------
    inputs
        (20,): the buffer's indices of the ship state (3, 6) in row order (value [m, rad],
        rate [m/s, rad/s], acceleration [m/s^2, rad/s^2] of x, y, z, roll, pitch, yaw)
        and of the winch set-point phi_sp [rad], phi_sp_rate [rad/s].
    checked
        (m,): the output fields that must be finite (the simulation's outputs).
    outputs, fields, booleans
        (k,): where in the buffer each output goes, its output field, and whether it is a
        Boolean (written as 1.0 or 0.0).

    Returns
    -------
    np.ndarray
        intp: m, k, then the five arrays one after the other.
    """
    if len(inputs) != 20 or not len(outputs) == len(fields) == len(booleans):
        raise ValueError(f"a buffer plan needs 20 inputs and as many fields and flags as outputs "
                         f"({len(inputs)} inputs, {len(outputs)} outputs, {len(fields)} fields, {len(booleans)} flags)")
    return np.concatenate([[len(checked), len(outputs)], inputs, checked, outputs, fields,
                           np.asarray(booleans, dtype=bool)]).astype(np.intp)


@njit(cache=True)
def step_on_values(stepper, values: np.ndarray, plan: np.ndarray, t_end: float, payout_limit: float) -> int:
    """Step the stepper's state to ``t_end`` [s] with the inputs in ``values`` and write the
    outputs there.

    Parameters
    ----------
    stepper
        The :class:`~towcable_fmu.ancf.stepper.Stepper` (recording every output field).
    values
        The buffer of values (float64).
    plan
        Where the inputs and outputs are (:func:`buffer_plan`).
    t_end
        The end of the step [s]: the state's time t0 is advanced by ``t_end - t0``, as
        :meth:`~towcable_fmu.runtime.driver.SimulationDriver.step_row` steps by its ``dt``
        (not finite or <= 0: :data:`BAD_INPUT`).
    payout_limit
        The largest payout the drum holds [m] (a step beyond it is refused; ``inf``: no limit).

    Returns
    -------
    int
        :data:`DONE`, :data:`BAD_INPUT` or :data:`ROLL_BACK` (also after a step that took a
        spool end's fed element out of its band: the Python step makes it again and
        remeshes, :meth:`~towcable_fmu.ancf.remeshing.Remeshing._after_event`).
    """
    m, k = plan[0], plan[1]
    inputs = plan[2:22]
    checked = plan[22:22 + m]
    outputs = plan[22 + m:22 + m + k]
    fields = plan[22 + m + k:22 + m + 2 * k]
    booleans = plan[22 + m + 2 * k:22 + m + 3 * k]
    t0 = stepper.st.clock[CLOCK_TIME]
    dt = t_end - t0
    if not (math.isfinite(dt) and dt > 0.0):
        return BAD_INPUT
    for i in range(20):
        if not math.isfinite(values[inputs[i]]):
            return BAD_INPUT
    ship = np.empty((3, 6))
    for r in range(3):
        for c in range(6):
            ship[r, c] = values[inputs[6 * r + c]]
    save_state(stepper)
    if step_to(stepper, t0 + dt, t0, ship, values[inputs[18]], values[inputs[19]]) != 1:
        return ROLL_BACK
    if feed_event(stepper.model):  # a spool end's fed element left its band: Python remeshes
        return ROLL_BACK
    row = stepper.rows[0]
    for i in range(m):
        if not math.isfinite(row[checked[i]]):
            return ROLL_BACK
    if row[_PAYOUT] > payout_limit:
        return ROLL_BACK
    for i in range(k):
        x = row[fields[i]]
        values[outputs[i]] = (1.0 if x != 0.0 else 0.0) if booleans[i] != 0 else x
    return DONE
