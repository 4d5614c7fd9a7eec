"""Randomised misuse of an FMU (issue 37): call scripts, what FMI 2.0 says each call
returns, and an executor of the scripts in this process (ctypes, no fmpy wrapper).

A script is text, one FMI call a line: ``EXPECTED OP ARGS...`` with EXPECTED the status
the call must return (0 OK ... 4 fatal; ``-`` for lines that are no FMI call or return
nothing). The same scripts run in the C test host (``tests/c_host/fmu_host.c
--misuse``), also under valgrind. Operations (I instance slot, F FMU 0 = the FMU under
test / 1 = another one, S state slot, B byte-buffer slot, VR value reference)::

    inst I F NAME          fmi2Instantiate (status 0: an instance, else NULL expected)
    free I                 fmi2FreeInstance (the slot keeps the stale pointer)
    setup I T0 / enter I / exit I / term I / reset I / step I T H
    setr I VR X / seti I VR N / setb I VR N / sets I VR TEXT   one value each
    getr I VR / geti I VR / getb I VR / gets I VR              one value each
    getr_null I            fmi2GetReal with a NULL value-reference array for one value
    record I VR,VR,...     fmi2GetReal; the values are the run's record
    gstate I S / sstate I S / fstate I S   get, set, free an FMU state (fstate keeps the
                           stale pointer in the slot)
    ser I S B              fmi2SerializedFMUstateSize + fmi2SerializeFMUstate into B
    ser_small I S          fmi2SerializeFMUstate into a buffer one byte too small
    deser I B S            fmi2DeSerializeFMUstate of B into S
    forge B MODE ARG       change B in the host: flip K (byte K mod size xor 0x55),
                           trunc K (keep K bytes), json, empty, guid (another build:
                           one GUID character changed, checksum recomputed), copy B2
    unprov I               fmi2GetDirectionalDerivative (not provided)

``python fmu_misuse.py`` runs scripts (see :func:`main`, :func:`run_main`,
:func:`cycles_main`). The generator builds a valid *backbone* (instantiate, parameters, initialise, steps with
inputs, records, terminate, free) and inserts, at random points, calls drawn from every
class of misuse; FMI 2.0's state machine (written here from the standard's table, not
from the loader's code) says what each inserted call returns. Inserted calls never
change the run: refused calls change nothing, the others are neutral (gets, state round
trips, refused steps with their inputs put back), so the backbone alone must give the
same records.
"""

from __future__ import annotations

import collections
import ctypes
import math
import struct
import sys
import xml.etree.ElementTree as ET
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

OK, WARNING, DISCARD, ERROR = 0, 1, 2, 3

PHASES = ("instantiated", "initialization", "step", "terminated", "error")
ALL = frozenset(PHASES)
#: FMI 2.0.4, section 4.2.4 (Co-Simulation): the states each call is allowed in.
ALLOWED = {
    "setup": {"instantiated"}, "enter": {"instantiated"}, "exit": {"initialization"},
    "step": {"step"}, "term": {"step"}, "reset": ALL,
    "get": {"initialization", "step", "terminated", "error"},
    "set": {"instantiated", "initialization", "step"},
    "state": ALL,
}
#: A String parameter value that makes fmi2ExitInitializationMode fail, per FMU.
BAD_INITIALISATION = {"TowCable": ("scene", "no_such_scene"), "HeaveCompensation": ("algorithm", "magic"),
                      "ShipMotion": ("motion.type", "tsunami")}
#: Outputs that depend on the wall clock, left out of the records.
DIAGNOSTIC = ("model_wall_time",)


@dataclass(frozen=True)
class Variable:
    name: str
    vr: int
    type: str
    causality: str
    variability: str
    initial: str
    min: float | None
    max: float | None
    start: str | None


def model(fmu_dir: Path) -> tuple[str, str, list[Variable]]:
    """modelIdentifier, GUID and variables of an extracted FMU."""
    root = ET.parse(Path(fmu_dir) / "modelDescription.xml").getroot()
    out = []
    for sv in root.find("ModelVariables").findall("ScalarVariable"):
        kind = next(child for child in sv if child.tag in ("Real", "Integer", "Boolean", "String"))
        number = (lambda key: float(kind.get(key)) if kind.get(key) is not None else None)
        out.append(Variable(sv.get("name"), int(sv.get("valueReference")), kind.tag, sv.get("causality", "local"),
                            sv.get("variability", "continuous"), sv.get("initial", ""), number("min"),
                            number("max"), kind.get("start")))
    return root.find("CoSimulation").get("modelIdentifier"), root.get("guid"), out


def settable(var: Variable, phase: str) -> bool:
    """FMI 2.0.4 notes 1, 3 and 6 of the state table (inputs also before initialisation,
    as they carry start values)."""
    if var.causality == "input":
        return phase in ("instantiated", "initialization", "step")
    if var.variability == "constant":
        return False
    if phase == "instantiated":
        return var.initial in ("exact", "approx")
    if phase == "initialization":
        return var.initial == "exact"
    if phase == "step":
        return var.causality == "parameter" and var.variability == "tunable"
    return False


def _value_text(var: Variable, value) -> str:
    return repr(float(value)) if var.type == "Real" else str(value)


class Generator:
    """Misuse scripts of one FMU (``fmu_dir``), another FMU (``other_dir``) giving the
    foreign states and bytes.

    Parameters
    ----------
    params
        Parameter name -> value the backbone sets (e.g. TowCable's scene).
    steps, step_size
        The backbone's communication steps [s].
    """

    def __init__(self, fmu_dir: Path, params: dict, steps: int = 4, step_size: float = 0.01) -> None:
        self.name, self.guid, self.variables = model(fmu_dir)
        self.by_name = {v.name: v for v in self.variables}
        self.params = params
        self.steps, self.h = steps, step_size
        self.inputs = [v for v in self.variables if v.causality == "input" and v.type == "Real"]
        self.outputs = [v for v in self.variables if v.causality == "output" and v.type == "Real"
                        and v.name not in DIAGNOSTIC]
        self.largest_vr = max(v.vr for v in self.variables)
        #: The classes of the misuses inserted so far (class -> count).
        self.drawn: dict[str, int] = {}

    # ------------------------------------------------------------------ backbone
    def input_values(self, k: int) -> dict[str, float]:
        """Inputs at communication point k: start values, the ship heaving gently."""
        values = {v.name: float(v.start or 0.0) for v in self.inputs}
        t = k * self.h
        for name, value in (("ship.z", 0.2 * math.sin(0.5 * t)), ("ship.vz", 0.1 * math.cos(0.5 * t))):
            if name in values:
                values[name] = value
        return values

    def _set_lines(self, slot: int, values: dict) -> list[str]:
        ops = {"Real": "setr", "Integer": "seti", "Boolean": "setb", "String": "sets"}
        return [f"0 {ops[self.by_name[n].type]} {slot} {self.by_name[n].vr} {_value_text(self.by_name[n], v)}"
                for n, v in values.items()]

    def _record(self, slot: int) -> str:
        return f"0 record {slot} " + ",".join(str(v.vr) for v in self.outputs)

    def script(self, rng: np.random.Generator | None, density: float = 3.0) -> list[str]:
        """A script; ``rng`` None gives the backbone alone (and the fixed segments), else
        on average ``density`` misuses are inserted at each point of the backbone."""
        lines: list[str] = []
        state = {"phase": "instantiated", "t": 0.0, "inputs": self.input_values(0)}

        def insert(weight: float = 1.0):  # the phases before and after the steps have fewer points
            if rng is None:
                return
            for _ in range(rng.poisson(density * weight)):
                kind, misuse = self._misuse(rng, state)
                lines.extend(misuse)
                if misuse:
                    self.drawn[kind] = self.drawn.get(kind, 0) + 1

        # instance 2: another FMU, its state and bytes (state 7, bytes 3)
        lines += ["0 inst 2 1 other", "0 gstate 2 7", "0 ser 2 7 3"]
        # instance 1: this FMU, initialised, a state taken (6), then freed: a stale instance
        # and the state of a freed instance (checked at once: no state made since); the
        # instance under test (0) is made before, so that it cannot take the freed address
        lines += ["0 inst 0 0 main", "0 inst 1 0 second", "0 setup 1 0.0", *self._set_lines(1, self.params),
                  "0 enter 1", "0 exit 1", "0 gstate 1 6", "- free 1", "3 sstate 0 6", "3 step 1 0.0 0.01"]
        insert(3)
        lines += ["0 setup 0 0.0", *self._set_lines(0, self.params)]
        insert(3)
        lines.append("0 enter 0")
        state["phase"] = "initialization"
        lines += self._set_lines(0, state["inputs"])
        insert(4)
        lines += ["0 exit 0", self._record(0)]
        state["phase"] = "step"
        for k in range(self.steps):
            insert()
            state["inputs"] = self.input_values(k)
            lines += self._set_lines(0, state["inputs"])
            insert()
            lines += [f"0 step 0 {k * self.h!r} {self.h!r}", self._record(0)]
            state["t"] = (k + 1) * self.h
        insert()
        lines.append("0 term 0")
        state["phase"] = "terminated"
        insert(4)
        lines += ["- free 0"]
        lines += self._recovery()
        lines += ["- free 2"]
        return lines

    def cycle(self, name: str) -> list[str]:
        """One instance's life in slot 0: instantiate, initialise, step, terminate, free."""
        lines = [f"0 inst 0 0 {name}", "0 setup 0 0.0", *self._set_lines(0, self.params), "0 enter 0",
                 *self._set_lines(0, self.input_values(0)), "0 exit 0"]
        for k in range(self.steps):
            lines += [*self._set_lines(0, self.input_values(k)), f"0 step 0 {k * self.h!r} {self.h!r}"]
        return lines + ["0 term 0", "- free 0"]

    def _recovery(self) -> list[str]:
        """Instance 3: a failed initialisation (the error state), a state restored from
        before it, then fmi2Reset; both runs must start as instance 0's did."""
        key, bad = BAD_INITIALISATION[self.name]
        first = self.input_values(0)
        init = [*self._set_lines(3, first), "0 exit 3", self._record(3)]
        return ["0 inst 3 0 recovery", "0 setup 3 0.0", *self._set_lines(3, self.params), "0 gstate 3 5",
                *self._set_lines(3, {key: bad}), "0 enter 3", "3 exit 3", "3 step 3 0.0 0.01",
                f"0 getr 3 {self.outputs[0].vr}", "3 term 3", "0 sstate 3 5", "0 enter 3", *init,
                "0 reset 3", "0 setup 3 0.0", *self._set_lines(3, self.params), "0 enter 3", *init,
                "0 fstate 3 5", "- free 3"]

    # ------------------------------------------------------------------ misuse
    def _misuse(self, rng: np.random.Generator, state: dict) -> tuple[str, list[str]]:
        """One inserted misuse for the phase in ``state``: its class and its lines (none
        if the class drew a valid call that would change the run)."""
        kind = str(rng.choice(["call", "bad_step", "get", "set", "nan_step", "roundtrip", "bad_bytes", "foreign",
                               "freed_state", "stale", "unprovided", "small_buffer", "null"]))
        return self._lines(kind, rng, state)

    def _lines(self, kind: str, rng: np.random.Generator, state: dict) -> tuple[str, list[str]]:  # noqa: C901
        phase = state["phase"]
        allowed = lambda what: phase in ALLOWED[what]  # noqa: E731
        if kind == "call":
            op = str(rng.choice(["setup", "enter", "exit", "term", "step"]))
            if allowed(op):
                return kind, []  # valid: it would change the run
            args = {"setup": " 0.0", "step": f" {state['t']!r} {self.h!r}"}.get(op, "")
            return f"call {op} in {phase}", [f"{ERROR} {op} 0{args}"]
        if kind == "bad_step":
            t_model = state["t"]
            t_bad, h_bad = [(t_model, 0.0), (t_model, -self.h), (t_model, math.nan), (t_model, math.inf),
                            (t_model + 0.5, self.h), (math.nan, self.h)][rng.integers(6)]
            return kind, [f"{DISCARD if allowed('step') else ERROR} step 0 {t_bad!r} {h_bad!r}"]
        if kind == "get":
            return self._get(rng, phase)
        if kind == "set":
            return self._bad_set(rng, phase)
        ship = [v for v in self.inputs if v.name.startswith("ship.")]  # every model refuses a non-finite ship
        if kind == "nan_step" and phase == "step" and ship:
            var = ship[rng.integers(len(ship))]
            value = [math.nan, math.inf, -math.inf][rng.integers(3)]
            return kind, [f"0 setr 0 {var.vr} {value!r}", f"{DISCARD} step 0 {state['t']!r} {self.h!r}",
                          f"0 setr 0 {var.vr} {state['inputs'][var.name]!r}"]
        if kind == "roundtrip":
            if rng.integers(2):
                return "state round trip", ["0 gstate 0 0", "0 sstate 0 0", "0 fstate 0 0"]
            return "serialised round trip", ["0 gstate 0 0", "0 ser 0 0 0", "0 deser 0 0 1", "0 sstate 0 1",
                                             "0 fstate 0 1", "0 fstate 0 0"]
        if kind == "bad_bytes":
            mode = ["flip", "trunc", "json", "empty", "guid", "other"][rng.integers(6)]
            forge = {"flip": f"- forge 1 flip {rng.integers(1 << 30)}", "trunc": f"- forge 1 trunc {rng.integers(200)}",
                     "json": "- forge 1 json 0", "empty": "- forge 1 empty 0", "guid": "- forge 1 guid 0",
                     "other": "- forge 1 copy 3"}[mode]
            lines = ["0 gstate 0 0", "0 ser 0 0 1"] if mode != "other" else ["0 gstate 0 0"]
            return f"bytes {mode}", lines + [forge, f"{ERROR} deser 0 1 2", "0 fstate 0 0"]
        if kind == "foreign":
            return kind, [f"{ERROR} {op} 0 7" for op in ("sstate", "fstate")] + [f"{ERROR} ser 0 7 2"]
        if kind == "freed_state":
            return kind, ["0 gstate 0 0", "0 fstate 0 0", f"{ERROR} sstate 0 0", f"{ERROR} fstate 0 0"]
        if kind == "stale":
            op = str(rng.choice([f"step 1 {state['t']!r} {self.h!r}", f"getr 1 {self.outputs[0].vr}", "enter 1",
                                 "reset 1", "gstate 1 4"]))
            return kind, [f"{ERROR} {op}"]
        if kind == "unprovided":
            return kind, [f"{ERROR} unprov 0"]
        if kind == "small_buffer":
            return kind, ["0 gstate 0 0", f"{ERROR} ser_small 0 0", "0 fstate 0 0"]
        if kind == "null":
            return kind, [f"{ERROR} getr_null 0"]
        return kind, []

    def _get(self, rng: np.random.Generator, phase: str) -> tuple[str, list[str]]:
        kind = ["Real", "Integer", "Boolean", "String"][rng.integers(4)]
        op = {"Real": "getr", "Integer": "geti", "Boolean": "getb", "String": "gets"}[kind]
        known = [v for v in self.variables if v.type == kind]
        if known and rng.integers(2):
            var = known[rng.integers(len(known))]
            return ("get" if phase in ALLOWED["get"] else f"get in {phase}",
                    [f"{OK if phase in ALLOWED['get'] else ERROR} {op} 0 {var.vr}"])
        wrong_type = [v.vr for v in self.variables if v.type != kind and not any(w.vr == v.vr for w in known)]
        unknown = [self.largest_vr + 1 + int(rng.integers(1000)), 2**32 - 1, *wrong_type[:1]]
        vr = unknown[rng.integers(len(unknown))]
        return "get of an unknown value reference", [f"{ERROR} {op} 0 {vr}"]

    def _bad_set(self, rng: np.random.Generator, phase: str) -> tuple[str, list[str]]:
        """A set the state machine or the variable's range refuses ([] if it drew a valid one)."""
        ops = {"Real": "setr", "Integer": "seti", "Boolean": "setb", "String": "sets"}
        var = self.variables[rng.integers(len(self.variables))]
        choice = rng.integers(4)
        if choice == 0:  # an unknown value reference
            vr = self.largest_vr + 1 + int(rng.integers(1000))
            return "set of an unknown value reference", [f"{ERROR} setr 0 {vr} 1.0"]
        if phase not in ALLOWED["set"] or not settable(var, phase):
            value = {"Real": "1.0", "Integer": "1", "Boolean": "1", "String": "x"}[var.type]
            return f"set of a {var.causality} in {phase}", [f"{ERROR} {ops[var.type]} 0 {var.vr} {value}"]
        if var.causality == "parameter" and var.type == "Real" and choice == 1:
            value = [math.nan, math.inf, -math.inf][rng.integers(3)]
            return "non-finite parameter", [f"{ERROR} setr 0 {var.vr} {value!r}"]
        if var.causality == "parameter" and var.type in ("Real", "Integer") and (var.min is not None
                                                                                 or var.max is not None):
            value = var.max + 1 if var.max is not None else var.min - 1
            text = _value_text(var, value if var.type == "Real" else int(value))
            return "parameter out of range", [f"{ERROR} {ops[var.type]} 0 {var.vr} {text}"]
        return "set", []  # a valid set: it would change the run


# ---------------------------------------------------------------------- executor
class _Callbacks(ctypes.Structure):
    _fields_ = [("logger", ctypes.c_void_p), ("allocateMemory", ctypes.c_void_p), ("freeMemory", ctypes.c_void_p),
                ("stepFinished", ctypes.c_void_p), ("componentEnvironment", ctypes.c_void_p)]


_LOGGER = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_char_p)


class Executor:
    """Runs scripts on extracted FMUs (``dirs[F]``) through their C functions."""

    def __init__(self, dirs: list[Path]) -> None:
        self.dirs = [Path(d) for d in dirs]
        self.libs, self.guids = [], []
        for d in self.dirs:
            identifier, guid, _ = model(d)
            self.libs.append(ctypes.CDLL(str(d / "binaries" / "linux64" / f"{identifier}.so")))
            self.guids.append(guid)
        self.messages: collections.deque[str] = collections.deque(maxlen=100)  # the last ones
        self._logger = _LOGGER(lambda env, name, status, category, message: self.messages.append(
            f"[{status}] {(message or b'').decode(errors='replace')}"))
        libc = ctypes.CDLL(None)
        self._callbacks = _Callbacks(ctypes.cast(self._logger, ctypes.c_void_p).value,
                                     ctypes.cast(libc.calloc, ctypes.c_void_p).value,
                                     ctypes.cast(libc.free, ctypes.c_void_p).value, None, None)

    def run(self, lines: list[str]) -> tuple[list[tuple[int, str, int]], list[list[float]]]:
        """Run a script: the mismatches (line number, line, status returned) and the records."""
        inst: dict[int, tuple[ctypes.CDLL, int]] = {}
        states: dict[int, ctypes.c_void_p] = {}
        data: dict[int, bytes] = {}
        mismatches, records = [], []
        for number, line in enumerate(lines):
            expected, op, rest = (line.split(" ", 2) + [""])[:3]
            status = self._do(op, rest, inst, states, data, records)
            if expected != "-" and status != int(expected):
                mismatches.append((number, line, status))
        return mismatches, records

    def _do(self, op, rest, inst, states, data, records) -> int | None:  # noqa: C901 - one branch per op
        a = rest.split(" ")
        if op == "forge":
            data[int(a[0])] = forge(data.get(int(a[0]), b""), a[1], a[2], data)
            return None
        slot = int(a[0])
        if op == "inst":
            lib = self.libs[int(a[1])]
            lib.fmi2Instantiate.restype = ctypes.c_void_p
            uri = (self.dirs[int(a[1])] / "resources").as_uri().encode()
            c = lib.fmi2Instantiate(a[2].encode(), 1, self.guids[int(a[1])].encode(), uri,
                                    ctypes.byref(self._callbacks), 0, 0)
            inst[slot] = (lib, c)
            return OK if c else ERROR
        lib, c = inst[slot]
        c = ctypes.c_void_p(c)
        f = lambda name: getattr(lib, name)  # noqa: E731
        d = ctypes.c_double
        if op == "free":
            f("fmi2FreeInstance")(c)
            return None
        if op == "setup":
            return f("fmi2SetupExperiment")(c, 0, d(0.0), d(float(a[1])), 0, d(0.0))
        simple = {"enter": "fmi2EnterInitializationMode", "exit": "fmi2ExitInitializationMode",
                  "term": "fmi2Terminate", "reset": "fmi2Reset"}
        if op in simple:
            return f(simple[op])(c)
        if op == "step":
            return f("fmi2DoStep")(c, d(float(a[1])), d(float(a[2])), 1)
        if op in ("setr", "seti", "setb", "sets", "getr", "geti", "getb", "gets"):
            kind = {"r": (ctypes.c_double, "Real", float), "i": (ctypes.c_int, "Integer", int),
                    "b": (ctypes.c_int, "Boolean", int), "s": (ctypes.c_char_p, "String", str.encode)}[op[-1]]
            vr = (ctypes.c_uint * 1)(int(a[1]))
            if op.startswith("set"):
                text = rest.split(" ", 2)[2]
                value = (kind[0] * 1)(kind[2](text))
                return f(f"fmi2Set{kind[1]}")(c, vr, ctypes.c_size_t(1), value)
            return f(f"fmi2Get{kind[1]}")(c, vr, ctypes.c_size_t(1), (kind[0] * 1)())
        if op == "getr_null":
            return f("fmi2GetReal")(c, None, ctypes.c_size_t(1), (ctypes.c_double * 1)())
        if op == "record":
            vrs = [int(x) for x in a[1].split(",")]
            out = (ctypes.c_double * len(vrs))()
            status = f("fmi2GetReal")(c, (ctypes.c_uint * len(vrs))(*vrs), ctypes.c_size_t(len(vrs)), out)
            records.append([slot, *out])
            return status
        if op == "unprov":
            return f("fmi2GetDirectionalDerivative")(c, None, ctypes.c_size_t(0), None, ctypes.c_size_t(0), None, None)
        s = int(a[1])
        if op == "gstate":
            ref = ctypes.c_void_p(None)
            status = f("fmi2GetFMUstate")(c, ctypes.byref(ref))
            states[s] = ref
            return status
        if op == "sstate":
            return f("fmi2SetFMUstate")(c, states.get(s, ctypes.c_void_p(None)))
        if op == "fstate":
            ref = ctypes.c_void_p(states.get(s, ctypes.c_void_p(None)).value)
            return f("fmi2FreeFMUstate")(c, ctypes.byref(ref))  # the slot keeps the stale pointer
        if op in ("ser", "ser_small"):
            size = ctypes.c_size_t(0)
            status = f("fmi2SerializedFMUstateSize")(c, states.get(s), ctypes.byref(size))
            if status > WARNING:
                return status
            small = op == "ser_small"
            buffer = ctypes.create_string_buffer(max(size.value - small, 1))
            second = f("fmi2SerializeFMUstate")(c, states.get(s), buffer, ctypes.c_size_t(size.value - small))
            status = max(status, second)
            if not small:
                data[int(a[2])] = buffer.raw[:size.value]
            return status
        if op == "deser":
            raw = data.get(s, b"")
            ref = ctypes.c_void_p(None)
            status = f("fmi2DeSerializeFMUstate")(c, ctypes.create_string_buffer(raw, max(len(raw), 1)),
                                                  ctypes.c_size_t(len(raw)), ctypes.byref(ref))
            states[int(a[2])] = ref
            return status
        raise ValueError(f"unknown operation {op!r}")


def envelope(raw: bytes) -> dict:
    """The fields of serialised state bytes, read here from the layout of
    ``towcable_fmu/fmu_build/csrc/state_bytes.h``; ``crc_ok`` compares the checksum with zlib's."""
    magic, version, phase, name_length = struct.unpack_from("<8sIII", raw, 0)
    at = 20 + name_length
    name = raw[20:at].decode()
    (guid_length,) = struct.unpack_from("<I", raw, at)
    guid = raw[at + 4:at + 4 + guid_length].decode()
    at += 4 + guid_length
    (payload_length,) = struct.unpack_from("<Q", raw, at)
    payload = raw[at + 8:at + 8 + payload_length]
    (crc,) = struct.unpack_from("<I", raw, len(raw) - 4)
    return {"magic": magic, "format": version, "phase": phase, "name": name, "guid": guid, "payload": payload,
            "crc_ok": crc == zlib.crc32(raw[:-4]) and at + 8 + payload_length == len(raw) - 4}


def forge(raw: bytes, mode: str, arg: str, data: dict[int, bytes]) -> bytes:
    """Bytes changed as a hostile or unlucky host would (see the module docstring)."""
    if mode == "flip":
        if not raw:
            return raw
        k = int(arg) % len(raw)
        return raw[:k] + bytes([raw[k] ^ 0x55]) + raw[k + 1:]
    if mode == "trunc":
        return raw[:int(arg) % max(len(raw), 1)]
    if mode == "json":
        return b'{"fmu": "TowCable", "values": {}}'
    if mode == "empty":
        return b""
    if mode == "copy":
        return data.get(int(arg), b"")
    if mode == "guid":  # the envelope's GUID field: after magic, format, phase, name
        name_length = struct.unpack_from("<I", raw, 16)[0]
        at = 20 + name_length + 4
        changed = raw[:at] + bytes([raw[at] ^ 0x01]) + raw[at + 1:-4]
        return changed + struct.pack("<I", zlib.crc32(changed))
    raise ValueError(f"unknown forge mode {mode!r}")


def resident_bytes() -> int:
    """This process's resident memory [bytes] (Linux)."""
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * 4096


class _Mallinfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                                                     "fsmblks", "uordblks", "fordblks", "keepcost")]


def heap_in_use() -> int:
    """Bytes allocated with malloc and not freed (glibc's mallinfo2: small and mmapped
    chunks); unlike the resident memory it does not hide a leak in memory freed earlier.
    With ``PYTHONMALLOC=malloc`` it includes Python's objects."""
    mallinfo2 = ctypes.CDLL(None).mallinfo2
    mallinfo2.restype = _Mallinfo2
    info = mallinfo2()
    return info.uordblks + info.hblkhd


def cycles_main(argv: list[str]) -> int:
    """``python fmu_misuse.py cycles FMU_DIR N PARAMS_JSON``: N instance lives (:meth:`Generator.cycle`)
    in this process; prints the heap in use (:func:`heap_in_use`) and the resident memory
    after each as JSON lists [bytes]."""
    import json

    fmu_dir, count, params = Path(argv[0]), int(argv[1]), json.loads(argv[2])
    gen = Generator(fmu_dir, params)
    executor = Executor([fmu_dir, fmu_dir])
    heap, resident = [], []
    for i in range(count):
        mismatches, _ = executor.run(gen.cycle(f"cycle{i}"))
        if mismatches:
            print(json.dumps({"mismatches": mismatches, "messages": list(executor.messages)[-5:]}))
            return 1
        heap.append(heap_in_use())
        resident.append(resident_bytes())
    print(json.dumps({"heap": heap, "resident": resident}))
    return 0


def run_main(argv: list[str]) -> int:
    """``python fmu_misuse.py run FMU_DIR OTHER_DIR SCRIPT``: one script file; prints the
    mismatches and the records as JSON."""
    import json

    executor = Executor([Path(argv[0]), Path(argv[1])])
    mismatches, records = executor.run(Path(argv[2]).read_text(encoding="utf-8").splitlines())
    print(json.dumps({"mismatches": mismatches, "records": records, "messages": list(executor.messages)}))
    return 0


def main(argv: list[str]) -> int:
    """``python fmu_misuse.py FMU_DIR OTHER_DIR SEED SCRIPTS PARAMS_JSON [WRITE_DIR]``:
    runs SCRIPTS random scripts (seeds SEED, SEED+1, ...) and the backbone, prints a JSON
    summary; with WRITE_DIR also writes the scripts there (for the C host)."""
    import json

    fmu_dir, other_dir, seed, count, params = Path(argv[0]), Path(argv[1]), int(argv[2]), int(argv[3]), \
        json.loads(argv[4])
    gen = Generator(fmu_dir, params)
    executor = Executor([fmu_dir, other_dir])
    backbone = gen.script(None)
    _, expected = executor.run(backbone)
    summary = {"fmu": gen.name, "mismatches": [], "differences": 0, "calls": 0, "records": len(expected)}
    first = [r[1:] for r in expected if r[0] == 0]
    summary["recovery_matches"] = [r[1:] for r in expected if r[0] == 3] == first[:1] * 2
    for i in range(count):
        lines = gen.script(np.random.default_rng(seed + i))
        if len(argv) > 5:
            (Path(argv[5]) / f"script_{i}.txt").write_text("\n".join(lines) + "\n", encoding="utf-8")
        mismatches, records = executor.run(lines)
        summary["calls"] += len(lines)
        summary["mismatches"] += [(i, *m) for m in mismatches]
        summary["differences"] += sum(a != b for a, b in zip(records, expected)) + abs(len(records) - len(expected))
    summary["messages"] = list(executor.messages)[-5:]
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    commands = {"cycles": cycles_main, "run": run_main}
    sys.exit(commands[sys.argv[1]](sys.argv[2:]) if sys.argv[1] in commands else main(sys.argv[1:]))
