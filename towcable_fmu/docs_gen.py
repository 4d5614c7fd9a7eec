"""Reference documentation generated from the code, so that it cannot drift.

Three Markdown files: every scene key of every model (from the scene schemas,
:mod:`towcable_fmu.scene.model` and :mod:`towcable_fmu.scene.rigid_link` via
:func:`towcable_fmu.scene.schema.describe`; the ``[motion]`` and ``[compensation]``
tables, which :mod:`ship_motion` and :mod:`controllers` validate, from
:func:`motion_key_rows` and :func:`compensation_key_rows`, whose key sets, defaults and
ranges tests/test_docs.py checks against those validators), every FMU variable and
connection (from the variable contract, :mod:`towcable_fmu.contract`), and the command
line (from the argument parser of :mod:`towcable_fmu.cli`).

Regenerate with ``towcable docs --output docs/reference``; a test compares the committed
files with a fresh generation.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Iterable, Sequence

from . import contract
from .scene.model import Scene
from .scene.schema import describe

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
def _row(key: str, type_: str, unit: str, default: object, allowed: str, doc: str, probe: object = None
         ) -> dict[str, object]:
    """One documented key. A string ``default`` is written as given (a TOML string literal
    must carry its quotes; other text describes the default), other values as TOML;
    ``probe`` is a value the validator must refuse (for the tests)."""
    from .scene.schema import toml_text

    text = default if isinstance(default, str) else toml_text(default)
    return {"key": key, "type": type_, "unit": unit, "default": text, "allowed": allowed, "doc": doc,
            "probe": probe}


def motion_key_rows() -> dict[str, list[dict[str, object]]]:
    """The keys of a scene's ``[motion]`` table by ``type`` (validated by
    :func:`ship_motion.config.motion_from_config`).

    Defaults are taken from :data:`ship_motion.config.DEFAULT_SEA` and the frigate's
    particulars where the validator takes them from there. Each row may carry a
    ``probe``: a value outside the allowed range (tests/test_docs.py checks that the
    validator refuses it naming the key).

    Returns
    -------
    dict
        ``type`` value -> rows (keys as in :func:`towcable_fmu.scene.schema.describe`).
    """
    from ship_motion.config import _PARTICULAR_RANGES, DEFAULT_SEA, TYPES
    from ship_motion.irregular import DEFAULT_BAND
    from ship_motion.rao import FRIGATE
    from ship_motion.spectrum import SPACINGS

    def one_of(values) -> str:
        return "one of " + ", ".join(repr(v) for v in values)

    d = DEFAULT_SEA
    kind = _row("motion.type", "string", "", "required", one_of(TYPES),
                "kind of motion; the other keys depend on it", "wavy")
    rows: dict[str, list[dict[str, object]]] = {"none": [dict(kind, doc="'none': the ship is still (no other keys)")]}
    regular = [kind, _row("motion.ramp", "number", "s", 0.0, ">= 0 [s]",
                          "the oscillations grow from zero over this time (the means do not)", -1.0)]
    for dof, unit in (("surge", "m"), ("sway", "m"), ("heave", "m"), ("roll", "deg"), ("pitch", "deg"),
                      ("yaw", "deg")):
        limit = {"roll": "; |mean| + amplitude < 90 deg", "pitch": "; |mean| + amplitude < 90 deg",
                 "yaw": "; <= 180 deg"}.get(dof, "")
        regular += [
            _row(f"motion.{dof}", "table", "", "absent", "a table",
                 f"{dof} q(t) = mean + ramp(t) amplitude sin(2 pi t / period + phase) (absent: 0)"),
            _row(f"motion.{dof}.mean", "number", unit, 0.0, f"a finite number [{unit}]", f"mean {dof}", "x"),
            _row(f"motion.{dof}.amplitude", "number", unit, 0.0, f">= 0 [{unit}]{limit}", f"{dof} amplitude",
                 -1.0),
            _row(f"motion.{dof}.period", "number", "s", "absent", "> 0 [s]; required when amplitude > 0",
                 f"{dof} period", 0.0),
            _row(f"motion.{dof}.phase", "number", "deg", 0.0, "a finite number [deg]", f"{dof} phase", "x"),
        ]
    rows["regular"] = regular
    rows["time_series"] = [
        kind,
        _row("motion.file", "string", "", "required", "a CSV file (relative to the scene file's folder)",
             "recorded motion: columns t, x, y, z, roll, pitch, yaw (position format) or t, vx, vy, vz, roll, "
             "pitch, yaw (velocity format); interpolated by a quintic spline, no extrapolation", 1.0),
        _row("motion.format", "string", "", "absent", one_of(("position", "velocity")),
             "column layout (absent: from the header)", "speed"),
        _row("motion.angle_unit", "string", "", '"deg"', one_of(("deg", "rad")), "unit of the angle columns",
             "grad"),
        _row("motion.initial_position", "list of 3 numbers", "m", [0.0, 0.0, 0.0], "3 finite numbers [m]",
             "CG position at the first sample (velocity format only: the velocities are integrated from it)",
             [0.0, 0.0]),
        _row("motion.time_offset", "number", "s", 0.0, "a finite number [s]",
             "record time at simulation time 0", "x"),
    ]
    band = f"{DEFAULT_BAND[0]:g} x 2 pi / tp"  # the validator's default band
    irregular = [
        kind,
        _row("motion.hs", "number", "m", d["hs"], ">= 0 and <= 20 [m]", "significant wave height (JONSWAP)", 21.0),
        _row("motion.tp", "number", "s", d["tp"], ">= 2 and <= 30 [s]", "peak period", 1.0),
        _row("motion.gamma", "number", "-", d["gamma"], ">= 1 and <= 10", "peak enhancement factor "
             "(1: Pierson-Moskowitz)", 0.5),
        _row("motion.heading", "number", "deg", d["heading"], "a finite number [deg]",
             "direction the waves travel, from the ship's X axis counter-clockwise (180: head seas)", "x"),
        _row("motion.speed", "number", "m/s", d["speed"], ">= 0 and <= 25 [m/s]",
             "ship speed for the encounter frequency (in [motion.waves] of a manoeuvre: its speed)", -1.0),
        _row("motion.components", "integer", "-", d["components"], ">= 1 and <= 5000", "wave components", 0),
        _row("motion.omega_min", "number", "rad/s", band, "> 0 and <= 20 [rad/s]", "lower end of the wave band",
             0.0),
        _row("motion.omega_max", "number", "rad/s", f"{DEFAULT_BAND[1]:g} x 2 pi / tp",
             "> omega_min and <= 20 [rad/s]", "upper end of the wave band", 21.0),
        _row("motion.spacing", "string", "", f'"{d["spacing"]}"', one_of(SPACINGS),
             "component frequencies: random within each bin, or the bin centres", "log"),
        _row("motion.seed", "integer", "-", d["seed"], ">= 0", "seed of the random phases (and frequencies)", -1),
        _row("motion.ramp", "number", "s", d["ramp"], ">= 0 [s]", "the sea grows from calm over this time", -1.0),
        _row("motion.rao", "table", "", "the closed-form frigate below", "a table",
             "response amplitude operators: the hull particulars below (closed form), or a file"),
    ]
    docs = {"length": "length between perpendiculars", "beam": "beam", "draught": "draught",
            "block_coefficient": "block coefficient", "roll_period": "natural roll period",
            "roll_damping": "roll damping (fraction of critical)"}
    for name, (lo, lo_open, hi, unit) in _PARTICULAR_RANGES.items():
        irregular.append(_row(f"motion.rao.{name}", "number", unit, getattr(FRIGATE, name),
                              f"{'>' if lo_open else '>='} {lo:g} and <= {hi:g}" + (f" [{unit}]" if unit != "-" else ""),
                              docs[name], hi + 1.0))
    irregular += [
        _row("motion.rao.file", "string", "", "absent", "an RAO CSV file (then no hull particulars)",
             "RAO table: columns omega, heading, <dof>_amp, <dof>_phase; must cover the wave band and heading", 1.0),
        _row("motion.rao.angle_unit", "string", "", '"deg"', one_of(("deg", "rad")),
             "unit of the rotational amplitudes and of all phases in the RAO file"),
    ]
    rows["irregular"] = irregular
    rows["manoeuvre"] = [
        kind,
        _row("motion.speed", "number", "m/s", "required", ">= 0 and <= 30 [m/s]", "cruise speed", 31.0),
        _row("motion.speed_ramp", "number", "s", 0.0, ">= 0 [s]",
             "time to ramp from initial_speed to speed, from t = 0", -1.0),
        _row("motion.initial_speed", "number", "m/s", "absent", ">= 0 and <= 30 [m/s]; differing from speed "
             "needs speed_ramp > 0", "speed at t = 0 (absent: 0 with a speed ramp, else speed)", 31.0),
        _row("motion.heading", "number", "deg", 0.0, "a finite number [deg]", "initial heading (yaw)", "x"),
        _row("motion.position", "list of 2 numbers", "m", [0.0, 0.0], "2 finite numbers [m]", "initial CG (x, y)",
             [0.0]),
        _row("motion.turn_angle", "number", "deg", 0.0, ">= 0 and <= 36000 [deg]; >= |turn_rate| x turn_ramp",
             "total heading change of the turn (0: no turn)", -1.0),
        _row("motion.turn_rate", "number", "deg/s", "absent", ">= -20 and <= 20 [deg/s], non-zero; required when "
             "turn_angle > 0", "yaw rate of the turn (> 0 turns to port)", 21.0),
        _row("motion.turn_start", "number", "s", 0.0, ">= 0 [s]", "time the yaw rate starts to ramp up", -1.0),
        _row("motion.turn_ramp", "number", "s", 10.0, "> 0 [s]", "time for the yaw rate to ramp up (and down)", 0.0),
        _row("motion.waves", "table", "", "absent", "a table with type = 'regular' or 'irregular'",
             "waves superposed on the manoeuvre: the keys of that type, under motion.waves."),
    ]
    return rows


#: Defaults of the ``[compensation]`` keys in a scene (the scene supplies some).
COMPENSATION_DEFAULTS: dict[str, str] = {
    "algorithm": "required",
    "reference_point": "the sheave centre (without a sheave: the top of the winch drum)",
    "winch_radius": "the winch's (to the cable centreline)",
    "phi_nom": "winch.phi_nom",
    "theta_nom": "the model's own static departure angle",
    "waterline_z": "water.surface_z (0 without water)",
    "max_payout": "absent",
    "max_winch_speed": "absent",
    "max_winch_acceleration": "absent",
    "tension_target": "absent (required by constant_tension)",
    "tension_gain": "absent (required by constant_tension)",
}


#: Meanings of ``[compensation]`` keys whose docstring entry does not read well alone.
COMPENSATION_DOCS: dict[str, str] = {
    "algorithm": "set-point algorithm: W(2) sheave or W(1) waterline reference, simplified (nominal departure "
                 "angle) or rigorous (measured sheave angle); constant_tension: a constant-tension winch (payout "
                 "from the measured tension); 'none' holds the winch",
}


def _parameter_docs(cls: type) -> dict[str, str]:
    """The numpy-style ``Parameters`` section of a class docstring: name -> first sentence."""
    import inspect
    import re

    text = inspect.getdoc(cls) or ""
    section = text.split("Parameters\n----------\n", 1)[-1].split("\n\n", 1)[0] if "Parameters" in text else ""
    docs: dict[str, list[str]] = {}
    name = None
    for line in section.splitlines():
        if line and not line.startswith(" "):
            name = line.split(":")[0].strip()
            docs[name] = []
        elif name is not None:
            docs[name].append(line.strip())
    out = {}
    for key, lines in docs.items():
        joined = " ".join(lines)
        out[key] = re.split(r"(?<=\.)\s", joined, maxsplit=1)[0].rstrip(".").replace("``", "")
    return out


def compensation_key_rows() -> list[dict[str, object]]:
    """The keys of a scene's ``[compensation]`` table (validated by
    :func:`controllers.config.setpoint_config_from_table`): names and meanings from
    :class:`controllers.config.SetpointConfig`, allowed values (with the unit) from
    :data:`controllers.config.ALLOWED`, defaults from :data:`COMPENSATION_DEFAULTS`."""
    import dataclasses
    import re

    from controllers.config import ALLOWED, SetpointConfig

    meaning = _parameter_docs(SetpointConfig)
    rows = []
    for f in dataclasses.fields(SetpointConfig):
        allowed = ALLOWED[f.name]
        units = re.findall(r"\[([^\[\]]+)\]", allowed)  # the last [...] without brackets inside
        kind = ("string" if f.name == "algorithm" else "list of 3 numbers" if f.name == "reference_point"
                else "number")
        default = COMPENSATION_DEFAULTS[f.name]
        rows.append({"key": f"compensation.{f.name}", "type": kind, "unit": units[-1] if units else "",
                     "default": default, "allowed": allowed,
                     "doc": COMPENSATION_DOCS.get(f.name) or meaning.get(f.name, "")})
    return rows


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
    from .scene.loader import MODELS

    rows = describe(Scene)
    model = {"key": "model", "type": "string", "unit": "", "default": '"ancf"',
             "allowed": "one of " + ", ".join(repr(m) for m in MODELS),
             "doc": "the model: 'ancf' for the cable models of this page (cable.formulation chooses ANCF or "
                    "nodal-position elements), 'rigid_link' for the tug-and-tow model of chains of rigid links "
                    "(its keys are listed at the end)"}
    lines = _header("Scene keys", "the scene schemas (towcable_fmu/scene/model.py, towcable_fmu/scene/rigid_link.py)"
                    " and the [motion] and [compensation] key lists of towcable_fmu/docs_gen.py")
    lines += ["A scene is a TOML file (see the README, section Scenes). Keys are listed by their dotted path, as "
              "`towcable ... --set KEY=VALUE` takes them; `[]` marks an array of tables (`[[cable.segments]]`, "
              "overridden as `cable.segments[0].elements`). Units are SI unless given; `-` is dimensionless. "
              "Default \"absent\" means the key or table is left out (its meaning then says what happens); "
              "\"required\" keys must be given when their table is. A table's default is the whole table "
              "used when it is left out. Unknown keys and values outside the allowed range are errors that "
              "name the key.", "",
              "Contents: the cable models (`model = \"ancf\"`, the default), with the keys of the ship motion "
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
    lines = _header("FMU variables", "the variable contract (towcable_fmu/contract.toml)")
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
