"""One rule refuses a scene table a formulation does not model
(towcable_fmu/runtime/tables.py): the nodal-position cable lists the tables it models, the
ANCF cable's list is what its force terms declare (``TABLES``) and what its simulation
reads itself; every optional table the schema has is modelled by the ANCF cable."""

from __future__ import annotations

import dataclasses
import tomllib
import typing
from importlib import resources

import pytest

from towcable_fmu.ancf.simulation import MODELLED_TABLES
from towcable_fmu.common.errors import SceneError
from towcable_fmu.nodal.model import check_scene
from towcable_fmu.runtime.tables import DATA_TABLES, optional_tables, reject_unmodelled
from towcable_fmu.scene import load_scene
from towcable_fmu.scene import model as scene_model
from towcable_fmu.scene.loader import scene_from_table


def _scene_table(name: str) -> dict:
    return tomllib.loads((resources.files("towcable_fmu") / "builtin_scenes" / f"{name}.toml").read_text(encoding="utf-8"))


def schema_tables(cls: type, prefix: str = "") -> list[str]:
    """The optional tables (default None, a table when given) the scene schema declares."""
    hints = typing.get_type_hints(cls, vars(scene_model))
    found = []
    for field in dataclasses.fields(cls):
        kinds = [k for k in typing.get_args(hints[field.name]) or (hints[field.name],) if k is not type(None)]
        table = next((k for k in kinds if dataclasses.is_dataclass(k) or k is dict), None)
        if table is None:
            continue
        if field.default is None:
            found.append(prefix + field.name)
        if dataclasses.is_dataclass(table):
            found.extend(schema_tables(table, prefix + field.name + "."))
    return found


def test_the_tables_of_a_scene_are_the_headers_of_its_file():
    """full_scale.toml's optional tables, read from its file's headers by hand."""
    assert optional_tables(load_scene("full_scale")) == [
        "water", "winch", "sheave", "compensation", "towbody", "towbody.lift", "motion"]


def test_a_table_the_nodal_cable_does_not_model_is_refused_naming_it():
    """[sheave] and [water.turbulence] (ANCF only) on the nodal cable: refused by the one
    rule, naming the table; the same tables on the ANCF cable are accepted."""
    for key in ("sheave", "water.turbulence"):
        table = _scene_table("snapping_cable_nodal")
        if key == "sheave":
            table["sheave"] = _scene_table("full_scale")["sheave"]
        else:
            table["water"]["turbulence"] = _scene_table("flume")["water"]["turbulence"]
        with pytest.raises(SceneError, match=rf"{key} = '\[{key}\]'.*absent with formulation = 'nodal_position'"):
            check_scene(scene_from_table(table))
        table["model"] = "ancf"
        table["solver"]["integrator"] = "genalpha"
        scene = scene_from_table(table)
        assert key in optional_tables(scene)
        reject_unmodelled(scene, MODELLED_TABLES, "ancf")


def test_every_table_of_the_schema_is_modelled_by_the_ancf_cable():
    """A new schema table that no force term declares (and the simulation does not read)
    is refused by the ANCF cable: this list (with the data tables no run reads) and the
    schema's are the same."""
    assert sorted(schema_tables(scene_model.Scene)) == sorted(MODELLED_TABLES + DATA_TABLES)


def test_the_rule_refuses_a_table_no_one_declared():
    """A scene type with one more optional table than the ANCF cable models."""
    @dataclasses.dataclass(frozen=True)
    class Seabed:
        depth: float = -10.0

    @dataclasses.dataclass(frozen=True)
    class Extended:
        water: scene_model.Water | None = None
        seabed: Seabed | None = None

    reject_unmodelled(Extended(water=scene_model.Water()), MODELLED_TABLES, "ancf")
    with pytest.raises(SceneError, match=r"seabed = '\[seabed\]'.*formulation = 'ancf'"):
        reject_unmodelled(Extended(seabed=Seabed()), MODELLED_TABLES, "ancf")
