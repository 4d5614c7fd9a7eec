"""The co-simulation master's stepping loop as one compiled kernel.

The master (:mod:`towcable_fmu.cosim.master`) spends per communication step nine FMI calls
(set, get, step) and the copies between the FMUs' value buffers. Made from Python,
each FMI call goes through ctypes (argument conversion, the GIL released and taken
back) and the copies through numpy's indexing; together that was as much time as the
FMUs' own glue. :func:`advance` makes the same calls, in the same order, straight
from compiled code: the FMI functions are called through their addresses
(:func:`fmi_functions`) with the GIL held, so an FMU that runs Python (pythonfmu)
enters it at once.

The loop's arguments travel as four bundles: :class:`Calls` (the FMUs' functions),
:class:`Buffers` (the values exchanged), :class:`BooleanOutputs` (the Boolean outputs
recorded) and :class:`Record` (the rows written). Layout of the buffers (``n`` FMUs in
the contract's order; ``out_off``/``in_off`` have ``n + 1`` entries, FMU ``i`` owns the
range ``off[i]:off[i + 1]``):

* ``outputs``: every FMU's Real outputs, as last read (``out_vr`` their value references);
* ``inputs``: every FMU's connected Real inputs (``in_vr``); input ``j`` takes the value
  ``outputs[in_src[j]]``;
* ``feedthrough[i]``: FMU ``i`` is an algebraic block (direct feedthrough): at each
  communication point it is fed and its outputs read *before* the row is recorded and
  before the others are fed; the others are fed after recording, and read after all
  have stepped. (The docstring of :mod:`towcable_fmu.cosim` gives the order.)
"""

from __future__ import annotations

import ctypes
from typing import NamedTuple

import numpy as np

from ..jit.kernel_cache import njit

#: ``fmi2Status (*)(fmi2Component, const fmi2ValueReference*, size_t, void*)``: fmi2Get/SetReal/Boolean.
VALUES_PROTOTYPE = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t,
                                    ctypes.c_void_p)
#: ``fmi2Status (*)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean)``: fmi2DoStep.
STEP_PROTOTYPE = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_int)

#: FMI call kinds in :attr:`Stop.call` (failing call = kind * 100 + FMU index).
SET_REAL, GET_REAL, DO_STEP, GET_BOOLEAN = 1, 2, 3, 4
CALL_NAMES = {SET_REAL: "fmi2SetReal", GET_REAL: "fmi2GetReal", DO_STEP: "fmi2DoStep", GET_BOOLEAN: "fmi2GetBoolean"}


class FmiFunctions(NamedTuple):
    """The FMI functions of one FMU instance, callable from compiled code."""

    component: int
    do_step: object
    get_real: object
    set_real: object
    get_boolean: object


def fmi_functions(dll: ctypes.CDLL, component: int) -> FmiFunctions:
    """The instance's fmi2DoStep, fmi2GetReal, fmi2SetReal and fmi2GetBoolean by address.

    Parameters
    ----------
    dll
        The FMU's loaded library (fmpy's ``FMU2Slave.dll``).
    component
        The instance (``fmi2Component`` as an integer address).
    """
    def address(name: str) -> int:
        return ctypes.cast(getattr(dll, name), ctypes.c_void_p).value

    return FmiFunctions(int(component), STEP_PROTOTYPE(address("fmi2DoStep")),
                        VALUES_PROTOTYPE(address("fmi2GetReal")), VALUES_PROTOTYPE(address("fmi2SetReal")),
                        VALUES_PROTOTYPE(address("fmi2GetBoolean")))


class Calls(NamedTuple):
    """Per FMU (contract order): the instance and its functions (:func:`fmi_functions`)."""

    components: np.ndarray  #: (n,) intp: the fmi2Component addresses
    do_steps: tuple         #: fmi2DoStep of each FMU
    get_reals: tuple        #: fmi2GetReal of each FMU
    set_reals: tuple        #: fmi2SetReal of each FMU


class Buffers(NamedTuple):
    """The values exchanged, in the layout of the module docstring."""

    out_vr: np.ndarray       #: uint32 value references of every FMU's Real outputs
    out_off: np.ndarray      #: (n + 1,) intp: FMU i's outputs are out_off[i]:out_off[i + 1]
    outputs: np.ndarray      #: the Real outputs as last read
    in_vr: np.ndarray        #: uint32 value references of every FMU's connected Real inputs
    in_off: np.ndarray       #: (n + 1,) intp: FMU i's inputs are in_off[i]:in_off[i + 1]
    in_src: np.ndarray       #: intp: input j takes outputs[in_src[j]]
    inputs: np.ndarray       #: the Real inputs as last set
    feedthrough: np.ndarray  #: (n,) bool: FMU i is an algebraic block


class BooleanOutputs(NamedTuple):
    """The Boolean outputs recorded: those of one FMU."""

    get_boolean: object  #: that FMU's fmi2GetBoolean
    fmu: int             #: its index in the contract order
    vr: np.ndarray       #: uint32 value references read
    values: np.ndarray   #: int32 buffer of the values read


class Record(NamedTuple):
    """The rows a run writes."""

    time: np.ndarray      #: (rows,) time [s]
    outputs: np.ndarray   #: (rows, outputs) every FMU's Real outputs
    booleans: np.ndarray  #: (rows, booleans) the recorded Boolean outputs


# feed and read are inlined into advance: called as kernels of their own, passing the two
# bundles of arrays cost reference counting at every call (about 1 us each, six per step).
@njit(cache=True, inline="always")
def feed(i, calls, buffers):
    """Gather FMU ``i``'s inputs from the outputs and set them; the status (0 = nothing to set)."""
    buf = buffers
    a, b = buf.in_off[i], buf.in_off[i + 1]
    if b == a:
        return 0
    for j in range(a, b):
        buf.inputs[j] = buf.outputs[buf.in_src[j]]
    return calls.set_reals[i](calls.components[i], buf.in_vr[a:].ctypes.data, b - a, buf.inputs[a:].ctypes.data)


@njit(cache=True, inline="always")
def read(i, calls, buffers):
    """Get FMU ``i``'s Real outputs into ``buffers.outputs``; the status."""
    a, b = buffers.out_off[i], buffers.out_off[i + 1]
    if b == a:
        return 0
    return calls.get_reals[i](calls.components[i], buffers.out_vr[a:].ctypes.data, b - a,
                              buffers.outputs[a:].ctypes.data)


@njit(cache=True)
def advance(k_start, k_stop, finish, t0, h, stride, row, calls, buffers, bools, record):
    """Communication steps ``k_start`` to ``k_stop - 1`` (and, if ``finish``, the
    communication point ``k_stop`` without a step: the last row).

    Step ``k`` goes from ``t0 + k h`` to ``t0 + (k + 1) h`` [s]. At every communication
    point: feed and read the feedthrough FMUs; if ``k % stride == 0`` record row
    ``row`` (time, all outputs, the Boolean outputs of ``bools``); feed the others;
    step all in order; read the others.

    Parameters
    ----------
    k_start, k_stop, finish
        Communication steps to make, and whether to end with the exchange at ``k_stop``.
    t0, h
        Start time and communication step [s].
    stride, row
        Record every ``stride``-th communication point, from row ``row`` on.
    calls, buffers, bools, record
        The FMUs' functions (:class:`Calls`), the values exchanged (:class:`Buffers`),
        the Boolean outputs recorded (:class:`BooleanOutputs`) and the rows
        (:class:`Record`).

    Returns
    -------
    (k, row, call, status)
        ``k``: ``k_stop`` if all went well, else the communication point of the failed
        call; ``row``: the next free row; ``call``: 0, or the failing call (kind * 100 +
        FMU index, see :data:`CALL_NAMES`) with its fmi2Status ``status``.
    """
    n = calls.components.size
    outputs, feedthrough = buffers.outputs, buffers.feedthrough
    for k in range(k_start, k_stop + 1 if finish else k_stop):
        t = t0 + k * h
        for i in range(n):
            if feedthrough[i]:
                status = feed(i, calls, buffers)
                if status > 1:
                    return k, row, SET_REAL * 100 + i, status
                status = read(i, calls, buffers)
                if status > 1:
                    return k, row, GET_REAL * 100 + i, status
        if k % stride == 0:
            record.time[row] = t
            record.outputs[row, :] = outputs
            if bools.values.size:
                status = bools.get_boolean(calls.components[bools.fmu], bools.vr.ctypes.data, bools.vr.size,
                                           bools.values.ctypes.data)
                if status > 1:
                    return k, row, GET_BOOLEAN * 100 + bools.fmu, status
                record.booleans[row, :] = bools.values
            row += 1
        if k == k_stop:
            break
        for i in range(n):
            if not feedthrough[i]:
                status = feed(i, calls, buffers)
                if status > 1:
                    return k, row, SET_REAL * 100 + i, status
        dt = (t0 + (k + 1) * h) - t
        for i in range(n):
            status = calls.do_steps[i](calls.components[i], t, dt, 1)
            if status > 1:
                return k, row, DO_STEP * 100 + i, status
        for i in range(n):
            if not feedthrough[i]:
                status = read(i, calls, buffers)
                if status > 1:
                    return k, row, GET_REAL * 100 + i, status
    return k_stop, row, 0, 0

