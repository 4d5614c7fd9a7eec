"""The simulation object: a scene, its compiled model, the integrator state, and outputs.

This is the physics without FMI: load a scene, initialise (statics), step, read
outputs, get and set the complete state. The FMU slave, the command line, the tests
and the benchmarks all drive this same object. Two parts of it live beside it: remeshing
during a run (:mod:`.remeshing`) and what it tells of its state beyond the outputs
(:mod:`.state_queries`). It names no force term: what a term adds to a run (outputs,
state, work between steps, queries) is its hooks' (:mod:`towcable_fmu.ancf.forces.hooks`),
which it calls in loops.
"""

from __future__ import annotations

import math
import operator
from typing import Any, Iterable, Mapping, NamedTuple

import numpy as np

from ..runtime import drive as drive_poly
from .feed import apply_feed
from .initial_layout import initial_coordinates, layout_from_scene
from .mesh import build_mesh, build_model
from .model import CableModel, Mesh
from .compensation_setup import compensation_config, compensation_table
from .output_kernel import (CABLE_OUTPUTS, ENERGY_FIELDS, OUTPUT_FIELDS, OutputLayout, OutputScene, Recording,
                            advance_recording)
from ..common.errors import SceneError, SolverError
from ..hydro.turbulence import TurbulenceSeries
from ..hydro.water import still_water
from . import genalpha
from .statics import solve_statics
from ..scene.model import Scene
from ..runtime.ship_input import check_ship_state, motion_source
from .winch_program import program_setpoints
from ..runtime.driver import SimulationDriver
from ..runtime.tables import reject_unmodelled
from .forces import TABLES as TERM_TABLES, build_hooks
from .forces.hooks import TermHooks
from .stepper import new_stepper, save_state, step_to
from .buffer_step import DONE, ROLL_BACK, buffer_plan, step_on_values
from . import native_step
from .remeshing import Remeshing
from .state_queries import PROFILE_XI as _PROFILE_XI, StateQueries

#: The scene tables the ANCF cable models: its force terms' and those the simulation reads itself.
MODELLED_TABLES = TERM_TABLES + ("water.turbulence", "compensation", "motion")
#: fewest nominal steps in a block of the run loop (one compiled call, one drive table)
BLOCK_STEPS = 100
#: advance_recording's arguments to step without outputs, and to read all outputs of a state
_NO_OUTPUTS = np.zeros(0, dtype=np.intp)
_NO_ROWS = np.empty((1, 0))
_ALL_OUTPUTS = np.arange(len(OUTPUT_FIELDS), dtype=np.intp)
_NO_DRIVE = (np.zeros(1), np.zeros((1, 3, 7)))
#: The index of ``winch.payout`` among the output fields.
_PAYOUT = OUTPUT_FIELDS.index("winch.payout")


def solver_options(scene: Scene) -> genalpha.SolverOptions:
    """Integrator options from a scene's [solver] table (and winch gains when present)."""
    s = scene.solver
    w = scene.winch
    return genalpha.SolverOptions(h_max=s.time_step, rho_inf=s.rho_inf, adaptive=s.adaptive, rtol=s.rtol,
                                  atol=s.atol, newton_tol=s.newton_tol, max_iter=s.max_newton_iterations,
                                  jac_max_age=s.jacobian_max_age, h_min=s.min_time_step,
                                  winch_kp=0.0 if w is None else w.kp, winch_kd=0.0 if w is None else w.kd,
                                  locate_events=s.locate_events)


class TaylorDrive(NamedTuple):
    """The drive of an FMU step: the ship state and winch set-point at the step's start,
    extrapolated (:func:`towcable_fmu.runtime.drive.taylor_drive`, without building its table)."""

    t0: float              #: the step's start [s]
    ship: np.ndarray       #: ship state (3, 6) at t0
    setpoint: tuple[float, float]  #: phi_sp [rad], phi_sp_rate [rad/s] at t0


class Simulation(Remeshing, StateQueries, SimulationDriver):
    """One ANCF towed-cable system in time (the protocol of :mod:`towcable_fmu.runtime.protocol`,
    its common part in :mod:`towcable_fmu.runtime.driver`).

    Parameters
    ----------
    scene
        A validated scene (see :func:`towcable_fmu.scene.load_scene`).

    Examples
    --------
    >>> sim = Simulation.from_scene("hanging_cable", {"solver.time_step": 0.01})  # doctest: +SKIP
    >>> sim.initialize()                                                         # doctest: +SKIP
    >>> out = sim.advance(1.0)                                                   # doctest: +SKIP
    >>> out["tension.top"]                                                       # doctest: +SKIP
    """

    STATE_FIELDS = genalpha.IntegratorState._fields
    COUNTER_NAMES = genalpha.STAT_NAMES

    def __init__(self, scene: Scene) -> None:
        if scene.cable.formulation != "ancf":
            raise SceneError("cable.formulation", scene.cable.formulation, "'ancf' for this class (a nodal-position "
                             "cable runs in towcable_fmu.nodal.simulation.NodalSimulation)")
        reject_unmodelled(scene, MODELLED_TABLES, "ancf")
        self._keep(scene)  # read here only: afterwards every part has its own data
        #: the element layout (a spool end's fed element at its length after the last remesh)
        self._mesh: Mesh = build_mesh(scene.cable.segments)
        self.model: CableModel = build_model(scene, self._mesh)
        self._scene_mesh = self._mesh
        #: cable stored on the drum of a spool end at phi_nom [m] (None: no spool end)
        self._stored_length = scene.winch.stored_length if scene.cable.top.type == "spool" else None
        #: the winch's payout program (times [s], payouts [m]; None: none)
        self._program = (None if scene.winch is None or not scene.winch.program_times else
                         (np.array(scene.winch.program_times, dtype=float),
                          np.array(scene.winch.program_payout, dtype=float)))
        self.options = solver_options(scene)
        self.motion = motion_source(scene)
        #: what the initial shape needs of the scene
        self.start = layout_from_scene(scene)
        self._statics_settings = scene.statics
        self._turbulence_settings = None if scene.water is None else scene.water.turbulence
        #: the compensation's settings over the scene's geometry (None: the set-point is given)
        self._compensation_table = None if scene.compensation is None else compensation_table(scene)
        #: the set-point algorithm (built at initialisation: it may need the steady departure
        #: angle), or the constant-tension winch's controller (built here: its state is restored)
        self.compensation = None
        if self._compensation_table is not None:
            config = compensation_config(self._compensation_table, 0.0)  # validated now, before any computation
            if config.method == "tension":
                from controllers import TensionControl

                self.compensation = TensionControl(config)
        self.state = genalpha.new_state(self.model)
        self.workspace = genalpha.new_workspace(self.model)
        self._moving_mesh = False
        #: the force terms' hooks (:mod:`towcable_fmu.ancf.forces.hooks`), in the order of their terms
        self.hooks: tuple[TermHooks, ...] = build_hooks(scene, self)
        #: the hooks whose term moves the mesh: the only ones with events (:meth:`_after_event`)
        self._remeshing = tuple(h for h in self.hooks if h.MOVES_MESH)
        self._moving_mesh = bool(self._remeshing)
        #: the hooks with a state of their own, those acting between steps, those with outputs in Python
        self._saving = tuple(h for h in self.hooks if h.save() is not None)
        self._staggered = tuple(h for h in self.hooks if h.STAGGERED)
        self._python_outputs = tuple(h for h in self.hooks if set(h.outputs) - set(OUTPUT_FIELDS))
        #: the constant loads of the statics when a term changes them (a held rigid load; None: the model's)
        self._held_forces = self._statics_loads(self.model)
        self._statics: dict[str, float] = {}
        self.turbulence: TurbulenceSeries | None = None
        self._setpoint = (0.0, 0.0)
        #: largest winch payout [m] the drum holds: the payout at initialisation plus the cable
        #: then wound on the drum (None: no drum contact, no limit)
        self._payout_limit: float | None = None
        self._initialized = False
        self._last_outputs: dict[str, float] = {}
        #: all outputs at the state a step reached, recorded by the step's own kernel call
        #: (one call from Python per FMU step instead of two), with the state's fingerprint
        self._stepped: tuple[float, np.ndarray] | None = None
        #: the Stepper of the FMU's steps (:mod:`towcable_fmu.ancf.stepper`) with what it holds
        self._stepper: tuple | None = None
        #: The outputs this scene has (names in docs/design.md): the cable's and its terms', see :meth:`outputs`.
        self.layout = OutputLayout(CABLE_OUTPUTS + (("winch.payout",) if scene.winch is not None else ())
                                   + tuple(name for h in self.hooks for name in h.outputs))
        self.names = self.layout.names
        #: What the compiled outputs need of the scene (the terms' fields from their hooks).
        self.output_scene = OutputScene(
            xi=_PROFILE_XI, body_mass=-1.0,
            has_winch=scene.winch is not None,
            sheave_position=np.array(scene.sheave.position if scene.sheave is not None else [np.nan] * 3, dtype=float),
            payout_radius=self.start.winch_radius,
            phi_nom=float(scene.winch.phi_nom) if scene.winch is not None else 0.0)
        for hooks in self.hooks:
            self.output_scene = self.output_scene._replace(**hooks.output_scene)

    # ------------------------------------------------------------------ time
    @property
    def mesh(self) -> Mesh:
        """The element layout now: with a spool end, the fed first element at its current
        length (:mod:`towcable_fmu.ancf.feed`)."""
        if not self._moving_mesh:
            return self._mesh
        lengths = self.model.el_len.copy()
        return Mesh(lengths, self._mesh.segment_of_element, np.concatenate([[0.0], np.cumsum(lengths)]))

    @property
    def n_elements(self) -> int:
        """Number of cable elements."""
        return self.mesh.n_nodes - 1

    @property
    def time(self) -> float:
        """Current simulation time [s]."""
        return float(self.state.clock[genalpha.CLOCK_TIME])

    def _initial_state(self, t0: float, ship: np.ndarray | None, setpoint: tuple[float, float] | None,
                       statics: bool | None, q0: np.ndarray | None = None) -> None:
        """Lay out the initial shape, solve the statics and set consistent accelerations.

        A term may change the statics' constant loads (a rigid load with ``held = true`` is
        held along the cable's initial direction and let go at ``t0``,
        :meth:`~towcable_fmu.ancf.forces.hooks.TermHooks.statics_loads`).
        ``q0``: start from these coordinates (full vector, e.g. the equilibrium of the same
        mesh under a slightly different load, to follow a load sweep) instead of the
        laid-out initial shape; the prescribed entries are overwritten.
        """
        ship0 = self.motion.evaluate(t0) if ship is None else ship
        check_ship_state(ship0)
        self._stepped = None
        if setpoint is not None:
            self._setpoint = setpoint
        for hooks in self.hooks:
            hooks.reset()
        st = self.state
        st.phi[:] = 0.0
        if self.output_scene.has_winch:
            st.phi[0] = self._setpoint[0] if setpoint is not None else self.output_scene.phi_nom
            self._setpoint = (float(st.phi[0]), self._setpoint[1] if setpoint is not None else 0.0)
            if setpoint is None and self._program is not None:  # where the payout program starts
                st.phi[0] = self._program_setpoints(np.array([t0]))[0, 0]
                self._setpoint = (float(st.phi[0]), 0.0)
        for hooks in self.hooks:
            hooks.start(float(st.phi[0]))
        apply_feed(self.model, st.phi)  # a spool end's first element at the winch's rotation
        st.q[:] = (initial_coordinates(self.start, self.mesh, self.model, ship0, st.phi) if q0 is None
                   else self._checked_coordinates(q0, "q0"))
        st.v[:] = 0.0
        st.a[:] = 0.0
        st.stats[:] = 0
        st.jac[:] = 0.0
        st.jac[genalpha.JAC_ETA] = 1.0
        st.clock[:] = (t0, self.options.h_max, 0.0, 0.0)
        cfg = self._statics_settings
        if cfg.enabled if statics is None else statics:
            steady = self.model._replace(water=still_water(self.model.water))
            if self._held_forces is not None:  # released at t0 (the run's own loads)
                steady = steady._replace(f_const=self._held_forces)
            result = solve_statics(steady, st.q, ship0, st.phi, t0, tolerance=cfg.tolerance,
                                   max_iterations=cfg.max_iterations)
            self._statics = {"solver.statics_iterations": result.iterations,
                             "solver.statics_residual": result.residual_norm,
                             "solver.statics_wall_time": result.wall_time}
            st.q[:] = result.q
        self._start_turbulence(t0)
        self.workspace.ship[:, :] = ship0
        if self._tension_control():  # starts at the winch's set-point, at rest
            config = self.compensation.config
            self.compensation.set_state({"payout": (config.phi_nom - self._setpoint[0]) * config.winch_radius,
                                         "rate": 0.0})
        elif self._compensation_table is not None:
            from controllers import SetpointAlgorithm

            theta = self._compensation_table.get("theta_nom")
            if theta is None:  # the model's own steady-state departure angle (sheave, or drum)
                theta = self.outputs()["sheave_angle"]
            self.compensation = SetpointAlgorithm(compensation_config(self._compensation_table, float(theta)))
            if setpoint is None:
                sp = self.compensation.compute(ship0, None)
                self._setpoint = (float(sp.phi_sp), float(sp.phi_sp_rate))
        self._payout_limit = self._drum_payout_limit()
        drive = drive_poly.taylor_drive(t0, ship0, self._setpoint)
        if not genalpha.initial_acceleration(self.model, self.options, st, self.workspace, t0, *drive):
            raise SolverError("the initial state has no finite acceleration (singular mass matrix or "
                              "non-finite forces)")

    def _start_turbulence(self, t0: float) -> None:
        """(Re)start the turbulence series at t0 (same seed: same series)."""
        cfg = self._turbulence_settings
        self.turbulence = None if cfg is None else TurbulenceSeries(cfg, t0)
        self._cover(t0)

    def _cover(self, t_end: float) -> None:
        """Make the turbulence table reach t_end (the compiled kernels read it)."""
        if self.turbulence is not None and self.turbulence.extend_to(t_end):
            tb = self.turbulence
            self.model = self.model._replace(water=self.model.water._replace(
                turb=tb.samples, turb_t0=tb.t0, turb_dt=tb.dt))

    def set_coordinates(self, q: np.ndarray, v: np.ndarray | None = None) -> dict[str, float]:
        """Replace the cable configuration at the current time (e.g. to release it from a
        displaced shape) and recompute consistent accelerations.

        Parameters
        ----------
        q
            Full coordinate vector (nodal positions [m] and slopes [-]); the prescribed
            entries are overwritten by the end kinematics.
        v
            Full velocity vector [m/s, 1/s]; default zero.

        Returns
        -------
        dict
            Outputs in the new state.
        """
        self._require_initialized()
        q = self._checked_coordinates(q, "q")
        v = np.zeros_like(q) if v is None else self._checked_coordinates(v, "v")
        st = self.state
        self._stepped = None
        st.q[:] = q
        st.v[:] = v
        t = self.time
        ship = self.motion.evaluate(t)
        if not genalpha.initial_acceleration(self.model, self.options, st, self.workspace, t,
                                             *drive_poly.taylor_drive(t, ship, self._setpoint)):
            raise SolverError("the given configuration has no finite acceleration")
        return self.outputs()

    def _checked_coordinates(self, x: np.ndarray, name: str) -> np.ndarray:
        """A coordinate (or velocity) vector of this model as a float array.

        Raises
        ------
        SceneError
            If its shape is not the model's or it is not finite.
        """
        x = np.asarray(x, dtype=float)
        if x.shape != self.state.q.shape:
            raise SceneError(name, f"array of shape {x.shape}", f"an array of shape {self.state.q.shape}")
        if not np.all(np.isfinite(x)):
            raise SceneError(name, "non-finite values", "finite coordinates and velocities")
        return x

    def _integrate_to(self, t_end: float, drive: tuple[np.ndarray, np.ndarray] | TaylorDrive) -> None:
        """Integrate to ``t_end`` [s] with the drive table, or the one knot of a
        :class:`TaylorDrive` (the caller rolls back on failure).

        Raises
        ------
        SolverError
            If Newton fails at the minimum step size.
        """
        self._cover(t_end)
        t_start = self.time
        if self._integrate(t_end, drive) != genalpha.OK:
            raise SolverError(f"the solver could not advance from t = {t_start:.6g} s to t = {t_end:.6g} s: Newton "
                              f"failed at the minimum step size {self.options.h_min:g} s near t = {self.time:.6g} s"
                              f"{self._failure_hint()}")
        if self._payout_limit is not None:
            payout = self._payout()
            if payout > self._payout_limit:
                raise self._payout_error(self.time, payout)

    def _failure_hint(self) -> str:
        """What a failed step may be due to, as the terms tell (empty: nothing to say)."""
        return "".join(hooks.failure_hint() for hooks in self.hooks)

    def _integrate(self, t_end: float, drive: tuple[np.ndarray, np.ndarray] | TaylorDrive) -> int:
        """genalpha.advance to t_end; with a term that acts between steps (the wake
        oscillators' staggered coupling, :mod:`towcable_fmu.ancf.viv_coupling`), one solver
        step at a time between its hooks. Returns the solver status."""
        if not self._staggered:
            return self._step_to(t_end, drive)
        if isinstance(drive, TaylorDrive):
            drive = drive_poly.taylor_drive(*drive)
        while self.time < t_end - 1e-12 * max(1.0, abs(t_end)):
            t = self.time
            h = min(self.options.h_max, t_end - t)
            if t_end - (t + h) < 1e-9 * h:
                h = t_end - t
            for hooks in self._staggered:
                hooks.before_step(h)
            status = self._step_to(t + h, drive)
            if status != genalpha.OK:
                return status
            for hooks in self._staggered:
                hooks.after_step(self.time - t)
        return genalpha.OK

    def advance(self, t_end: float) -> dict[str, float]:
        """Advance to ``t_end`` with the scene's own ship motion; return the outputs there.

        Raises
        ------
        SolverError
            If a step fails; the state is then left as it was before the call.
        """
        self._require_initialized()
        t0 = self.time
        if not (math.isfinite(t_end) and t_end > t0):
            raise SceneError("t_end", t_end, f"a finite time > {t0:g} s")
        return self._named(self._guarded(
            lambda: self._integrate_to(t_end, self._drive(np.array([t0, t_end]), self.options.h_max))))

    def _setpoints_at(self, times: np.ndarray, ships: np.ndarray) -> np.ndarray:
        """The drive table's winch set-points: a compensating scene's algorithm at the knots,
        with the measured sheave angle (rigorous algorithms) of the current state, or the
        constant-tension winch's set-point from the tension of the current state (one
        control interval: the table's span); the scene's payout program
        (:mod:`towcable_fmu.ancf.winch_program`); else the set-point held."""
        if self._program is not None:  # (the scene has no compensation algorithm then)
            setpoints = self._program_setpoints(times)
            self._setpoint = (float(setpoints[-1, 0]), float(setpoints[-1, 1]))
            return setpoints
        if self.compensation is None:
            return np.tile(self._setpoint, (times.size, 1))
        if self._tension_control():  # the rate decided at the last sample; then the next from the tension now
            sp = self.compensation.setpoint()
            self.compensation.advance(self._measured_tension(), float(times[-1] - times[0]))
            setpoints = np.column_stack([sp.phi_sp + sp.phi_sp_rate * (times - times[0]),
                                         np.full(times.size, sp.phi_sp_rate)])
            self._setpoint = (float(setpoints[-1, 0]), float(setpoints[-1, 1]))
            return setpoints
        # the measured sheave angle (rigorous algorithms) is that at the start of the interval
        angle = self._current_outputs().get("sheave_angle", np.nan) if self.compensation.config.rigorous else np.nan
        sp = self.compensation.compute_series(ships, np.full(times.size, angle))
        setpoints = np.column_stack([sp.phi_sp, sp.phi_sp_rate])
        self._setpoint = (float(setpoints[-1, 0]), float(setpoints[-1, 1]))
        return setpoints

    def _program_setpoints(self, times: np.ndarray) -> np.ndarray:
        """The scene's payout program as drive set-points at ``times`` [s]: (k, 2) phi_sp [rad], rate [rad/s]."""
        return program_setpoints(times, *self._program, self.output_scene.payout_radius, self.output_scene.phi_nom)

    def _current_outputs(self) -> dict[str, float]:
        """The outputs of the current state (the latest, unless the state moved since)."""
        return self._last_outputs if self._last_outputs.get("time") == self.time else self.outputs()

    def _measured_tension(self) -> float:
        """The tension a constant-tension winch measures [N]: at the drum (``tension.winch``),
        else at the top of the cable."""
        out = self._current_outputs()
        return float(out["tension.winch"] if "tension.winch" in out else out["tension.top"])

    def _advance(self, dt: float, ship: np.ndarray, setpoint: tuple[float, float] | None) -> None:
        """One communication step: the ship state at its start extrapolated with constant
        acceleration, the winch set-point (default: unchanged) held; with a payout program
        in the scene, the program's set-point at the step's start, its rate held (the
        given set-point is not used)."""
        t0 = self.time
        if self._program is not None:
            setpoint = tuple(self._program_setpoints(np.array([t0]))[0])
        if setpoint is not None:
            self._setpoint = setpoint
        self._integrate_to(t0 + dt, TaylorDrive(t0, ship, self._setpoint))

    def _model_for(self, mesh: Mesh, phi_ref: float) -> CableModel:
        """The model of ``mesh`` with this run's water; a spool end's fed element has the
        mesh's first length at the winch rotation ``phi_ref`` [rad]."""
        model = build_model(self.scene, mesh)._replace(water=self.model.water)
        for hooks in self.hooks:
            hooks.rebuilt(model, mesh.lengths, phi_ref)
        return model

    def _statics_loads(self, model: CableModel) -> np.ndarray | None:
        """The constant loads of ``model``'s statics when a term changes them (None: the model's)."""
        return next((f for f in (h.statics_loads(model) for h in self.hooks) if f is not None), None)

    def _remodel(self, mesh: Mesh, phi_ref: float) -> None:
        """Make ``mesh`` the simulation's, with its model (:meth:`_model_for`) and a new state."""
        model = self._model_for(mesh, phi_ref)
        self._use(mesh, model, genalpha.new_state(model))

    def _use(self, mesh: Mesh, model: CableModel, state: genalpha.IntegratorState) -> None:
        """Make ``mesh``, its ``model`` and ``state`` the simulation's, with a new workspace."""
        self._mesh, self.model, self.state = mesh, model, state
        if self._held_forces is not None:  # (statics of a later initialisation)
            self._held_forces = self._statics_loads(model)
        self.workspace = genalpha.new_workspace(model)
        self._stepped = None
        self._snapshot_buffers = None
        self._last_outputs = {}

    # --------------------------------------------------------------- outputs
    def outputs(self) -> dict[str, float]:
        """Named outputs at the current time (names as in docs/design.md), SI units.

        ``tension.top`` and ``tension.bottom`` are the support reactions at a
        prescribed end (the consistent nodal force, which converges faster than the
        strain), else the axial force from the strain; ``tension.towbody`` is the force
        the cable exerts on the body (its mass times acceleration minus its other forces).
        The latest are kept (a set-point from measurements reads them, see
        :meth:`_current_outputs`).
        """
        return super().outputs()

    def _named(self, row: np.ndarray) -> dict[str, float]:
        self._last_outputs = super()._named(row)
        return self._last_outputs

    def only_outputs(self, wanted: Iterable[str]) -> None:
        """From now on compute only the outputs in ``wanted`` and those the terms compute in
        Python: :attr:`names` leaves the others out. An FMU that reports no energy saves
        the energies' share of every step's outputs (:data:`~towcable_fmu.ancf.output_kernel.ENERGY_FIELDS`)."""
        wanted = set(wanted)
        self.layout = OutputLayout(name for name in self.layout.names
                                   if name in wanted or name not in OUTPUT_FIELDS)
        self.names = self.layout.names
        self.output_scene = self.output_scene._replace(energies=any(name in self.names for name in ENERGY_FIELDS))
        self._stepped = None
        self._last_outputs = {}

    def _output_row(self) -> np.ndarray:
        if not self._python_outputs:
            return self._output_array()[self.layout.index]
        row = np.empty(len(self.names))
        row[self.layout.compiled] = self._output_array()[self.layout.index]
        row[self.layout.python] = [value for hooks in self._python_outputs for value in hooks.values()]
        return row

    def _output_array(self) -> np.ndarray:
        """All fields of :data:`~towcable_fmu.ancf.output_kernel.OUTPUT_FIELDS` (NaN: not in the scene)."""
        if self._stepped is not None and self._stepped[0] == self._fingerprint():
            return self._stepped[1]
        rows = np.empty((1, len(OUTPUT_FIELDS)))
        advance_recording(self.model, self.options, self.state, self.workspace, np.array([self.time]), *_NO_DRIVE,
                          Recording(self.output_scene, _ALL_OUTPUTS, rows, False, False, self.time))
        return rows[0]

    def _step_to(self, t_end: float, drive: tuple[np.ndarray, np.ndarray] | TaylorDrive) -> int:
        """genalpha.advance to t_end through advance_recording, which also records all outputs
        there (kept for :meth:`_output_array`; not with wake oscillators, whose coupling
        changes the loads after the step); the solver status. A :class:`TaylorDrive` (an
        FMU step) goes through the model's :class:`~towcable_fmu.ancf.stepper.Stepper`."""
        if isinstance(drive, TaylorDrive):
            return self._step_taylor(t_end, drive)
        keep = not self._staggered
        rows = np.empty((1, len(OUTPUT_FIELDS))) if keep else _NO_ROWS
        while True:  # (a spool end's fed element is split or merged between steps)
            reached = advance_recording(self.model, self.options, self.state, self.workspace, np.array([t_end]),
                                        *drive, Recording(self.output_scene, _ALL_OUTPUTS if keep else _NO_OUTPUTS,
                                                          rows, False, False, t_end))
            # (an event of the step that reached t_end is handled too: else a run of steps
            # each one solver step long would never remesh)
            if not self._after_event() or reached == 1:
                break
        self._stepped = (self._fingerprint(), rows[0]) if keep and reached == 1 else None
        return genalpha.OK if reached == 1 else genalpha.FAILED_MIN_STEP

    def _step_taylor(self, t_end: float, drive: TaylorDrive) -> int:
        """:meth:`_step_to` with the one knot of an FMU step, in one compiled call
        (:func:`towcable_fmu.ancf.stepper.step_to`) that does not unbox the model."""
        while True:  # (a spool end's fed element is split or merged between steps)
            stepper, rows, _ = self._current_stepper()
            reached = step_to(stepper, t_end, drive.t0, drive.ship, drive.setpoint[0], drive.setpoint[1])
            if not self._after_event() or reached == 1:  # (as _step_to)
                break
        self._stepped = (self._fingerprint(), rows[0]) if reached == 1 else None
        return genalpha.OK if reached == 1 else genalpha.FAILED_MIN_STEP

    def _current_stepper(self) -> tuple[Any, np.ndarray, genalpha.IntegratorState]:
        """The :class:`~towcable_fmu.ancf.stepper.Stepper` of the current model, options, state,
        workspace and output scene (built again when one of them was replaced), its row
        of outputs and its saved state."""
        held = (self.model, self.options, self.state, self.workspace, self.output_scene)
        if self._stepper is None or not all(map(operator.is_, held, self._stepper[0])):
            rows = np.empty((1, len(OUTPUT_FIELDS)))
            saved = genalpha.IntegratorState(*(np.empty_like(x) for x in self.state))
            stepper = new_stepper(*held, _ALL_OUTPUTS, rows, np.zeros(1), np.zeros((1, 3, drive_poly.N_CHANNELS)),
                                  saved)
            self._stepper = (held, stepper, rows, saved)
        return self._stepper[1], self._stepper[2], self._stepper[3]

    def buffer_plan(self, inputs: np.ndarray, outputs: np.ndarray, positions: np.ndarray,
                    booleans: np.ndarray) -> np.ndarray | None:
        """Where an FMU keeps this simulation's inputs and outputs in its buffer of values
        (:func:`~towcable_fmu.ancf.buffer_step.buffer_plan`, for :meth:`step_on_values`);
        None if its steps need Python (a term acting between steps or with outputs or a
        state of its own in Python, a payout program).

        Parameters
        ----------
        inputs
            (20,): the buffer's indices of the ship state (3, 6) in row order and of
            phi_sp [rad], phi_sp_rate [rad/s].
        outputs, positions, booleans
            (k,): the buffer's index of each output, its position in :attr:`names`, and
            whether it is a Boolean.
        """
        if self._staggered or self._python_outputs or self._saving or self._program is not None:
            return None
        index = np.asarray(self.layout.index)
        return buffer_plan(inputs, index, outputs, index[np.asarray(positions, dtype=np.intp)], booleans)

    def step_on_values(self, t_end: float, values: np.ndarray, plan: np.ndarray) -> bool:
        """:meth:`step_row` to ``t_end`` [s] (by ``t_end - time``) with the inputs read from
        the buffer ``values`` and the outputs written into it (:meth:`buffer_plan`), in one
        compiled call (:func:`~towcable_fmu.ancf.buffer_step.step_on_values`).

        Returns
        -------
        bool
            True if the step is made; False if not, with nothing changed: the step is for
            :meth:`step_row` to make or to refuse with the reason (non-finite inputs or step,
            a failed step, non-finite outputs, a payout beyond the drum, a spool end's fed element
            out of its band: step_row remeshes).
        """
        if self.turbulence is not None:
            self._cover(t_end)
        stepper, rows, saved = self._current_stepper()
        status = step_on_values(stepper, values, plan, t_end,
                                math.inf if self._payout_limit is None else self._payout_limit)
        if status == DONE:
            self._setpoint = (float(values[plan[20]]), float(values[plan[21]]))
            self._stepped = (self._fingerprint(), rows[0])
            return True
        if status == ROLL_BACK:
            self._restore((saved, self._extra_state()))
        return False

    def native_step(self, count: int, plan: np.ndarray) -> tuple[int, np.ndarray] | None:
        """The C function that makes :meth:`step_on_values` without Python, for an FMU's
        loader layer (:data:`~towcable_fmu.ancf.native_step.STEP`: its address), and its data
        for a buffer of ``count`` values laid out as ``plan`` (:meth:`buffer_plan`); None if
        the steps need Python (turbulence: its series is extended in Python). The data hold
        until a call changes the Simulation: the caller takes the steps over first
        (:meth:`native_steps_made`)."""
        if self.turbulence is not None:
            return None
        stepper, _, _ = self._current_stepper()
        limit = math.inf if self._payout_limit is None else self._payout_limit
        data = native_step.step_data(stepper, count, plan, limit)
        return None if data is None else (native_step.STEP, data)

    def native_steps_made(self, data: np.ndarray) -> None:
        """Take over what the C steps of :meth:`native_step`'s ``data`` did: the set-point and
        the outputs of the last step made, and the rollback of one they refused (as
        :meth:`step_on_values`); the counts in ``data`` start again."""
        if data[native_step.STEPS] > 0.0:
            self._setpoint = (float(data[native_step.PHI_SP]), float(data[native_step.PHI_SP_RATE]))
            self._stepped = (self._fingerprint(), self._current_stepper()[1][0])
            data[native_step.STEPS] = 0.0
        if data[native_step.STATUS] == ROLL_BACK:
            self._restore((self._current_stepper()[2], self._extra_state()))
        data[native_step.STATUS] = DONE

    def _snapshot(self) -> tuple[genalpha.IntegratorState, dict[str, Any]]:
        """The state arrays, copied by one compiled call into the Stepper's saved state, and
        the extra state."""
        stepper, _, saved = self._current_stepper()
        save_state(stepper)
        return saved, self._extra_state()

    def _fingerprint(self) -> float:
        """What identifies the state a step reached among those the kept outputs may be
        asked of: its time [s] (every other move of the state drops them: the run loop,
        a restore, new coordinates, a new model)."""
        return float(self.state.clock[genalpha.CLOCK_TIME])

    def _counters(self) -> np.ndarray:
        return self.state.stats

    def _extra_statistics(self) -> dict[str, float]:
        return {"solver.last_error_estimate": float(self.state.clock[genalpha.CLOCK_ERROR]),
                "solver.time_step": float(self.state.clock[genalpha.CLOCK_STEP])}

    # ----------------------------------------------------------------- state
    def _state_arrays(self) -> genalpha.IntegratorState:
        return self.state

    def _extra_state(self) -> dict[str, Any]:
        return {"setpoint": list(self._setpoint), "payout_limit": self._payout_limit,
                "winch_control": self.compensation.get_state() if self._tension_control() else None,
                "turbulence_t0": None if self.turbulence is None else self.turbulence.t0,
                "terms": {hooks.name: hooks.save() for hooks in self._saving}}

    def set_state(self, data: Mapping[str, Any]) -> None:
        """Restore a state of :meth:`get_state` (see
        :meth:`~towcable_fmu.runtime.driver.SimulationDriver.set_state`), also one saved
        before a spool end's fed element was split or merged: the model of its mesh is
        rebuilt first (and put back if the state is refused)."""
        kept = (self._mesh, self.model, self.state, self.workspace)
        saved = data.get("terms", {})
        for hooks in self._saving:
            hooks.adopt(saved.get(hooks.name))
        try:
            super().set_state(data)
        except SceneError:
            self._use(*kept[:3])
            self.workspace = kept[3]
            raise

    def _load_extra_state(self, data: Mapping[str, Any]) -> None:
        saved = data.get("terms", {})
        for hooks in self._saving:
            hooks.restore(saved.get(hooks.name))
        t0 = data.get("turbulence_t0")
        if t0 is not None and (self.turbulence is None or self.turbulence.t0 != t0):
            self._start_turbulence(float(t0))
        self._setpoint = (float(data["setpoint"][0]), float(data["setpoint"][1]))
        self._payout_limit = data.get("payout_limit")
        if data.get("winch_control") is not None and self._tension_control():
            self.compensation.set_state(data["winch_control"])

    def _restored(self) -> None:
        self._stepped = None
        self._last_outputs = {}  # they were of another state
        self._cover(self.time)
        apply_feed(self.model, self.state.phi)
        genalpha.refactorize_from_state(self.model, self.options, self.state, self.workspace)

    # ------------------------------------------------------------------- run
    def _tension_control(self) -> bool:
        """Whether the winch is a constant-tension winch (its controller: ``self.compensation``)."""
        return self.compensation is not None and self.compensation.config.method == "tension"

    def _feedback(self) -> bool:
        """Whether the set-point needs a measurement of the latest state (the sheave angle of
        a rigorous compensation, the tension of a constant-tension winch)."""
        return self._tension_control() or (self.compensation is not None and self.compensation.config.rigorous)

    def _block_size(self, interval: float) -> int:
        # per sample when the set-point needs a measurement of the latest state; else
        # at least BLOCK_STEPS steps of the nominal size (each block pays the drive table's
        # motion and set-points in Python and a kernel call: 10 % of full_scale's run with
        # blocks of 1 s, 20 steps)
        if self._feedback():
            return 1
        return max(super()._block_size(interval), int(BLOCK_STEPS * self.options.h_max / interval))

    def _record(self, block: np.ndarray, rows: np.ndarray, t_land: float) -> int:
        """Step through the sample times ``block`` [s] and write their outputs into ``rows``.

        In the compiled recording loop, the integrator keeps its own steps and reads the
        samples from its interpolant (not with a set-point from measurements, which needs the
        state at every sample); a term's outputs computed in Python and the work of a
        staggered term between steps (the wake coupling) are recorded
        in Python, one sample at a time.
        """
        self._stepped = None  # (the outputs kept of the last step are not those of the states reached here)
        feedback = self._feedback()
        in_python = bool(self._python_outputs or self._staggered)
        interpolate = not in_python and not feedback
        h = self.options.h_max
        if interpolate:
            marks = self._interpolation_marks(block, self.time, float(self.workspace.step_start[0]), h, t_land)
        else:
            marks = np.concatenate([[self.time], block])
        drive = self._drive(marks, h)
        self._cover(float(marks.max()))
        if not in_python:
            reached = 0
            while True:  # (a spool end's fed element is split or merged between steps)
                reached += advance_recording(self.model, self.options, self.state, self.workspace, block[reached:],
                                             *drive, Recording(self.output_scene, self.layout.index, rows[reached:],
                                                               True, interpolate, t_land))
                if not self._after_event() or reached == block.size:  # (as _step_to)
                    break
        else:
            reached = 0
            while reached < block.size and self._integrate(block[reached], drive) == genalpha.OK:
                rows[reached] = self._output_row()
                if not np.all(np.isfinite(rows[reached])):
                    break
                reached += 1
        if self._payout_limit is not None:
            payout = rows[:reached, self.names.index("winch.payout")]
            beyond = np.flatnonzero(payout > self._payout_limit)
            if beyond.size:
                raise self._payout_error(float(block[beyond[0]]), float(payout[beyond[0]]))
        return reached

    def _drum_payout_limit(self) -> float | None:
        """The largest payout [m] of the current state's drum: the payout now plus the
        unstretched cable from its end to where it leaves the drum (None: no drum contact)."""
        if self._stored_length is not None:
            return self._stored_length
        wound = self._answer("wound_length")()
        return None if wound is None else self._payout() + wound

    def _payout(self) -> float:
        """``winch.payout`` of the current state [m]."""
        return float(self._output_array()[_PAYOUT])

    def _payout_error(self, t: float, payout: float) -> SolverError:
        return SolverError(f"winch.payout = {payout:.4g} m at t = {t:.6g} s exceeds the {self._payout_limit:.4g} m "
                           "the drum holds (the payout at the start plus the cable then wound on it): the cable's end "
                           "would leave the drum; limit the set-point (compensation.max_payout) or, with a "
                           "constant-tension winch, lower compensation.tension_gain if the loop is unstable")

    def _failure(self, t: float) -> SolverError:
        if self.time < t - 1e-12 * max(1.0, abs(t)):
            return SolverError(f"the solver could not advance to t = {t:.6g} s: Newton failed at the minimum step "
                               f"size {self.options.h_min:g} s near t = {self.time:.6g} s{self._failure_hint()}")
        return SolverError(f"non-finite outputs at t = {t:.6g} s")

    def _end_recording(self) -> None:
        self.outputs()
