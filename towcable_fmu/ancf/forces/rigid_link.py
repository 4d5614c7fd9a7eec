"""Force term: a rigid 6-DOF towed body and the link that hangs it from the cable's last node.

The body's six coordinates (CG [m], roll, pitch, yaw [rad]) follow the cable's
(``index``); its equations are those of :mod:`towcable_fmu.hydro.rigid_body`. It hangs from the
last node by a stiff spring-damper to its tow point (the ANCF node keeps its slope
coordinates free: the joint is spherical).
"""

from __future__ import annotations

import math
from typing import Any, Iterable, NamedTuple

import numpy as np

from ...jit.kernel_cache import njit
from ...hydro.rigid_body import (RigidBodyModel, angular_kinematics, attitude_ok, body_residual, build_rigid_body,
                                 tow_point_state)
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from .hooks import TermHooks
from .term import add_block

NAME = "rigid_link"
#: The scene tables this term models (absent in a scene: the term is disabled).
TABLES = ("towbody.rigid",)

#: Stiffness of the link between the cable's last node and a rigid body's tow point, as
#: a multiple of the axial stiffness EA/L of the last element [-]. The link then stretches
#: 1/100 as much as that element under the same force (T/k; 5e-9 m in the free-decay
#: test, 0.5 mm at the 30 kN of the sea-trial body); tests/test_rigid_towbody.py shows
#: the results do not move beyond their tolerances when the factor changes tenfold
#: either way. The link mode (the last node's mass on k) lies far above any resolved
#: frequency; the implicit integrator damps it numerically, and a damper
#: c = 2 sqrt(k m_N) (critical for that node's mass m_N) damps it physically. Newton
#: measures the corrections at the link's ends by the force they make in it (the
#: ``free_scale`` of :func:`towcable_fmu.ancf.mesh.build_model`). A stiffer link would
#: raise the round-off floor of the residual (k eps |X|) towards the statics tolerance on
#: short, stiff cables.
RIGID_LINK_FACTOR = 100.0


class Data(NamedTuple):
    """The rigid body and its link for the kernels."""

    enabled: bool
    body: RigidBodyModel  #: the body (see towcable_fmu/hydro/rigid_body.py)
    index: int            #: first of the body's six coordinates (CG [m], roll, pitch, yaw [rad])
    k: float              #: stiffness of the link last node - tow point [N/m]
    c: float              #: damping of that link [N s/m]


def build(scene: Scene, mesh: Mesh, model: CableModel) -> Data:
    """The scene's rigid towed body (disabled unless ``towbody.model == "rigid"``)."""
    body = build_rigid_body(scene)
    k = RIGID_LINK_FACTOR * model.el_ea[-1] / model.el_len[-1]
    c = 2.0 * np.sqrt(k * (model.el_mass[-1, 2, 2] + model.node_mass[-1, 0]))
    return Data(bool(body.enabled), body, 6 * mesh.n_nodes, float(k), float(c))


@njit(cache=True)
def link_rows(term: Data, model: CableModel, zq: np.ndarray, zv: np.ndarray, za: np.ndarray, t: float,
              rows: np.ndarray) -> None:
    """The residual rows of the body and its link to the cable end.

    Parameters
    ----------
    term, model
        The body and the cable system.
    zq, zv, za
        Local coordinates, rates and accelerations (9 each): the last node's position
        [m], then the body's CG [m] and roll, pitch, yaw [rad].
    t
        Time [s].
    rows
        Output (9,): the link force on the last node's position rows [N], then the six
        body residuals of :func:`~towcable_fmu.hydro.rigid_body.body_residual` [N, N m].

    Notes
    -----
    The link is a stiff spring-damper between the last node X_N and the tow point
    p = r + R p_b: the cable end feels ``-f``, the body ``+f`` at its tow point, with
    ``f = k (X_N - p) + c (V_N - dp/dt)``. ``body_residual`` takes the force the body
    exerts on the cable end, ``-f``.
    """
    xt = np.empty(3)
    vt = np.empty(3)
    at = np.empty(3)
    tow_point_state(term.body, zq[3:9], zv[3:9], za[3:9], xt, vt, at)
    f = np.empty(3)
    for c in range(3):
        f[c] = term.k * (zq[c] - xt[c]) + term.c * (zv[c] - vt[c])
        rows[c] = f[c]
    body_residual(model.water, term.body, model.gravity, zq[3:9], zv[3:9], za[3:9], t, -f, rows[3:9])


@njit(cache=True, inline="always")
def _coords(term: Data) -> np.ndarray:
    """The 9 local coordinates: the last node's position, then the body's six."""
    coords = np.empty(9, dtype=np.int64)
    for c in range(3):
        coords[c] = term.index - 6 + c
    for c in range(6):
        coords[3 + c] = term.index + c
    return coords


@njit(cache=True, inline="always")
def _gather(x: np.ndarray, coords: np.ndarray, z: np.ndarray) -> None:
    for k in range(coords.shape[0]):
        z[k] = x[coords[k]]


# IR-inlined into its only caller: a kernel of its own would be one more library for the
# caller to link and optimise again, with all the code beneath it.
@njit(cache=True, inline="always")
def residual(term: Data, model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
             out: np.ndarray) -> None:
    """Add the body's rows and its link force on the last node to ``out``."""
    if stop != model.el_len.shape[0]:
        return
    coords = _coords(term)
    zq, zv, za, rows = np.empty(9), np.empty(9), np.empty(9), np.empty(9)
    _gather(motion.q, coords, zq)
    _gather(motion.v, coords, zv)
    _gather(a, coords, za)
    link_rows(term, model, zq, zv, za, motion.t, rows)
    if not attitude_ok(zq[3:9]) or abs(zq[7]) > 0.5 * np.pi:
        # Euler angles singular (pitch +-pi/2): no residual, the step fails (the nodal
        # cable's integrators stop there too; Simulation names the cause)
        rows[:] = np.nan
    for k in range(9):
        out[coords[k]] += rows[k]


@njit(cache=True, inline="always")  # (as residual)
def block(term: Data, model: CableModel, motion: Motion, ca: float, cv: float, cq: float) -> np.ndarray:
    """``ca M + cv C + cq K`` of the body and its link over the 9 local coordinates.

    The body's equations are nonlinear in its angles and in the relative flow; their
    derivatives are taken by differences of :func:`link_rows` (central for q and v,
    one-sided for a, in which the rows are linear), at zero acceleration: the change of
    the inertia forces with the attitude (terms in the body's acceleration) is left
    out, as modified Newton allows. Rows and columns: the last node's position, then the
    body's coordinates.
    """
    coords = _coords(term)
    zq, zv, za = np.empty(9), np.empty(9), np.zeros(9)
    _gather(motion.q, coords, zq)
    _gather(motion.v, coords, zv)
    r0, rp, rm = np.empty(9), np.empty(9), np.empty(9)
    out = np.zeros((9, 9))
    t = motion.t
    link_rows(term, model, zq, zv, za, t, r0)
    for j in range(9):
        if ca != 0.0:
            za[j] = 1.0
            link_rows(term, model, zq, zv, za, t, rp)
            za[j] = 0.0
            for r in range(9):
                out[r, j] += ca * (rp[r] - r0[r])
        for kind in range(2):
            weight = cq if kind == 0 else cv
            if weight == 0.0:
                continue
            z = zq if kind == 0 else zv
            keep = z[j]
            h = 1e-6 * max(1.0, abs(keep))
            z[j] = keep + h
            link_rows(term, model, zq, zv, za, t, rp)
            z[j] = keep - h
            link_rows(term, model, zq, zv, za, t, rm)
            z[j] = keep
            for r in range(9):
                out[r, j] += weight * (rp[r] - rm[r]) / (2.0 * h)
    return out


@njit(cache=True, inline="always")  # (as residual)
def tangent(term: Data, model: CableModel, motion: Motion, ca: float, cv: float, cq: float,
            ab: np.ndarray) -> None:
    """Add :func:`block` to the band storage ``ab``."""
    add_block(model, _coords(term), block(term, model, motion, ca, cv, cq), ab)



class Hooks(TermHooks):
    """The body's outputs (in the compiled output kernel), its state and motion (the
    simulation's ``body_state`` and ``set_body_motion``), a hint when a step fails."""

    OUTPUTS = ("tension.towbody", "towbody.x", "towbody.y", "towbody.z", "towbody.vx", "towbody.vy", "towbody.vz",
               "towbody.roll", "towbody.pitch", "towbody.yaw")

    def __init__(self, name: str, scene: Scene, sim: Any) -> None:
        super().__init__(name, scene, sim)
        self.outputs = self.OUTPUTS if self.term.enabled else ()

    def failure_hint(self) -> str:
        """The body's pitch, when near the singularity of its Euler angles."""
        if not self.term.enabled:
            return ""
        pitch = float(self.sim.state.q[self.term.index + 4])
        return (f"; the rigid body's pitch is {pitch:.4g} rad, its Euler angles are singular at +-pi/2"
                if abs(math.cos(pitch)) < 0.1 else "")

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
        link, st = self.term, self.sim.state
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
        link, st = self.term, self.sim.state
        if not link.enabled or not self.sim._initialized:
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
        return self.sim.set_coordinates(st.q.copy(), v)
