"""Declarative configuration schema: one declaration gives validation, typed objects and docs.

Every configuration table of the project (the scene's sections, the ship motion's
``[motion]`` of each ``type``, the compensation's ``[compensation]``) is a frozen
dataclass whose fields carry a :func:`spec` in their metadata (unit, allowed range or
choices, description). :func:`parse` walks a TOML table against such a dataclass, fills
defaults, and raises :class:`~towcable_fmu.common.errors.SceneError` naming the dotted key, the
bad value and what is allowed; unknown keys are errors too (with a "did you mean" hint).
:func:`describe` turns the same declaration into the rows of the generated reference
(``docs/reference/scene_keys.md``).

Beyond the keys one by one, a declaration may have

* a ``validate(self, key)`` method for rules across keys (raising SceneError), with
  ``RULES``, a class attribute ``{field: rule in words}``, that the reference shows;
* variants: a field typed as a union of dataclasses, each with a class attribute
  ``KIND``, is a table whose ``type`` key picks the dataclass (:func:`parse_variant`);
* for a dataclass built directly in code rather than from a table,
  :func:`check_fields` applies the same checks to its fields.

This module sits below every package (the scene, :mod:`ship_motion`, :mod:`controllers`).
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import numbers
import types
import typing
from collections.abc import Mapping
from typing import Any

from .errors import SceneError

REQUIRED = dataclasses.MISSING

#: The key of a table that picks one of several declarations (see :func:`parse_variant`).
TAG = "type"


@dataclasses.dataclass(frozen=True)
class Spec:
    """Metadata of one configuration key.

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
    notation
        How a range and choices are written: ``"comparison"`` (``> 0 and <= 10 [s]``,
        ``one of 'a', 'b'``) or ``"interval"`` (``a finite number in (0, 10] s``,
        ``one of a, b``).
    default_text
        The default in words, for a default that is not a constant of the declaration
        (absent in the table and computed from other values); shown in the reference.
    """

    unit: str = ""
    doc: str = ""
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    choices: tuple[str, ...] | None = None
    length: int | None = None
    notation: str = "comparison"
    default_text: str = ""

    def allowed(self, integer: bool = False) -> str:
        """Human-readable description of the allowed values, with the unit (``integer``:
        the value is an integer)."""
        if self.choices is not None:
            words = self.choices if self.notation == "interval" else [repr(c) for c in self.choices]
            return "one of " + ", ".join(words)
        if self.notation == "interval":
            return self._interval(integer)
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

    def _interval(self, integer: bool) -> str:
        """The range in interval notation (``a finite number in [0, 20] m``)."""
        unit = f" {self.unit}" if self.unit and self.unit != "-" and not integer else ""
        if self.length is not None:
            return f"a list of {self.length} finite numbers" + (f" [{self.unit}]" if unit else "")
        what = "an integer" if integer else "a finite number"
        lo, lo_open = (self.gt, True) if self.gt is not None else (self.ge, False)
        hi, hi_open = (self.lt, True) if self.lt is not None else (self.le, False)
        if lo is not None and hi is not None:
            return f"{what} in {'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}{unit}"
        if lo is not None:
            return f"{what} {'>' if lo_open else '>='} {lo:g}{unit}"
        if hi is not None:
            return f"{what} {'<' if hi_open else '<='} {hi:g}{unit}"
        return what + (f" [{self.unit}]" if unit else "")


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
    """``X | None`` -> (X, True); a union of several types stays a union."""
    origin = typing.get_origin(tp)
    if origin in (typing.Union, types.UnionType):
        args = tuple(a for a in typing.get_args(tp) if a is not type(None))
        optional = len(args) < len(typing.get_args(tp))
        return (args[0] if len(args) == 1 else typing.Union[args]), optional
    return tp, False


def variants(tp: Any) -> dict[str, type] | None:
    """``KIND`` -> dataclass for a union of dataclasses (a table with variants), else None."""
    if typing.get_origin(tp) not in (typing.Union, types.UnionType):
        return None
    members = typing.get_args(tp)
    if not all(_is_dataclass_type(m) and hasattr(m, "KIND") for m in members):
        return None
    return {m.KIND: m for m in members}


def _join(key: str, name: str) -> str:
    return f"{key}.{name}" if key else name


def _check_number(key: str, value: Any, sp: Spec, integer: bool) -> float | int:
    allowed = sp.allowed(integer)
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise SceneError(key, value, allowed if sp.notation == "interval"
                         else ("an integer" if integer else "a number") + f" ({allowed})")
    if integer and not isinstance(value, numbers.Integral):
        if math.isfinite(value) and float(value).is_integer():
            value = int(value)
        else:
            raise SceneError(key, value, allowed if sp.notation == "interval" else f"an integer ({allowed})")
    if not math.isfinite(value):
        raise SceneError(key, value, allowed)
    if ((sp.gt is not None and not value > sp.gt) or (sp.ge is not None and not value >= sp.ge)
            or (sp.lt is not None and not value < sp.lt) or (sp.le is not None and not value <= sp.le)):
        raise SceneError(key, value, allowed)
    return int(value) if integer else float(value)


def _convert(key: str, value: Any, tp: Any, sp: Spec) -> Any:
    tp, optional = _unwrap_optional(tp)
    if value is None:
        if optional:
            return None
        raise SceneError(key, value, sp.allowed())
    options = variants(tp)
    if options is not None:
        return parse_variant(options, value, key)
    if _is_dataclass_type(tp):
        if not isinstance(value, dict):
            raise SceneError(key, value, "a table")
        return parse(tp, value, key)
    origin = typing.get_origin(tp)
    if origin in (list, tuple):
        (item_tp, *_) = typing.get_args(tp) or (Any,)
        items = value.tolist() if hasattr(value, "tolist") and hasattr(value, "ndim") and value.ndim == 1 else value
        if not isinstance(items, (list, tuple)):
            raise SceneError(key, value, sp.allowed() if sp.notation == "interval" and not _is_dataclass_type(item_tp)
                             else "a list" if not _is_dataclass_type(item_tp) else "an array of tables")
        if _is_dataclass_type(item_tp):
            if not value:
                raise SceneError(key, value, "at least one entry")
            return tuple(parse(item_tp, v, f"{key}[{i}]") if isinstance(v, dict)
                         else _raise(SceneError(f"{key}[{i}]", v, "a table")) for i, v in enumerate(value))
        if sp.length is not None and len(items) != sp.length:
            raise SceneError(key, value, sp.allowed())
        integer = item_tp is int
        return tuple(_check_number(f"{key}[{i}]", v, sp, integer) for i, v in enumerate(items))
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


def parse_fields(cls: type, table: Mapping[str, Any], key: str, tag: str | None = None) -> dict[str, Any]:
    """Validate ``table`` against the dataclass ``cls``, key by key.

    Parameters
    ----------
    cls
        A dataclass whose fields carry :func:`spec` metadata.
    table
        The TOML table (already parsed).
    key
        Dotted path of the table, used in error messages.
    tag
        A key of the table read already (the ``type`` of a variant): accepted, not a field.

    Returns
    -------
    dict
        The keyword arguments of ``cls`` for the keys given (converted: floats, tuples,
        nested dataclasses); absent keys are left to the defaults.

    Raises
    ------
    SceneError
        On an unknown key, a missing required key, or a value of the wrong type or
        out of range.
    """
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    names = sorted([*fields, tag] if tag else fields)
    for name in table:
        if name not in fields and name != tag:
            close = difflib.get_close_matches(name, names, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise SceneError(_join(key, name), table[name], "one of the keys " + ", ".join(names) + hint)
    kwargs = {}
    for name, f in fields.items():
        sp = f.metadata.get("spec", Spec())
        if name in table:
            kwargs[name] = _convert(_join(key, name), table[name], hints[name], sp)
        elif f.default is REQUIRED and f.default_factory is REQUIRED:  # type: ignore[misc]
            raise SceneError(_join(key, name), "<missing>", f"a value ({sp.allowed(hints[name] is int)}); "
                                                            "the key is required")
    return kwargs


def parse(cls: type, table: Mapping[str, Any], key: str, tag: str | None = None) -> Any:
    """Validate ``table`` against the dataclass ``cls`` and build an instance.

    The keys are checked by :func:`parse_fields`, then the instance's ``validate(key)``
    (if it has one) checks the rules across keys.

    Raises
    ------
    SceneError
        On an unknown key, a missing required key, a value of the wrong type or out of
        range, or a broken rule across keys.
    """
    obj = cls(**parse_fields(cls, table, key, tag))
    check = getattr(obj, "validate", None)
    if check is not None:
        check(key)
    return obj


def parse_variant(options: Mapping[str, type], table: Any, key: str) -> Any:
    """Validate a table whose ``type`` key (:data:`TAG`) picks its declaration.

    Parameters
    ----------
    options
        ``type`` value -> dataclass (as :func:`variants` gives for a union).
    table
        The TOML table.
    key
        Dotted path of the table, used in error messages.

    Raises
    ------
    SceneError
        If ``table`` is not a table, its ``type`` is missing or not one of ``options``,
        or its other keys do not validate against the chosen dataclass.
    """
    kinds = " | ".join(options)
    if not isinstance(table, Mapping):
        raise SceneError(key, table, f"a table with {TAG} = {kinds}")
    allowed = "one of " + ", ".join(repr(k) for k in options)
    if TAG not in table:
        raise SceneError(_join(key, TAG), "<missing>", f"a value ({allowed}); the key is required")
    kind = table[TAG]
    if not isinstance(kind, str) or kind not in options:
        raise SceneError(_join(key, TAG), kind, allowed)
    return parse(options[kind], table, key, tag=TAG)


def check_fields(obj: Any, key: str) -> None:
    """Apply the declared checks to the fields of ``obj``, a frozen dataclass built in code
    (not by :func:`parse`), and store the converted values (floats, tuples).

    Raises
    ------
    SceneError
        Naming ``<key>.<field>``, the value as given and what is allowed.
    """
    hints = typing.get_type_hints(type(obj))
    for f in dataclasses.fields(obj):
        if "spec" in f.metadata:
            name = _join(key, f.name)
            object.__setattr__(obj, f.name, _convert(name, getattr(obj, f.name), hints[f.name], f.metadata["spec"]))


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
    if tp is int:
        return sp.allowed(integer=True)
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
    sp = f.metadata.get("spec", Spec())
    if sp.default_text:
        return sp.default_text
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
        of its keys. A table with variants has one row ("a table with type = ...");
        :func:`describe_variants` lists the keys of each variant. The rules of the class's
        ``RULES`` follow the allowed values of their key.
    """
    rows: list[dict[str, str]] = []
    hints = typing.get_type_hints(cls)
    rules = getattr(cls, "RULES", {})
    for f in dataclasses.fields(cls):
        sp = f.metadata.get("spec", Spec())
        tp, _ = _unwrap_optional(hints[f.name])
        path = f"{key}.{f.name}" if key else f.name
        origin = typing.get_origin(tp)
        item = typing.get_args(tp)[0] if origin in (list, tuple) and typing.get_args(tp) else None
        allowed = _allowed_text(tp, sp) + (f"; {rules[f.name]}" if f.name in rules else "")
        row = {"key": path, "type": _type_name(tp, sp), "unit": sp.unit, "default": _default_text(f),
               "allowed": allowed, "doc": sp.doc}
        options = variants(tp)
        if options is not None:
            rows.append(dict(row, type="table", allowed=f"a table with {TAG} = "
                             + " or ".join(repr(k) for k in options)))
        elif _is_dataclass_type(tp):
            rows.append(dict(row, type="table", allowed="a table"))
            rows.extend(describe(tp, path))
        elif item is not None and _is_dataclass_type(item):
            rows.append(dict(row, type="array of tables", allowed="one or more tables"))
            rows.extend(describe(item, path + "[]"))
        else:
            rows.append(row)
    return rows


def describe_variants(options: Mapping[str, type], key: str) -> dict[str, list[dict[str, str]]]:
    """The rows of :func:`describe` for each variant of a table (see :func:`parse_variant`).

    Returns
    -------
    dict
        ``type`` value -> rows: the ``type`` key itself (its meaning: the first line of the
        variant's docstring, first letter in lower case), then the variant's keys.
    """
    allowed = "one of " + ", ".join(repr(k) for k in options)
    out = {}
    for kind, cls in options.items():
        doc = (cls.__doc__ or "").strip().splitlines()[0].rstrip(".")
        doc = doc[:1].lower() + doc[1:]
        out[kind] = [{"key": _join(key, TAG), "type": "string", "unit": "", "default": "required",
                      "allowed": allowed, "doc": f"{kind!r}: {doc}"}] + describe(cls, key)
    return out
