"""Read the variable contract (``contract.toml``): names, units and descriptions."""

from __future__ import annotations

import dataclasses
import functools
import tomllib
from importlib import resources


@dataclasses.dataclass(frozen=True)
class Signal:
    """One named signal of the contract.

    Attributes
    ----------
    name
        Dotted name, e.g. ``tension.sheave``.
    unit
        Unit symbol as in FMI UnitDefinitions (``"1"`` for dimensionless).
    description
        One-line meaning.
    type
        FMI type: ``"Real"`` or ``"Boolean"``.
    diagnostic
        True for signals that are not physics (e.g. ``model_wall_time``): left out of
        result files and of the determinism checks.
    """

    name: str
    unit: str
    description: str
    type: str = "Real"
    diagnostic: bool = False


@functools.cache
def _document() -> dict:
    text = (resources.files(__package__) / "contract.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


@functools.cache
def signals() -> dict[str, Signal]:
    """All signals of the contract by name."""
    return {name: Signal(name=name, **entry) for name, entry in _document()["signals"].items()}


def units() -> dict[str, dict[str, float]]:
    """Unit symbol -> SI base-unit exponents (for FMI UnitDefinitions), plus ``factor``
    (and ``offset``) to SI where the unit is not coherent (``deg``)."""
    return {name: dict(entry) for name, entry in _document()["units"].items()}


def unit_of(name: str) -> str:
    """Unit of an output name; solver statistics (``solver.*``) are counters or seconds."""
    sig = signals().get(name)
    if sig is not None:
        return sig.unit
    if name.startswith("solver."):
        return "s" if name.endswith(("time", "time_step")) else "1"
    raise KeyError(f"'{name}' is not in the variable contract (towcable_fmu/common/contract.toml)")


# ------------------------------------------------------------------ FMUs and the system
#: FMI base units (the order of the BaseUnit attributes in modelDescription.xml).
BASE_UNITS = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")


@dataclasses.dataclass(frozen=True)
class Variable:
    """One variable of an FMU, as registered by its slave and written to modelDescription.xml.

    Attributes
    ----------
    name
        Variable name (a signal name for inputs and outputs, a dotted key for parameters).
    causality
        ``"parameter"``, ``"input"`` or ``"output"``.
    type
        ``"Real"``, ``"Integer"``, ``"Boolean"`` or ``"String"``.
    unit
        Unit symbol (Real variables; ``None`` for the other types, which FMI 2.0 gives no unit).
    description
        One-line meaning.
    start
        Start value (parameters and inputs; outputs are calculated at initialisation).
    diagnostic
        True for non-physics outputs (``model_wall_time``).
    min, max
        Range of a Real or Integer parameter the model accepts (inclusive; None: unbounded
        on that side), written into modelDescription.xml.
    """

    name: str
    causality: str
    type: str
    unit: str | None
    description: str
    start: object = None
    diagnostic: bool = False
    min: float | None = None
    max: float | None = None


@dataclasses.dataclass(frozen=True)
class FmuSpec:
    """One FMU of the contract.

    Attributes
    ----------
    name
        Model name and model identifier (``ShipMotion``, ``HeaveCompensation``, ``TowCable``).
    slave
        ``"module:Class"`` of the pythonfmu slave in the installed packages.
    description
        Model description.
    parameters, inputs, outputs
        The variables, in value-reference order (parameters, inputs, outputs).
    """

    name: str
    slave: str
    description: str
    parameters: tuple[Variable, ...]
    inputs: tuple[Variable, ...]
    outputs: tuple[Variable, ...]

    @property
    def variables(self) -> tuple[Variable, ...]:
        """All variables in value-reference order."""
        return self.parameters + self.inputs + self.outputs

    def variable(self, name: str) -> Variable:
        """The variable called ``name``.

        Raises
        ------
        KeyError
            If the FMU has no such variable.
        """
        for v in self.variables:
            if v.name == name:
                return v
        raise KeyError(f"FMU {self.name} has no variable '{name}' (towcable_fmu/common/contract.toml)")

    def names(self, causality: str) -> tuple[str, ...]:
        """Names of the parameters, inputs or outputs."""
        return tuple(v.name for v in getattr(self, causality + "s"))


@dataclasses.dataclass(frozen=True)
class Connection:
    """One signal copied from an output of one FMU to the input of the same name of another.

    ``delayed`` marks a feedback: the value of the previous communication point is used.
    """

    source: str
    target: str
    signal: str
    delayed: bool = False


def _expand(patterns: list[str] | str, where: str) -> list[str]:
    """Signal names from a list of names and ``prefix.*`` patterns, in [signals] order."""
    if isinstance(patterns, str):
        patterns = [patterns]
    known = signals()
    names: list[str] = []
    for pattern in patterns:
        if pattern.endswith(".*"):
            found = [n for n in known if n.startswith(pattern[:-1])]
            if not found:
                raise ValueError(f"{where}: pattern '{pattern}' matches no signal of the contract")
            names.extend(found)
        elif pattern in known:
            names.append(pattern)
        else:
            raise ValueError(f"{where}: '{pattern}' is not a signal of the contract")
    if len(set(names)) != len(names):
        raise ValueError(f"{where}: a signal is listed twice")
    return names


def _signal_variable(name: str, causality: str) -> Variable:
    sig = signals()[name]
    unit = sig.unit if sig.type == "Real" else None
    start = None if causality == "output" else (False if sig.type == "Boolean" else 0.0)
    return Variable(name=name, causality=causality, type=sig.type, unit=unit, description=sig.description,
                    start=start, diagnostic=sig.diagnostic)


def _parameter(entry: dict, where: str) -> Variable:
    kind = entry["type"]
    if kind not in ("Real", "Integer", "Boolean", "String"):
        raise ValueError(f"{where}.{entry['name']}: unknown type '{kind}'")
    unit = entry.get("unit") if kind == "Real" else None
    if kind == "Real" and unit not in units():
        raise ValueError(f"{where}.{entry['name']}: Real parameters need a unit of [units], got {unit!r}")
    cast = {"Real": float, "Integer": int, "Boolean": bool, "String": str}[kind]
    start = cast(entry["start"])
    bounds = {key: cast(entry[key]) for key in ("min", "max") if key in entry}
    if bounds and kind not in ("Real", "Integer"):
        raise ValueError(f"{where}.{entry['name']}: only Real and Integer parameters have a range")
    if not bounds.get("min", start) <= start <= bounds.get("max", start):
        raise ValueError(f"{where}.{entry['name']}: start {start!r} outside [{bounds.get('min')}, {bounds.get('max')}]")
    return Variable(name=entry["name"], causality="parameter", type=kind, unit=unit,
                    description=entry["description"], start=start, **bounds)


@functools.cache
def fmus() -> dict[str, FmuSpec]:
    """The FMUs of the contract by name, with their variables in value-reference order."""
    out = {}
    for name, entry in _document()["fmus"].items():
        where = f"fmus.{name}"
        out[name] = FmuSpec(
            name=name, slave=entry["slave"], description=entry["description"],
            parameters=tuple(_parameter(p, where) for p in entry.get("parameters", [])),
            inputs=tuple(_signal_variable(n, "input") for n in _expand(entry["inputs"], where + ".inputs")),
            outputs=tuple(_signal_variable(n, "output") for n in _expand(entry["outputs"], where + ".outputs")))
        names = [v.name for v in out[name].variables]
        if len(set(names)) != len(names):
            raise ValueError(f"{where}: a variable name is used twice")
    return out


def fmu(name: str) -> FmuSpec:
    """One FMU of the contract (``ShipMotion``, ``HeaveCompensation``, ``TowCable``)."""
    try:
        return fmus()[name]
    except KeyError:
        raise KeyError(f"'{name}' is not an FMU of the contract; known: {', '.join(fmus())}") from None


def system() -> dict:
    """Name, description and component order of the co-simulated system."""
    doc = _document()["system"]
    return {"name": doc["name"], "description": doc["description"], "components": list(doc["components"])}


@functools.cache
def connections() -> tuple[Connection, ...]:
    """Every connection of the system, one per signal, patterns expanded.

    Each signal must be an output of the source FMU and an input of the target FMU;
    every input of every FMU must be connected exactly once.
    """
    specs = fmus()
    out: list[Connection] = []
    for k, entry in enumerate(_document()["system"]["connections"]):
        where = f"system.connections[{k}]"
        src, dst = specs[entry["from"]], specs[entry["to"]]
        names = entry["signals"]
        if isinstance(names, str) and names.endswith(".*"):
            prefix = names[:-1]
            names = [n for n in src.names("output") if n.startswith(prefix) and n in dst.names("input")]
        for n in _expand(names, where):
            if n not in src.names("output"):
                raise ValueError(f"{where}: '{n}' is not an output of {src.name}")
            if n not in dst.names("input"):
                raise ValueError(f"{where}: '{n}' is not an input of {dst.name}")
            out.append(Connection(source=src.name, target=dst.name, signal=n, delayed=bool(entry.get("delayed", False))))
    targets = [(c.target, c.signal) for c in out]
    if len(set(targets)) != len(targets):
        raise ValueError("system.connections: an input is connected twice")
    for spec in specs.values():
        for n in spec.names("input"):
            if (spec.name, n) not in targets:
                raise ValueError(f"system.connections: input '{n}' of {spec.name} is not connected")
    return tuple(out)
