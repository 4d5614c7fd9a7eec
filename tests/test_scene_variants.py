"""A scene ``based_on`` another (towcable_fmu.builtin_scenes.scene_document): the base's
keys with the variant's laid over, tables merged key by key, other values replaced; loops
and missing bases are errors that name the key."""

from __future__ import annotations

import dataclasses

import pytest

from ship_motion.fmu import _config_table
from towcable_fmu.builtin_scenes import scene_document
from towcable_fmu.common.errors import SceneError
from towcable_fmu.scene import load_scene


def _same_but_provenance(a, b) -> None:
    """Two scenes equal in every field but the ones that say where they came from."""
    skip = {"title", "description", "base_dir", "based_on"}
    for field in dataclasses.fields(a):
        if field.name not in skip:
            assert getattr(a, field.name) == getattr(b, field.name), field.name


def test_a_variant_file_is_its_base_with_its_own_keys_laid_over(tmp_path):
    (tmp_path / "mine.toml").write_text('based_on = "full_scale"\ntitle = "mine"\n'
                                        '[solver]\ntime_step = 0.02\n[water]\ndensity = 1000.0\n[water.current]\ntype = "none"\n')
    scene = load_scene(tmp_path / "mine.toml")
    assert scene.title == "mine" and scene.based_on == "full_scale"
    # a table merges key by key (the rest of [solver] and [water] are the base's) ...
    expected = load_scene("full_scale", {"solver.time_step": 0.02, "water.density": 1000.0,
                                         "water.current.type": "none"})
    _same_but_provenance(scene, expected)
    # ... at any depth: [water.current] keeps the base's velocity
    assert scene.water.current.velocity == load_scene("full_scale").water.current.velocity


def test_an_array_of_tables_is_replaced_as_a_whole_and_bases_chain(tmp_path):
    """A base that is based on another, found relative to the file that names it."""
    base = load_scene("full_scale")
    first = base.cable.segments[0]
    (tmp_path / "short.toml").write_text(
        'based_on = "full_scale"\n[[cable.segments]]\n'
        + "".join(f"{k} = {v!r}\n" for k, v in (("length", 2.0), ("elements", 2), ("diameter", first.diameter),
                                                 ("mass_per_length", first.mass_per_length),
                                                 ("EA", first.EA), ("EI", first.EI))))
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "shorter.toml").write_text('based_on = "../short.toml"\n[solver]\ntime_step = 0.01\n')
    doc, folder = scene_document(tmp_path / "sub" / "shorter.toml")
    assert folder == (tmp_path / "sub").resolve()
    assert doc["based_on"] == "../short.toml" and doc["solver"]["time_step"] == 0.01
    assert len(doc["cable"]["segments"]) == 1 and doc["cable"]["segments"][0]["length"] == 2.0
    full, _ = scene_document("full_scale")
    assert doc["winch"] == full["winch"] and doc["solver"]["newton_tol"] == full["solver"]["newton_tol"]


def test_a_loop_of_bases_and_a_missing_base_are_errors_naming_based_on(tmp_path):
    (tmp_path / "a.toml").write_text('based_on = "b.toml"\n')
    (tmp_path / "b.toml").write_text('based_on = "a.toml"\n')
    with pytest.raises(SceneError, match=r"based_on = 'a.toml'.*not based on itself.*a\.toml -> .*b\.toml -> .*a\.toml"):
        load_scene(tmp_path / "a.toml")
    (tmp_path / "c.toml").write_text('based_on = "full_scael"\n')
    with pytest.raises(SceneError, match=r"based_on = 'full_scael'.*did you mean 'full_scale'"):
        load_scene(tmp_path / "c.toml")
    (tmp_path / "d.toml").write_text("based_on = 3\n")
    with pytest.raises(SceneError, match=r"based_on = 3 is invalid.*a string"):
        load_scene(tmp_path / "d.toml")


def test_shipmotion_reads_a_variants_sea_from_its_base(tmp_path):
    """motion.config with a built-in variant or a variant file: the base's [motion]."""
    base, _ = _config_table("full_scale")
    assert base["type"] == "irregular"
    assert _config_table("full_scale_waves")[0] == base
    (tmp_path / "calm.toml").write_text('based_on = "full_scale"\n[motion]\nhs = 1.0\n')
    motion, folder = _config_table(str(tmp_path / "calm.toml"))
    assert motion == {**base, "hs": 1.0} and folder == tmp_path.resolve()
