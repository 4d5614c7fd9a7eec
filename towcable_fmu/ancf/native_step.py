"""The ANCF cable's FMU step as a C function the FMU's loader layer calls without Python.

The loader layer (``fmu_build/csrc/shared_values.h``) makes ``fmi2DoStep`` with a slave's
``CompiledStep``, ``int32 step(double *values, const double *model, double t, double h)``,
if it has one. :data:`STEP` is that function for
:func:`~towcable_fmu.ancf.buffer_step.step_on_values` on a
:class:`~towcable_fmu.ancf.stepper.Stepper`: the Stepper's type depends on the scene, so
the C function cannot be compiled for it ahead of time; it calls instead the native
code numba already compiled for ``step_on_values`` at that type, through its address
(:func:`callee_address`), with the Stepper by its address (a structref is passed to
compiled code as the pointer to its memory block, whatever its fields). Neither is
compiled again, nor linked into :data:`STEP` (which would optimise all the integrator's
code once more: about a minute).

Its data (one float64 array, :func:`step_data`; addresses are below 2**53, exact in a
float64)::

    [callee, stepper, count, payout_limit, p, status, steps, phi_sp, phi_sp_rate, plan (p)]

``count`` is the number of shared values, ``plan`` the
:func:`~towcable_fmu.ancf.buffer_step.buffer_plan`. :data:`STEP` writes back ``status``
(that of its last call: :data:`~towcable_fmu.ancf.buffer_step.DONE`, ``BAD_INPUT``,
``ROLL_BACK``; an error inside the compiled step counts as ``ROLL_BACK``), counts the
steps it made in ``steps`` and keeps the set-point of the last one: what the Python
side takes over (:meth:`~towcable_fmu.ancf.simulation.Simulation.native_steps_made`)
before any other call reaches the Simulation. It returns 0 only for a step made; any
other call changed nothing the loader sees, and the Python step, which reports the
reason, follows (after the rollback ``status`` asks for).
"""

from __future__ import annotations

import numba
import numpy as np
from numba import carray, cfunc, types
from numba.core import cgutils
from numba.extending import intrinsic

from ..jit.kernel_cache import install, njit
from .buffer_step import BAD_INPUT, DONE, ROLL_BACK, step_on_values
from .stepper import Stepper, StepperType

CALLEE, STEPPER, COUNT, PAYOUT_LIMIT, PLAN_SIZE, STATUS, STEPS, PHI_SP, PHI_SP_RATE = range(9)
_HEAD = 9
#: ``int32 step(double *values, const double *model, double t, double h)``
STEP_SIGNATURE = types.int32(types.CPointer(types.float64), types.CPointer(types.float64), types.float64,
                             types.float64)
#: A Stepper type standing for any: every structref reaches compiled code as one pointer
_ANY_STEPPER = StepperType(fields=(("any", types.float64),))
_VALUES = types.Array(types.float64, 1, "C")
_PLAN = types.Array(types.intp, 1, "C")
_ARGS = (_ANY_STEPPER, _VALUES, _PLAN, types.float64, types.float64)
#: below this an address is exact in a float64
_EXACT = 2.0 ** 53


@intrinsic
def _address_of(typingctx, ref):
    """The address of a structref's memory block (intp)."""
    def codegen(context, builder, sig, args):
        proxy = cgutils.create_struct_proxy(sig.args[0])(context, builder, value=args[0])
        return builder.ptrtoint(proxy.meminfo, cgutils.intp_t)

    return types.intp(ref), codegen


@njit(cache=True)
def stepper_address(stepper: Stepper) -> int:
    """The address of ``stepper``'s memory block (valid while the Stepper lives)."""
    return _address_of(stepper)


@intrinsic
def _call_step(typingctx, callee, stepper, values, plan, t_end, payout_limit):
    """``step_on_values(stepper, values, plan, t_end, payout_limit)`` through the address of
    its native code (numba's calling convention) with the Stepper given by its address;
    -1 if it raised."""
    def codegen(context, builder, sig, args):
        fnty = context.call_conv.get_function_type(types.int64, _ARGS)
        function = builder.inttoptr(args[0], fnty.as_pointer())
        ref = cgutils.create_struct_proxy(_ANY_STEPPER)(context, builder)
        ref.meminfo = builder.inttoptr(args[1], ref.meminfo.type)
        status, result = context.call_conv.call_function(builder, function, types.int64, _ARGS,
                                                         [ref._getvalue(), *args[2:]])
        return builder.select(status.is_ok, result, context.get_constant(types.int64, -1))

    return types.int64(callee, stepper, values, plan, t_end, payout_limit), codegen


install()


@cfunc(STEP_SIGNATURE, cache=True)
def _step(values_ptr, model_ptr, t, h):
    head = carray(model_ptr, _HEAD)
    p = int(head[PLAN_SIZE])
    plan = np.empty(p, dtype=np.intp)
    for i in range(p):
        plan[i] = int(model_ptr[_HEAD + i])
    values = carray(values_ptr, int(head[COUNT]))
    status = _call_step(int(head[CALLEE]), int(head[STEPPER]), values, plan, t + h, head[PAYOUT_LIMIT])
    if status == DONE:
        head[STEPS] += 1.0
        head[PHI_SP] = values[plan[20]]
        head[PHI_SP_RATE] = values[plan[21]]
    elif status != BAD_INPUT:
        status = ROLL_BACK
    head[STATUS] = status
    return np.int32(0 if status == DONE else 1)


#: The address of the compiled step (C).
STEP = _step.address


def callee_address(stepper: Stepper) -> int:
    """The address of the native code of ``step_on_values`` for ``stepper``'s type (compiled,
    or loaded from the kernel cache, if it is not yet)."""
    key = (numba.typeof(stepper), _VALUES, _PLAN, types.float64, types.float64)
    step_on_values.compile(key)
    result = step_on_values.overloads[key]
    return result.library.get_pointer_to_function(result.fndesc.llvm_func_name)


def step_data(stepper: Stepper, count: int, plan: np.ndarray, payout_limit: float) -> np.ndarray | None:
    """The data of :data:`STEP` (module docstring) for ``stepper`` on a buffer of ``count``
    values laid out as ``plan``; None if an address is not exact in a float64."""
    callee, address = callee_address(stepper), stepper_address(stepper)
    if not (0 < callee < _EXACT and 0 < address < _EXACT):
        return None
    return np.concatenate([[callee, address, count, payout_limit, plan.size, DONE, 0.0, np.nan, np.nan],
                           np.asarray(plan, dtype=float)])
