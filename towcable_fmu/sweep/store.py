"""The results table of a sweep: one CSV row per case, appended as each case finishes.

Columns: ``case_id``, ``status`` (``ok``/``failed``), the swept parameters (names as in
the sweep file), the run settings and fixed overrides (``mode``, ``scene``, ``duration``,
..., ``fixed.<key>``: the full parameter set), the statistics (header ``name [unit]``),
``wall_time [s]``, ``worker`` and ``error``. Each row is flushed and synced to disk when
written, so an interrupted sweep loses at most the row being written; a torn last line
is dropped when the table is opened again.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import os
from pathlib import Path
from typing import Any, Iterable

import numpy as np

from .case import CaseResult
from .spec import Case, SpecError, SweepSpec
from .statistics import STATISTICS

SETTING_COLUMNS = ("mode", "scene", "duration", "settle", "interval", "step", "fraction")


def header(spec: SweepSpec) -> list[str]:
    """The column names of the table."""
    return (["case_id", "status"] + list(spec.parameters) + list(SETTING_COLUMNS)
            + [f"fixed.{k}" for k in spec.fixed]
            + [f"{n} [{STATISTICS[n].unit}]" for n in spec.statistics] + ["wall_time [s]", "worker", "error"])


def _cell(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "" if math.isnan(value) else f"{value:.10g}"
    if isinstance(value, (list, dict)):
        return json.dumps(value)
    return str(value)


class ResultTable:
    """The CSV table of a sweep, opened for appending.

    Parameters
    ----------
    path
        The CSV file (created with its header if missing).
    spec
        The sweep; an existing table must have the same columns.

    Raises
    ------
    SpecError
        An existing table with other columns (another sweep writes to the same folder).
    """

    def __init__(self, path: Path, spec: SweepSpec) -> None:
        self.path = Path(path)
        self.spec = spec
        self.columns = header(spec)
        self.rows: dict[str, dict[str, str]] = {}
        if self.path.exists() and self.path.stat().st_size > 0:
            self._load()
        else:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._rewrite([])

    def _load(self) -> None:
        text = self.path.read_text(encoding="utf-8")
        lines = text.splitlines(keepends=True)
        torn = bool(lines) and not lines[-1].endswith("\n")
        reader = csv.reader(lines[:-1] if torn else lines)
        found = next(reader, None)
        if found != self.columns:
            raise SpecError("sweep.output", str(self.path.parent),
                            f"a folder whose {self.path.name} has this sweep's columns (it has {found}); "
                            "use another output folder or remove the table")
        kept = []
        for row in reader:
            if len(row) != len(self.columns):
                continue  # a row cut short by an interruption
            record = dict(zip(self.columns, row))
            if record["case_id"] not in self.rows:
                kept.append(row)
            self.rows[record["case_id"]] = record
        if torn or len(kept) != sum(1 for _ in csv.reader(lines[1:])):
            self._rewrite(kept)

    def _rewrite(self, rows: list[list[str]]) -> None:
        tmp = self.path.with_suffix(".tmp")
        with open(tmp, "w", newline="", encoding="utf-8") as fh:
            writer = csv.writer(fh)
            writer.writerow(self.columns)
            writer.writerows(rows)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, self.path)

    def done(self) -> set[str]:
        """Case ids with a row (ok or failed)."""
        return set(self.rows)

    def drop_failed(self) -> int:
        """Remove the rows of failed cases (to run them again); returns how many."""
        failed = [cid for cid, row in self.rows.items() if row["status"] != "ok"]
        for cid in failed:
            del self.rows[cid]
        self._rewrite([[row[c] for c in self.columns] for row in self.rows.values()])
        return len(failed)

    def append(self, case: Case, result: CaseResult) -> bool:
        """Write the row of a finished case (flushed and synced); False if it has one already."""
        if case.case_id in self.rows:
            return False
        s = dataclasses.asdict(case.settings)
        values: dict[str, Any] = {"case_id": case.case_id, "status": result.status, **case.values,
                                  **{k: s[k] for k in SETTING_COLUMNS},
                                  **{f"fixed.{k}": v for k, v in self.spec.fixed.items()},
                                  "wall_time [s]": result.wall_time, "worker": result.worker,
                                  "error": result.error}
        values.update({f"{n} [{STATISTICS[n].unit}]": result.statistics.get(n, math.nan) for n in case.statistics})
        row = [_cell(values[c]) for c in self.columns]
        with open(self.path, "a", newline="", encoding="utf-8") as fh:
            csv.writer(fh).writerow(row)
            fh.flush()
            os.fsync(fh.fileno())
        self.rows[case.case_id] = dict(zip(self.columns, row))
        return True


def write_series(folder: Path, case_id: str, series: dict[str, np.ndarray]) -> Path:
    """Write a case's time series as ``folder/<case_id>.csv`` (columns = output names)."""
    from ..cli import write_csv

    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{case_id}.csv"
    tmp = path.with_suffix(".tmp")
    write_csv(tmp, series)
    os.replace(tmp, path)
    return path


def read_table(path: Path) -> list[dict[str, str]]:
    """The rows of a results table as dicts keyed by column name."""
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


def column(rows: Iterable[dict[str, str]], name: str) -> np.ndarray:
    """A numeric column (empty cells -> NaN)."""
    return np.array([float(r[name]) if r[name] != "" else math.nan for r in rows])
