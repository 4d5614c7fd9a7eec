"""The built-in scenes with waves (issue 42 item 5) are their base scenes with the waves on."""

from __future__ import annotations

import dataclasses
import tomllib
from importlib import resources

import pytest

from towcable_fmu.scene import load_scene


def table(name: str) -> dict:
    path = resources.files("towcable_fmu") / "builtin_scenes" / f"{name}.toml"
    return tomllib.loads(path.read_text(encoding="utf-8"))


@pytest.mark.parametrize("base", ["full_scale", "full_scale_recovery"])
def test_waves_variant_is_the_base_scene_with_the_waves_on(base):
    """The variant's own file says only what differs (based_on); loaded, it is the base with
    the waves on and its own title and description."""
    variant = table(f"{base}_waves")
    assert variant.pop("based_on") == base and variant.pop("water") == {"waves": "motion"}
    assert set(variant) == {"title", "description"}
    scene = load_scene(f"{base}_waves")
    assert scene.water.waves == "motion" and scene.motion["type"] == "irregular"
    assert dataclasses.replace(scene.water, waves="off") == load_scene(base).water
