"""Reference documentation generated from the code, so that it cannot drift.

Three Markdown files: every scene key of every model (from the declarations that also
validate them, through :func:`towcable_fmu.common.schema.describe`: the scene's in
:mod:`towcable_fmu.scene.model` and :mod:`towcable_fmu.scene.rigid_link`, the
``[motion]`` table's in :mod:`ship_motion.config`, the ``[compensation]`` table's in
:mod:`controllers.config`), every FMU variable and connection (from the variable
contract, :mod:`towcable_fmu.common.contract`), and the command line (from the argument parser
of :mod:`towcable_fmu.cli`).

Regenerate with ``towcable docs --output docs/reference``; a test compares the committed
files with a fresh generation.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Iterable, Sequence

from .common import contract
from .scene.model import Scene
from .common.schema import describe, describe_variants

#: The command that regenerates the committed reference (quoted in every file).
REGENERATE = "towcable docs --output docs/reference"

#: Tables of a scene whose keys another package validates: where their behaviour is
#: described at length (relative to docs/reference/); their keys are listed here too.
EXTERNAL_TABLES = {
    "motion": "../../ship_motion/README.md",
    "compensation": "../../controllers/README.md",
}


def _header(title: str, source: str) -> list[str]:
    return [f"# {title}", "",
            f"<!-- Generated from {source} by `{REGENERATE}` (towcable_fmu/docs_gen.py). Do not edit by hand. -->",
            ""]


def _cell(text: object) -> str:
    """Text safe inside a Markdown table cell."""
    return str(text).replace("\\", "\\\\").replace("|", "\\|").replace("\n", " ")


def _code(text: object) -> str:
    """Inline code in a table cell (empty stays empty)."""
    text = str(text)
    return f"`{_cell(text)}`" if text else ""


def _table(head: Sequence[str], rows: Iterable[Sequence[str]]) -> list[str]:
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return lines + [""]


# ------------------------------------------------------------------ scene keys
def motion_key_rows() -> dict[str, list[dict[str, str]]]:
    """The keys of a scene's ``[motion]`` table by ``type``, from their declarations
    (:data:`ship_motion.config.MOTION_TABLES`, validated by
    :func:`ship_motion.config.motion_from_config`)."""
    from ship_motion.config import MOTION_TABLES

    return describe_variants(MOTION_TABLES, "motion")


def compensation_key_rows() -> list[dict[str, str]]:
    """The keys of a scene's ``[compensation]`` table, from their declaration
    (:class:`controllers.config.SetpointConfig`)."""
    from controllers.config import SetpointConfig

    return describe(SetpointConfig, "compensation")


def _section(rows: Sequence[dict], level: str, suffix: str = "") -> list[str]:
    """A heading per table (keys grouped by their top-level name) and a table of keys."""
    lines: list[str] = []
    sections: dict[str, list[dict]] = {"": []}  # the top-level keys first
    for row in rows:
        top = str(row["key"]).split(".")[0].split("[")[0]
        name = top if any(str(r["key"]).startswith(top + ".") for r in rows) or top in EXTERNAL_TABLES else ""
        sections.setdefault(name, []).append(row)
    for name, section in sections.items():
        if not section:
            continue
        lines += [f"{level} [{name}]{suffix}" if name else f"{level} Top level{suffix}", ""]
        lines += _key_table(section)
        if name == "motion" and not suffix:
            lines += _motion_section(level + "#")
        if name == "compensation" and not suffix:
            lines += ["With a `[compensation]` table the scene's own ship motion drives the winch set-point "
                      "(heave compensation; the co-simulation uses the HeaveCompensation FMU instead). "
                      f"Algorithms and formulas: [controllers/README.md]({EXTERNAL_TABLES['compensation']}).", ""]
            lines += _key_table(compensation_key_rows())
    return lines


def _describes(default: str) -> bool:
    """True for a default written in words (not a TOML value)."""
    return default in ("required", "absent") or (" " in default and not default.startswith(("[", "{", '"')))


def _key_table(rows: Iterable[dict]) -> list[str]:
    return _table(("key", "type", "unit", "default", "allowed", "meaning"),
                  ((_code(r["key"]), str(r["type"]), _cell(r["unit"]),
                    _cell(r["default"]) if _describes(str(r["default"])) else _code(r["default"]),
                    _cell(r["allowed"]), _cell(r["doc"])) for r in rows))


def _motion_section(level: str) -> list[str]:
    lines = ["Ship motion of the scene's own runs (and, in the co-simulation, of the ShipMotion FMU). "
             f"Conventions and formulas: [ship_motion/README.md]({EXTERNAL_TABLES['motion']}). Angles in the "
             "table are in degrees. The keys depend on `type`:", ""]
    for kind, rows in motion_key_rows().items():
        lines += [f'{level} `type = "{kind}"`', ""]
        lines += _key_table(rows)
    return lines


def scene_keys_markdown() -> str:
    """Every scene key of every model: meaning, unit, default and allowed values, by table."""
    from .scene.rigid_link import RigidLinkScene
    from .scene.loader import ModelChoice

    rows = describe(Scene)
    model = describe(ModelChoice)[0]
    lines = _header("Scene keys", "the declarations of towcable_fmu/scene/model.py, towcable_fmu/scene/rigid_link.py, "
                    "ship_motion/config.py and controllers/config.py")
    lines += ["A scene is a TOML file (see the README, section Scenes). Keys are listed by their dotted path, as "
              "`towcable ... --set KEY=VALUE` takes them; `[]` marks an array of tables (`[[cable.segments]]`, "
              "overridden as `cable.segments[0].elements`). Units are SI unless given; `-` is dimensionless. "
              "Default \"absent\" means the key or table is left out (its meaning then says what happens); "
              "\"required\" keys must be given when their table is. A table's default is the whole table "
              "used when it is left out. Unknown keys and values outside the allowed range are errors that "
              "name the key.", "",
              "Contents: the cable models (`model = \"ancf\"`, the default, and `model = \"nodal_position\"`), "
              "with the keys of the ship motion "
              "(`[motion]`) and of the heave compensation (`[compensation]`); then the rigid-link model "
              "(`model = \"rigid_link\"`).", ""]
    lines += _section([model] + rows, "##")
    lines += ['## Rigid-link model (`model = "rigid_link"`)', "",
              "A tug and a towed vessel joined by a chain of rigid links (towcable_fmu/rigidlink). A scene with "
              "`model = \"rigid_link\"` takes these keys only.", ""]
    lines += _section(describe(RigidLinkScene), "###", " (rigid link)")
    return "\n".join(lines)


# ---------------------------------------------------------------- FMU variables
def _start(value: object) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return _code(f'"{value}"')
    return _code(repr(value))


def fmu_variables_markdown() -> str:
    """Every signal, every FMU's parameters, inputs and outputs, and the connections."""
    lines = _header("FMU variables", "the variable contract (towcable_fmu/common/contract.toml)")
    lines += ["Names, units and descriptions are those written into each FMU's `modelDescription.xml`; the "
              "command line (`towcable static --json`, `towcable run` CSV columns) uses the same names. "
              "Within an FMU the value references follow the order of the tables below: parameters, inputs, "
              "outputs. Units are FMI unit symbols (`1`: dimensionless). Parameters are `fixed` (they act at "
              "initialisation; a value outside [min, max] is refused by its setter with fmi2Error); outputs are "
              "`initial=\"calculated\"` (computed at initialisation).", "", "## Signals", ""]
    fmus = contract.fmus()
    users: dict[str, list[str]] = {}
    for spec in fmus.values():
        for v in spec.inputs + spec.outputs:
            users.setdefault(v.name, []).append(f"{spec.name} ({v.causality})")
    lines += _table(("signal", "type", "unit", "description", "FMUs"),
                    ((_code(s.name), s.type, _code(s.unit), _cell(s.description)
                      + (" (diagnostic)" if s.diagnostic else ""), ", ".join(users.get(s.name, [])))
                     for s in contract.signals().values()))
    lines += ["Signals used by no FMU are outputs of the Python `Simulation` and the command line only.", ""]
    for spec in fmus.values():
        lines += [f"## {spec.name}", "", _cell(spec.description), "", f"Slave: `{spec.slave}`.", ""]
        for causality in ("parameter", "input", "output"):
            variables = getattr(spec, causality + "s")
            if not variables:
                continue
            lines += [f"### {causality.capitalize()}s", ""]
            if causality == "parameter":  # fixed: set before initialisation; the range is modelDescription's
                lines += _table(("name", "type", "unit", "start", "min", "max", "description"),
                                ((_code(v.name), v.type, _code(v.unit or ""), _start(v.start), _start(v.min),
                                  _start(v.max), _cell(v.description)) for v in variables))
            else:
                lines += _table(("name", "type", "unit", "description"),
                                ((_code(v.name), v.type, _code(v.unit or ""), _cell(v.description))
                                 for v in variables))
    system = contract.system()
    lines += [f"## Connections of {system['name']}", "", _cell(system["description"]) + ".", "",
              "Components in evaluation order: " + ", ".join(system["components"]) + ". A delayed connection "
              "carries the value of the previous communication point.", ""]
    lines += _table(("from", "to", "signal", "delayed"),
                    ((c.source, c.target, _code(c.signal), "yes" if c.delayed else "")
                     for c in contract.connections()))
    return "\n".join(lines)


# ---------------------------------------------------------------- command line
def _help(action: argparse.Action, prog: str) -> str:
    text = action.help or ""
    if "%(" in text:
        text = text % dict(vars(action), prog=prog)
    return _cell(text)


def _argument(action: argparse.Action) -> str:
    if action.option_strings:
        flags = ", ".join(action.option_strings)
        if action.nargs == 0:
            return _code(flags)
        metavar = action.metavar if action.metavar is not None else action.dest.upper()
        if isinstance(metavar, tuple):
            metavar = " ".join(metavar)
        elif action.nargs in ("+", "*"):
            metavar = f"{metavar} ..."
        elif isinstance(action.nargs, int) and action.nargs > 1:
            metavar = " ".join([metavar] * action.nargs)
        return _code(f"{flags} {metavar}")
    return _code(action.metavar or action.dest.upper())


def _values(action: argparse.Action) -> str:
    if action.choices is not None:
        return ", ".join(_code(c) for c in action.choices)
    if action.nargs == 0:
        return "flag"
    if action.type is not None and hasattr(action.type, "__name__"):
        return {"float": "number", "int": "integer", "_positive": "number > 0"}.get(action.type.__name__, "text")
    return "text"


def _default(action: argparse.Action) -> str:
    if action.required:
        return "required"
    if action.nargs == 0 or action.default is None:
        return ""
    if isinstance(action.default, (list, tuple)):
        return _code(" ".join(str(v) for v in action.default))
    return _code(action.default)


def _command_section(name: str, summary: str, parser: argparse.ArgumentParser) -> list[str]:
    actions = [a for a in parser._actions if not isinstance(a, argparse._HelpAction)]
    synopsis = [f"{parser.prog}"]
    for a in actions:
        if not a.option_strings:
            synopsis.append(a.metavar or a.dest.upper())
        elif a.required:
            synopsis.append(_argument(a).strip("`"))
    if any(a.option_strings and not a.required for a in actions):
        synopsis.append("[options]")
    lines = [f"## `towcable {name}`", "", _cell(summary[:1].upper() + summary[1:]) + ".", ""]
    if parser.description:
        lines += [_cell(parser.description), ""]
    lines += ["```text", " ".join(synopsis), "```", ""]
    if not actions:
        return lines
    return lines + _table(("argument", "value", "default", "meaning"),
                          ((_argument(a), _values(a), _default(a), _help(a, parser.prog)) for a in actions))


def cli_markdown(parser: argparse.ArgumentParser) -> str:
    """Every subcommand with its arguments, from the command line's argument parser."""
    lines = _header("Command line", "the argument parser (towcable_fmu/cli.py)")
    lines += [_cell(parser.description), "", f"`{parser.prog} COMMAND --help` prints the same information.", ""]
    (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    summaries = {a.dest: a.help or "" for a in sub._choices_actions}
    lines += _table(("command", "what it does"),
                    ((f"[`{name}`](#towcable-{name})", _cell(summaries.get(name, ""))) for name in sub.choices))
    for name, command in sub.choices.items():
        lines += _command_section(name, summaries.get(name, ""), command)
    return "\n".join(lines)


# ------------------------------------------------------------------ files
def render(parser: argparse.ArgumentParser) -> dict[str, str]:
    """File name -> Markdown text of the whole reference; ``parser`` is the command line's
    (:func:`towcable_fmu.cli.build_parser`: the command line calls this, not the other way)."""
    return {"scene_keys.md": scene_keys_markdown(), "fmu_variables.md": fmu_variables_markdown(),
            "cli.md": cli_markdown(parser)}


def write_reference(output: Path, parser: argparse.ArgumentParser) -> list[Path]:
    """Write the reference into the folder ``output`` (created); return the files written."""
    output.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, text in render(parser).items():
        path = output / name
        path.write_text(text, encoding="utf-8")
        paths.append(path)
    return paths
