"""A ship's sea as the ShipMotion FMU's ``motion.config`` names it, as a ``[motion]`` table
and as TOML text, for the TowCable FMU's scene.

The TowCable FMU's waves (``[water] waves = "motion"``) are the sea of its scene's
``[motion]``; the item ``motion = {...}`` of its ``overrides`` replaces that table. A
ShipMotion ``motion.config`` (TOML text, a TOML file or a built-in scene; read by
:func:`ship_motion.fmu.motion_table`, the ShipMotion FMU's own reading) becomes that item
here, so that both FMUs get the same realisation. Relative file paths in the table (an
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


def motion_config_text(table: Mapping[str, Any], base: Path | None = None) -> str:
    """A ``motion.config`` value (TOML text) for the motion ``table``, its relative file
    paths resolved against ``base``."""
    return format_overrides([("motion", absolute_paths(table, base))]).replace("motion=", "motion = ", 1)
