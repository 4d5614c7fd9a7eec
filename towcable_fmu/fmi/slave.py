"""Base class of the three FMU slaves: variables from the contract, errors as FMI statuses.

pythonfmu 0.7 turns any Python exception that leaves a slave method into ``fmi2Fatal``
and releases the Python instance (later calls on it are undefined), and its C layer
returns ``fmi2OK`` from every call that does not raise. The slaves therefore never
raise: :class:`ContractSlave` wraps every entry point and logs the reason with the
status the call should have; the FMU's loader layer (``towcable_fmu/fmu_build/csrc/
fmu_loader.c``) passes such messages to the host whatever its logging setting and makes
the call return the most severe status logged during it. So

* a parameter out of the contract's range is an ``fmi2Error`` of the setter (the value
  is not set), naming the parameter, the value and the range;
* a parameter or scene that cannot be used (unknown scene, a value the model rejects)
  is an ``fmi2Error`` of ``fmi2ExitInitializationMode``, with the key, the value and
  what is allowed; every later step is refused with ``fmi2Error``;
* a step that cannot be done (non-finite inputs, a step size <= 0, a communication point
  that is not the model's time, a solver failure) is ``fmi2Discard`` with the reason;
  the outputs keep their last valid values (never NaN).

The FMI 2.0 state machine (which call is allowed in which state, which variable may be
set when, unknown value references, untrusted FMU-state bytes) is enforced once, in the
loader layer (``csrc/state_machine.c``, applied in ``csrc/fmu_loader.c``), before a call
reaches pythonfmu; FMUs built without the layer (no C compiler, Windows) do not have it.
This class keeps the model-side rules: parameter ranges, refused steps, and a state that
cannot be restored leaving the instance as it was. Its setters hold the slave weakly, so
that the slave and its model are freed as soon as pythonfmu drops them (a reference
cycle kept them until the garbage collector's next full pass: on ``full_scale`` the heap
rose by 70 kB per instance life, now 9 kB; docs/design.md).

With the loader layer, an initialised slave hands its values over to the layer at the
end of every entry point (:mod:`towcable_fmu.fmi.shared_values`): the layer then answers
gets and sets of inputs without Python, and steps without Python where the subclass
gives a compiled step (:meth:`ContractSlave._compiled_functions`). Every entry point
first takes the values back (the inputs set and, after compiled calls, the outputs and
the communication time); a compiled call that declines lands in the Python method.

Subclasses set ``fmu_name`` (a key of ``[fmus]`` in the contract) and implement
``_initialize()``, ``_step(t, dt)`` and optionally ``_model_state()`` /
``_restore_model_state()``, ``_inputs_changed()`` and ``_compiled_functions()``.
"""

from __future__ import annotations

import functools
import json
import math
import numbers
import operator
import sys
import time
import traceback
import weakref
from typing import Any, Callable, ClassVar

import numpy as np
from pythonfmu import Boolean, Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.enums import Fmi2Status

from ..common import contract
from ..jit import kernel_cache
from ..common.errors import TowcableError
from .shared_values import SharedValues, loader_values_address

_TYPES = {"Real": Real, "Integer": Integer, "Boolean": Boolean, "String": String}
_CAST: dict[str, Callable[[Any], Any]] = {"Real": float, "Integer": int, "Boolean": bool, "String": str}

#: Version written to every modelDescription.xml.
MODEL_VERSION = "0.1.0"


@functools.cache
def ship_signal_names() -> tuple[str, ...]:
    """The 18 ``ship.*`` signals of the contract in ship-state order: row k of the
    (3, 6) state (value, rate, acceleration), columns x, y, z, roll, pitch, yaw."""
    names = tuple(n for n in contract.signals() if n.startswith("ship."))
    if len(names) != 18:
        raise ValueError(f"the contract must list 18 ship.* signals, found {len(names)}")
    return names


class ShipStateReader:
    """Builds the ship state (3, 6) from named values (a slave's ``values``).

    Parameters
    ----------
    names
        The ship signals the values hold (default: all 18); the others are 0 in the state.
    """

    def __init__(self, names: tuple[str, ...] | None = None) -> None:
        all_names = ship_signal_names()
        given = all_names if names is None else tuple(name for name in all_names if name in names)
        self._get = values_getter(given)
        # the usual cases (all signals, or positions and rates without accelerations) are a
        # prefix of the state: padded with zeros in one array call
        self._prefix = given == all_names[:len(given)]
        self._padding = (0.0,) * (18 - len(given))
        self._index = np.array([all_names.index(name) for name in given], dtype=np.intp)
        #: the signals read, in ship-state order
        self.names = given

    def __call__(self, values: dict[str, Any]) -> np.ndarray:
        """The ship state: rows position/attitude [m, rad], their rates [m/s, rad/s] and
        accelerations [m/s^2, rad/s^2]; columns x, y, z, roll, pitch, yaw."""
        if self._prefix:
            return np.array(self._get(values) + self._padding, dtype=float).reshape(3, 6)
        state = np.zeros(18)
        state[self._index] = self._get(values)
        return state.reshape(3, 6)


@functools.cache
def values_getter(names: tuple[str, ...]) -> Callable[[Any], tuple]:
    """A function returning the values of ``names`` in a mapping as a tuple (any number of
    names; one C-level ``itemgetter`` lookup for two or more)."""
    if len(names) >= 2:
        return operator.itemgetter(*names)
    return lambda mapping: tuple(mapping[name] for name in names)


def _entry(hand_over: str) -> Callable:
    """Decorate an FMI entry point of :class:`ContractSlave`: the values are taken back from
    the loader layer first and handed over again at the end (``hand_over``: ``"all"``
    values, or only the ``"outputs"`` for an entry point that changes no other value)."""

    def decorate(method: Callable) -> Callable:
        @functools.wraps(method)
        def entry(self, *args, **kwargs):
            if self._shared is None or self._in_entry:  # no layer, or called by another entry point
                return method(self, *args, **kwargs)
            self._in_entry = True
            try:
                self._take_back()
                return method(self, *args, **kwargs)
            finally:
                self._hand_over(hand_over)
                self._in_entry = False

        return entry

    return decorate


def _in_range(var: contract.Variable, value: Any) -> bool:
    """Whether a parameter value lies in the contract's range (always, without one)."""
    if var.min is None and var.max is None:
        return True
    return (isinstance(value, numbers.Real) and not math.isnan(value)
            and (var.min is None or value >= var.min) and (var.max is None or value <= var.max))


def _range_text(var: contract.Variable) -> str:
    unit = f" {var.unit}" if var.unit and var.unit != "1" else ""
    if var.min is not None and var.max is not None:
        return f"[{var.min:g}, {var.max:g}]{unit}"
    return f">= {var.min:g}{unit}" if var.min is not None else f"<= {var.max:g}{unit}"


def _carried_kernels_note() -> str:
    """Why the precompiled kernels the FMU carries did not serve (the activation module
    records it, :func:`towcable_fmu.jit.machine_cache.use_carried_kernels`), as a clause of
    the compile message; empty if they were not looked for."""
    package = __name__.split(".")[0]
    reason = getattr(sys.modules.get(f"{package}_activate"), "CARRIED_KERNELS", {}).get(package)
    return f"; its precompiled kernels were not used: {reason}" if reason else ""


class ContractSlave(Fmi2Slave):
    """A pythonfmu slave whose variables are those of one FMU of the contract.

    Variable values live in ``self.values`` (name -> value). Value references follow
    the contract order: parameters, inputs, outputs.
    """

    #: Key of ``[fmus]`` in the contract.
    fmu_name: ClassVar[str] = ""

    def __init__(self, **kwargs) -> None:
        super().__init__(**kwargs)
        spec = contract.fmu(self.fmu_name)
        self.spec = spec
        self.modelName = spec.name
        self.description = spec.description
        self.author = "towcable"
        self.version = MODEL_VERSION
        self.license = "MIT"
        self.values: dict[str, Any] = {}
        self.start_time = 0.0
        self.initialized = False
        self.failed: str | None = None
        self.in_initialization = False
        self._model_time = 0.0
        self._communication_time = 0.0  # the time the next step starts from [s]
        for var in spec.variables:
            self.values[var.name] = var.start if var.start is not None else _CAST[var.type](0)
            self.register_variable(self._scalar(var), nested=False)
        self._output_slots = [(v.name, _CAST[v.type], v.type == "Real") for v in spec.outputs if not v.diagnostic]
        self._real_input_names = tuple(v.name for v in spec.inputs if v.type == "Real")
        # the per-step paths look names up in C (itemgetter) and test finiteness in C (map)
        self._real_input_values = values_getter(self._real_input_names)
        self._output_copy: _OutputCopy | None = None
        # block access without pythonfmu's per-variable dispatch: value reference -> name
        self._readable = {kind.__name__: {vr: var.name for vr, var in self.vars.items() if isinstance(var, kind)}
                          for kind in (Real, Boolean)}
        self._real_inputs = {vr: var.name for vr, var in self.vars.items()
                             if isinstance(var, Real) and var.causality == Fmi2Causality.input}
        self._last_block: dict[int, tuple[list[int], tuple[tuple[str, ...], Callable[[Any], tuple]]]] = {}
        self._in_entry = False
        self._shared = self._share(kwargs.get("resources"))
        self._compiled: tuple | None = None  # the compiled functions handed over last

    # ------------------------------------------------------------ values shared with the loader
    def _share(self, resources: str | None) -> SharedValues | None:
        """The loader layer's shared values for this instance (None: no layer)."""
        try:
            address = loader_values_address(resources, self.spec.name)
            if not address:
                return None
            groups: dict[str, list] = {"input": [], "output": [], "other": []}
            for vr, var in self.vars.items():
                if isinstance(var, (Real, Integer, Boolean)):
                    kind = var.causality.name if var.causality.name in ("input", "output") else "other"
                    groups[kind].append((var.name, vr, _CAST[type(var).__name__]))
            return SharedValues(address, groups["input"], groups["output"], groups["other"])
        except Exception as exc:  # noqa: BLE001 - the slave works without: it serves every call itself
            self.log(f"{self.instance_name}: the loader's shared values are not used: {exc}", Fmi2Status.warning)
            return None

    def _take_back(self) -> None:
        """Take the values back from the loader layer if it serves them: the inputs set
        there (the model is told, :meth:`_inputs_changed`), the outputs and the time of
        its compiled calls."""
        shared = self._shared
        if not shared.served:
            return
        outputs = self._compiled is not None or shared.outputs_changed
        inputs_set, now = shared.take_back(self.values, outputs)
        self._communication_time = now
        if outputs and "model_wall_time" in self.values:
            self._model_time = self.values["model_wall_time"]
        if inputs_set:
            self._guard("inputs", self._inputs_changed)

    def _hand_over(self, which: str) -> None:
        """Let the loader layer serve the values (an initialised slave that has not
        failed) with the compiled functions of :meth:`_compiled_functions`."""
        if not self.initialized or self.failed is not None or self.in_initialization:
            return
        try:
            compiled = self._compiled_functions()
            if compiled is not None:
                step, outputs, model = compiled
                timer = next((vr for vr, var in self.vars.items() if var.name == "model_wall_time"), -1)
                compiled = (step, outputs, model, timer)
            if (compiled is None) != (self._compiled is None):
                which = "all"  # the loader has not the outputs of the other kind of step
            self._compiled = compiled
            self._shared.hand_over(self.values, self._communication_time, which, compiled)
        except Exception as exc:  # noqa: BLE001 - nothing may reach pythonfmu's C layer
            self._shared.withdraw()
            self._compiled = None
            self._report("shared values", exc, Fmi2Status.warning)

    def _step_values(self, t: float, dt: float, values: np.ndarray) -> bool:
        """Advance from ``t`` by ``dt`` [s] reading the inputs from and writing the outputs
        (``model_wall_time`` too) into the shared ``values`` (by value reference); False,
        with nothing changed, if the step is for :meth:`_step` to make or refuse (it is
        then called). Default: always False."""
        return False

    def _compiled_functions(self) -> tuple[int, int, np.ndarray] | None:
        """The model's step compiled for the loader layer, if it has one in its present
        configuration: (the address of a ``CompiledStep``, that of a ``CompiledOutputs``
        or 0, the float64 array they take as data; ``fmu_build/csrc/shared_values.h``).
        Default: none (steps run in Python)."""
        return None

    def _buffer_size(self) -> int:
        """The number of shared values (value references 0 .. size - 1)."""
        return self._shared.values.size

    # ------------------------------------------------------------ registration
    def _scalar(self, var: contract.Variable):
        name, cast = var.name, _CAST[var.type]
        values = self.values
        # the setters reach the slave through a weak reference: a closure holding the slave
        # would make a reference cycle (slave -> variable -> setter -> slave) that keeps the
        # freed slave and its model alive until the garbage collector's next full pass
        slave = weakref.ref(self)

        def getter():
            return values[name]

        kw: dict[str, Any] = {"description": var.description}
        if var.causality == "parameter":
            kw["causality"] = Fmi2Causality.parameter
            kw["variability"] = Fmi2Variability.fixed  # every parameter acts at initialisation only
            kw["initial"] = Fmi2Initial.exact

            def setter(value):
                if slave().initialized:
                    slave().log(f"parameter '{name}' is fixed after initialisation; the new value is ignored",
                                Fmi2Status.warning)
                    return
                value = cast(value)
                if not _in_range(var, value):
                    slave().log_error(f"parameter {name} = {value!r} is invalid: allowed {_range_text(var)}; "
                                      "the value is not set")
                    return
                values[name] = value
        elif var.causality == "input":
            kw["causality"] = Fmi2Causality.input
            kw["variability"] = Fmi2Variability.discrete if var.type == "Boolean" else Fmi2Variability.continuous

            def setter(value):
                values[name] = cast(value)
        else:
            kw["causality"] = Fmi2Causality.output
            kw["variability"] = Fmi2Variability.discrete if var.type == "Boolean" else Fmi2Variability.continuous
            kw["initial"] = Fmi2Initial.calculated  # computed at initialisation (an InitialUnknown)

            def setter(value):
                slave().log(f"'{name}' is an output and cannot be set", Fmi2Status.warning)
        return _TYPES[var.type](name, getter=getter, setter=setter, **kw)

    # ------------------------------------------------------------ logging
    def log_error(self, message: str, status: Fmi2Status = Fmi2Status.error) -> None:
        """Log a message for the host (category from the status)."""
        self.log(f"{self.instance_name}: {message}", status)

    def _guard(self, what: str, fn: Callable[[], Any], default: Any = None, status=Fmi2Status.error) -> Any:
        """Run ``fn``; on any exception log it and return ``default`` (never raise to pythonfmu)."""
        try:
            return fn()
        except Exception as exc:  # noqa: BLE001 - nothing may reach pythonfmu's C layer
            self._report(what, exc, status)
        return default

    def _report(self, what: str, exc: Exception, status: Fmi2Status) -> None:
        """Log an exception: our own errors by their message, anything else with its traceback."""
        if isinstance(exc, TowcableError):
            self.log_error(f"{what}: {exc}", status)
        else:
            self.log_error(f"{what}: unexpected {type(exc).__name__}: {exc}\n{traceback.format_exc()}", status)

    def timed(self, fn: Callable[..., Any], *args, **kwargs) -> Any:
        """Call the model's own computation and add its wall time to ``model_wall_time``."""
        t0 = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            self._model_time += time.perf_counter() - t0
            if "model_wall_time" in self.values:
                self.values["model_wall_time"] = self._model_time

    # ------------------------------------------------------------ FMI entry points
    @_entry("all")
    def setup_experiment(self, start_time: float, stop_time=None, tolerance=None) -> None:
        self.start_time = float(start_time)

    @_entry("all")
    def enter_initialization_mode(self) -> None:
        self.in_initialization = True
        self._guard("inputs", self._inputs_changed, status=Fmi2Status.warning)

    @_entry("all")
    def exit_initialization_mode(self) -> None:
        def run():
            if not math.isfinite(self.start_time):
                raise ValueError(f"start time {self.start_time} is not finite")
            self._initialize()
            return True

        compiling = kernel_cache.WATCH.seconds
        ok = self._guard("initialisation failed", run, default=False)
        compiling = kernel_cache.WATCH.seconds - compiling
        if compiling > 0.0:
            self.log(f"{self.instance_name}: compiled the numerical kernels in {compiling:.0f} s (first use of "
                     f"this code on this machine; cached in {kernel_cache.kernel_folder()}){_carried_kernels_note()}")
        self.in_initialization = False
        if ok:
            self.initialized = True
            self.failed = None
            self._communication_time = self.start_time
        else:
            self.failed = "initialisation failed (see the previous message); the FMU cannot step"

    def do_step(self, current_time: float, step_size: float) -> bool:
        if self._shared is not None and not self._in_entry and self._step_in_buffer(current_time, step_size):
            return True
        return self._do_step(current_time, step_size)

    def _step_in_buffer(self, t: float, dt: float) -> bool:
        """A step on the values the loader layer serves, left there (:meth:`_step_values`);
        False if it is not made (not served, compiled functions handed over, a step the
        Python step must refuse or report), with nothing changed."""
        shared = self._shared
        if not shared.served or self._compiled is not None:
            return False
        header = shared.header
        if not (math.isfinite(t) and math.isfinite(dt) and dt > 0.0) or abs(t - header.time) > 1e-9 * max(1.0, abs(t)):
            return False
        if not self._step_values(t, dt, shared.values):
            return False
        header.time = self._communication_time = t + dt
        shared.outputs_changed = True
        return True

    @_entry("outputs")
    def _do_step(self, current_time: float, step_size: float) -> bool:
        try:
            if self.failed is not None:
                self.log_error(self.failed)
                return False
            if not self.initialized:
                self.log_error("do_step before exit_initialization_mode")
                return False
            if not (math.isfinite(step_size) and step_size > 0.0):
                self.log_error(f"communication step size {step_size!r} is invalid: allowed a finite step > 0 s",
                               Fmi2Status.discard)
                return False
            if not math.isfinite(current_time):
                self.log_error(f"communication point {current_time!r} is not finite", Fmi2Status.discard)
                return False
            now = self._communication_time
            if abs(current_time - now) > 1e-9 * max(1.0, abs(current_time)):
                self.log_error(f"communication point t = {current_time!r} s is not the model time {now!r} s "
                               "(steps must follow each other, or restore a state first)", Fmi2Status.discard)
                return False
            if not self._step(float(current_time), float(step_size)):
                return False
            self._communication_time = current_time + step_size
            return True
        except Exception as exc:  # noqa: BLE001 - nothing may reach pythonfmu's C layer
            self._report(f"step from t = {current_time:.6g} s by {step_size:.6g} s failed", exc, Fmi2Status.discard)
            return False

    @_entry("all")
    def terminate(self) -> None:
        pass

    def _block(self, table: dict[int, str], vrs) -> tuple[tuple[str, ...], Callable[[Any], tuple]] | None:
        """Names of the value references ``vrs`` in ``table`` and the getter of their values
        (:func:`values_getter`); None if one reference is not in the table.

        A master sends the same block of references at every step: the last block asked
        of each table is kept with its names and getter, and a repeated block is
        recognised by one list comparison.
        """
        last = self._last_block.get(id(table))
        if last is not None and last[0] == vrs:
            return last[1]
        try:
            names = tuple(table[vr] for vr in vrs)
        except KeyError:
            return None
        block = (names, values_getter(names))
        self._last_block[id(table)] = (list(vrs), block)
        return block

    def _read(self, kind: str, vrs) -> list | None:
        """Values of ``vrs`` if all are variables of type ``kind``, else None."""
        block = self._block(self._readable[kind], vrs)
        if block is None:
            return None
        return list(block[1](self.values))

    @_entry("outputs")
    def get_real(self, vrs):
        fast = self._read("Real", vrs)
        if fast is not None:
            return fast
        return self._guard("getReal", lambda: super(ContractSlave, self).get_real(vrs), default=[0.0] * len(vrs))

    @_entry("outputs")
    def get_integer(self, vrs):
        return self._guard("getInteger", lambda: super(ContractSlave, self).get_integer(vrs), default=[0] * len(vrs))

    @_entry("outputs")
    def get_boolean(self, vrs):
        fast = self._read("Boolean", vrs)
        if fast is not None:
            return fast
        return self._guard("getBoolean", lambda: super(ContractSlave, self).get_boolean(vrs),
                           default=[False] * len(vrs))

    @_entry("outputs")
    def get_string(self, vrs):
        return self._guard("getString", lambda: super(ContractSlave, self).get_string(vrs), default=[""] * len(vrs))

    @_entry("all")
    def set_real(self, vrs, values):
        block = self._block(self._real_inputs, vrs)
        if block is None:  # parameters, outputs or unknown references: pythonfmu's checks and messages
            self._guard("setReal", lambda: super(ContractSlave, self).set_real(vrs, values))
        else:  # inputs only: no per-variable setter needed
            self.values.update(zip(block[0], map(float, values)))
        self._guard("inputs", self._inputs_changed)

    @_entry("all")
    def set_integer(self, vrs, values):
        self._guard("setInteger", lambda: super(ContractSlave, self).set_integer(vrs, values))
        self._guard("inputs", self._inputs_changed)

    @_entry("all")
    def set_boolean(self, vrs, values):
        self._guard("setBoolean", lambda: super(ContractSlave, self).set_boolean(vrs, values))
        self._guard("inputs", self._inputs_changed)

    @_entry("all")
    def set_string(self, vrs, values):
        self._guard("setString", lambda: super(ContractSlave, self).set_string(vrs, values))
        self._guard("inputs", self._inputs_changed)

    # ------------------------------------------------------------ state
    @_entry("outputs")
    def _get_fmu_state(self) -> dict[str, Any]:
        def run():
            return {"fmu": self.fmu_name, "values": dict(self.values), "initialized": self.initialized,
                    "failed": self.failed, "start_time": self.start_time, "time": self._communication_time,
                    "model": self._model_state() if self.initialized else None}

        return self._guard("getFMUstate", run, default={"fmu": self.fmu_name, "invalid": True})

    @_entry("all")
    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        """Restore a state of :meth:`_get_fmu_state`; a state that cannot be restored is an
        error and leaves the instance as it was (the state before the call is put back)."""

        def check(saved: dict[str, Any]) -> None:
            if saved.get("fmu") != self.fmu_name or saved.get("invalid"):
                reason = saved.get("invalid") if isinstance(saved.get("invalid"), str) else "it is not valid"
                raise TowcableError(f"the state does not belong to a valid {self.fmu_name} instance ({reason})")
            if not isinstance(saved.get("values"), dict) or not set(saved["values"]) <= set(self.values):
                raise TowcableError(f"the state's values are not those of {self.fmu_name}")

        def run(saved: dict[str, Any]) -> None:
            keep = self._model_time
            self.values.update(saved["values"])
            self.values["model_wall_time"] = keep
            self.start_time = float(saved["start_time"])
            self._communication_time = float(saved["time"])
            self.failed = saved["failed"]
            self.initialized = bool(saved["initialized"])
            if self.initialized:
                self._restore_model_state(saved["model"])

        if not self._guard("setFMUstate", lambda: check(state) or True, default=False):
            return
        before = self._get_fmu_state()
        if self._guard("setFMUstate", lambda: run(state) or True, default=False):
            return
        if not self._guard("setFMUstate (putting the previous state back)", lambda: run(before) or True,
                           default=False):
            self.failed = "the FMU state could not be restored, nor the previous one (see the previous messages)"

    @staticmethod
    def _fmu_state_to_bytes(state: dict[str, Any]) -> bytes:
        """The state as JSON text (pythonfmu calls this on the class: it must never raise,
        or pythonfmu releases the instance's Python objects; a state that cannot be
        encoded becomes an invalid state that :meth:`_set_fmu_state` refuses)."""
        try:
            return json.dumps(state).encode("utf-8")
        except (TypeError, ValueError) as exc:
            return json.dumps({"invalid": f"the state could not be encoded: {exc}"}).encode("utf-8")

    @staticmethod
    def _fmu_state_from_bytes(data: bytes) -> dict[str, Any]:
        """The state of JSON text; text that is not a state's becomes an invalid state that
        :meth:`_set_fmu_state` refuses (never raises, see :meth:`_fmu_state_to_bytes`).
        The loader layer has checked the bytes' FMU, build and checksum before."""
        try:
            state = json.loads(data.decode("utf-8"))
        except (UnicodeDecodeError, ValueError) as exc:
            return {"invalid": f"the bytes are not JSON text: {exc}"}
        return state if isinstance(state, dict) else {"invalid": "the JSON text is not an object"}

    # ------------------------------------------------------------ hooks
    def _initialize(self) -> None:
        """Build the model from the parameters and compute the outputs at ``start_time``."""
        raise NotImplementedError

    def _step(self, t: float, dt: float) -> bool:
        """Advance from ``t`` by ``dt``; return False (after logging) if the step cannot be done."""
        raise NotImplementedError

    def _model_state(self) -> Any:
        """JSON-able model state beyond the variable values (default: none)."""
        return None

    def _restore_model_state(self, data: Any) -> None:
        """Restore :meth:`_model_state` (the variable values are already restored)."""

    def _inputs_changed(self) -> None:
        """Called after every set* call and on entering initialisation mode (direct-feedthrough
        models recompute their outputs)."""

    # ------------------------------------------------------------ helpers
    def non_finite_inputs(self) -> list[str]:
        """Names of Real inputs that are NaN or infinite."""
        values = self.values
        if all(map(math.isfinite, self._real_input_values(values))):
            return []
        return [name for name in self._real_input_names if not math.isfinite(values[name])]

    def set_outputs(self, outputs: dict[str, Any]) -> list[str]:
        """Copy outputs by name (names the model does not provide, or gives as None, become 0 / false).

        Returns the names not provided. Raises ValueError (nothing copied) if a Real value
        is not a finite number.
        """
        copy = self._output_copy
        if copy is None or outputs.keys() != copy.keys:  # the model provides other names than last time
            copy = self._output_copy = _OutputCopy(self._output_slots, outputs)
        reals = copy.reals(outputs)
        try:
            finite = all(map(math.isfinite, reals))
        except TypeError:
            finite = False
        if not finite:
            for name, value in zip(copy.real_names, reals):
                if not (isinstance(value, numbers.Real) and math.isfinite(value)):
                    raise ValueError(f"output '{name}' = {value!r} is not a finite number")
        values = self.values
        values.update(zip(copy.real_names, map(float, reals)))
        if copy.others:
            values.update((name, cast(outputs[name])) for name, cast in copy.others)
        if copy.zeros:
            values.update(copy.zeros)
        return list(copy.missing)


class _OutputCopy:
    """How :meth:`ContractSlave.set_outputs` copies outputs that provide one set of names
    (worked out once: a model provides the same names at every step).

    Parameters
    ----------
    slots
        The FMU's outputs: (name, cast, is Real).
    outputs
        The model's outputs (name -> value; None counts as not provided).
    """

    def __init__(self, slots: list[tuple[str, Callable[[Any], Any], bool]], outputs: dict[str, Any]) -> None:
        # with a None value the key set differs from ``outputs.keys()``: rebuilt at every call
        self.keys = frozenset(name for name, value in outputs.items() if value is not None)
        self.real_names = tuple(name for name, _, real in slots if real and name in self.keys)
        self.reals = values_getter(self.real_names)
        self.others = tuple((name, cast) for name, cast, real in slots if not real and name in self.keys)
        self.zeros = {name: cast(0) for name, cast, _ in slots if name not in self.keys}
        self.missing = tuple(self.zeros)
