"""Reference documentation: generated files up to date and complete; worked examples run."""

from __future__ import annotations

import difflib
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from towcable_fmu.common import contract
from towcable_fmu.cli import build_parser
from towcable_fmu.docs_gen import REGENERATE, render, write_reference
from towcable_fmu.scene.model import Scene
from towcable_fmu.common.schema import describe

DOCS = Path(__file__).resolve().parents[1] / "docs"
EXAMPLES = sorted((DOCS / "examples").glob("*.md"))
BLOCK = re.compile(r"^```(python|bash)\n(.*?)^```", re.S | re.M)


def test_committed_reference_matches_a_fresh_generation(tmp_path):
    written = write_reference(tmp_path, build_parser())
    committed = sorted(p.name for p in (DOCS / "reference").glob("*.md"))
    assert committed == sorted(p.name for p in written), f"docs/reference has other files; run `{REGENERATE}`"
    for path in written:
        old = (DOCS / "reference" / path.name).read_text(encoding="utf-8")
        new = path.read_text(encoding="utf-8")
        diff = "".join(list(difflib.unified_diff(old.splitlines(True), new.splitlines(True), "committed",
                                                 "generated"))[:40])
        assert old == new, (f"docs/reference/{path.name} is out of date with the code: regenerate it with "
                            f"`{REGENERATE}` and commit the result.\n{diff}")


def test_every_scene_key_has_a_meaning_and_numbers_a_unit():
    text = render(build_parser())["scene_keys.md"]
    for row in describe(Scene):
        assert row["doc"], f"scene key {row['key']} has no description in towcable_fmu/scene/model.py"
        if row["type"] in ("number", "integer") or row["type"].startswith("list of"):
            assert row["unit"], f"scene key {row['key']} has no unit in towcable_fmu/scene/model.py"
        assert f"| `{row['key']}` |" in text


def test_scene_reference_shows_defaults_and_ranges():
    rows = {r["key"]: r for r in describe(Scene)}
    assert rows["solver.time_step"]["default"] == "0.01"
    assert rows["solver.time_step"]["allowed"] == "> 0 and <= 10 [s]"
    assert rows["cable.segments[].length"]["default"] == "required"
    assert rows["cable.top"]["default"] == '{type = "pinned", position = [0.0, 0.0, 0.0]}'
    assert rows["water"]["default"] == "absent"
    assert rows["solver.adaptive"]["allowed"] == "true or false"


def test_every_fmu_variable_is_in_the_reference():
    text = render(build_parser())["fmu_variables.md"]
    for spec in contract.fmus().values():
        section = text.split(f"## {spec.name}\n", 1)[1].split("\n## ", 1)[0]
        for v in spec.variables:
            unit = f"`{v.unit}`" if v.unit else ""
            assert f"| `{v.name}` | {v.type} | {unit} |" in section, (spec.name, v.name)
    assert text.count("| ShipMotion | TowCable |") == 18


def test_every_command_and_option_is_in_the_reference():
    text = render(build_parser())["cli.md"]
    parser = build_parser()
    (sub,) = [a for a in parser._actions if a.dest == "command"]
    for name, command in sub.choices.items():
        assert f"## `towcable {name}`" in text
        section = text.split(f"## `towcable {name}`", 1)[1].split("\n## ", 1)[0]
        for action in command._actions:
            for flag in action.option_strings:
                if flag not in ("-h", "--help"):
                    assert f"`{flag}" in section, (name, flag)


def test_docs_command_writes_the_reference(tmp_path):
    from towcable_fmu.cli import main

    assert main(["docs", "--output", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cli.md", "fmu_variables.md", "scene_keys.md"]


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.stem)
def test_worked_example_runs(example, tmp_path):
    blocks = BLOCK.findall(example.read_text(encoding="utf-8"))
    assert blocks, f"{example.name} has no ```python or ```bash block"
    env = dict(os.environ, PATH=os.path.dirname(sys.executable) + os.pathsep + os.environ.get("PATH", ""),
               MPLBACKEND="Agg")
    for k, (language, code) in enumerate(blocks):
        command = [sys.executable, "-c", code] if language == "python" else ["bash", "-e", "-c", code]
        done = subprocess.run(command, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, (f"{example.name}, block {k + 1} ({language}) failed:\n{code}\n"
                                      f"--- stdout\n{done.stdout}\n--- stderr\n{done.stderr}")


# ------------------------------------------------------- the declarations of ship_motion and controllers
def _motion_error(table: dict) -> str:
    from ship_motion import motion_from_config
    from towcable_fmu.common.errors import SceneError

    with pytest.raises(SceneError) as info:
        motion_from_config(table, key="motion")
    return str(info.value)


def _accepted_keys(message: str) -> set[str]:
    """The key names an 'unknown key' error lists ("... one of the keys a, b, c")."""
    return set(re.search(r"one of the keys ([\w, ]+)", message).group(1).split(", "))


#: A valid table of each motion type, to which a probed key is added.
MOTION_BASE = {"none": {"type": "none"}, "regular": {"type": "regular"},
               "time_series": {"type": "time_series", "file": "motion.csv"},
               "irregular": {"type": "irregular"}, "manoeuvre": {"type": "manoeuvre", "speed": 5.0}}


def test_motion_key_lists_match_the_validator():
    from towcable_fmu.docs_gen import motion_key_rows

    rows = motion_key_rows()
    assert set(rows) == set(MOTION_BASE)
    for kind, kind_rows in rows.items():
        documented = {str(r["key"]).split(".")[1] for r in kind_rows}
        assert _accepted_keys(_motion_error({**MOTION_BASE[kind], "no_such_key": 1})) == documented, kind
    regular = {str(r["key"]).split(".", 2)[2] for r in rows["regular"] if str(r["key"]).startswith("motion.heave.")}
    assert _accepted_keys(_motion_error({"type": "regular", "heave": {"no_such_key": 1}})) == regular
    rao = {str(r["key"]).split(".", 2)[2] for r in rows["irregular"] if str(r["key"]).startswith("motion.rao.")}
    particulars = _accepted_keys(_motion_error({"type": "irregular", "rao": {"no_such_key": 1}}))
    from_file = _accepted_keys(_motion_error({"type": "irregular", "rao": {"file": "r.csv", "no_such_key": 1}}))
    assert particulars | from_file == rao


def _outside(cls: type) -> list[tuple[str, object]]:
    """(key, a value just outside its declared range) for every bounded number of the
    declaration ``cls``, and for those of its nested tables (``name.key``)."""
    import dataclasses
    import typing

    out = []
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        sp = f.metadata.get("spec")
        tp = hints[f.name]
        if type(None) in typing.get_args(tp) and len(typing.get_args(tp)) == 2:  # X | None
            tp = next(a for a in typing.get_args(tp) if a is not type(None))
        if dataclasses.is_dataclass(tp):
            out += [(f"{f.name}.{name}", value) for name, value in _outside(tp)]
        elif sp is not None and tp in (int, float):
            out += [(f.name, value) for value in (sp.gt, None if sp.ge is None else sp.ge - 1, sp.lt,
                                                  None if sp.le is None else sp.le + 1) if value is not None]
    return out


def test_motion_key_ranges_match_the_validator():
    """A value outside a declared range is refused, and the error names that key (the
    reference's allowed ranges come from the same declarations)."""
    from ship_motion.config import MOTION_TABLES

    probed = 0
    for kind, cls in MOTION_TABLES.items():
        for key, value in _outside(cls):
            table = {k: (dict(v) if isinstance(v, dict) else v) for k, v in MOTION_BASE[kind].items()}
            *parents, name = key.split(".")
            target = table
            for part in parents:
                target = target.setdefault(part, {})
            target[name] = value
            message = _motion_error(table)
            assert message.startswith(f"motion.{key} = "), (key, value, message)
            probed += 1
    assert probed > 40


def test_compensation_key_ranges_match_the_validator():
    from controllers.config import SetpointConfig, setpoint_config_from_table
    from towcable_fmu.common.errors import SceneError

    base = {"algorithm": "simplified_sheave", "reference_point": [0.0, 0.0, 1.0], "winch_radius": 0.3,
            "phi_nom": 0.0, "theta_nom": 0.1}
    probes = _outside(SetpointConfig)
    assert len(probes) >= 8
    for key, value in probes:
        with pytest.raises(SceneError) as info:
            setpoint_config_from_table({**base, key: value})
        assert str(info.value).startswith(f"compensation.{key} = "), (key, value, str(info.value))


def test_every_motion_compensation_and_rigid_link_key_is_in_the_reference():
    from towcable_fmu.docs_gen import compensation_key_rows, motion_key_rows
    from towcable_fmu.scene.rigid_link import RigidLinkScene

    text = render(build_parser())["scene_keys.md"]
    rows = [r for rs in motion_key_rows().values() for r in rs] + compensation_key_rows() + describe(RigidLinkScene)
    for row in rows:
        assert row["doc"], row["key"]
        if row["type"] in ("number", "integer") or str(row["type"]).startswith("list of"):
            assert row["unit"], row["key"]
        assert f"| `{row['key']}` |" in text, row["key"]
    from controllers.config import SetpointConfig
    import dataclasses

    assert {r["key"] for r in compensation_key_rows()} == {f"compensation.{f.name}"
                                                           for f in dataclasses.fields(SetpointConfig)}
    assert '## Rigid-link model (`model = "rigid_link"`)' in text and "### [tug] (rigid link)" in text
