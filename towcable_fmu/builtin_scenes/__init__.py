"""The scenes shipped with towcable: one TOML file ``<name>.toml`` per scene (data).

The code that validates a scene is :mod:`towcable_fmu.scene`; this module only finds the
files by name, so that packages below the scene package (the ShipMotion FMU, the FMU
build's warm-up) can list and read them.
"""

from __future__ import annotations

from importlib import resources


def builtin_scene_names() -> list[str]:
    """Names of the scenes shipped with the package, sorted."""
    return sorted(p.name[:-5] for p in resources.files(__name__).iterdir() if p.name.endswith(".toml"))


def builtin_scene_text(name: str) -> str:
    """The TOML text of the built-in scene ``name`` (one of :func:`builtin_scene_names`)."""
    return (resources.files(__name__) / f"{name}.toml").read_text(encoding="utf-8")
