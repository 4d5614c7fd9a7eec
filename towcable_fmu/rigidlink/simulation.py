"""The rigid-link model in time (the protocol of :mod:`towcable_fmu.runtime.protocol`, its
common part in :mod:`towcable_fmu.runtime.driver`).

:class:`RigidLinkSimulation` integrates with one of scipy's ODE solvers; outputs use the contract's names where
they exist (``ship.*`` is the tug's fairlead, ``towbody.*`` the towed vessel's,
``tension.top`` the tension at the tug, ``tension.towbody`` at the towed vessel) plus
the model's own (:data:`EXTRA_UNITS`).
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK45, Radau

from ..common import contract
from ..common.errors import SolverError
from ..runtime.protocol import SOLVER_STATISTICS
from ..runtime.driver import SimulationDriver
from .dynamics import accelerations, end_tensions, link_forces, node_kinematics
from .initial import parabola_angles
from ..scene.rigid_link import RigidLinkScene, Vessel
from .statics import solve_statics
from .thrust import thrust_at

#: Outputs of this model that are not in the variable contract, with their units.
EXTRA_UNITS = {"tension.min": "N", "cable.span": "m", "cable.taut": "1", "cable.sag": "m", "tug.thrust": "N"}

_METHODS = {"LSODA": LSODA, "Radau": Radau, "BDF": BDF, "DOP853": DOP853, "RK45": RK45}

#: Recorded time series, in column order.
SERIES = ("time", "ship.x", "ship.z", "ship.vx", "ship.vz", "towbody.x", "towbody.z", "towbody.vx", "towbody.vz",
          "tension.top", "tension.towbody", "tension.min", "cable.span", "cable.taut", "tug.thrust")


def _vessel_vector(v: Vessel) -> np.ndarray:
    return np.array([v.mass, v.heave_kp, v.heave_kd, v.resistance])


def _heave_reference(v: Vessel, z0: float, t: float) -> tuple[float, float]:
    """Heave reference z_ref [m] and its rate [m/s] of one vessel at time t [s]."""
    w = 2.0 * math.pi / v.wave_period
    return (z0 + v.wave_amplitude * math.sin(w * t + v.wave_phase),
            v.wave_amplitude * w * math.cos(w * t + v.wave_phase))


class RigidLinkSimulation(SimulationDriver):
    """Tug - n rigid links - towed vessel, integrated with one of scipy's ODE solvers.

    The tug is driven by the scene's thrust ramp and heave references, not by a
    prescribed ship motion: :meth:`step` takes no ship state and no winch set-point.

    Parameters
    ----------
    scene
        The validated scene.
    """

    STATE_FIELDS = ("y", "clock", "counters")
    #: :data:`~towcable_fmu.runtime.protocol.SOLVER_STATISTICS` without their ``solver.`` prefix.
    COUNTER_NAMES = tuple(name.removeprefix("solver.") for name in SOLVER_STATISTICS)
    NEEDS_SHIP = False

    def __init__(self, scene: RigidLinkScene) -> None:
        self._keep(scene)
        n = scene.cable.links
        self.theta0, link = parabola_angles(n, scene.layout)
        self.l = np.full(n, link)
        self.m = np.full(n, scene.cable.mass_per_length * link)
        self.k = np.full(n - 1, scene.cable.EI / link)
        self.c = np.full(n - 1, scene.cable.bending_damping / link)
        self.tug = _vessel_vector(scene.tug)
        self.towed = _vessel_vector(scene.towed)
        self.g = scene.environment.gravity
        # what the run reads of the scene, kept here: the scene is read once, in this constructor
        self._thrust = scene.thrust
        self._vessels = (scene.tug, scene.towed)
        self._layout = scene.layout
        self._mass_per_length = scene.cable.mass_per_length
        self._solver_options = scene.solver
        #: the state [q, qdot] (q: tug x, z, link angles), the time [s] and the counters
        self.y = np.concatenate(([scene.layout.span, scene.layout.height], self.theta0, np.zeros(n + 2)))
        self.clock = np.zeros(1)
        self.counters = np.zeros(len(self.COUNTER_NAMES), dtype=np.int64)
        self.names = SERIES[1:]
        self._statics: dict[str, float] = {}
        self._solver = None  # the ODE solver of a run in progress

    @property
    def time(self) -> float:
        """Current simulation time [s]."""
        return float(self.clock[0])

    @property
    def length(self) -> float:
        """Cable length n l [m]."""
        return float(self.l.sum())

    def unit_of(self, name: str) -> str:
        """Unit of an output name (the contract's, or this model's own)."""
        return EXTRA_UNITS.get(name) or contract.unit_of(name)

    # -------------------------------------------------------------- model evaluation
    def _inputs(self, t: float) -> tuple[float, np.ndarray]:
        z0 = self._layout.height
        tug, towed = self._vessels
        refs = np.array([*_heave_reference(tug, z0, t), *_heave_reference(towed, z0, t)])
        return thrust_at(t, self._thrust), refs

    def _rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        dim = self.l.size + 2
        thrust, refs = self._inputs(t)
        qdd, _, _ = accelerations(y[:dim], y[dim:], self.l, self.m, self.k, self.c, self.tug, self.towed,
                                  thrust, refs, self.g)
        return np.concatenate((y[dim:], qdd))

    def _output_row(self) -> np.ndarray:
        return self._outputs_at(self.time, self.y)

    def _outputs_at(self, t: float, y: np.ndarray) -> np.ndarray:
        """Output values (:attr:`names`) at time ``t`` [s] for the state ``y = [q, qdot]``."""
        dim = self.l.size + 2
        q, qd = y[:dim], y[dim:]
        thrust, refs = self._inputs(t)
        qdd, _, fb = accelerations(q, qd, self.l, self.m, self.k, self.c, self.tug, self.towed, thrust, refs,
                                   self.g)
        F = link_forces(q, qd, qdd, self.l, self.m, self.towed[0], fb, self.g)
        t_tug, t_towed, t_min = end_tensions(q, F)
        r, v = node_kinematics(q, qd, self.l)
        span = float(np.hypot(*(r[0] - r[-1])))
        taut = span >= (1.0 - self._solver_options.taut_tolerance) * self.length
        return np.array([r[0, 0], r[0, 1], v[0, 0], v[0, 1], r[-1, 0], r[-1, 1], v[-1, 0], v[-1, 1],
                         t_tug, t_towed, t_min, span, float(taut), thrust], dtype=float)

    # -------------------------------------------------------------- public interface
    @property
    def n_elements(self) -> int:
        """Number of rigid links."""
        return int(self.l.size)

    def _initial_state(self, t0: float, ship: np.ndarray | None, setpoint: tuple[float, float] | None,
                       statics: bool | None) -> dict[str, float] | None:
        """The parabola at rest at ``t0`` [s]; with ``statics`` also the equilibrium.

        ``ship`` and ``setpoint`` are not used (see the class). With ``statics=True`` the
        cable's equilibrium between the two fairleads held at their initial positions is
        solved (:mod:`.statics`) and reported (instead of the outputs) as
        ``tension.top``, ``tension.towbody``, ``cable.sag`` and ``angle.top`` [rad, between
        the cable at the tug and the downward vertical]; the run itself starts from the
        reference's parabola at rest.
        """
        self.clock[0] = t0
        if not statics:
            return None
        start = time.perf_counter()
        lay = self._layout
        w = self.g * self._mass_per_length
        H0 = w * lay.span ** 2 / (8.0 * lay.sag) if lay.sag > 0 else w * lay.span
        eq = solve_statics(self.theta0, self.l, self.m, self.k, lay.span, self.g, force0=(-H0, 0.5 * w * self.length))
        self._statics = {"solver.statics_iterations": eq.iterations, "solver.statics_residual": eq.residual,
                         "solver.statics_wall_time": time.perf_counter() - start}
        angle_top = math.atan2(abs(math.cos(eq.theta[0])), -math.sin(eq.theta[0]))
        return {"tension.top": eq.tension_tug, "tension.towbody": eq.tension_towed, "cable.sag": eq.sag,
                "angle.top": float(angle_top), "cable.span": lay.span}

    def _new_solver(self, t_end: float):
        opts = self._solver_options
        return _METHODS[opts.method](self._rhs, self.time, self.y, t_end, rtol=opts.rtol, atol=opts.atol,
                                     max_step=opts.max_step)

    def _solver_step(self, solver) -> None:
        """One step of the scipy solver, counted; a SolverError if it fails."""
        message = solver.step()
        if solver.status == "failed":
            raise SolverError(f"{self._solver_options.method} failed near t = {solver.t:.6g} s: {message}")
        self.counters[0] += 1

    def _begin_recording(self, samples: np.ndarray) -> None:
        self._solver = self._new_solver(float(samples[-1]))

    def _record(self, block: np.ndarray, rows: np.ndarray, t_land: float) -> int:
        """Step the run's ODE solver past the samples ``block`` [s], read from its dense output."""
        solver = self._solver
        dense = None
        for k, t in enumerate(block):
            while t > solver.t:
                self._solver_step(solver)
                dense = None
            dense = dense or solver.dense_output()
            rows[k] = self._outputs_at(float(t), solver.y if t == solver.t else dense(t))
        return block.size

    def _end_recording(self) -> None:
        self._count(self._solver)
        self.clock[0], self.y = float(self._solver.t), self._solver.y.copy()
        self._solver = None

    def _failure(self, t: float) -> SolverError:
        return SolverError(f"{self._solver_options.method} did not reach t = {t:.6g} s")

    def _advance(self, dt: float, ship: np.ndarray | None, setpoint: tuple[float, float] | None) -> None:
        """Advance by ``dt`` [s]: each call starts the scene's ODE solver afresh from the
        current state, so a state restored with :meth:`set_state` continues exactly as the
        original run did."""
        t_end = self.time + dt
        solver = self._new_solver(t_end)
        while solver.status == "running":
            self._solver_step(solver)
        if not np.all(np.isfinite(solver.y)):
            raise SolverError(f"{self._solver_options.method} produced non-finite values at t = {t_end:.6g} s")
        self._count(solver)
        self.clock[0], self.y = float(t_end), solver.y.copy()

    def _state_arrays(self) -> tuple[np.ndarray, ...]:
        return self.y, self.clock, self.counters

    def _count(self, solver) -> None:
        """Add a finished scipy solver's right-hand-side evaluations and LU factorisations."""
        self.counters[1] += int(solver.nfev)
        self.counters[2] += int(getattr(solver, "nlu", 0))

    def _counters(self) -> np.ndarray:
        """Accepted steps, right-hand-side evaluations, LU factorisations of the implicit methods."""
        return self.counters
