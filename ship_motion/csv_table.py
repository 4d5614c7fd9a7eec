"""Reading small numeric CSV files with one header row.

Blank lines and lines starting with ``#`` are skipped. Column names are compared
case-insensitively, with surrounding spaces and a trailing unit in brackets removed
(``"Roll [deg]"`` is the column ``roll``).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from towcable_fmu.common.errors import SceneError

_UNIT = re.compile(r"\s*[\[(][^\])]*[\])]\s*$")


def column_name(text: str) -> str:
    """Normalised column name: lower case, no spaces, no trailing ``[unit]``."""
    return _UNIT.sub("", text.strip()).strip().lower()


def read_csv_table(path: Path, key: str) -> tuple[list[str], np.ndarray]:
    """Read a CSV file with a header row and numeric data.

    Parameters
    ----------
    path
        The file.
    key
        Dotted configuration key that named the file (for error messages).

    Returns
    -------
    names : list of str
        Normalised column names.
    data : ndarray, shape (rows, columns)

    Raises
    ------
    SceneError
        If the file is missing, a row has the wrong number of fields, a field is not
        a finite number, or a column name repeats.
    """
    if not path.is_file():
        raise SceneError(key, str(path), "an existing CSV file")
    names: list[str] | None = None
    rows: list[list[float]] = []
    with path.open(encoding="utf-8") as handle:
        for number, line in enumerate(handle, start=1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            fields = [f.strip() for f in text.split(",")]
            if names is None:
                names = [column_name(f) for f in fields]
                if len(set(names)) != len(names):
                    raise SceneError(key, str(path),
                                     f"a CSV file with distinct column names (header: {text})")
                continue
            if len(fields) != len(names):
                raise SceneError(key, str(path), f"a CSV file with {len(names)} fields on every "
                                 f"row (line {number} has {len(fields)})")
            try:
                values = [float(f) for f in fields]
            except ValueError:
                raise SceneError(key, str(path), f"a CSV file of numbers after the header "
                                 f"(line {number}: {text!r})") from None
            if not all(np.isfinite(values)):
                raise SceneError(key, str(path), f"a CSV file of finite numbers (line {number})")
            rows.append(values)
    if names is None:
        raise SceneError(key, str(path), "a CSV file with a header row")
    return names, np.array(rows, dtype=float).reshape(len(rows), len(names))
