"""Declarative scene schema: one declaration gives validation, typed objects and docs.

A scene section is a frozen dataclass whose fields carry a :func:`spec` in their
metadata (unit, allowed range or choices, description). :func:`parse` walks a TOML
table against such a dataclass, fills defaults, and raises
:class:`~towcable_fmu.errors.SceneError` naming the dotted key, the bad value and what
is allowed. Unknown keys are errors too (with a "did you mean" hint).
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import types
import typing
from typing import Any

from .errors import SceneError

REQUIRED = dataclasses.MISSING


@dataclasses.dataclass(frozen=True)
class Spec:
    """Metadata of one scene key.

    Parameters
    ----------
    unit
        Physical unit of the value ("m", "N", "-" for dimensionless, "" for none).
    doc
        One-sentence meaning of the key.
    gt, ge, lt, le
        Exclusive/inclusive bounds for numbers (applied element-wise to vectors).
    choices
        Allowed values for strings.
    length
        Required length for vectors (lists of numbers).
    """

    unit: str = ""
    doc: str = ""
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    choices: tuple[str, ...] | None = None
    length: int | None = None

    def allowed(self) -> str:
        """Human-readable description of the allowed values, with the unit."""
        if self.choices is not None:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        parts = []
        if self.gt is not None:
            parts.append(f"> {self.gt:g}")
        if self.ge is not None:
            parts.append(f">= {self.ge:g}")
        if self.lt is not None:
            parts.append(f"< {self.lt:g}")
        if self.le is not None:
            parts.append(f"<= {self.le:g}")
        text = " and ".join(parts) if parts else "a finite number"
        if self.length is not None:
            text = f"a list of {self.length} numbers, each {text}"
        unit = f" [{self.unit}]" if self.unit and self.unit != "-" else ""
        return text + unit


def spec(default: Any = REQUIRED, **kwargs: Any) -> Any:
    """A dataclass field with a :class:`Spec` in its metadata.

    Mutable defaults (lists) are copied per instance.
    """
    meta = {"spec": Spec(**kwargs)}
    if isinstance(default, list):
        return dataclasses.field(default_factory=lambda d=default: list(d), metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def _is_dataclass_type(tp: Any) -> bool:
    return isinstance(tp, type) and dataclasses.is_dataclass(tp)


def _unwrap_optional(tp: Any) -> tuple[Any, bool]:
    origin = typing.get_origin(tp)
    if origin in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        if len(args) == 1 and len(typing.get_args(tp)) == 2:
            return args[0], True
    return tp, False


def _check_number(key: str, value: Any, sp: Spec, integer: bool) -> float | int:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SceneError(key, value, ("an integer" if integer else "a number") + f" ({sp.allowed()})")
    if integer and not isinstance(value, int):
        if float(value).is_integer():
            value = int(value)
        else:
            raise SceneError(key, value, f"an integer ({sp.allowed()})")
    if not math.isfinite(value):
        raise SceneError(key, value, sp.allowed())
    if ((sp.gt is not None and not value > sp.gt) or (sp.ge is not None and not value >= sp.ge)
            or (sp.lt is not None and not value < sp.lt) or (sp.le is not None and not value <= sp.le)):
        raise SceneError(key, value, sp.allowed())
    return int(value) if integer else float(value)


def _convert(key: str, value: Any, tp: Any, sp: Spec) -> Any:
    tp, optional = _unwrap_optional(tp)
    if value is None:
        if optional:
            return None
        raise SceneError(key, value, sp.allowed())
    if _is_dataclass_type(tp):
        if not isinstance(value, dict):
            raise SceneError(key, value, "a table")
        return parse(tp, value, key)
    origin = typing.get_origin(tp)
    if origin in (list, tuple):
        (item_tp, *_) = typing.get_args(tp) or (Any,)
        if not isinstance(value, (list, tuple)):
            raise SceneError(key, value, "a list" if not _is_dataclass_type(item_tp) else "an array of tables")
        if _is_dataclass_type(item_tp):
            if not value:
                raise SceneError(key, value, "at least one entry")
            return tuple(parse(item_tp, v, f"{key}[{i}]") if isinstance(v, dict)
                         else _raise(SceneError(f"{key}[{i}]", v, "a table")) for i, v in enumerate(value))
        if sp.length is not None and len(value) != sp.length:
            raise SceneError(key, value, sp.allowed())
        integer = item_tp is int
        return tuple(_check_number(f"{key}[{i}]", v, sp, integer) for i, v in enumerate(value))
    if tp is bool:
        if not isinstance(value, bool):
            raise SceneError(key, value, "true or false")
        return value
    if tp is str:
        if not isinstance(value, str):
            raise SceneError(key, value, sp.allowed() if sp.choices else "a string")
        if sp.choices is not None and value not in sp.choices:
            raise SceneError(key, value, sp.allowed())
        return value
    if tp is int or tp is float:
        return _check_number(key, value, sp, tp is int)
    if tp is dict or typing.get_origin(tp) is dict:
        if not isinstance(value, dict):
            raise SceneError(key, value, "a table")
        return value
    raise TypeError(f"schema type {tp!r} of {key} is not supported")  # programming error


def _raise(exc: Exception) -> typing.NoReturn:
    raise exc


def parse(cls: type, table: dict, key: str) -> Any:
    """Validate ``table`` against the dataclass ``cls`` and build an instance.

    Parameters
    ----------
    cls
        A dataclass whose fields carry :func:`spec` metadata.
    table
        The TOML table (already parsed).
    key
        Dotted path of the table, used in error messages.

    Raises
    ------
    SceneError
        On an unknown key, a missing required key, or a value of the wrong type or
        out of range.
    """
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    prefix = f"{key}." if key else ""
    for name in table:
        if name not in fields:
            close = difflib.get_close_matches(name, list(fields), n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise SceneError(prefix + name, table[name],
                             "one of the keys " + ", ".join(sorted(fields)) + hint)
    kwargs = {}
    for name, f in fields.items():
        sp = f.metadata.get("spec", Spec())
        if name in table:
            kwargs[name] = _convert(prefix + name, table[name], hints[name], sp)
        elif f.default is REQUIRED and f.default_factory is REQUIRED:  # type: ignore[misc]
            raise SceneError(prefix + name, "<missing>", f"a value ({sp.allowed()}); the key is required")
    obj = cls(**kwargs)
    check = getattr(obj, "validate", None)
    if check is not None:
        check(key)
    return obj


def _type_name(tp: Any, sp: Spec) -> str:
    """Kind of value a key takes, in words."""
    origin = typing.get_origin(tp)
    if origin in (list, tuple):
        count = f"{sp.length} " if sp.length is not None else ""
        item = typing.get_args(tp)[0] if typing.get_args(tp) else float
        return f"list of {count}" + ("integers" if item is int else "numbers")
    if tp is dict or origin is dict:
        return "table"
    return {bool: "boolean", str: "string", int: "integer", float: "number"}.get(tp, getattr(tp, "__name__", str(tp)))


def _allowed_text(tp: Any, sp: Spec) -> str:
    """What a key allows, by its type and :class:`Spec`."""
    if tp is bool:
        return "true or false"
    if tp is str and sp.choices is None:
        return "any string"
    if tp is dict or typing.get_origin(tp) is dict:
        return "a table"
    return sp.allowed()


def toml_text(value: Any) -> str:
    """A default value written as in a scene file (TOML); ``None`` is "absent"."""
    if value is None:
        return "absent"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_text(v) for v in value) + "]"
    if dataclasses.is_dataclass(value):
        base = type(value)()
        changed = [(f.name, getattr(value, f.name)) for f in dataclasses.fields(value)
                   if getattr(value, f.name) != getattr(base, f.name)]
        return "{" + ", ".join(f"{name} = {toml_text(v)}" for name, v in changed) + "}"
    return repr(value)


def _default_text(f: dataclasses.Field) -> str:
    if f.default is not REQUIRED:
        return toml_text(f.default)
    if f.default_factory is not REQUIRED:  # type: ignore[misc]
        return toml_text(f.default_factory())  # type: ignore[misc]
    return "required"


def describe(cls: type, key: str = "") -> list[dict[str, str]]:
    """Flatten the schema of ``cls`` into rows for generated reference documentation.

    Parameters
    ----------
    cls
        A dataclass whose fields carry :func:`spec` metadata.
    key
        Dotted path of ``cls``'s table.

    Returns
    -------
    list of dict
        One row per key, in declaration order, with the entries ``key`` (dotted; ``[]``
        marks an array of tables), ``type``, ``unit``, ``default`` (as written in TOML;
        "required", or "absent" for an optional table or value), ``allowed`` and
        ``doc``. A nested table has a row of its own (type "table" or "array of
        tables"; its default is the whole table when it is left out) before the rows
        of its keys.
    """
    rows: list[dict[str, str]] = []
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        sp = f.metadata.get("spec", Spec())
        tp, _ = _unwrap_optional(hints[f.name])
        path = f"{key}.{f.name}" if key else f.name
        origin = typing.get_origin(tp)
        item = typing.get_args(tp)[0] if origin in (list, tuple) and typing.get_args(tp) else None
        row = {"key": path, "type": _type_name(tp, sp), "unit": sp.unit, "default": _default_text(f),
               "allowed": _allowed_text(tp, sp), "doc": sp.doc}
        if _is_dataclass_type(tp):
            rows.append(dict(row, type="table", allowed="a table"))
            rows.extend(describe(tp, path))
        elif item is not None and _is_dataclass_type(item):
            rows.append(dict(row, type="array of tables", allowed="one or more tables"))
            rows.extend(describe(item, path + "[]"))
        else:
            rows.append(row)
    return rows
