"""A nodal-position cable scene in time, with the run interface of the ANCF Simulation.

``NodalSimulation(scene).run(duration, interval)`` returns a dict of arrays named as the
ANCF outputs (``tension.top``, ``angle.top``, ``tension.max``, ``tension.min``,
``towbody.x/y/z/vx/vy/vz``); the ship motion comes from the scene's ``[motion]`` through
``ship_motion`` (``evaluate_many`` at knots no farther apart than the step, as
:class:`towcable_fmu.simulation.Simulation` does). ``solver.integrator`` picks the
implicit generalised-alpha (default) or the paper's explicit RK4.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from .. import drive as drive_poly
from ..errors import SolverError
from ..numerics.genalpha import scheme_coefficients
from ..scene import load_scene
from ..scene.model import Scene
from ..simulation import _motion_source
from .integrators import INTEGRATORS, STAT_NAMES, accelerations, advance_recording, output_values, prescribe_top
from .model import NodalModel, build_nodal_model
from .statics import solve_statics
from ..sampling import output_interval, sample_times

#: Outputs of every nodal scene, then those of a scene with a towed body.
OUTPUT_NAMES = ("tension.top", "angle.top", "tension.max", "tension.min")
BODY_NAMES = ("towbody.x", "towbody.y", "towbody.z", "towbody.vx", "towbody.vy", "towbody.vz")


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
        self.motion = _motion_source(scene)
        self.method = INTEGRATORS[scene.solver.integrator]
        s = scene.solver
        self.coef = np.array(scheme_coefficients(s.rho_inf))
        n = 3 * self.model.n_nodes
        self.q, self.v, self.x, self.acc = (np.zeros(n) for _ in range(4))
        self.clock = np.array([0.0, s.time_step])
        self.stats = np.zeros(len(STAT_NAMES), dtype=np.int64)
        self.names = OUTPUT_NAMES + (BODY_NAMES if scene.towbody is not None else ())
        self._statics: dict[str, float] = {}
        self._initialized = False

    @classmethod
    def from_scene(cls, name_or_path: str | Path,
                   overrides: Mapping[str, Any] | Iterable[tuple[str, Any]] = ()) -> "NodalSimulation":
        """Load a built-in scene by name, or a scene file, with dotted-key overrides."""
        return cls(load_scene(name_or_path, overrides))

    @property
    def time(self) -> float:
        """Current simulation time [s]."""
        return float(self.clock[0])

    def _drive(self, marks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Drive table of the scene's ship motion through ``marks`` [s], knots <= one step apart."""
        pieces = [marks[:1]]
        for a, b in zip(marks[:-1], marks[1:]):
            k = max(1, math.ceil((b - a) / self.scene.solver.time_step - 1e-9))
            pieces.append(np.linspace(a, b, k + 1)[1:])
        times = np.concatenate(pieces)
        return drive_poly.knot_drive(times, self.motion.evaluate_many(times), np.zeros((times.size, 2)))

    def initialize(self, t0: float = 0.0, statics: bool | None = None) -> dict[str, float]:
        """Lay the cable straight along ``cable.initial.direction`` from the top, solve the
        statics (default: ``statics.enabled``) and set consistent accelerations.

        Raises
        ------
        SolverError
            If the statics do not converge or the accelerations are not finite.
        """
        m = self.model
        drive = drive_poly.taylor_drive(t0, self.motion.evaluate(t0), (0.0, 0.0))
        self.clock[:] = (t0, self.scene.solver.time_step)
        self.stats[:] = 0
        self.v[:] = 0.0
        self.x[:] = 0.0
        prescribe_top(m, *drive, t0, self.q, self.v, self.x)
        direction = np.array(self.scene.cable.initial.direction, dtype=float)
        arc = np.concatenate([[0.0], np.cumsum(m.L0)])
        self.q[:] = (self.q[:3] + arc[:, None] * direction / np.linalg.norm(direction)).ravel()
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
        values = np.empty(len(OUTPUT_NAMES) + len(BODY_NAMES))
        output_values(self.model, self.q, self.v, self.x, self.time, values)
        return dict(zip(self.names, values.tolist()))

    def node_positions(self) -> np.ndarray:
        """Node positions [m], shape (n_nodes, 3)."""
        return self.q.reshape(-1, 3).copy()

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
        values = np.empty((n + 1, len(OUTPUT_NAMES) + len(BODY_NAMES)))
        output_values(self.model, self.q, self.v, self.x, t0, values[0])
        s = self.scene.solver
        chunk = max(1, int(1.0 / dt))
        for first in range(0, n, chunk):
            stop = min(n, first + chunk)
            drive = self._drive(np.concatenate([[self.time], samples[first:stop]]))
            reached = first + advance_recording(
                self.model, self.method, s.time_step, s.min_time_step, self.coef, s.newton_tol,
                s.max_newton_iterations, self.q, self.v, self.x, self.acc, self.clock, self.stats,
                samples[first:stop], *drive, values[first + 1:stop + 1])
            if reached < stop:
                raise SolverError(f"the {s.integrator} integrator could not advance to t = {samples[reached]:.6g} s "
                                  f"(step {self.clock[1]:.3g} s; an explicit RK4 step must resolve the "
                                  f"highest axial frequency of the mesh)")
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
