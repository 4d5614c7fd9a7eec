"""What every simulation does the same way, whatever its model: the checks of its inputs,
the run loop that records samples, the drive tables from the scene's ship motion, rollback
of a failed step, the JSON state, the solver counters and progress reports.

:class:`SimulationDriver` is the base of the ANCF, nodal-position and rigid-link
simulations; each implements the protocol :class:`~towcable_fmu.runtime.protocol.CableSimulation`
by supplying the model's part through a few hooks (see the class). The registry
:mod:`towcable_fmu.models` picks the class.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from ..common import contract
from . import drive as drive_poly
from ..common.errors import SceneError, SolverError
from .sampling import output_interval, sample_times
from ..scene import load_scene
from .ship_input import check_ship_state


def checked_ship(ship: Any) -> np.ndarray:
    """A ship state (3, 6) as a float array (value, rate, acceleration of x, y, z [m], roll,
    pitch, yaw [rad]).

    Raises
    ------
    SceneError
        Naming the entry, if the shape is not (3, 6) or a value is not finite.
    """
    ship = np.asarray(ship, dtype=float)
    check_ship_state(ship)
    return ship


def checked_setpoint(setpoint: Iterable[float]) -> tuple[float, float]:
    """A winch set-point (phi_sp [rad], phi_sp_rate [rad/s]) as two floats.

    Raises
    ------
    SceneError
        If it is not two finite numbers.
    """
    values = tuple(map(float, setpoint))
    if len(values) != 2 or not all(map(math.isfinite, values)):
        raise SceneError("setpoint", tuple(setpoint), "finite phi_sp [rad] and phi_sp_rate [rad/s]")
    return values


def checked_step(dt: float) -> float:
    """A communication step [s]: finite and > 0 (else a SceneError naming ``dt``)."""
    if not (math.isfinite(dt) and dt > 0.0):
        raise SceneError("dt", dt, "a finite step > 0 s")
    return float(dt)


class SimulationDriver:
    """The common part of a simulation (SI units throughout).

    A subclass calls :meth:`_keep` with its scene and sets ``names`` (its outputs, ``time``
    excluded) in its constructor and implements:

    * ``time`` (property): the current time [s];
    * ``_initial_state(t0, ship, setpoint, statics, **start)``: the state at ``t0`` (inputs
      already checked; ``ship`` and ``setpoint`` may be None; ``start``: the model's own
      keywords of :meth:`initialize`); returns None, or a dict of results that
      :meth:`initialize` returns instead of the outputs;
    * ``_advance(dt, ship, setpoint)``: one communication step (raises SolverError if it
      cannot; :meth:`step` rolls the state back);
    * ``_output_row()``: the outputs at the current state in the order of ``names``;
    * ``_record(block, rows, t_land)``: step through the sample times ``block`` [s] and
      write their outputs into ``rows``; returns how many were reached (never past
      ``t_land``, the run's last sample);
    * ``_failure(t)``: the SolverError of a run that could not reach the sample time ``t``;
    * ``_state_arrays()``: the arrays that hold the whole state, named by
      ``STATE_FIELDS``; ``_counters()``: the solver counters named by ``COUNTER_NAMES``.

    and may override ``_extra_state``/``_load_extra_state``/``_restored`` (state beyond
    the arrays), ``_begin_recording``/``_end_recording`` and ``_block_size`` (the run
    loop), ``_setpoints_at`` (the drive table's winch set-point) and
    ``_extra_statistics``.
    """

    #: Names of the arrays of ``_state_arrays()`` in :meth:`get_state`.
    STATE_FIELDS: tuple[str, ...] = ()
    #: Names of the counters of ``_counters()`` (``solver.`` is prefixed in :meth:`statistics`).
    COUNTER_NAMES: tuple[str, ...] = ()
    #: Whether :meth:`step` needs the ship state (a model driven by the ship's motion).
    NEEDS_SHIP = True

    #: The scene the simulation was built from (kept only to name it: title, animation).
    scene: Any
    names: tuple[str, ...]
    #: The scene's output interval [s], the default of :meth:`run`.
    default_interval: float
    _initialized: bool = False
    #: The statics' figures of the last initialisation (``solver.statics_*``).
    _statics: dict[str, float]
    #: Buffers of the last :meth:`_snapshot` (reused: a step is a co-simulation's hot path).
    _snapshot_buffers: list[np.ndarray] | None = None

    # ------------------------------------------------------------ construction
    @classmethod
    def from_scene(cls, name_or_path: str | Path,
                   overrides: Mapping[str, Any] | Iterable[tuple[str, Any]] = ()) -> "SimulationDriver":
        """Load a built-in scene by name, or a scene file, with dotted-key overrides."""
        return cls(load_scene(name_or_path, overrides))

    def _keep(self, scene: Any) -> None:
        """Keep ``scene`` (its name and title) and what the driver itself needs of it."""
        self.scene = scene
        self.default_interval = float(scene.output.interval)

    # ----------------------------------------------------------------- outputs
    @property
    def output_names(self) -> tuple[str, ...]:
        """The outputs this scene has, ``time`` first: the keys of :meth:`outputs` and the
        columns of :meth:`run` (units: :meth:`unit_of`)."""
        return ("time", *self.names)

    def unit_of(self, name: str) -> str:
        """Unit of an output name (the variable contract's)."""
        return contract.unit_of(name)

    def outputs(self) -> dict[str, float]:
        """The outputs at the current state, keyed by :attr:`output_names`."""
        return self._named(self._output_row())

    def only_outputs(self, wanted: Iterable[str]) -> None:
        """A caller that reads only the outputs in ``wanted`` says so: a model may then leave
        the others out of :attr:`names` and not compute them (this one computes all)."""

    def _named(self, row: np.ndarray) -> dict[str, float]:
        """The outputs of the current state from their row (the order of ``names``)."""
        return {"time": self.time, **dict(zip(self.names, row.tolist()))}

    # -------------------------------------------------------------------- time
    def initialize(self, t0: float = 0.0, ship: np.ndarray | None = None,
                   setpoint: tuple[float, float] | None = None, statics: bool | None = None,
                   **start: Any) -> dict[str, float]:
        """The initial state at ``t0`` [s]: the model's initial shape, its statics if
        ``statics`` (None: the scene's choice) and consistent accelerations.

        Parameters
        ----------
        t0
            Start time [s].
        ship
            Ship state (3, 6) at t0; default: the scene's motion at t0.
        setpoint
            Winch set-point (phi_sp [rad], phi_sp_rate [rad/s]); default: the scene's.
        statics
            Solve the statics first (default: the scene's ``statics.enabled``).
        **start
            The model's own start options (the ANCF cable's ``q0``: start from these
            coordinates instead of the laid-out shape, see its ``_initial_state``).

        Returns
        -------
        dict
            The outputs at t0.

        Raises
        ------
        SceneError
            If an input is not finite or has the wrong shape; nothing is changed.
        SolverError
            If the statics do not converge or the state has no finite acceleration.
        """
        if not math.isfinite(t0):
            raise SceneError("t0", t0, "a finite start time [s]")
        ship = None if ship is None else checked_ship(ship)
        setpoint = None if setpoint is None else checked_setpoint(setpoint)
        self._statics = {}
        result = self._initial_state(float(t0), ship, setpoint, statics, **start)
        self._initialized = True
        return self.outputs() if result is None else result

    def _require_initialized(self) -> None:
        if not self._initialized:
            raise SolverError("call initialize() before stepping the simulation")

    def step(self, dt: float, ship: np.ndarray | None = None,
             setpoint: tuple[float, float] | None = None) -> dict[str, float]:
        """Advance by ``dt`` [s] with the ship state (3, 6) given at the start of the step
        (FMU style: extrapolated with constant acceleration over the step) and the winch
        set-point (phi_sp [rad], phi_sp_rate [rad/s]; default: unchanged).

        Returns
        -------
        dict
            The outputs at the new time.

        Raises
        ------
        SceneError
            Bad inputs (non-finite, wrong shape, non-positive dt); nothing is changed.
        SolverError
            If the step fails; the state is then left as it was before the call.
        """
        return self._named(self.step_row(dt, ship, setpoint))

    def step_row(self, dt: float, ship: np.ndarray | None = None,
                 setpoint: tuple[float, float] | None = None) -> np.ndarray:
        """:meth:`step` with the outputs as an array in the order of :attr:`names` (without
        ``time``): what an FMU copies at every step, without building a dict.

        Raises
        ------
        SceneError, SolverError
            As :meth:`step`.
        """
        self._require_initialized()
        dt = checked_step(dt)
        if ship is None and self.NEEDS_SHIP:
            raise SceneError("ship", None, "a ship state: an array of shape (3, 6)")
        ship = None if ship is None else checked_ship(ship)
        setpoint = None if setpoint is None else checked_setpoint(setpoint)
        return self._guarded(lambda: self._advance(dt, ship, setpoint))

    def _guarded(self, advance: Callable[[], None]) -> np.ndarray:
        """Run ``advance``; the outputs after it (:meth:`_output_row`), or the state rolled back
        and the error raised."""
        saved = self._snapshot()
        try:
            advance()
            row = self._output_row()
            if not np.isfinite(row).all():
                raise SolverError(f"non-finite outputs at t = {self.time:.6g} s")
        except SolverError:
            self._restore(saved)
            raise
        return row

    def _drive(self, marks: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
        """Drive table of the scene's ship motion (``self.motion``) through the times
        ``marks`` [s], knots at the marks and between them no farther apart than ``h`` [s]
        (the quintic Hermite pieces then follow any motion a step of ``h`` resolves), with
        the winch set-points of :meth:`_setpoints_at`."""
        times = drive_poly.knot_times(marks, h)
        ships = self.motion.evaluate_many(times)
        return drive_poly.knot_drive(times, ships, self._setpoints_at(times, ships))

    def _setpoints_at(self, times: np.ndarray, ships: np.ndarray) -> np.ndarray:
        """Winch set-points (knots, 2) of the drive table (phi_sp [rad], rate [rad/s]): none here."""
        return np.zeros((times.size, 2))

    # --------------------------------------------------------------------- run
    def run(self, duration: float, interval: float | None = None,
            progress: Callable[[float, float], None] | None = None) -> dict[str, np.ndarray]:
        """Initialise if needed and record the outputs every ``interval`` [s] for
        ``duration`` [s] with the scene's own motion.

        Parameters
        ----------
        duration
            Simulated time [s] (> 0).
        interval
            Output interval [s]; default: the scene's ``output.interval``.
        progress
            Called as ``progress(t, t_end)`` [s] at the start and after every block of
            samples (at least 1 s of simulated time; the ANCF simulation's blocks hold at
            least 100 nominal steps).

        Returns
        -------
        dict
            :attr:`output_names` -> array over the samples (the start included).

        Raises
        ------
        SceneError
            If the duration or the interval is not a finite time > 0.
        SolverError
            If a step fails or an output is not finite; the state is then that of the
            last accepted step.
        """
        dt = output_interval(duration, interval, self.default_interval)
        if not self._initialized:
            self.initialize()
        t0 = self.time
        samples = sample_times(t0, duration, dt)
        values = np.empty((samples.size + 1, len(self.names)))
        values[0] = self._output_row()
        chunk = self._block_size(dt)
        t_land = float(samples[-1])
        if progress is not None:
            progress(t0, t_land)
        self._begin_recording(samples)
        for first in range(0, samples.size, chunk):
            stop = min(samples.size, first + chunk)
            reached = first + self._record(samples[first:stop], values[first + 1:stop + 1], t_land)
            if reached < stop:
                raise self._failure(float(samples[reached]))
            if progress is not None:
                progress(float(samples[stop - 1]), t_land)
        self._end_recording()
        out = {"time": np.concatenate([[t0], samples])}
        out.update(zip(self.names, values.T))
        return out

    def _block_size(self, interval: float) -> int:
        """Samples per block of the run loop: about a second of simulated time."""
        return max(1, int(1.0 / interval))

    def _begin_recording(self, samples: np.ndarray) -> None:
        """Called once before the run loop with all its sample times [s]."""

    def _end_recording(self) -> None:
        """Called once after the run loop has reached its last sample."""

    @staticmethod
    def _interpolation_marks(block: np.ndarray, time: float, step_start: float, h: float,
                             t_land: float) -> np.ndarray:
        """Times [s] a block's drive table must pass through when its samples are read from
        the integrator's interpolant: from the start of the last step (samples inside it:
        ``step_start``, the state being at ``time``) to one step ``h`` past the block."""
        start = min(time, step_start) if block[0] < time else time
        end = min(t_land, float(block[-1]) + h)
        return np.unique(np.concatenate([[start], block[block > start], [end]]))

    # ------------------------------------------------------------------- state
    def _extra_state(self) -> dict[str, Any]:
        """JSON-able state beyond the arrays (saved by :meth:`get_state` and rollbacks)."""
        return {}

    def _load_extra_state(self, data: Mapping[str, Any]) -> None:
        """Restore what :meth:`_extra_state` saved (before the arrays are written)."""

    def _restored(self) -> None:
        """Called after the arrays were written back (e.g. to refactorise)."""

    def _snapshot(self) -> tuple[list[np.ndarray], dict[str, Any]]:
        """The state arrays (copied into buffers kept for the next snapshot: a step is the
        hot path of a co-simulation) and the extra state."""
        arrays = self._state_arrays()
        buffers = self._snapshot_buffers
        if buffers is None or len(buffers) != len(arrays) or any(b.shape != x.shape for b, x in zip(buffers, arrays)):
            buffers = self._snapshot_buffers = [np.empty_like(x) for x in arrays]
        for b, x in zip(buffers, arrays):
            np.copyto(b, x)
        return buffers, self._extra_state()

    def _restore(self, saved: tuple[list[np.ndarray], dict[str, Any]]) -> None:
        arrays, extra = saved
        self._load_extra_state(extra)
        for dst, src in zip(self._state_arrays(), arrays):
            dst[...] = src
        self._restored()

    def _n_coordinates(self) -> int:
        return int(self._state_arrays()[0].size)

    def get_state(self) -> dict[str, Any]:
        """The complete state as JSON-able data (lists and floats)."""
        data = {"fields": {name: np.asarray(x).tolist() for name, x in zip(self.STATE_FIELDS, self._state_arrays())},
                "n_coordinates": self._n_coordinates(), "initialized": self._initialized,
                "statics": dict(self._statics)}
        data.update(self._extra_state())
        return data

    def set_state(self, data: Mapping[str, Any]) -> None:
        """Restore a state from :meth:`get_state`; the run then continues bit-identically.

        Raises
        ------
        SceneError
            If the data does not belong to this model; nothing is changed.
        """
        n = self._n_coordinates()
        if int(data.get("n_coordinates", -1)) != n:
            raise SceneError("state.n_coordinates", data.get("n_coordinates"),
                             f"{n} (the state belongs to a different model)")
        arrays = []
        for name, dst in zip(self.STATE_FIELDS, self._state_arrays()):
            src = np.asarray(data["fields"][name], dtype=dst.dtype)
            if src.shape != dst.shape:
                raise SceneError(f"state.fields.{name}", f"array of shape {src.shape}", f"shape {dst.shape}")
            arrays.append(src)
        self._restore((arrays, data))
        self._statics = dict(data["statics"])
        self._initialized = bool(data["initialized"])

    # -------------------------------------------------------------- statistics
    def statistics(self) -> dict[str, float]:
        """Solver counters since initialisation (:data:`~towcable_fmu.runtime.protocol.SOLVER_STATISTICS`
        and the model's own ``solver.*``), plus the statics' figures."""
        out = {f"solver.{name}": int(v) for name, v in zip(self.COUNTER_NAMES, self._counters())}
        out.update(self._extra_statistics())
        out.update(self._statics)
        return out

    def _extra_statistics(self) -> dict[str, float]:
        return {}
