"""Typed, range-checked reading of configuration tables (TOML tables parsed to dicts).

Every reader takes the table, the entry name and the dotted path of the table, and
raises :class:`towcable_fmu.errors.SceneError` naming the full key
(``motion.heave.period``), the value and what is allowed (range with units).
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping, Sequence
from numbers import Integral, Real

from towcable_fmu.errors import SceneError

#: Marker for a required entry.
REQUIRED = object()


def join(path: str, name: str) -> str:
    """Dotted key of entry ``name`` in the table at ``path``."""
    return f"{path}.{name}" if path else name


def check_table(value: object, path: str, allowed: str) -> Mapping[str, object]:
    """Return ``value`` if it is a table (mapping), else raise SceneError."""
    if not isinstance(value, Mapping):
        raise SceneError(path, value, allowed)
    return value


def check_keys(table: Mapping[str, object], allowed: Collection[str], path: str) -> None:
    """Raise SceneError for the first entry of ``table`` whose name is not allowed."""
    for name, value in table.items():
        if name not in allowed:
            raise SceneError(join(path, name), value,
                             "one of the keys " + ", ".join(sorted(allowed)))


def range_text(lo: float | None, hi: float | None, *, lo_open: bool = False,
               hi_open: bool = False, unit: str = "") -> str:
    """Human-readable range, e.g. ``"a finite number > 0 s"``."""
    u = f" {unit}" if unit else ""
    if lo is not None and hi is not None:
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        return f"a finite number in {left}{lo:g}, {hi:g}{right}{u}"
    if lo is not None:
        return f"a finite number {'>' if lo_open else '>='} {lo:g}{u}"
    if hi is not None:
        return f"a finite number {'<' if hi_open else '<='} {hi:g}{u}"
    return "a finite number" + (f" [{unit}]" if unit else "")


def _is_real(value: object) -> bool:
    return isinstance(value, Real) and not isinstance(value, bool)


def number(table: Mapping[str, object], name: str, path: str, *,
           default: object = REQUIRED, lo: float | None = None, hi: float | None = None,
           lo_open: bool = False, hi_open: bool = False, unit: str = "") -> float:
    """Read a finite real number within a range.

    Parameters
    ----------
    table
        The configuration table.
    name
        Entry name.
    path
        Dotted path of ``table`` (for error messages).
    default
        Value when the entry is absent; :data:`REQUIRED` makes it mandatory.
    lo, hi
        Range limits (None: unbounded); ``lo_open``/``hi_open`` exclude the limit.
    unit
        Unit shown in the error message.

    Returns
    -------
    float
    """
    allowed = range_text(lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
    key = join(path, name)
    if name not in table:
        if default is REQUIRED:
            raise SceneError(key, None, "required: " + allowed)
        return default  # type: ignore[return-value]
    value = table[name]
    if not _is_real(value) or not math.isfinite(value):
        raise SceneError(key, value, allowed)
    x = float(value)
    if lo is not None and (x < lo or (lo_open and x == lo)):
        raise SceneError(key, value, allowed)
    if hi is not None and (x > hi or (hi_open and x == hi)):
        raise SceneError(key, value, allowed)
    return x


def integer(table: Mapping[str, object], name: str, path: str, *, default: object = REQUIRED,
            lo: int | None = None, hi: int | None = None) -> int:
    """Read an integer within ``[lo, hi]`` (see :func:`number`)."""
    if lo is not None and hi is not None:
        allowed = f"an integer in [{lo}, {hi}]"
    elif lo is not None:
        allowed = f"an integer >= {lo}"
    else:
        allowed = "an integer"
    key = join(path, name)
    if name not in table:
        if default is REQUIRED:
            raise SceneError(key, None, "required: " + allowed)
        return default  # type: ignore[return-value]
    value = table[name]
    if not isinstance(value, Integral) or isinstance(value, bool):
        raise SceneError(key, value, allowed)
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        raise SceneError(key, value, allowed)
    return int(value)


def choice(table: Mapping[str, object], name: str, path: str, choices: Sequence[str], *,
           default: object = REQUIRED) -> str:
    """Read a string that must be one of ``choices``."""
    allowed = "one of " + ", ".join(f'"{c}"' for c in choices)
    key = join(path, name)
    if name not in table:
        if default is REQUIRED:
            raise SceneError(key, None, "required: " + allowed)
        return default  # type: ignore[return-value]
    value = table[name]
    if not isinstance(value, str) or value not in choices:
        raise SceneError(key, value, allowed)
    return value


def string(table: Mapping[str, object], name: str, path: str, allowed: str) -> str:
    """Read a required non-empty string; ``allowed`` describes it in errors."""
    key = join(path, name)
    value = table.get(name)
    if not isinstance(value, str) or not value.strip():
        raise SceneError(key, value, allowed)
    return value


def vector(table: Mapping[str, object], name: str, path: str, length: int, *,
           default: object = REQUIRED, unit: str = "") -> tuple[float, ...]:
    """Read a list of ``length`` finite numbers."""
    allowed = f"a list of {length} finite numbers" + (f" [{unit}]" if unit else "")
    key = join(path, name)
    if name not in table:
        if default is REQUIRED:
            raise SceneError(key, None, "required: " + allowed)
        return default  # type: ignore[return-value]
    value = table[name]
    if (not isinstance(value, Sequence) or isinstance(value, str) or len(value) != length
            or not all(_is_real(v) and math.isfinite(v) for v in value)):
        raise SceneError(key, value, allowed)
    return tuple(float(v) for v in value)
