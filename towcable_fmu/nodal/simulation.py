"""A nodal-position cable scene in time, with the run interface of the ANCF Simulation.

``NodalSimulation(scene).run(duration, interval)`` returns a dict of arrays named as the
ANCF outputs (``tension.top``, ``angle.top``, ``tension.max``, ``tension.min``,
``towbody.x/y/z/vx/vy/vz``; with a rigid towed body those of its CG, then
``tension.towbody`` and ``towbody.roll/pitch/yaw``); the ship motion comes from the scene's ``[motion]`` through
``ship_motion`` (``evaluate_many`` at knots no farther apart than the step, as
:class:`towcable_fmu.simulation.Simulation` does). ``solver.integrator`` picks the
implicit generalised-alpha (default) or the paper's explicit RK4.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from .. import contract
from .. import drive as drive_poly
from ..errors import SceneError, SolverError
from ..numerics.genalpha import scheme_coefficients
from ..scene import load_scene
from ..scene.model import Scene
from ..ship_input import check_ship_state, motion_source
from .integrators import (CLOCK_STEP, CLOCK_TIME, INTEGRATORS, STAT_NAMES, accelerations, advance_recording,
                          new_interpolant, output_values, prescribe_top)
from .assembly import cable_residual, expand
from .model import NodalModel, build_nodal_model, n_coordinates
from ..rigid_body import ROW_TOW, angular_kinematics, rotation
from .statics import solve_statics
from ..sampling import output_interval, sample_times

#: Outputs of every nodal scene, then those of a scene with a towed body.
OUTPUT_NAMES = ("tension.top", "angle.top", "tension.max", "tension.min")
BODY_NAMES = ("towbody.x", "towbody.y", "towbody.z", "towbody.vx", "towbody.vy", "towbody.vz")
#: Further outputs of a scene with a rigid towed body (``towbody.model = "rigid"``).
RIGID_NAMES = ("tension.towbody", "towbody.roll", "towbody.pitch", "towbody.yaw")
_N_VALUES = len(OUTPUT_NAMES) + len(BODY_NAMES) + len(RIGID_NAMES)


def _checked_ship(ship: np.ndarray) -> np.ndarray:
    """The ship state as a float array, checked by :func:`check_ship_state`."""
    ship = np.asarray(ship, dtype=float)
    check_ship_state(ship)
    return ship


#: Names of the integrator's state arrays in :meth:`NodalSimulation.get_state`.
_STATE_FIELDS = ("q", "v", "x", "acc", "clock", "stats")


class NodalSimulation:
    """One nodal-position cable (with its lumped towed body) in time.

    Parameters
    ----------
    scene
        A validated scene with ``cable.formulation = "nodal_position"``.
    """

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.model: NodalModel = build_nodal_model(scene)
        self.motion = motion_source(scene)
        self.method = INTEGRATORS[scene.solver.integrator]
        s = scene.solver
        self.coef = np.array(scheme_coefficients(s.rho_inf))
        n = n_coordinates(self.model)
        self.q, self.v, self.x, self.acc = (np.zeros(n) for _ in range(4))
        self.clock = np.array([0.0, s.time_step])
        self._interpolant = new_interpolant(n)  # the last step's start, for samples inside it
        self.stats = np.zeros(len(STAT_NAMES), dtype=np.int64)
        self.names = OUTPUT_NAMES + (BODY_NAMES if scene.towbody is not None else ())
        if self.model.rigid.enabled:
            self.names += RIGID_NAMES
        self._statics: dict[str, float] = {}
        self._initialized = False

    @property
    def output_names(self) -> tuple[str, ...]:
        """The outputs this scene has, ``time`` first: the columns of :meth:`run` (units:
        :meth:`unit_of`)."""
        return ("time", *self.names)

    def unit_of(self, name: str) -> str:
        """Unit of an output name (the variable contract's)."""
        return contract.unit_of(name)

    @classmethod
    def from_scene(cls, name_or_path: str | Path,
                   overrides: Mapping[str, Any] | Iterable[tuple[str, Any]] = ()) -> "NodalSimulation":
        """Load a built-in scene by name, or a scene file, with dotted-key overrides."""
        return cls(load_scene(name_or_path, overrides))

    @property
    def time(self) -> float:
        """Current simulation time [s]."""
        return float(self.clock[CLOCK_TIME])

    def _drive(self, marks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Drive table of the scene's ship motion through ``marks`` [s], knots <= one step apart."""
        times = drive_poly.knot_times(marks, self.scene.solver.time_step)
        return drive_poly.knot_drive(times, self.motion.evaluate_many(times), np.zeros((times.size, 2)))

    @property
    def n_elements(self) -> int:
        """Number of cable elements."""
        return self.model.n_nodes - 1

    def initialize(self, t0: float = 0.0, ship: np.ndarray | None = None, setpoint: tuple[float, float] | None = None,
                   statics: bool | None = None) -> dict[str, float]:
        """Lay the cable straight along ``cable.initial.direction`` from the top, solve the
        statics (default: ``statics.enabled``) and set consistent accelerations.

        Parameters
        ----------
        t0
            Start time [s].
        ship
            Ship state (3, 6) at t0 (value, rate, acceleration of x, y, z [m], roll,
            pitch, yaw [rad]); default: the scene's ``[motion]`` at t0.
        setpoint
            Accepted for the interface of :class:`towcable_fmu.simulation.Simulation`; a
            nodal-position cable has no winch, so it is not used.
        statics
            Solve the statics first (default: the scene's ``statics.enabled``).

        Raises
        ------
        SceneError
            If ``t0`` or the ship state is not finite or has the wrong shape.
        SolverError
            If the statics do not converge or the accelerations are not finite.
        """
        if not math.isfinite(t0):
            raise SceneError("t0", t0, "a finite start time [s]")
        m = self.model
        ship0 = self.motion.evaluate(t0) if ship is None else _checked_ship(ship)
        drive = drive_poly.taylor_drive(t0, ship0, (0.0, 0.0))
        self.clock[:] = (t0, self.scene.solver.time_step)
        self.stats[:] = 0
        self.v[:] = 0.0
        self.x[:] = 0.0
        prescribe_top(m, *drive, t0, self.q, self.v, self.x)
        direction = np.array(self.scene.cable.initial.direction, dtype=float)
        arc = np.concatenate([[0.0], np.cumsum(m.L0)])
        nodes = (self.q[:3] + arc[:, None] * direction / np.linalg.norm(direction)).ravel()
        if m.rigid.enabled:  # the tow point on the last node, the body at its initial attitude
            attitude = np.array(self.scene.towbody.rigid.attitude, dtype=float)
            cg = nodes[-3:] - rotation(*attitude) @ m.rigid.axes[ROW_TOW]
            nodes = np.concatenate([nodes[:-3], cg, attitude])
        self.q[:] = nodes
        prescribe_top(m, *drive, t0, self.q, self.v, self.x)
        if self.scene.statics.enabled if statics is None else statics:
            cfg = self.scene.statics
            ok, iterations, res = solve_statics(m, self.q, t0, cfg.tolerance, cfg.max_iterations)
            self._statics = {"solver.statics_iterations": int(iterations), "solver.statics_residual": float(res)}
            if not ok:
                raise SolverError(f"the statics did not converge in {iterations} iterations "
                                  f"(out-of-balance force {res:.3g} N)")
        if not accelerations(m, self.q, self.v, self.x, t0, self.stats):
            raise SolverError("the initial state has no finite acceleration")
        self.acc[:] = self.x
        self._initialized = True
        return self.outputs()

    def outputs(self) -> dict[str, float]:
        """Outputs at the current state (names in :attr:`names`)."""
        values = np.zeros(_N_VALUES)
        output_values(self.model, self.q, self.v, self.x, self.time, values)
        return dict(zip(self.names, values[:len(self.names)].tolist()))

    def step(self, dt: float, ship: np.ndarray, setpoint: tuple[float, float] | None = None) -> dict[str, float]:
        """Advance by ``dt`` [s] with the ship state given at the start of the step (FMU style).

        The ship state (3, 6) is extrapolated with constant acceleration over the step;
        ``setpoint`` is not used (no winch). On failure the state is left as it was.

        Raises
        ------
        SceneError
            Bad inputs (non-finite, wrong shape, non-positive dt); nothing is changed.
        SolverError
            If the integrator cannot complete the step.
        """
        if not self._initialized:
            raise SolverError("initialize() must be called before step()")
        if not (math.isfinite(dt) and dt > 0.0):
            raise SceneError("dt", dt, "a finite step > 0 s")
        ship = _checked_ship(ship)
        saved = [x.copy() for x in self._state_arrays()]
        s = self.scene.solver
        t0 = self.time
        values = np.zeros((1, _N_VALUES))
        drive = drive_poly.taylor_drive(t0, ship, (0.0, 0.0))
        reached = advance_recording(self.model, self.method, s.time_step, s.min_time_step, self.coef, s.newton_tol,
                                    s.max_newton_iterations, self.q, self.v, self.x, self.acc, self.clock,
                                    self.stats, np.array([t0 + dt]), *drive, values, self._interpolant, False,
                                    t0 + dt)
        if reached < 1:
            for dst, src in zip(self._state_arrays(), saved):
                dst[:] = src
            raise SolverError(f"the {s.integrator} integrator could not advance from t = {t0:.6g} s by {dt:.6g} s")
        return dict(zip(self.names, values[0, :len(self.names)].tolist()))

    def get_state(self) -> dict[str, Any]:
        """The complete integrator state as JSON-able data (lists and floats)."""
        data: dict[str, Any] = {name: x.tolist() for name, x in zip(_STATE_FIELDS, self._state_arrays())}
        data.update(statics=dict(self._statics), initialized=self._initialized, n_coordinates=int(self.q.size))
        return data

    def _state_arrays(self) -> tuple[np.ndarray, ...]:
        """The integrator's state arrays, in the order of ``_STATE_FIELDS``."""
        return self.q, self.v, self.x, self.acc, self.clock, self.stats

    def set_state(self, data: Mapping[str, Any]) -> None:
        """Restore a state from :meth:`get_state`; the run then continues bit-identically.

        Raises
        ------
        SceneError
            If the data does not belong to this model.
        """
        if int(data.get("n_coordinates", -1)) != self.q.size:
            raise SceneError("state.n_coordinates", data.get("n_coordinates"),
                             f"{self.q.size} (the state belongs to a different mesh)")
        for name, dst in zip(_STATE_FIELDS, self._state_arrays()):
            dst[:] = np.asarray(data[name], dtype=dst.dtype)
        self._statics = dict(data["statics"])
        self._initialized = bool(data["initialized"])

    def node_positions(self) -> np.ndarray:
        """Node positions [m], shape (n_nodes, 3) (with a rigid body the last is its tow point)."""
        n = 3 * self.model.n_nodes
        q, v, a = np.empty(n), np.empty(n), np.empty(n)
        expand(self.model, self.q, self.v, self.x, q, v, a)
        return q.reshape(-1, 3)

    def body_state(self) -> dict[str, np.ndarray]:
        """State of a rigid towed body: ``position`` (CG) [m] and ``velocity`` [m/s]
        (inertial), ``attitude`` (roll, pitch, yaw) [rad], ``rotation`` R (body -> inertial),
        ``angular_velocity`` [rad/s] (body axes), ``angular_momentum`` R J w [kg m^2/s]
        (inertial axes, about the CG; J without added inertia), ``tow_point`` [m] and
        ``cable_force`` [N], the force of the cable on the body (minus the cable's
        residual at its last node: the end tension and that node's share of the cable's
        distributed loads and inertia).

        Raises
        ------
        ValueError
            If the scene has no rigid towed body.
        """
        m = self.model
        if not m.rigid.enabled:
            raise ValueError("the scene has no rigid towed body (towbody.model = 'rigid')")
        i = self.q.size - 6
        rot, _, w, _ = angular_kinematics(self.q[i:], self.v[i:], self.x[i:])
        n = 3 * m.n_nodes
        q, v, a, r = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
        expand(m, self.q, self.v, self.x, q, v, a)
        cable_residual(m, q, v, a, self.time, r)
        return {"position": self.q[i:i + 3].copy(), "velocity": self.v[i:i + 3].copy(),
                "attitude": self.q[i + 3:].copy(), "rotation": rot, "angular_velocity": w,
                "angular_momentum": rot @ (m.rigid.inertia @ w), "tow_point": q[-3:], "cable_force": -r[-3:]}

    def set_body_motion(self, velocity: Iterable[float] | None = None,
                        angular_velocity: Iterable[float] | None = None) -> None:
        """Give an initialised rigid towed body a CG velocity [m/s] (inertial) and an
        angular velocity [rad/s] (body axes), then make the accelerations consistent.
        The cable's nodes keep their velocities (the tow point follows the body).

        Raises
        ------
        ValueError
            Without a rigid body, or before :meth:`initialize`.
        SolverError
            If the accelerations are not finite.
        """
        if not self.model.rigid.enabled or not self._initialized:
            raise ValueError("set_body_motion needs an initialised scene with a rigid towed body")
        i = self.q.size - 6
        if velocity is not None:
            self.v[i:i + 3] = np.asarray(velocity, dtype=float)
        if angular_velocity is not None:
            _, g, _, _ = angular_kinematics(self.q[i:], self.v[i:], self.x[i:])
            self.v[i + 3:] = np.linalg.solve(g, np.asarray(angular_velocity, dtype=float))
        if not accelerations(self.model, self.q, self.v, self.x, self.time, self.stats):
            raise SolverError("the state has no finite acceleration")
        self.acc[:] = self.x

    def run(self, duration: float, interval: float | None = None,
            progress: Callable[[float, float], None] | None = None) -> dict[str, np.ndarray]:
        """Initialise if needed and record the outputs every ``interval`` [s] for ``duration`` [s].

        Returns
        -------
        dict
            ``time`` and every output name -> array over the samples (including the start).

        Raises
        ------
        SolverError
            If a step fails or an output is not finite.
        """
        dt = output_interval(duration, interval, self.scene.output.interval)
        if not self._initialized:
            self.initialize()
        t0 = self.time
        samples = sample_times(t0, duration, dt)
        n = samples.size
        values = np.zeros((n + 1, _N_VALUES))
        output_values(self.model, self.q, self.v, self.x, t0, values[0])
        s = self.scene.solver
        chunk = max(1, int(1.0 / dt))
        t_land = float(samples[-1])  # the integrator's own steps, samples read from its interpolant
        for first in range(0, n, chunk):
            stop = min(n, first + chunk)
            # from the last step's start (samples inside it), one step past the block
            start = min(self.time, float(self._interpolant.t0[0])) if samples[first] < self.time else self.time
            end = min(t_land, float(samples[stop - 1]) + s.time_step)
            block = samples[first:stop]
            drive = self._drive(np.unique(np.concatenate([[start], block[block > start], [end]])))
            reached = first + advance_recording(
                self.model, self.method, s.time_step, s.min_time_step, self.coef, s.newton_tol,
                s.max_newton_iterations, self.q, self.v, self.x, self.acc, self.clock, self.stats,
                block, *drive, values[first + 1:stop + 1], self._interpolant, True, t_land)
            if reached < stop:
                pitch = (f"; the rigid body's pitch is {self.q[-2]:.4g} rad, its Euler angles are singular at "
                         f"+-pi/2" if self.model.rigid.enabled else "")
                raise SolverError(f"the {s.integrator} integrator could not advance to t = {samples[reached]:.6g} s "
                                  f"(step {self.clock[CLOCK_STEP]:.3g} s; an explicit RK4 step must resolve the "
                                  f"highest axial frequency of the mesh{pitch})")
            if progress is not None:
                progress(self.time, t0 + duration)
        out = {"time": np.concatenate([[t0], samples])}
        out.update(zip(self.names, values[:, :len(self.names)].T))
        return out

    def statistics(self) -> dict[str, float]:
        """Solver counters since initialisation, plus the statics result."""
        out = {f"solver.{k}": int(v) for k, v in zip(STAT_NAMES, self.stats)}
        out.update(self._statics)
        return out
