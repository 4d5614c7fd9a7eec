"""The sea of a scene given as the ShipMotion FMU gives it: a ``motion.config`` value.

The TowCable FMU's waves (``[water] waves = "motion"``) are the sea of its scene's
``[motion]``; its parameter ``motion.config`` replaces that table with the one a
ShipMotion ``motion.config`` names (TOML text, a TOML file or a built-in scene; read by
:func:`ship_motion.fmu.motion_table`, the ShipMotion FMU's own reading), so that one value
given to both FMUs gives both the same realisation. Relative file paths in the table (an
RAO or a spectrum file) are made absolute against the folder they are relative to, so the
table means the same inside the TowCable's scene, whose own folder may be another.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

from .loader import format_overrides

#: keys of a ``[motion]`` table (at any level) that name files
PATH_KEYS = ("file", "spectrum_file")


def absolute_paths(table: Mapping[str, Any], base: Path | None) -> dict[str, Any]:
    """A copy of the motion ``table`` with the relative file paths of :data:`PATH_KEYS`
    resolved against ``base`` (None: left as they are)."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        if isinstance(value, Mapping):
            out[key] = absolute_paths(value, base)
        elif key in PATH_KEYS and isinstance(value, str) and base is not None and not Path(value).is_absolute():
            out[key] = str((Path(base) / value).resolve())
        else:
            out[key] = value
    return out


def motion_config_table(config: str) -> dict[str, Any]:
    """The ``[motion]`` table a ShipMotion ``motion.config`` value names, paths absolute.

    Raises
    ------
    SceneError
        ``motion.config`` names no file, scene or TOML text of a ``[motion]`` table.
    """
    from ship_motion.fmu import motion_table

    table, base = motion_table({"motion.config": config})
    return absolute_paths(table, base)


def motion_override(config: str) -> tuple[str, dict[str, Any]]:
    """The scene override that makes ``motion.config`` the scene's ``[motion]``."""
    return "motion", motion_config_table(config)


def motion_config_text(table: Mapping[str, Any], base: Path | None = None) -> str:
    """A ``motion.config`` value (TOML text) for the motion ``table``, its relative file
    paths resolved against ``base``."""
    return format_overrides([("motion", absolute_paths(table, base))]).replace("motion=", "motion = ", 1)
