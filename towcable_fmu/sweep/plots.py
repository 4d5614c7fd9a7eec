"""Plots of a sweep's results: heat maps of a statistic over two swept parameters, and
exceedance curves of the tension from the per-case time series."""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from .spec import SpecError
from .store import column, read_table


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def statistic_column(rows: Sequence[Mapping[str, str]], statistic: str) -> str:
    """The table column of a statistic name (``tension.sheave.max`` -> ``tension.sheave.max [N]``)."""
    names = list(rows[0]) if rows else []
    for name in names:
        if name == statistic or name.split(" [")[0] == statistic:
            return name
    raise SpecError("--statistic", statistic, "a statistic column of the table: "
                    + ", ".join(n.split(" [")[0] for n in names if n.endswith("]") and n != "wall_time [s]"))


def heatmap_grid(rows: Sequence[Mapping[str, str]], statistic: str, x: str, y: str
                 ) -> tuple[list[str], list[str], np.ndarray, np.ndarray]:
    """A statistic on the grid of two swept parameters.

    Parameters
    ----------
    rows
        Table rows (:func:`~towcable_fmu.sweep.store.read_table`).
    statistic
        Statistic name or column.
    x, y
        Swept parameter columns.

    Returns
    -------
    (x values, y values, mean, count)
        Distinct values as they appear in the table (numbers sorted), and ``(ny, nx)``
        arrays: the mean of the statistic over the successful cases in each cell (over
        the other swept parameters; NaN where none) and how many cases that mean holds.
    """
    col = statistic_column(rows, statistic)
    for name in (x, y):
        if not rows or name not in rows[0]:
            raise SpecError("--x/--y", name, "a parameter column of the table: "
                            + ", ".join(list(rows[0])[2:] if rows else []))
    xs, ys = _levels([r[x] for r in rows]), _levels([r[y] for r in rows])
    total = np.zeros((len(ys), len(xs)))
    count = np.zeros((len(ys), len(xs)))
    for row in rows:
        if row["status"] != "ok" or row[col] == "" or math.isnan(float(row[col])):
            continue
        i, j = ys.index(row[y]), xs.index(row[x])
        total[i, j] += float(row[col])
        count[i, j] += 1
    with np.errstate(invalid="ignore"):
        mean = np.where(count > 0, total / np.maximum(count, 1), np.nan)
    return xs, ys, mean, count


def _levels(values: Sequence[str]) -> list[str]:
    distinct = list(dict.fromkeys(values))
    try:
        return sorted(distinct, key=float)
    except ValueError:
        return distinct


def plot_heatmap(table: Path, statistic: str, x: str, y: str, path: Path) -> Path:
    """Heat map of ``statistic`` over the parameters ``x`` and ``y`` (mean over the
    other swept parameters; cells annotated with the value, grey where no case succeeded)."""
    rows = read_table(table)
    xs, ys, mean, count = heatmap_grid(rows, statistic, x, y)
    col = statistic_column(rows, statistic)
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(1.2 * len(xs) + 3, 0.8 * len(ys) + 2.5))
    cmap = plt.get_cmap("viridis").with_extremes(bad="0.8")
    image = ax.imshow(np.ma.masked_invalid(mean), origin="lower", aspect="auto", cmap=cmap)
    ax.set_xticks(range(len(xs)), xs)
    ax.set_yticks(range(len(ys)), ys)
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    finite = mean[np.isfinite(mean)]
    middle = 0.5 * (finite.min() + finite.max()) if finite.size else 0.0
    for i in range(len(ys)):
        for j in range(len(xs)):
            text = "failed" if count[i, j] == 0 else f"{mean[i, j]:.4g}"
            ax.text(j, i, text, ha="center", va="center", fontsize=8,
                    color="white" if count[i, j] and mean[i, j] < middle else "black")
    fig.colorbar(image, ax=ax, label=col)
    others = int(count.max()) if count.size else 0
    ax.set_title(f"{col}" + (f" (mean of up to {others} cases per cell)" if others > 1 else ""), fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def exceedance(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Empirical exceedance curve: levels sorted in decreasing order and the share of
    samples above or at each level, ``P(X >= level)`` in (0, 1]."""
    levels = np.sort(np.asarray(values, dtype=float))[::-1]
    return levels, np.arange(1, levels.size + 1) / levels.size


def _read_series(path: Path, names: Sequence[str]) -> dict[str, np.ndarray]:
    with open(path, newline="", encoding="utf-8") as fh:
        reader = csv.reader(fh)
        head = next(reader)
        data = np.array([[float(v) for v in row] for row in reader])
    missing = [n for n in names if n not in head]
    if missing:
        raise SpecError("--signal", missing[0], f"an output in the series files ({', '.join(head)})")
    return {n: data[:, head.index(n)] for n in names}


def plot_exceedance(table: Path, path: Path, signal: str = "tension.sheave", label: Sequence[str] = ()) -> Path:
    """Exceedance curves of ``signal`` (after each case's settling time), one per case.

    Parameters
    ----------
    table
        The results table (CSV or Parquet); the series are read from ``series/<case_id>.csv`` next to it
        (a sweep with ``series = true``).
    path
        PNG to write.
    signal
        Output name [its unit].
    label
        Parameter columns shown in the legend (default: all swept parameters).

    Raises
    ------
    SpecError
        No series files (the sweep did not keep them).
    """
    rows = [r for r in read_table(table) if r["status"] == "ok"]
    folder = table.parent / "series"
    rows = [r for r in rows if (folder / f"{r['case_id']}.csv").is_file()]
    if not rows:
        raise SpecError("sweep.series", False, f"true: no time series in {folder} (run the sweep with "
                                               "series = true)")
    fixed_columns = {"case_id", "status", "mode", "scene", "duration", "settle", "interval", "step", "fraction"}
    keys = list(label) or [c for c in rows[0] if c not in fixed_columns and not c.startswith("fixed.")
                           and "[" not in c and c not in ("worker", "error")]
    settle = column(rows, "settle")
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 5))
    for row, t0 in zip(rows, settle):
        data = _read_series(folder / f"{row['case_id']}.csv", ("time", signal))
        levels, share = exceedance(data[signal][data["time"] >= t0 - 1e-9])
        ax.semilogy(levels, share, lw=1.0, label=", ".join(f"{k}={row[k]}" for k in keys))
    from ..common import contract

    ax.set_xlabel(f"{signal} [{contract.unit_of(signal)}]")
    ax.set_ylabel("share of time exceeded [-]")
    ax.grid(alpha=0.3, which="both")
    if len(rows) <= 20:
        ax.legend(fontsize=7)
    ax.set_title(f"exceedance of {signal} after the settling time, {len(rows)} cases", fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
