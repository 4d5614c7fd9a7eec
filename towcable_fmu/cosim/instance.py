"""One FMU under the master: instantiate, log, set and get values, step (fmpy's low-level API)."""

from __future__ import annotations

import ctypes
import itertools
import shutil
import sys
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from ..common import contract
from ..common.errors import TowcableError


class CosimError(TowcableError, RuntimeError):
    """An FMU refused to initialise or to step; the message carries the FMU's log."""


# ---------------------------------------------------------------------------- one FMU
#: Instances by the component environment their FMU passes back to the logger.
_LOG_TARGETS: dict[int, "FmuInstance"] = {}
_ENVIRONMENT_IDS = itertools.count(1)
#: The one ctypes logger of this process (kept alive here; see ``FmuInstance.instantiate``).
_LOG_ROUTER = None


def _route_log_message(env, instance, status, category, message) -> None:
    """Hand an FMU's log message to the :class:`FmuInstance` whose environment id ``env`` is."""
    target = _LOG_TARGETS.get(int(env or 0))
    if target is not None:
        target._logger(env, instance, status, category, message)


class FmuInstance:
    """One FMU instance on fmpy's low-level FMI 2.0 interface, addressed by contract names.

    Parameters
    ----------
    spec
        The FMU's contract entry.
    path
        The ``.fmu`` file.
    instance_name
        Instance name (default: the FMU name).
    echo
        Print the FMU's warnings and errors on stderr as they arrive.
    """

    def __init__(self, spec: contract.FmuSpec, path: str | Path, instance_name: str | None = None,
                 echo: bool = True) -> None:
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.spec = spec
        self.name = instance_name or spec.name
        self.md = read_model_description(str(path))
        self.unzipdir = extract(str(path))
        self.variables = {v.name: v for v in self.md.modelVariables}
        missing = [v.name for v in spec.variables if v.name not in self.variables]
        if missing:
            raise CosimError(f"{path} lacks the contract variables {', '.join(missing)}: rebuild the FMUs")
        self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzipdir,
                             modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=self.name)
        self.messages: list[tuple[int, str]] = []
        self.echo = echo
        self.real_outputs = [v.name for v in spec.outputs if v.type == "Real"]
        self.bool_outputs = [v.name for v in spec.outputs if v.type == "Boolean"]
        self.real_output_vrs = self.vrs(self.real_outputs)
        self.bool_output_vrs = self.vrs(self.bool_outputs)
        self._callbacks = None
        self.active = False

    def vrs(self, names: Iterable[str]) -> list[int]:
        """Value references of variables by name."""
        return [self.variables[n].valueReference for n in names]

    # -------------------------------------------------------------- lifecycle
    def _logger(self, env, instance, status, category, message) -> None:
        text = message.decode("utf-8", "replace") if isinstance(message, bytes) else str(message)
        self.messages.append((int(status), text))
        if self.echo and status >= 1:
            label = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "PENDING"][min(int(status), 5)]
            print(f"[{self.name}] {label}: {text}", file=sys.stderr)

    def instantiate(self, start_time: float = 0.0, logging_on: bool = True) -> None:
        """fmi2Instantiate (with a logger that keeps the messages) and fmi2SetupExperiment."""
        from fmpy import calloc, free
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE, fmi2CallbackFunctions,
                               fmi2CallbackLoggerTYPE)

        callbacks = fmi2CallbackFunctions()
        # fmpy's logger proxy keeps ONE process-wide logger: the same router for every
        # instance, which hands each message to the instance named by its environment
        global _LOG_ROUTER
        if _LOG_ROUTER is None:
            _LOG_ROUTER = fmi2CallbackLoggerTYPE(_route_log_message)
        self._environment = next(_ENVIRONMENT_IDS)
        _LOG_TARGETS[self._environment] = self
        callbacks.logger = _LOG_ROUTER
        callbacks.componentEnvironment = self._environment
        callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        try:
            from fmpy.logging import addLoggerProxy

            addLoggerProxy(ctypes.byref(callbacks))
        except Exception:  # noqa: BLE001 - without the proxy messages arrive unformatted
            pass
        self._callbacks = callbacks
        self.fmu.instantiate(callbacks=callbacks, loggingOn=logging_on)
        self.active = True
        self.fmu.setupExperiment(startTime=start_time)

    def set_parameters(self, values: Mapping[str, Any]) -> None:
        """Set parameters by name, one call per FMI type."""
        by_type: dict[str, tuple[list[int], list[Any]]] = {}
        for name, value in values.items():
            var = self.variables[name]
            vrs, vals = by_type.setdefault(var.type, ([], []))
            vrs.append(var.valueReference)
            vals.append(value)
        for kind, (vrs, vals) in by_type.items():
            setter = {"Real": self.fmu.setReal, "Integer": self.fmu.setInteger, "Boolean": self.fmu.setBoolean,
                      "String": self.fmu.setString}[kind]
            cast = {"Real": float, "Integer": int, "Boolean": bool, "String": str}[kind]
            setter(vrs, [cast(v) for v in vals])

    def errors_since(self, mark: int) -> list[str]:
        """Messages with status error or worse logged after message number ``mark``."""
        return [text for status, text in self.messages[mark:] if status >= 3]

    def log_text(self, mark: int = 0, least: int = 1) -> str:
        """The messages since ``mark`` with status >= ``least``, one per line."""
        return "\n".join(text for status, text in self.messages[mark:] if status >= least)

    def call(self, what: str, fn: Callable[..., Any], *args) -> Any:
        """Call an FMI function; turn a failure status into :class:`CosimError` with the FMU's log."""
        from fmpy.fmi1 import FMICallException

        mark = len(self.messages)
        try:
            return fn(*args)
        except FMICallException as exc:
            log = self.log_text(mark) or "(no message)"
            raise CosimError(f"{self.name}: {what} failed ({exc}): {log}") from None

    def exit_initialization(self) -> None:
        """fmi2ExitInitializationMode; raises CosimError if the FMU logged an error."""
        mark = len(self.messages)
        self.call("exitInitializationMode", self.fmu.exitInitializationMode)
        errors = self.errors_since(mark)
        if errors:
            prefix, text = f"{self.name}: initialisation failed", "\n".join(errors)
            raise CosimError(text if text.startswith(prefix) else f"{prefix}: {text}")  # our slaves say it

    def get_outputs(self) -> np.ndarray:
        """All Real outputs (contract order) in one fmi2GetReal."""
        return np.array(self.fmu.getReal(self.real_output_vrs))

    def free(self) -> None:
        """fmi2Terminate, fmi2FreeInstance, remove the extracted files."""
        if self.active:
            self.active = False
            try:
                self.fmu.terminate()
            except Exception:  # noqa: BLE001 - a failed FMU may refuse to terminate
                pass
            self.fmu.freeInstance()
            _LOG_TARGETS.pop(self._environment, None)
        shutil.rmtree(self.unzipdir, ignore_errors=True)
