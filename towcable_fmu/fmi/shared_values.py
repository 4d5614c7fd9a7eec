"""The values a slave shares with the FMU's loader layer (``fmu_build/csrc/shared_values.h``).

While the slave has handed its values over (:meth:`SharedValues.hand_over`), the loader
answers gets and sets of Real inputs from the buffer and, with a compiled step, steps
without Python; any call that reaches the slave finds the values it must take back
first (:meth:`SharedValues.take_back`). The slave finds the buffer of the instance being
created through an exported function of its own FMU's loader library, already loaded
in the process (``dlopen`` with ``RTLD_NOLOAD``): no FMI call carries the address, and
the function answers only during ``fmi2Instantiate`` and ``fmi2Reset``. Without the
loader (an FMU built without a C compiler, the slave used in-process) there is nothing
to share and the slave serves every call itself.
"""

from __future__ import annotations

import ctypes
import operator
import os
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

#: ``SHARED_VALUES_VERSION`` of shared_values.h.
VERSION = 1
#: Set to 1 to keep every call in Python (for comparisons).
PASS_THROUGH_ENV = "TOWCABLE_FMU_PASS_THROUGH"


class _Header(ctypes.Structure):
    """The fixed part of shared_values.h's ``SharedValues``."""

    _fields_ = [("version", ctypes.c_uint32), ("served", ctypes.c_int32), ("inputs_set", ctypes.c_int32),
                ("outputs_stale", ctypes.c_int32), ("compiled_steps", ctypes.c_uint64), ("time", ctypes.c_double),
                ("timer_vr", ctypes.c_int64), ("step", ctypes.c_void_p), ("outputs", ctypes.c_void_p),
                ("model", ctypes.c_void_p), ("count", ctypes.c_uint64)]


def loader_values_address(resources: str | None, model_identifier: str) -> int:
    """The address of the shared values the FMU's loader made for the instance being
    created on this thread (0: none: no loader, or not inside ``fmi2Instantiate``)."""
    if not resources or os.environ.get(PASS_THROUGH_ENV) == "1" or not hasattr(os, "RTLD_NOLOAD"):
        return 0  # (the layer is Linux's)
    library = Path(resources).parent / "binaries" / "linux64" / f"{model_identifier}.so"
    try:
        loader = ctypes.CDLL(str(library), mode=os.RTLD_NOLOAD | os.RTLD_LAZY)
    except OSError:  # not loaded in this process (or not there)
        return 0
    try:
        function = getattr(loader, "towcable_shared_values", None)
        if function is None:  # pythonfmu's own library: an FMU built without the layer
            return 0
        function.restype = ctypes.c_void_p
        return function() or 0
    finally:
        import _ctypes

        _ctypes.dlclose(loader._handle)  # the host keeps the library loaded


class SharedValues:
    """A slave's view of the loader's shared values.

    Parameters
    ----------
    address
        :func:`loader_values_address`.
    inputs, outputs
        Names and value references of the inputs and outputs (Real, Integer or Boolean),
        each with the cast of its type; ``outputs`` includes every output a compiled call
        may change.
    others
        The same of the other variables (parameters): written by :meth:`hand_over` only.
    """

    def __init__(self, address: int, inputs: Sequence[tuple[str, int, Callable]],
                 outputs: Sequence[tuple[str, int, Callable]], others: Sequence[tuple[str, int, Callable]]) -> None:
        header = _Header.from_address(address)
        if header.version != VERSION:
            raise ValueError(f"shared values of version {header.version}, expected {VERSION}")
        self.header = header
        count = int(header.count)
        self.values = np.ctypeslib.as_array((ctypes.c_double * count).from_address(address + ctypes.sizeof(_Header)))
        for name, vr, _ in (*inputs, *outputs, *others):
            if not 0 <= vr < count:
                raise ValueError(f"value reference {vr} of {name} is not in the shared values (0 to {count - 1})")
        self._inputs = _Group(inputs)
        self._outputs = _Group(outputs)
        self._all = _Group((*inputs, *outputs, *others))
        self._model: Any = None  # the compiled functions' data, kept alive while served
        #: the slave changed outputs in the buffer since the hand-over (its own step there)
        self.outputs_changed = False

    @property
    def served(self) -> bool:
        """Whether the loader holds the values (the slave must take them back)."""
        return bool(self.header.served)

    def take_back(self, values: dict[str, Any], outputs: bool) -> tuple[bool, float]:
        """Stop the loader serving and copy what changed there into ``values``: the inputs
        (if any were set) and, if ``outputs`` (compiled calls or a step of the slave's on
        the buffer may have changed them), the outputs.

        Returns
        -------
        (inputs_set, time)
            Whether inputs were set since the hand-over, and the communication point the
            next step starts from [s].
        """
        header = self.header
        header.served = 0
        inputs_set = bool(header.inputs_set)
        if inputs_set:
            self._inputs.read(self.values, values)
            header.inputs_set = 0
        if outputs:
            self._outputs.read(self.values, values)
        self.outputs_changed = False
        return inputs_set, header.time

    def hand_over(self, values: dict[str, Any], time: float, which: str, compiled=None) -> None:
        """Copy ``values`` into the buffer (``"all"``, or only the ``"outputs"`` after a step
        of the slave's) and let the loader serve.

        Parameters
        ----------
        values
            Name -> value.
        time
            The communication point the next step starts from [s].
        which
            ``"all"`` or ``"outputs"``.
        compiled
            None, or (step address, outputs address or 0, model data array, timer value
            reference or -1): the slave's compiled functions (:mod:`towcable_fmu.fmi.slave`).
        """
        (self._all if which == "all" else self._outputs).write(values, self.values)
        header = self.header
        header.time = time
        header.inputs_set = 0
        header.outputs_stale = 0
        if compiled is None:
            header.step = header.outputs = header.model = None
            header.timer_vr = -1
            self._model = None
        else:
            step, outputs, model, timer_vr = compiled
            self._model = model
            header.model = model.ctypes.data
            header.step = step or None
            header.outputs = outputs or None
            header.timer_vr = timer_vr
        header.served = 1

    def withdraw(self) -> None:
        """Stop the loader serving (the slave keeps its values)."""
        self.header.served = 0


class _Group:
    """Variables copied together between a values dict and the buffer."""

    def __init__(self, items: Sequence[tuple[str, int, Callable]]) -> None:
        reals = [(name, vr) for name, vr, cast in items if cast is float]
        self.real_names = tuple(name for name, _ in reals)
        self.real_vrs = np.array([vr for _, vr in reals], dtype=np.intp)
        self.others = tuple((name, vr, cast) for name, vr, cast in items if cast is not float)
        names = self.real_names
        self._get = operator.itemgetter(*names) if len(names) >= 2 else (lambda mapping: tuple(mapping[n] for n in names))

    def read(self, buffer: np.ndarray, values: dict[str, Any]) -> None:
        values.update(zip(self.real_names, buffer[self.real_vrs].tolist()))
        for name, vr, cast in self.others:
            values[name] = cast(buffer[vr])

    def write(self, values: dict[str, Any], buffer: np.ndarray) -> None:
        if self.real_names:
            buffer[self.real_vrs] = self._get(values)
        for name, vr, _ in self.others:
            buffer[vr] = float(values[name])
