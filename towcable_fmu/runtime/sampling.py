"""The output grid of a run: validated duration and interval, and the sample times."""

from __future__ import annotations

import math

import numpy as np

from ..common.errors import SceneError


def output_interval(duration: float, interval: float | None, default: float) -> float:
    """Check a run's duration [s] and return its output interval [s] (``default`` if None).

    Raises
    ------
    SceneError
        If the duration or the interval is not a finite number > 0.
    """
    if not (math.isfinite(duration) and duration > 0.0):
        raise SceneError("duration", duration, "a finite time > 0 s")
    dt = default if interval is None else interval
    if not (math.isfinite(dt) and dt > 0.0):
        raise SceneError("output.interval", dt, "a finite interval > 0 s")
    return dt


def sample_times(t0: float, duration: float, interval: float) -> np.ndarray:
    """Sample times [s] after ``t0``, every ``interval``, the last one at ``t0 + duration``."""
    n = max(1, int(math.ceil(duration / interval - 1e-9)))
    return t0 + np.minimum(np.arange(1, n + 1) * interval, duration)
