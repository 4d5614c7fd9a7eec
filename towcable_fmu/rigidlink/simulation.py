"""Driver of the rigid-link model with the interface the command line uses.

:class:`RigidLinkSimulation` offers ``initialize``, ``run`` and ``statistics`` like
:class:`towcable_fmu.simulation.Simulation`; outputs use the contract's names where
they exist (``ship.*`` is the tug's fairlead, ``towbody.*`` the towed vessel's,
``tension.top`` the tension at the tug, ``tension.towbody`` at the towed vessel) plus
the model's own (:data:`EXTRA_UNITS`).
"""

from __future__ import annotations

import math
import time
from typing import Any, Callable, Mapping

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK45, Radau

from .. import contract
from ..protocol import SOLVER_STATISTICS
from ..errors import SceneError, SolverError
from .dynamics import accelerations, end_tensions, link_forces, node_kinematics
from .initial import parabola_angles
from .scene import RigidLinkScene, Vessel
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


class RigidLinkSimulation:
    """Tug - n rigid links - towed vessel, integrated with one of scipy's ODE solvers.

    Parameters
    ----------
    scene
        The validated scene.
    """

    def __init__(self, scene: RigidLinkScene) -> None:
        self.scene = scene
        n = scene.cable.links
        self.theta0, link = parabola_angles(n, scene.layout)
        self.l = np.full(n, link)
        self.m = np.full(n, scene.cable.mass_per_length * link)
        self.k = np.full(n - 1, scene.cable.EI / link)
        self.c = np.full(n - 1, scene.cable.bending_damping / link)
        self.tug = _vessel_vector(scene.tug)
        self.towed = _vessel_vector(scene.towed)
        self.g = scene.environment.gravity
        self.time = 0.0
        self.y = np.concatenate(([scene.layout.span, scene.layout.height], self.theta0, np.zeros(n + 2)))
        self._stats = {name: 0 for name in SOLVER_STATISTICS}
        self._statics: dict[str, float] = {}

    @property
    def length(self) -> float:
        """Cable length n l [m]."""
        return float(self.l.sum())

    #: The outputs of this model, ``time`` first: the columns of :meth:`run`.
    output_names = SERIES

    def unit_of(self, name: str) -> str:
        """Unit of an output name (the contract's, or this model's own)."""
        return EXTRA_UNITS.get(name) or contract.unit_of(name)

    # -------------------------------------------------------------- model evaluation
    def _inputs(self, t: float) -> tuple[float, np.ndarray]:
        z0 = self.scene.layout.height
        refs = np.array([*_heave_reference(self.scene.tug, z0, t), *_heave_reference(self.scene.towed, z0, t)])
        return thrust_at(t, self.scene.thrust), refs

    def _rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        dim = self.l.size + 2
        thrust, refs = self._inputs(t)
        qdd, _, _ = accelerations(y[:dim], y[dim:], self.l, self.m, self.k, self.c, self.tug, self.towed,
                                  thrust, refs, self.g)
        return np.concatenate((y[dim:], qdd))

    def outputs(self) -> dict[str, float]:
        """Output values at the current state (names: :attr:`output_names`)."""
        return self._outputs_at(self.time, self.y)

    def _outputs_at(self, t: float, y: np.ndarray) -> dict[str, float]:
        """Output values at time ``t`` [s] for the state ``y = [q, qdot]``."""
        dim = self.l.size + 2
        q, qd = y[:dim], y[dim:]
        thrust, refs = self._inputs(t)
        qdd, _, fb = accelerations(q, qd, self.l, self.m, self.k, self.c, self.tug, self.towed, thrust, refs,
                                   self.g)
        F = link_forces(q, qd, qdd, self.l, self.m, self.towed[0], fb, self.g)
        t_tug, t_towed, t_min = end_tensions(q, F)
        r, v = node_kinematics(q, qd, self.l)
        span = float(np.hypot(*(r[0] - r[-1])))
        taut = span >= (1.0 - self.scene.solver.taut_tolerance) * self.length
        return {"time": t, "ship.x": r[0, 0], "ship.z": r[0, 1], "ship.vx": v[0, 0], "ship.vz": v[0, 1],
                "towbody.x": r[-1, 0], "towbody.z": r[-1, 1], "towbody.vx": v[-1, 0], "towbody.vz": v[-1, 1],
                "tension.top": t_tug, "tension.towbody": t_towed, "tension.min": t_min, "cable.span": span,
                "cable.taut": float(taut), "tug.thrust": thrust}

    # -------------------------------------------------------------- public interface
    @property
    def n_elements(self) -> int:
        """Number of rigid links."""
        return int(self.l.size)

    def initialize(self, t0: float = 0.0, ship: np.ndarray | None = None, setpoint: tuple[float, float] | None = None,
                   statics: bool | None = None) -> dict[str, float]:
        """Outputs at the start time ``t0`` [s] (the parabola at rest), or with ``statics``
        the equilibrium.

        ``ship`` and ``setpoint`` are accepted for the interface of
        :class:`towcable_fmu.simulation.Simulation` and not used: the tug is driven by the
        scene's thrust ramp and heave references, not by a prescribed ship motion.

        With ``statics=True`` the cable's equilibrium between the two fairleads held at
        their initial positions is solved (:mod:`.statics`) and reported as
        ``tension.top``, ``tension.towbody``, ``cable.sag`` and ``angle.top`` [rad, between
        the cable at the tug and the downward vertical]; the run itself starts from the
        reference's parabola at rest.
        """
        if not math.isfinite(t0):
            raise SceneError("t0", t0, "a finite start time [s]")
        self.time = float(t0)
        if not statics:
            return self.outputs()
        start = time.perf_counter()
        lay = self.scene.layout
        w = self.g * self.scene.cable.mass_per_length
        H0 = w * lay.span ** 2 / (8.0 * lay.sag) if lay.sag > 0 else w * lay.span
        eq = solve_statics(self.theta0, self.l, self.m, self.k, lay.span, self.g, force0=(-H0, 0.5 * w * self.length))
        self._statics = {"solver.statics_iterations": eq.iterations, "solver.statics_residual": eq.residual,
                         "solver.statics_wall_time": time.perf_counter() - start}
        angle_top = math.atan2(abs(math.cos(eq.theta[0])), -math.sin(eq.theta[0]))
        return {"tension.top": eq.tension_tug, "tension.towbody": eq.tension_towed, "cable.sag": eq.sag,
                "angle.top": float(angle_top), "cable.span": lay.span}

    def run(self, duration: float, interval: float | None = None,
            progress: Callable[[float, float], None] | None = None) -> dict[str, np.ndarray]:
        """Integrate for ``duration`` [s] and record the outputs every ``interval`` [s].

        Returns
        -------
        dict
            Output name -> array over the samples (including the start), see :data:`SERIES`.

        Raises
        ------
        SolverError
            If the ODE solver fails.
        """
        if not (math.isfinite(duration) and duration > 0.0):
            raise SceneError("duration", duration, "a finite time > 0 s")
        dt = self.scene.output.interval if interval is None else interval
        t0 = self.time
        count = max(1, int(math.ceil(duration / dt - 1e-9)))
        samples = t0 + np.minimum(np.arange(count + 1) * dt, duration)
        opts = self.scene.solver
        solver = _METHODS[opts.method](self._rhs, t0, self.y, samples[-1], rtol=opts.rtol, atol=opts.atol,
                                       max_step=opts.max_step)
        rows = [self.outputs()]
        nxt = 1
        last_report = t0
        while nxt <= count:
            message = solver.step()
            if solver.status == "failed":
                raise SolverError(f"{opts.method} failed near t = {solver.t:.6g} s: {message}")
            self._stats["solver.steps"] += 1
            dense = None
            while nxt <= count and samples[nxt] <= solver.t:
                dense = dense or solver.dense_output()
                y = solver.y if samples[nxt] == solver.t else dense(samples[nxt])
                rows.append(self._outputs_at(float(samples[nxt]), y))
                nxt += 1
            if progress is not None and solver.t - last_report >= 1.0:
                progress(solver.t, samples[-1])
                last_report = solver.t
        self._count(solver)
        self.time, self.y = float(samples[-1]), solver.y.copy()
        if progress is not None:
            progress(self.time, samples[-1])
        return {name: np.array([row[name] for row in rows]) for name in SERIES}

    def step(self, dt: float, ship: np.ndarray | None = None,
             setpoint: tuple[float, float] | None = None) -> dict[str, float]:
        """Advance by ``dt`` [s] (FMU style) and return the outputs at the new time.

        Each call starts the scene's ODE solver afresh from the current state, so a state
        restored with :meth:`set_state` continues exactly as the original run did.
        ``ship`` and ``setpoint`` are not used (see :meth:`initialize`).

        Raises
        ------
        SceneError
            If ``dt`` is not a finite step > 0; nothing is changed.
        SolverError
            If the ODE solver fails; the state is then left as it was.
        """
        if not (math.isfinite(dt) and dt > 0.0):
            raise SceneError("dt", dt, "a finite step > 0 s")
        opts = self.scene.solver
        t_end = self.time + dt
        solver = _METHODS[opts.method](self._rhs, self.time, self.y, t_end, rtol=opts.rtol, atol=opts.atol,
                                       max_step=opts.max_step)
        while solver.status == "running":
            message = solver.step()
            if solver.status == "failed":
                raise SolverError(f"{opts.method} failed near t = {solver.t:.6g} s: {message}")
            self._stats["solver.steps"] += 1
        if not np.all(np.isfinite(solver.y)):
            raise SolverError(f"{opts.method} produced non-finite values at t = {t_end:.6g} s")
        self._count(solver)
        self.time, self.y = float(t_end), solver.y.copy()
        return self.outputs()

    def get_state(self) -> dict[str, Any]:
        """The state (time [s], angles and rates) and counters as JSON-able data."""
        return {"time": self.time, "y": self.y.tolist(), "stats": dict(self._stats), "n_links": int(self.l.size)}

    def set_state(self, data: Mapping[str, Any]) -> None:
        """Restore a state from :meth:`get_state`.

        Raises
        ------
        SceneError
            If the data belongs to a model with another number of links.
        """
        if int(data.get("n_links", -1)) != self.l.size:
            raise SceneError("state.n_links", data.get("n_links"), f"{self.l.size} (the state belongs to another model)")
        self.time = float(data["time"])
        self.y = np.asarray(data["y"], dtype=float)
        self._stats = dict(data["stats"])

    def _count(self, solver) -> None:
        """Add a finished scipy solver's right-hand-side evaluations and LU factorisations."""
        self._stats["solver.residual_evaluations"] += int(solver.nfev)
        self._stats["solver.jacobian_factorisations"] += int(getattr(solver, "nlu", 0))

    def statistics(self) -> dict[str, float]:
        """Solver counters since construction (:data:`~towcable_fmu.protocol.SOLVER_STATISTICS`:
        accepted steps, right-hand-side evaluations, LU factorisations of the implicit
        methods), plus the statics result if solved."""
        return {**self._stats, **self._statics}
