"""One rule for every formulation: an optional scene table the formulation does not model
is an error naming the table, never silently ignored.

An optional table is a field of a scene table (nested ones too) whose default is None and
whose value, when given, is a table (``[viv]``, ``[water.turbulence]``, ``[motion]``).
Each formulation lists the tables it models; the ANCF cable's list is what its force
terms declare (``TABLES`` of each module of :mod:`towcable_fmu.ancf.forces`) and what its
simulation itself reads.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Collection

from ..common.errors import SceneError

#: Optional tables of data that no run reads, so every formulation accepts them: a cable
#: segment's rope data (breaking strength, construction), read by :mod:`towcable_fmu.rope_life`.
DATA_TABLES = ("cable.segments.rope",)


def optional_tables(table: Any, prefix: str = "") -> list[str]:
    """Dotted keys of the optional tables present in ``table`` (a scene or one of its
    tables, a frozen dataclass), in the order of the fields, nested ones after their parent."""
    found = []
    for field in dataclasses.fields(table):
        value = getattr(table, field.name)
        if value is None or not (dataclasses.is_dataclass(value) or isinstance(value, dict)):
            continue
        key = prefix + field.name
        if field.default is None:
            found.append(key)
        if dataclasses.is_dataclass(value):
            found.extend(optional_tables(value, key + "."))
    return found


def reject_unmodelled(scene: Any, modelled: Collection[str], formulation: str) -> None:
    """Refuse a scene with an optional table that ``formulation`` does not model.

    Raises
    ------
    SceneError
        Naming the first such table.
    """
    for key in optional_tables(scene):
        if key not in modelled and key not in DATA_TABLES:
            raise SceneError(key, f"[{key}]", f"absent with formulation = '{formulation}' (not modelled)")
