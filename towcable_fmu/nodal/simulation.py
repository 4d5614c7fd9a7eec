"""A nodal-position cable scene in time (the protocol of :mod:`towcable_fmu.runtime.protocol`,
its common part in :mod:`towcable_fmu.runtime.driver`).

``NodalSimulation(scene).run(duration, interval)`` returns a dict of arrays named as the
ANCF outputs (``tension.top``, ``angle.top``, ``tension.max``, ``tension.min``,
``towbody.x/y/z/vx/vy/vz``; with a rigid towed body those of its CG, then
``tension.towbody`` and ``towbody.roll/pitch/yaw``); the ship motion comes from the scene's ``[motion]`` through
``ship_motion`` (``evaluate_many`` at knots no farther apart than the step, as
:class:`towcable_fmu.ancf.simulation.Simulation` does). ``solver.integrator`` picks the
implicit generalised-alpha (default), the paper's explicit RK4 or the explicit leapfrog
with lumped masses (:mod:`.explicit`; the scene's step must be below its stability limit,
checked when the scene is loaded, :meth:`towcable_fmu.scene.model.Scene.validate`).
"""

from __future__ import annotations

from typing import Iterable

import numpy as np

from ..runtime import drive as drive_poly
from ..common.errors import SolverError
from ..numerics.alpha_scheme import scheme_coefficients
from ..hydro.rigid_body import angular_kinematics, hanging_coordinates
from ..scene.model import Scene
from ..runtime.ship_input import motion_source
from ..runtime.driver import SimulationDriver
from .assembly import cable_residual, expand
from .explicit import leapfrog_recording, lumped_accelerations, node_masses
from .integrators import (CLOCK_STEP, CLOCK_TIME, INTEGRATORS, LEAPFROG, STAT_NAMES, NodalOptions, NodalState,
                          accelerations, advance_recording, new_interpolant, new_state, output_values, prescribe_top)
from .model import NodalModel, build_nodal_model, n_coordinates
from .statics import solve_statics

#: Outputs of every nodal scene, then those of a scene with a towed body.
OUTPUT_NAMES = ("tension.top", "angle.top", "tension.max", "tension.min")
BODY_NAMES = ("towbody.x", "towbody.y", "towbody.z", "towbody.vx", "towbody.vy", "towbody.vz")
#: Further outputs of a scene with a rigid towed body (``towbody.model = "rigid"``).
RIGID_NAMES = ("tension.towbody", "towbody.roll", "towbody.pitch", "towbody.yaw")
_N_VALUES = len(OUTPUT_NAMES) + len(BODY_NAMES) + len(RIGID_NAMES)
#: the explicit path: simulated time per compiled call [s] (a call's dispatch costs about a
#: millisecond, a second of the snapping cable's steps 5 ms) and leapfrog steps per drive
#: knot (its step is set by the cable's axial waves, not by the motion: ten of the snapping
#: cable's are 2.5 ms, a quintic piece over 1/300 of its motion's period)
EXPLICIT_BLOCK = 30.0
EXPLICIT_KNOT_STEPS = 10


class NodalSimulation(SimulationDriver):
    """One nodal-position cable (with its lumped towed body) in time.

    Parameters
    ----------
    scene
        A validated scene with ``model = "nodal_position"``.
    """

    STATE_FIELDS = NodalState._fields
    COUNTER_NAMES = STAT_NAMES

    def __init__(self, scene: Scene) -> None:
        self._keep(scene)  # read here only: afterwards every part has its own data
        self.model: NodalModel = build_nodal_model(scene)
        self.motion = motion_source(scene)
        s = scene.solver
        self._integrator = s.integrator
        self._statics_settings = scene.statics
        #: the initial straight line's direction (inertial, unit) and a rigid body's attitude [rad]
        self._direction = np.array(scene.cable.initial.direction, dtype=float)
        self._direction /= np.linalg.norm(self._direction)
        self._attitude = (np.array(scene.towbody.rigid.attitude, dtype=float) if self.model.rigid.enabled
                          else np.zeros(3))
        self.options = NodalOptions(INTEGRATORS[s.integrator], s.time_step, s.min_time_step,
                                    np.array(scheme_coefficients(s.rho_inf)), s.newton_tol, s.max_newton_iterations)
        n = n_coordinates(self.model)
        #: the leapfrog's lumped node masses [kg] (None: an implicit or RK4 run)
        self._lumped = node_masses(self.model) if self.options.method == LEAPFROG else None
        self.state = new_state(n, s.time_step)
        self._interpolant = new_interpolant(n)  # the last step's start, for samples inside it
        self.names = OUTPUT_NAMES + (BODY_NAMES if scene.towbody is not None else ())
        if self.model.rigid.enabled:
            self.names += RIGID_NAMES
        self._statics: dict[str, float] = {}

    @property
    def time(self) -> float:
        """Current simulation time [s]."""
        return float(self.state.clock[CLOCK_TIME])

    @property
    def n_elements(self) -> int:
        """Number of cable elements."""
        return self.model.n_nodes - 1

    def _initial_state(self, t0: float, ship: np.ndarray | None, setpoint: tuple[float, float] | None,
                       statics: bool | None) -> None:
        """Lay the cable straight along ``cable.initial.direction`` from the top, solve the
        statics (default: ``statics.enabled``) and set consistent accelerations. A
        nodal-position cable has no winch: ``setpoint`` is not used."""
        m, st = self.model, self.state
        ship0 = self.motion.evaluate(t0) if ship is None else ship
        drive = drive_poly.taylor_drive(t0, ship0, (0.0, 0.0))
        st.clock[:] = (t0, self.options.h_max)
        st.stats[:] = 0
        st.v[:] = 0.0
        st.x[:] = 0.0
        prescribe_top(m, *drive, t0, st.q, st.v, st.x)
        arc = np.concatenate([[0.0], np.cumsum(m.L0)])
        nodes = (st.q[:3] + arc[:, None] * self._direction).ravel()
        if m.rigid.enabled:  # the tow point on the last node, the body at its initial attitude
            nodes = np.concatenate([nodes[:-3], hanging_coordinates(m.rigid, nodes[-3:], self._attitude)])
        st.q[:] = nodes
        prescribe_top(m, *drive, t0, st.q, st.v, st.x)
        cfg = self._statics_settings
        if cfg.enabled if statics is None else statics:
            ok, iterations, res = solve_statics(m, st.q, t0, cfg.tolerance, cfg.max_iterations)
            self._statics = {"solver.statics_iterations": int(iterations), "solver.statics_residual": float(res)}
            if not ok:
                raise SolverError(f"the statics did not converge in {iterations} iterations "
                                  f"(out-of-balance force {res:.3g} N)")
        if self._lumped is None:
            ok = accelerations(m, st.q, st.v, st.x, t0, st.stats)
        else:  # the leapfrog's own accelerations: lumped masses
            lumped_accelerations(m, self._lumped, st.q, st.v, np.empty(st.q.size), np.zeros((m.n_nodes, 6)), st.x)
            ok = bool(np.all(np.isfinite(st.x)))
        if not ok:
            raise SolverError("the initial state has no finite acceleration")
        st.acc[:] = st.x

    def _output_row(self) -> np.ndarray:
        values = np.zeros(_N_VALUES)
        output_values(self.model, self.state.q, self.state.v, self.state.x, self.time, values)
        return values[:len(self.names)]

    def _advance(self, dt: float, ship: np.ndarray, setpoint: tuple[float, float] | None) -> None:
        """One communication step with the ship state at its start, extrapolated with
        constant acceleration; ``setpoint`` is not used (no winch)."""
        t0 = self.time
        values = np.zeros((1, _N_VALUES))
        drive = drive_poly.taylor_drive(t0, ship, (0.0, 0.0))
        reached = self._advance_recording(np.array([t0 + dt]), drive, values, False, t0 + dt)
        if reached < 1:
            raise SolverError(f"the {self._integrator} integrator could not advance from "
                              f"t = {t0:.6g} s by {dt:.6g} s")

    def _advance_recording(self, samples: np.ndarray, drive: tuple[np.ndarray, np.ndarray], values: np.ndarray,
                           interpolate: bool, t_land: float) -> int:
        """The compiled recording loop of the scene's integrator (``advance_recording``'s
        contract): samples reached."""
        if self._lumped is not None:
            return leapfrog_recording(self.model, self._lumped, self.options, self.state, samples, *drive, values,
                                      self._interpolant, interpolate, t_land)
        return advance_recording(self.model, self.options, self.state, samples, *drive, values, self._interpolant,
                                 interpolate, t_land)

    def _state_arrays(self) -> tuple[np.ndarray, ...]:
        return tuple(self.state)

    def _counters(self) -> np.ndarray:
        return self.state.stats

    def node_positions(self) -> np.ndarray:
        """Node positions [m], shape (n_nodes, 3) (with a rigid body the last is its tow point)."""
        n = 3 * self.model.n_nodes
        q, v, a = np.empty(n), np.empty(n), np.empty(n)
        expand(self.model, self.state.q, self.state.v, self.state.x, q, v, a)
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
        i = self.state.q.size - 6
        rot, _, w, _ = angular_kinematics(self.state.q[i:], self.state.v[i:], self.state.x[i:])
        n = 3 * m.n_nodes
        q, v, a, r = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
        expand(m, self.state.q, self.state.v, self.state.x, q, v, a)
        cable_residual(m, q, v, a, self.time, r)
        return {"position": self.state.q[i:i + 3].copy(), "velocity": self.state.v[i:i + 3].copy(),
                "attitude": self.state.q[i + 3:].copy(), "rotation": rot, "angular_velocity": w,
                "angular_momentum": rot @ (m.rigid.inertia @ w), "tow_point": q[-3:], "cable_force": -r[-3:]}

    def set_body_motion(self, velocity: Iterable[float] | None = None,
                        angular_velocity: Iterable[float] | None = None) -> dict[str, float]:
        """Give an initialised rigid towed body a CG velocity [m/s] (inertial) and an
        angular velocity [rad/s] (body axes), then make the accelerations consistent.
        The cable's nodes keep their velocities (the tow point follows the body).

        Returns
        -------
        dict
            Outputs in the new state.

        Raises
        ------
        ValueError
            Without a rigid body, or before :meth:`initialize`.
        SolverError
            If the accelerations are not finite.
        """
        if not self.model.rigid.enabled or not self._initialized:
            raise ValueError("set_body_motion needs an initialised scene with a rigid towed body")
        i = self.state.q.size - 6
        if velocity is not None:
            self.state.v[i:i + 3] = np.asarray(velocity, dtype=float)
        if angular_velocity is not None:
            _, g, _, _ = angular_kinematics(self.state.q[i:], self.state.v[i:], self.state.x[i:])
            self.state.v[i + 3:] = np.linalg.solve(g, np.asarray(angular_velocity, dtype=float))
        if not accelerations(self.model, self.state.q, self.state.v, self.state.x, self.time, self.state.stats):
            raise SolverError("the state has no finite acceleration")
        self.state.acc[:] = self.state.x
        return self.outputs()

    def _block_size(self, interval: float) -> int:
        """Samples per block of the run loop: about a second of simulated time, the explicit
        path's EXPLICIT_BLOCK."""
        return max(1, int((EXPLICIT_BLOCK if self._lumped is not None else 1.0) / interval))

    def _record(self, block: np.ndarray, rows: np.ndarray, t_land: float) -> int:
        """The integrator's own steps through ``block``, samples read from its interpolant."""
        marks = self._interpolation_marks(block, self.time, float(self._interpolant.t0[0]), self.options.h_max,
                                          t_land)
        spacing = self.options.h_max
        if self._lumped is not None:  # the leapfrog's steps need no knots of their own, nor do the samples
            marks = marks[[0, -1]]
            spacing *= EXPLICIT_KNOT_STEPS
        values = np.zeros((block.size, _N_VALUES))
        reached = self._advance_recording(block, self._drive(marks, spacing), values, True, t_land)
        rows[:reached] = values[:reached, :len(self.names)]
        return reached

    def _failure(self, t: float) -> SolverError:
        pitch = (f"; the rigid body's pitch is {self.state.q[-2]:.4g} rad, its Euler angles are singular at "
                 f"+-pi/2" if self.model.rigid.enabled else "")
        return SolverError(f"the {self._integrator} integrator could not advance to t = {t:.6g} s "
                           f"(step {self.state.clock[CLOCK_STEP]:.3g} s; an explicit RK4 step must resolve the "
                           f"highest axial frequency of the mesh{pitch})")

