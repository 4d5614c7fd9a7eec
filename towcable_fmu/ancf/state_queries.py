"""What an ANCF simulation tells of its current state beyond the outputs: reactions,
node positions, the centreline, the tension profile; and, answered by the force term that
models them (its hooks, :mod:`towcable_fmu.ancf.forces.hooks`), a rigid towed body's
state (and setting its motion) and the contact along drum and sheave (a part of
:class:`~towcable_fmu.ancf.simulation.Simulation`).

The mixin uses the simulation's ``mesh``, ``model``, ``state``, ``workspace``, ``time``
and ``hooks``.
"""

from __future__ import annotations

from typing import Any, Callable, Iterable

import numpy as np

from . import element, measures
from .system import residual

#: Normalised element positions at which the tension profile is sampled.
PROFILE_XI = np.array([0.0, 0.5, 1.0])


class StateQueries:
    """Reactions, geometry, tension profile, body and contact state of the current state."""

    def reactions(self) -> np.ndarray:
        """Generalised forces the prescribed coordinates exert on the cable (full vector; zero on free rows) [N]."""
        st = self.state
        r = np.zeros_like(st.q)
        residual(self.model, st.q, st.v, st.a, self.time, self.workspace.ship, r)
        r[self.model.free_dofs] = 0.0
        return r

    def node_positions(self) -> np.ndarray:
        """Node positions [m], shape (nn, 3) (a rigid load's point is not a node)."""
        return self._cable_coordinates(self.state.q)[:, 0, :].copy()

    def _cable_coordinates(self, x: np.ndarray) -> np.ndarray:
        """The cable's part of a coordinate vector as (nn, 2, 3): position and slope per node."""
        return x[:6 * self.mesh.n_nodes].reshape(-1, 2, 3)

    def shape(self, points_per_element: int = 8) -> tuple[np.ndarray, np.ndarray]:
        """The cable centreline sampled within the elements (for plots and sag).

        Returns
        -------
        arc, positions
            Unstretched arc length from the top [m], shape (k,), and positions [m], (k, 3).
        """
        xi = np.linspace(0.0, 1.0, points_per_element + 1)[:-1]
        x = self._cable_coordinates(self.state.q).reshape(-1, 6)
        arcs, pts = [], []
        for e, length in enumerate(self.mesh.lengths):
            n = element.shape_functions(xi, length)
            pts.append(n[:, [0]] * x[e, :3] + n[:, [1]] * x[e, 3:] + n[:, [2]] * x[e + 1, :3] + n[:, [3]] * x[e + 1, 3:])
            arcs.append(self.mesh.node_arc[e] + xi * length)
        arcs.append([self.mesh.node_arc[-1]])
        pts.append(x[-1:, :3])
        return np.concatenate(arcs), np.concatenate(pts)

    def tension_profile(self) -> tuple[np.ndarray, np.ndarray]:
        """Tension along the cable at element ends and mid-points.

        Returns
        -------
        arc, tension
            Unstretched arc length from the top [m] and tension [N], shape (3 ne,).
        """
        t = measures.tension_profile(self.model, self.state.q, PROFILE_XI)
        arc = self.mesh.node_arc[:-1, None] + self.mesh.lengths[:, None] * PROFILE_XI[None, :]
        return arc.ravel(), t.ravel()

    def body_state(self) -> dict[str, np.ndarray]:
        """State of a rigid towed body: see :meth:`towcable_fmu.ancf.forces.rigid_link.Hooks.body_state`.

        Raises
        ------
        ValueError
            If the scene has no rigid towed body.
        """
        return self._answer("body_state")()

    def set_body_motion(self, velocity: Iterable[float] | None = None,
                        angular_velocity: Iterable[float] | None = None) -> dict[str, float]:
        """Give an initialised rigid towed body a CG velocity [m/s] (inertial) and an angular
        velocity [rad/s] (body axes): see :meth:`towcable_fmu.ancf.forces.rigid_link.Hooks.set_body_motion`.

        Returns
        -------
        dict
            Outputs in the new state.
        """
        return self._answer("set_body_motion")(velocity, angular_velocity)

    def contact_state(self) -> dict[str, np.ndarray]:
        """Contact at the current time: totals per surface and the force distribution; see
        :meth:`towcable_fmu.ancf.forces.contact.Hooks.contact_state`."""
        return self._answer("contact_state")()

    def _answer(self, query: str) -> Callable[..., Any]:
        """The method ``query`` of the first term's hooks that define it.

        Raises
        ------
        ValueError
            If no term answers it.
        """
        for hooks in self.hooks:
            method = getattr(hooks, query, None)
            if method is not None:
                return method
        raise ValueError(f"no force term of the ANCF cable answers {query}")
