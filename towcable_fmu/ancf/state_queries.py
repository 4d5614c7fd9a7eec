"""What an ANCF simulation tells of its current state beyond the outputs: reactions,
node positions, the centreline, the tension profile, a rigid towed body's state (and
setting its motion), the contact along drum and sheave (a part of
:class:`~towcable_fmu.ancf.simulation.Simulation`).

The mixin uses the simulation's ``mesh``, ``model``, ``state``, ``workspace``, ``time``
and its ``set_coordinates``.
"""

from __future__ import annotations

from typing import Iterable

import numpy as np

from ..hydro.rigid_body import angular_kinematics, tow_point_state
from . import element, measures
from .forces.contact import elements
from .forces.contact_quadrature import new_summary, surface_summary
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
        """State of a rigid towed body (as :meth:`NodalSimulation.body_state
        <towcable_fmu.nodal.simulation.NodalSimulation.body_state>`).

        Returns
        -------
        dict
            ``position`` (CG) [m] and ``velocity`` [m/s] (inertial), ``attitude`` (roll,
            pitch, yaw) [rad], ``rotation`` R (body -> inertial), ``angular_velocity``
            [rad/s] (body axes), ``angular_momentum`` R J w [kg m^2/s] (inertial axes, about
            the CG; J without added inertia), ``tow_point`` [m] and ``cable_force`` [N], the
            force of the cable on the body (the force in the link from the last node to the
            tow point), and ``link_stretch`` [m], the length of that link.

        Raises
        ------
        ValueError
            If the scene has no rigid towed body.
        """
        link, st = self.model.terms.rigid_link, self.state
        if not link.enabled:
            raise ValueError("the scene has no rigid towed body (towbody.model = 'rigid')")
        i = link.index
        p = i - 6
        rot, _, w, _ = angular_kinematics(st.q[i:i + 6], st.v[i:i + 6], st.a[i:i + 6])
        xt, vt, at = np.empty(3), np.empty(3), np.empty(3)
        tow_point_state(link.body, st.q[i:i + 6], st.v[i:i + 6], st.a[i:i + 6], xt, vt, at)
        d = st.q[p:p + 3] - xt
        force = link.k * d + link.c * (st.v[p:p + 3] - vt)
        return {"position": st.q[i:i + 3].copy(), "velocity": st.v[i:i + 3].copy(),
                "attitude": st.q[i + 3:i + 6].copy(), "rotation": rot, "angular_velocity": w,
                "angular_momentum": rot @ (link.body.inertia @ w), "tow_point": xt, "cable_force": force,
                "link_stretch": float(np.linalg.norm(d))}

    def set_body_motion(self, velocity: Iterable[float] | None = None,
                        angular_velocity: Iterable[float] | None = None) -> dict[str, float]:
        """Give an initialised rigid towed body a CG velocity [m/s] (inertial) and an
        angular velocity [rad/s] (body axes), then make the accelerations consistent.
        The cable's last node takes the new velocity of the tow point (the link is not
        set moving); the other nodes keep theirs.

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
        link, st = self.model.terms.rigid_link, self.state
        if not link.enabled or not self._initialized:
            raise ValueError("set_body_motion needs an initialised scene with a rigid towed body")
        i = link.index
        v = st.v.copy()
        if velocity is not None:
            v[i:i + 3] = np.asarray(velocity, dtype=float)
        if angular_velocity is not None:
            _, g, _, _ = angular_kinematics(st.q[i:i + 6], v[i:i + 6], st.a[i:i + 6])
            v[i + 3:i + 6] = np.linalg.solve(g, np.asarray(angular_velocity, dtype=float))
        xt, vt, at = np.empty(3), np.empty(3), np.empty(3)
        tow_point_state(link.body, st.q[i:i + 6], v[i:i + 6], st.a[i:i + 6], xt, vt, at)
        v[i - 6:i - 3] = vt
        return self.set_coordinates(st.q.copy(), v)

    def contact_state(self) -> dict[str, np.ndarray]:
        """Contact at the current time: totals per surface and the force distribution.

        Returns
        -------
        dict
            ``force`` (2, 3) total contact force on the cable of the winch (row 0) and the
            sheave (row 1) [N]; ``span`` (2, 2) smallest and largest angle of a touching
            point, measured about the surface axis from the ship's +Z towards +X [rad];
            ``ends`` (2, 4) element and position of the first and of the last touching point
            along the cable (element -1: no contact); ``lowest`` (2,) lowest height of the cable above its seated position over
            the upper half of each surface [m]; ``distribution`` (k, 3) rows (surface,
            angle [rad], force per unit length [N/m]).
        """
        m = self.model
        out = new_summary(4 * int(m.el_npts.sum()))
        rows = surface_summary(m.terms.contact, elements(m), self.state.q, self.state.v,
                               self.workspace.ship, out)
        return {"force": out.force, "span": out.span, "ends": out.ends, "lowest": out.lowest, "energy": out.energy,
                "distribution": out.dist[:rows]}
