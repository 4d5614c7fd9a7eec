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
    """

    name: str
    unit: str
    description: str
    type: str = "Real"


@functools.cache
def _document() -> dict:
    text = (resources.files("towcable_fmu") / "contract.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


@functools.cache
def signals() -> dict[str, Signal]:
    """All signals of the contract by name."""
    return {name: Signal(name=name, **entry) for name, entry in _document()["signals"].items()}


def units() -> dict[str, dict[str, int]]:
    """Unit symbol -> SI base-unit exponents (for FMI UnitDefinitions)."""
    return dict(_document()["units"])


def unit_of(name: str) -> str:
    """Unit of an output name; solver statistics (``solver.*``) are counters or seconds."""
    sig = signals().get(name)
    if sig is not None:
        return sig.unit
    if name.startswith("solver."):
        return "s" if name.endswith(("time", "time_step")) else "1"
    raise KeyError(f"'{name}' is not in the variable contract (towcable_fmu/contract.toml)")
