"""Finding, reading and overriding scene files.

A scene is named either by a built-in name (a file ``<name>.toml`` shipped in
``towcable_fmu/builtin_scenes``) or by a path to the user's own TOML file. Overrides are
``dotted.key=value`` strings (values in TOML syntax; bare words are strings), applied
before validation so that they are validated like the file itself.
"""

from __future__ import annotations

import copy
import dataclasses
import json
import re
import tomllib
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Mapping

from ..builtin_scenes import scene_document
from ..common.errors import SceneError
from ..common.schema import parse, spec
from .model import Scene

if TYPE_CHECKING:
    from .rigid_link import RigidLinkScene

_INDEX = re.compile(r"^(?P<name>[^\[\]]+)\[(?P<index>\d+)\]$")


def parse_override(text: str) -> tuple[str, Any]:
    """Split ``key=value`` and parse the value as TOML (falling back to a string).

    Examples: ``solver.time_step=0.005``, ``cable.segments[0].elements=20``,
    ``cable.top.position=[0, 0, 1]``, ``cable.top.type=clamped``.
    """
    if "=" not in text:
        raise SceneError("--set", text, "key=value with a dotted key, e.g. solver.time_step=0.005")
    key, raw = (s.strip() for s in text.split("=", 1))
    if not key:
        raise SceneError("--set", text, "a non-empty key before '='")
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw
    return key, value


def parse_overrides(text: str) -> list[tuple[str, Any]]:
    """``KEY=VALUE`` items separated by ``;`` or new lines (values in TOML syntax).

    A ``;`` inside brackets or quotes does not separate items.
    """
    items, depth, quote, current = [], 0, "", []
    for ch in text:
        if quote:
            quote = "" if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif depth == 0 and ch in ";\n":
            items.append("".join(current))
            current = []
            continue
        current.append(ch)
    items.append("".join(current))
    return [parse_override(item.strip()) for item in items if item.strip()]


def format_overrides(items: Iterable[tuple[str, Any]]) -> str:
    """Overrides as one line of ``key=value; ...`` in TOML syntax (the TowCable FMU's
    ``overrides`` parameter; :func:`parse_override` reads each item back)."""
    def toml(value: Any) -> str:
        if isinstance(value, bool):
            return "true" if value else "false"
        if isinstance(value, (int, float)):
            return repr(value)
        if isinstance(value, str):
            return json.dumps(value)
        if isinstance(value, (list, tuple)):
            return "[" + ", ".join(toml(v) for v in value) + "]"
        if isinstance(value, Mapping):
            return "{" + ", ".join(f"{k} = {toml(v)}" for k, v in value.items()) + "}"
        raise TypeError(f"cannot write {value!r} as TOML")

    return "; ".join(f"{key}={toml(value)}" for key, value in items)


def apply_overrides(table: dict, overrides: Mapping[str, Any] | Iterable[tuple[str, Any]]) -> dict:
    """Return a deep copy of ``table`` with dotted-path overrides applied.

    Parameters
    ----------
    table
        Parsed TOML document.
    overrides
        Mapping or pairs of dotted key -> value. A list index is written ``name[i]``.
    """
    out = copy.deepcopy(table)
    items = overrides.items() if isinstance(overrides, Mapping) else overrides
    for key, value in items:
        node: Any = out
        parts = key.split(".")
        for depth, part in enumerate(parts):
            last = depth == len(parts) - 1
            m = _INDEX.match(part)
            name, index = (m["name"], int(m["index"])) if m else (part, None)
            if not isinstance(node, dict):
                raise SceneError(key, value, f"a key inside a table ('{'.'.join(parts[:depth])}' is not a table)")
            if index is None:
                if last:
                    node[name] = value
                else:
                    node = node.setdefault(name, {})
            else:
                seq = node.get(name)
                if not isinstance(seq, list) or index >= len(seq):
                    size = len(seq) if isinstance(seq, list) else 0
                    raise SceneError(f"{key} (index {index} of '{'.'.join(parts[:depth] + [name])}')", value,
                                     f"an index below {size} (the scene has {size} entries)")
                if last:
                    seq[index] = value
                else:
                    node = seq[index]
    return out


def load_scene(name_or_path: str | Path,
               overrides: Mapping[str, Any] | Iterable[tuple[str, Any]] = ()) -> Scene | RigidLinkScene:
    """Load, override and validate a scene.

    Parameters
    ----------
    name_or_path
        Built-in scene name (see :func:`~towcable_fmu.builtin_scenes.builtin_scene_names`) or
        path to a TOML file; a scene ``based_on`` another is merged with it first
        (:func:`~towcable_fmu.builtin_scenes.scene_document`).
    overrides
        Dotted-key overrides applied before validation.

    Returns
    -------
    Scene or RigidLinkScene
        The validated scene (a rigid-link scene when its top-level ``model`` key is
        ``"rigid_link"``); relative file paths in it are resolved against
        ``Scene.base_dir``, which defaults to the scene file's folder.

    Raises
    ------
    SceneError
        Unknown scene, invalid TOML, unknown keys or out-of-range values.
    """
    table, base = scene_document(name_or_path)
    table = apply_overrides(table, overrides)
    if base is not None:
        table.setdefault("base_dir", str(base))
    return scene_from_table(table)


#: Model kinds a scene names with its top-level ``model`` key ("nodal_position" last: it
#: was first chosen by cable.formulation alone).
MODELS = ("ancf", "rigid_link", "nodal_position")


@dataclasses.dataclass(frozen=True)
class ModelChoice:
    """The one key that picks the model kind of a scene."""

    model: str = spec("ancf", choices=MODELS,
                      doc="the model kind: 'ancf' (gradient-deficient ANCF cable elements, Westin 2018) and "
                          "'nodal_position' (straight two-node elements in nodal positions, Sun et al., "
                          "towcable_fmu/nodal/; no bending, top pinned, bottom free with the lumped body) take the "
                          "cable keys of this page; 'rigid_link' is the tug-and-tow model of chains of rigid links "
                          "(its keys are listed at the end). Older scenes write the cable kinds as "
                          "cable.formulation, an alias kept for them")


def _model_kind(table: Mapping[str, Any]) -> str:
    """The model kind a scene document asks for: its ``model`` key, else the alias
    ``cable.formulation``, else "ancf". Both given must agree."""
    cable = table.get("cable")
    alias = cable.get("formulation") if isinstance(cable, Mapping) else None
    if "model" not in table:
        return "ancf" if alias is None else alias  # the Cable declaration validates the alias
    model = parse(ModelChoice, {"model": table["model"]}, "").model
    if alias is not None and alias != model:
        raise SceneError("cable.formulation", alias, f"absent: the top-level key model = {model!r} picks the model "
                         "kind (cable.formulation is its older alias)")
    return model


def scene_from_table(table: dict) -> Scene | RigidLinkScene:
    """Validate a parsed TOML document into a :class:`Scene` (or, with ``model =
    "rigid_link"``, a :class:`~towcable_fmu.scene.rigid_link.RigidLinkScene`).

    The top-level ``model`` key picks the model kind (:class:`ModelChoice`); for the
    cable kinds the scene's ``cable.formulation`` carries it (the key older scenes write).
    """
    model = _model_kind(table)
    if model == "rigid_link":
        from .rigid_link import RigidLinkScene

        return parse(RigidLinkScene, table, "")
    scene = {k: v for k, v in table.items() if k != "model"}
    if isinstance(scene.get("cable"), Mapping):
        scene["cable"] = {**scene["cable"], "formulation": model}
    return parse(Scene, scene, "")
