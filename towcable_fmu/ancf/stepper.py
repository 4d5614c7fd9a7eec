"""One step of the ANCF cable to a time, with its outputs, in a compiled call that does not
unbox the model.

numba unboxes every array of a NamedTuple argument at every call from Python: the
:class:`~towcable_fmu.ancf.model.CableModel` with its force terms holds about a hundred,
which cost 15 to 30 us a call, more than all the rest of the Python around a
co-simulation step. A :class:`Stepper` holds the model, the solver options, the
integrator state and workspace, the output scene and the buffers of one step (a numba
structref: the arrays are shared with Python, not copied), so that a call passes one
reference. It is built once per model (:func:`new_stepper`, one unboxing) and
:func:`step_to` then steps with the drive of one knot (the FMU's constant-acceleration
extrapolation of the ship, :func:`towcable_fmu.runtime.drive.taylor_drive`) and records every
output field at the end (:func:`towcable_fmu.ancf.output_kernel.advance_recording`).
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.core.extending import overload
from numba.experimental import structref

from ..jit.kernel_cache import njit
from ..numerics.arrays import copy_into
from .output_kernel import Recording, advance_recording


@structref.register
class StepperType(types.StructRef):
    """numba type of a :class:`Stepper` (its fields' types are those of the arguments of
    :func:`new_stepper`)."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class Stepper(structref.StructRefProxy):
    """A model with its integrator state, held for compiled calls (module docstring).

    Fields (read in compiled code): ``model``, ``opt``, ``st``, ``ws``, ``scene`` (the
    :class:`~towcable_fmu.ancf.output_kernel.OutputScene`), ``index`` (the output fields to
    record), ``rows`` (1, len(index): the outputs of the last step), ``drive_t`` (1,) and
    ``drive_x`` (1, 3, 7) (the drive of the last step) and ``saved`` (an
    :class:`~towcable_fmu.ancf.genalpha.IntegratorState` of the same shapes:
    :func:`save_state` copies the state there).
    """


structref.define_boxing(StepperType, Stepper)

_FIELDS = ("model", "opt", "st", "ws", "scene", "index", "rows", "drive_t", "drive_x", "saved")


def _make(model, opt, st, ws, scene, index, rows, drive_t, drive_x, saved):
    """Build a Stepper in compiled code (:func:`new_stepper`; no Python implementation)."""
    raise NotImplementedError("compiled code only: call new_stepper")


@overload(_make)
def _make_overload(model, opt, st, ws, scene, index, rows, drive_t, drive_x, saved):
    typ = StepperType(fields=tuple(zip(_FIELDS, (model, opt, st, ws, scene, index, rows, drive_t, drive_x, saved))))

    def impl(model, opt, st, ws, scene, index, rows, drive_t, drive_x, saved):
        s = structref.new(typ)
        s.model = model
        s.opt = opt
        s.st = st
        s.ws = ws
        s.scene = scene
        s.index = index
        s.rows = rows
        s.drive_t = drive_t
        s.drive_x = drive_x
        s.saved = saved
        return s

    return impl


@njit(cache=True)
def new_stepper(model, opt, st, ws, scene, index: np.ndarray, rows: np.ndarray, drive_t: np.ndarray,
                drive_x: np.ndarray, saved) -> Stepper:
    """A :class:`Stepper` holding these objects (not copies: the state the Python side
    holds is the one the calls step).

    Parameters
    ----------
    model, opt, st, ws
        The cable system, solver options, integrator state and workspace
        (:mod:`towcable_fmu.ancf.genalpha`).
    scene
        What the outputs need of the scene (:class:`~towcable_fmu.ancf.output_kernel.OutputScene`).
    index
        (k,) intp: the output fields :func:`step_to` records.
    rows
        (1, k): receives them.
    drive_t, drive_x
        (1,) and (1, 3, 7): the drive table :func:`step_to` fills.
    saved
        An integrator state of the shapes of ``st``: where :func:`save_state` copies it.
    """
    return _make(model, opt, st, ws, scene, index, rows, drive_t, drive_x, saved)


@njit(cache=True)
def save_state(stepper: Stepper) -> None:
    """Copy the integrator state into ``stepper.saved`` (a rollback point: one compiled
    call instead of a copy per array from Python)."""
    src, dst = stepper.st, stepper.saved
    copy_into(dst.q, src.q)
    copy_into(dst.v, src.v)
    copy_into(dst.a, src.a)
    copy_into(dst.abar, src.abar)
    copy_into(dst.phi, src.phi)
    copy_into(dst.clock, src.clock)
    copy_into(dst.jac, src.jac)
    copy_into(dst.jac_q, src.jac_q)
    copy_into(dst.jac_v, src.jac_v)
    copy_into(dst.jac_ship, src.jac_ship)
    copy_into(dst.stats, src.stats)
    copy_into(dst.taut, src.taut)
    copy_into(dst.a_hist, src.a_hist)
    copy_into(dst.h_hist, src.h_hist)


@njit(cache=True)
def step_to(stepper: Stepper, t_end: float, t0: float, ship: np.ndarray, phi_sp: float, phi_sp_rate: float) -> int:
    """Integrate to ``t_end`` [s] with the ship state (3, 6) given at ``t0`` [s] extrapolated
    with constant acceleration and the winch set-point ``phi_sp`` [rad] moving at
    ``phi_sp_rate`` [rad/s] from ``t0``, and record the output fields ``stepper.index``
    there into ``stepper.rows[0]``.

    Returns
    -------
    int
        1 if ``t_end`` was reached (outputs recorded), 0 if a step failed or a spool end's
        fed element left its band (as :func:`~towcable_fmu.ancf.output_kernel.advance_recording`).
    """
    s = stepper
    s.drive_t[0] = t0
    x = s.drive_x
    for k in range(3):
        for c in range(6):
            x[0, k, c] = ship[k, c]
    x[0, 0, 6] = phi_sp
    x[0, 1, 6] = phi_sp_rate
    x[0, 2, 6] = 0.0
    samples = np.empty(1)
    samples[0] = t_end
    return advance_recording(s.model, s.opt, s.st, s.ws, samples, s.drive_t, s.drive_x,
                             Recording(s.scene, s.index, s.rows, False, False, t_end))
