"""Ship motion from a measured (or precomputed) time series.

Two CSV layouts are read (header row required, columns in any order, ``#`` comment
lines allowed, a trailing ``[unit]`` in a column name is ignored):

* positions:  ``t, x, y, z, roll, pitch, yaw``
* velocities: ``t, vx, vy, vz, roll, pitch, yaw`` (linear velocities in the inertial
  frame, as the FFG-7 trial data used in section 5 of Westin 2018). The velocities
  are integrated with the trapezoidal rule from ``initial_position``, as in the
  thesis.

Times are in s, positions in m, velocities in m/s, angles in deg or rad. The six
signals are interpolated by one interpolating spline of degree 5 (scipy
``make_interp_spline``, not-a-knot end conditions); the rates and accelerations are
the first and second derivatives of that same spline, so they are continuous
(the spline is C4) and consistent with the positions. The angles are unwrapped
first, so a yaw record passing through +-180 deg does not jump.

Outside the record's time range :class:`TimeRangeError` is raised, naming t and the
range: there is no extrapolation.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import cumulative_trapezoid
from scipy.interpolate import make_interp_spline

from towcable_fmu.common.errors import SceneError, TowcableError

from .base import MotionSource, as_times
from .csv_table import read_csv_table

#: Columns of the position layout.
POSITION_COLUMNS: tuple[str, ...] = ("t", "x", "y", "z", "roll", "pitch", "yaw")
#: Columns of the velocity layout.
VELOCITY_COLUMNS: tuple[str, ...] = ("t", "vx", "vy", "vz", "roll", "pitch", "yaw")
#: Spline degree.
DEGREE = 5


class TimeRangeError(TowcableError, ValueError):
    """A time series was evaluated outside its time range."""


def integrate_velocities(t: ArrayLike, velocities: ArrayLike,
                         initial_position: ArrayLike = (0.0, 0.0, 0.0)) -> np.ndarray:
    """Positions from velocities by the cumulative trapezoidal rule.

    Parameters
    ----------
    t
        Sample times [s], shape (n,), increasing.
    velocities
        Inertial-frame velocities [m/s], shape (n, 3).
    initial_position
        Position at ``t[0]`` [m], shape (3,).

    Returns
    -------
    ndarray, shape (n, 3)
        Positions [m].
    """
    v = np.asarray(velocities, dtype=float)
    return cumulative_trapezoid(v, np.asarray(t, dtype=float), axis=0, initial=0.0) \
        + np.asarray(initial_position, dtype=float)


@dataclass(frozen=True)
class MotionRecord:
    """A ship motion record read from a file.

    Parameters
    ----------
    t
        Sample times [s], shape (n,).
    positions
        CG positions [m], shape (n, 3).
    attitudes
        Roll, pitch, yaw [rad], shape (n, 3).
    layout
        ``"position"`` or ``"velocity"``: the file's layout.
    label
        File name and layout, for descriptions.
    """

    t: np.ndarray
    positions: np.ndarray
    attitudes: np.ndarray
    layout: str
    label: str


def read_motion_csv(path: str | Path, *, layout: str | None = None, angle_unit: str = "deg",
                    initial_position: Sequence[float] = (0.0, 0.0, 0.0),
                    key: str = "file") -> MotionRecord:
    """Read a CSV file in the position or velocity layout (module docstring).

    Parameters
    ----------
    path
        The CSV file.
    layout
        ``"position"`` or ``"velocity"``; None detects it from the header.
    angle_unit
        ``"deg"`` or ``"rad"``: unit of the roll, pitch and yaw columns.
    initial_position
        CG position [m] at the first sample (velocity layout only).
    key
        Configuration key naming the file, used in error messages.

    Returns
    -------
    MotionRecord

    Raises
    ------
    SceneError
        If the file cannot be read or its header or data do not fit.
    """
    path = Path(path)
    names, data = read_csv_table(path, key)
    layouts = {"position": POSITION_COLUMNS, "velocity": VELOCITY_COLUMNS}
    names = ["t" if n == "time" else n for n in names]
    found = [name for name, cols in layouts.items() if sorted(names) == sorted(cols)]
    wanted = [layout] if layout is not None else list(layouts)
    if not found or found[0] not in wanted:
        allowed = " or ".join(", ".join(layouts[w]) for w in wanted)
        raise SceneError(key, str(path), f"a CSV file with the header {allowed} "
                         f"(found: {', '.join(names)})")
    column = {name: data[:, i] for i, name in enumerate(names)}
    t = column["t"]
    if t.size < DEGREE + 1 or np.any(np.diff(t) <= 0.0):
        raise SceneError(key, str(path), f"a CSV file with at least {DEGREE + 1} rows "
                         "and strictly increasing times")
    scale = np.pi / 180.0 if angle_unit == "deg" else 1.0
    attitudes = np.column_stack([column[n] for n in ("roll", "pitch", "yaw")]) * scale
    if found[0] == "velocity":
        velocities = np.column_stack([column[n] for n in ("vx", "vy", "vz")])
        positions = integrate_velocities(t, velocities, initial_position)
        label = (f"{path.name} (velocities, trapezoidal rule from "
                 f"{[float(p) for p in initial_position]} m)")
    else:
        positions = np.column_stack([column[n] for n in ("x", "y", "z")])
        label = f"{path.name} (positions)"
    return MotionRecord(t, positions, attitudes, found[0], label)


class TimeSeriesMotion(MotionSource):
    """Quintic-spline interpolation of sampled positions and attitudes.

    Parameters
    ----------
    t
        Sample times [s] of the record, shape (n,), strictly increasing, n >= 6.
    positions
        CG positions x, y, z [m], shape (n, 3).
    attitudes
        Roll, pitch, yaw [rad], shape (n, 3).
    time_offset
        Record time at simulation time 0 [s]: the state at simulation time ``t`` is
        the record's state at ``t + time_offset``.
    label
        Where the data came from (shown in :attr:`description`).
    """

    def __init__(self, t: ArrayLike, positions: ArrayLike, attitudes: ArrayLike, *,
                 time_offset: float = 0.0, label: str = "arrays") -> None:
        times = np.asarray(t, dtype=float)
        values = np.column_stack([np.asarray(positions, dtype=float),
                                  np.unwrap(np.asarray(attitudes, dtype=float), axis=0)])
        if times.ndim != 1 or values.shape != (times.size, 6):
            raise ValueError("t must have shape (n,), positions and attitudes (n, 3)")
        if times.size < DEGREE + 1:
            raise ValueError(f"a time series needs at least {DEGREE + 1} samples, got {times.size}")
        if not (np.all(np.isfinite(times)) and np.all(np.isfinite(values))
                and np.isfinite(time_offset)):
            raise ValueError("time series values must be finite")
        if np.any(np.diff(times) <= 0.0):
            raise ValueError("time series times must be strictly increasing")
        self.time_offset = float(time_offset)
        self.label = label
        self._t0, self._t1 = float(times[0]), float(times[-1])
        spline = make_interp_spline(times, values, k=DEGREE, axis=0)
        self._splines = (spline, spline.derivative(1), spline.derivative(2))

    @classmethod
    def from_csv(cls, path: str | Path, *, layout: str | None = None, angle_unit: str = "deg",
                 initial_position: Sequence[float] = (0.0, 0.0, 0.0),
                 time_offset: float = 0.0, key: str = "file") -> TimeSeriesMotion:
        """Read a CSV file (see :func:`read_motion_csv`) and interpolate it.

        Parameters
        ----------
        time_offset
            Record time at simulation time 0 [s].
        path, layout, angle_unit, initial_position, key
            As for :func:`read_motion_csv`.
        """
        record = read_motion_csv(path, layout=layout, angle_unit=angle_unit,
                                 initial_position=initial_position, key=key)
        return cls(record.t, record.positions, record.attitudes, time_offset=time_offset,
                   label=record.label)

    @property
    def time_range(self) -> tuple[float, float]:
        """First and last simulation time [s] at which the motion is defined."""
        return self._t0 - self.time_offset, self._t1 - self.time_offset

    def evaluate_many(self, t: ArrayLike) -> np.ndarray:
        times = as_times(t) + self.time_offset
        tol = 1e-9 * max(1.0, self._t1 - self._t0)
        outside = (times < self._t0 - tol) | (times > self._t1 + tol)
        if np.any(outside):
            bad = float(times[outside][0] - self.time_offset)
            lo, hi = self.time_range
            raise TimeRangeError(f"t = {bad:g} s is outside the time series range "
                                 f"[{lo:g}, {hi:g}] s of {self.label}")
        times = np.clip(times, self._t0, self._t1)
        return np.stack([s(times) for s in self._splines], axis=1)

    @property
    def description(self) -> str:
        lo, hi = self.time_range
        return (f"time series {self.label}: {lo:g} s to {hi:g} s, quintic spline "
                f"(error outside the range)")
