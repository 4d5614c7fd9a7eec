"""Scenes: TOML descriptions of towed-cable systems, validated into typed objects."""

from ..builtin_scenes import builtin_scene_names
from .loader import (apply_overrides, format_overrides, load_scene, parse_override, parse_overrides,
                     scene_from_table)
from .model import Cable, End, Scene, Segment

__all__ = ["apply_overrides", "builtin_scene_names", "format_overrides", "load_scene", "parse_override",
           "parse_overrides", "scene_from_table", "Cable", "End", "Scene", "Segment"]
