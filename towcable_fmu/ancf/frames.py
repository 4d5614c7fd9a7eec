"""Snapshots of the cable's shape during a run, for animations.

A normal run records scalar outputs only (:meth:`~towcable_fmu.ancf.simulation.Simulation.run`).
:func:`run_with_frames` runs the same simulation in pieces of one frame interval and
takes a snapshot of the geometry (node positions, centreline, ship pose, winch rotation,
rigid load) after each piece. The scalar outputs are those of a single run, at the same
sample times; the values agree to round-off, which contact and the Newton tolerance can
amplify (0.2 N of 4.2 kN after 20 s of the full_scale scene in its sea).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable

import numpy as np

from ..common.errors import SceneError
from .simulation import Simulation
from ..runtime.sampling import output_interval


@dataclasses.dataclass(frozen=True)
class Frames:
    """Geometry of the system at the frame times (inertial frame, SI units).

    Attributes
    ----------
    time
        Frame times [s], shape (k,).
    nodes
        Cable node positions [m], shape (k, nn, 3).
    centreline
        Cable centreline sampled within the elements [m], shape (k, m, 3).

        A cable whose winch adds and removes elements (a spool end) has fewer nodes in
        some frames: their rows repeat the last point (the bottom end) up to the most.
    ship
        Ship pose (x, y, z [m], roll, pitch, yaw [rad]), shape (k, 6).
    winch_phi
        Winch rotation [rad], shape (k,) (0 without a winch).
    load
        Centre of inertia of a rigid load [m], shape (k, 3); ``None`` without a load.
    """

    time: np.ndarray
    nodes: np.ndarray
    centreline: np.ndarray
    ship: np.ndarray
    winch_phi: np.ndarray
    load: np.ndarray | None

    @property
    def interval(self) -> float:
        """Time between frames [s] (the last one may be shorter)."""
        return float(self.time[1] - self.time[0]) if self.time.size > 1 else 0.0


class FrameRecorder:
    """Collects snapshots of one simulation's geometry.

    Parameters
    ----------
    sim
        The simulation to observe.
    points_per_element
        Centreline samples per element (the ANCF shape functions between the nodes).
    """

    def __init__(self, sim: Simulation, points_per_element: int = 4) -> None:
        self.sim = sim
        self.points_per_element = points_per_element
        self._rows: list[tuple] = []

    def capture(self) -> None:
        """Take a snapshot of the current state."""
        sim = self.sim
        t = sim.time
        load = None
        if sim.model.terms.rigid_load.enabled:
            i = sim.model.terms.rigid_load.index
            load = sim.state.q[i:i + 3].copy()
        self._rows.append((t, sim.node_positions(), sim.shape(self.points_per_element)[1],
                           sim.motion.evaluate(t)[0].copy(), float(sim.state.phi[0]), load))

    def frames(self) -> Frames:
        """The snapshots taken so far."""
        t, nodes, line, ship, phi, load = zip(*self._rows)
        return Frames(time=np.array(t), nodes=_padded(nodes), centreline=_padded(line), ship=np.stack(ship),
                      winch_phi=np.array(phi), load=None if load[0] is None else np.stack(load))


def _padded(rows: tuple[np.ndarray, ...]) -> np.ndarray:
    """(n_i, 3) point rows stacked to (k, max n_i, 3), each padded with its last point."""
    most = max(r.shape[0] for r in rows)
    return np.stack([np.concatenate([r, np.repeat(r[-1:], most - r.shape[0], axis=0)]) for r in rows])


def frame_stride(frame_interval: float, interval: float) -> int:
    """Output samples per frame: the frame interval rounded to a multiple of the output
    interval (at least one sample)."""
    if not (math.isfinite(frame_interval) and frame_interval > 0.0):
        raise SceneError("frame_interval", frame_interval, "a finite interval > 0 s")
    return max(1, round(frame_interval / interval))


def run_with_frames(sim: Simulation, duration: float, frame_interval: float, interval: float | None = None,
                    progress: Callable[[float, float], None] | None = None,
                    ) -> tuple[dict[str, np.ndarray], Frames]:
    """Initialise ``sim`` (statics), run it and take a snapshot every frame interval.

    Parameters
    ----------
    sim
        A simulation (it is initialised here).
    duration
        Simulated time [s] (> 0).
    frame_interval
        Time between snapshots [s]; rounded to a multiple of the output interval.
    interval
        Output interval [s]; default: the scene's ``output.interval``.
    progress
        Called as ``progress(t, t_end)`` as in :meth:`Simulation.run`.

    Returns
    -------
    series, frames
        The recorded outputs (as :meth:`Simulation.run` returns them for the same
        duration and interval, see the module notes) and the snapshots, the first at
        the start time.

    Raises
    ------
    SceneError
        If the duration or an interval is not a finite positive number.
    SolverError
        If a step fails.
    """
    dt = output_interval(duration, interval, sim.scene.output.interval)
    frame_dt = frame_stride(frame_interval, dt) * dt
    sim.initialize()
    recorder = FrameRecorder(sim)
    recorder.capture()
    t0 = sim.time
    t_end = t0 + duration
    report = None if progress is None else (lambda t, _: progress(t, t_end))
    pieces = []
    for j in range(max(1, math.ceil(duration / frame_dt - 1e-9))):
        target = t0 + min((j + 1) * frame_dt, duration)
        piece = sim.run(target - sim.time, interval=dt, progress=report)
        pieces.append(piece if j == 0 else {k: v[1:] for k, v in piece.items()})
        recorder.capture()
    series = {k: np.concatenate([p[k] for p in pieces]) for k in pieces[0]}
    return series, recorder.frames()
