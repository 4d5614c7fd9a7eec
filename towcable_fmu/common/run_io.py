"""What a long run shows and leaves behind: the progress line on stderr (:class:`Progress`)
and the recorded series as CSV (:func:`write_csv`). The command line, the co-simulation
master, the studies and the sweeps all use these two."""

from __future__ import annotations

import csv
import math
import sys
import time
from pathlib import Path


class Progress:
    """Prints progress of a long run to stderr, at most every ``every`` seconds of wall time.

    The clock starts at the first report (the run's start time), so the rate and the
    remaining time are those of the run, not of the set-up or the kernels' compiling
    before it. Silent for runs that finish within ``every`` seconds.
    """

    def __init__(self, every: float = 2.0, stream=sys.stderr) -> None:
        self.every = every
        self.stream = stream
        self.start: float | None = None
        self.last = 0.0
        self.t_start = 0.0

    def __call__(self, t: float, t_end: float) -> None:
        now = time.perf_counter()
        if self.start is None:  # the run's start: nothing done yet to report
            self.start, self.last, self.t_start = now, now, t
            return
        if now - self.last < self.every and t < t_end:
            return
        if now - self.start < self.every:
            return
        self.last = now
        elapsed = now - self.start
        done = t - self.t_start
        total = t_end - self.t_start
        share = 100.0 * done / total if total > 0 else 100.0
        rate = done / elapsed
        eta = (total - done) / rate if rate > 0 else float("nan")
        eta_text = f"{eta:6.1f} s" if math.isfinite(eta) else "    -- s"
        self.stream.write(f"\r  t = {t:9.2f} / {t_end:.2f} s  ({share:5.1f} %)  "
                          f"{rate:7.1f} x real time  ETA {eta_text}")
        if t >= t_end:
            self.stream.write("\n")
        self.stream.flush()


def write_csv(path: Path, series: dict) -> None:
    """Write output series as CSV; the header row holds the contract names."""
    names = list(series)
    n = len(series[names[0]])
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(names)
        for i in range(n):
            writer.writerow([f"{float(series[k][i]):.10g}" for k in names])


def read_csv(path: Path) -> dict:
    """The series of a CSV written by :func:`write_csv`: column name -> numpy array.

    Raises
    ------
    ValueError
        The file has no header and rows, or a cell that is not a number (named by row and column).
    """
    import numpy as np

    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    if len(rows) < 2:
        raise ValueError(f"{path}: no recorded samples (a header row and at least one row of numbers expected)")
    names = rows[0]
    try:
        data = np.array(rows[1:], dtype=float)
    except ValueError:
        for i, row in enumerate(rows[1:], start=2):
            for name, cell in zip(names, row):
                try:
                    float(cell)
                except ValueError:
                    raise ValueError(f"{path}: row {i}, column '{name}': '{cell}' is not a number") from None
        raise ValueError(f"{path}: rows of unequal length") from None
    return {name: data[:, j] for j, name in enumerate(names)}
