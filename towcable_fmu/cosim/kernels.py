"""The master's stepping loop (:mod:`towcable_fmu.cosim.loop`) as jobs for
:mod:`towcable_fmu.jit.parallel_compile`.

``towcable cosim`` compiles them ahead with the cable's kernels and the inputs' (the
light FMUs' models, :mod:`towcable_fmu.runtime.input_kernels`), so that a first run
compiles nothing once its clock runs (its progress and speed are those of a warm run).
The arguments have the types the master and the slaves pass: the loop's FMI functions
are ctypes function pointers of :data:`~towcable_fmu.cosim.loop.VALUES_PROTOTYPE` and
:data:`~towcable_fmu.cosim.loop.STEP_PROTOTYPE` (their numba type does not depend on the
address), one per FMU of the contract's system.
"""

from __future__ import annotations

import numpy as np

from ..common import contract
from ..jit.parallel_compile import Job
from . import loop


def _dummy(prototype):
    """A function pointer of ``prototype`` (only its type matters here)."""
    return prototype(lambda *args: 0)


def _bundles() -> tuple:
    """Calls, Buffers, BooleanOutputs and Record of the master's types."""
    n = len(contract.system()["components"])
    calls = loop.Calls(np.zeros(n, dtype=np.intp), tuple(_dummy(loop.STEP_PROTOTYPE) for _ in range(n)),
                       tuple(_dummy(loop.VALUES_PROTOTYPE) for _ in range(n)),
                       tuple(_dummy(loop.VALUES_PROTOTYPE) for _ in range(n)))
    offsets = np.zeros(n + 1, dtype=np.intp)
    buffers = loop.Buffers(np.zeros(1, dtype=np.uint32), offsets, np.zeros(1), np.zeros(1, dtype=np.uint32),
                           offsets, np.zeros(1, dtype=np.intp), np.zeros(1), np.zeros(n, dtype=bool))
    bools = loop.BooleanOutputs(_dummy(loop.VALUES_PROTOTYPE), 0, np.zeros(1, dtype=np.uint32),
                                np.zeros(1, dtype=np.int32))
    record = loop.Record(np.zeros(1), np.zeros((1, 1)), np.zeros((1, 1), dtype=np.int32))
    return calls, buffers, bools, record


def _advance() -> tuple:
    calls, buffers, bools, record = _bundles()
    return 0, 1, True, 0.0, 0.01, 1, 0, calls, buffers, bools, record


def _exchange() -> tuple:
    calls, buffers, _, _ = _bundles()
    return 0, calls, buffers


def kernel_jobs() -> list[Job]:
    """The master's kernels (costs: estimated compile time [s] on one core)."""
    return [
        Job("cosim.feed", loop.feed, _exchange, 1.0),
        Job("cosim.read", loop.read, _exchange, 1.0),
        Job("cosim.advance", loop.advance, _advance, 3.0),
    ]
