"""Force term: a rigid load hanging from the cable's last node, W(138)-(139).

The load's point P is the last node; its centre of inertia I has three coordinates of
its own (``index``, after the cable's). Its mass matrix W(138) couples P and I; a stiff
link of rest length L_PI joins them, W(139). The load's weight is in the model's
constant load (``f_const``, see :func:`towcable_fmu.ancf.mesh.build_model`).
"""

from __future__ import annotations

import functools
from typing import Any, NamedTuple

import numpy as np

from ...jit.kernel_cache import njit
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from .hooks import TermHooks
from .term import add_block

NAME = "rigid_load"
#: The scene tables this term models (absent in a scene: the term is disabled).
TABLES = ("load",)


class Data(NamedTuple):
    """The rigid load for the kernels."""

    enabled: bool
    index: int           #: first coordinate of the load's centre of inertia I
    mass: np.ndarray     #: (3,) entries m_PP, m_PI, m_II of the load mass matrix W(138) [kg]
    k: float             #: k_L, stiffness of the link P-I [N]
    length: float        #: L_PI, rest length of the link [m]


def build(scene: Scene, mesh: Mesh, model: CableModel) -> Data:
    """The scene's ``[load]`` (disabled without one)."""
    load = scene.load
    if load is None:
        return Data(False, 0, np.zeros(3), 0.0, 1.0)
    kappa = load.length_pg / load.length_pi
    mass = np.array([2.0 * load.mass * (1.0 - kappa), load.mass * (kappa - 1.0), load.mass])
    return Data(True, 6 * mesh.n_nodes, mass, float(load.stiffness), float(load.length_pi))


@njit(cache=True, inline="always")
def _link(term: Data, q: np.ndarray) -> tuple:
    """Separation d = r_P - r_I, its length and the link strain."""
    i = term.index
    p = i - 6
    dx, dy, dz = q[p] - q[i], q[p + 1] - q[i + 1], q[p + 2] - q[i + 2]
    length = np.sqrt(dx * dx + dy * dy + dz * dz)
    return dx, dy, dz, length, (length - term.length) / term.length


@njit(cache=True, inline="always")
def residual(term: Data, model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
             out: np.ndarray) -> None:
    """Inertia W(138) and link force W(139) (P = last node, I = the load's point)."""
    if stop != model.el_len.shape[0]:
        return
    i = term.index
    p = i - 6
    m_pp, m_pi, m_ii = term.mass[0], term.mass[1], term.mass[2]
    dx, dy, dz, _, eps = _link(term, motion.q)
    k = term.k * eps
    for c, dc in enumerate((dx, dy, dz)):
        out[p + c] += m_pp * a[p + c] + m_pi * a[i + c] + k * dc
        out[i + c] += m_pi * a[p + c] + m_ii * a[i + c] - k * dc


@njit(cache=True, inline="always")
def tangent(term: Data, model: CableModel, motion: Motion, ca: float, cv: float, cq: float,
            ab: np.ndarray) -> None:
    """Mass and link stiffness over P and I (exact)."""
    i = term.index
    p = i - 6
    dx, dy, dz, length, eps = _link(term, motion.q)
    d = (dx, dy, dz)
    block = np.zeros((6, 6))
    mass = term.mass
    coords = np.empty(6, dtype=np.int64)
    for r in range(3):
        coords[r] = p + r
        coords[3 + r] = i + r
        block[r, r] += ca * mass[0]
        block[r, 3 + r] += ca * mass[1]
        block[3 + r, r] += ca * mass[1]
        block[3 + r, 3 + r] += ca * mass[2]
        for c in range(3):
            kk = cq * term.k * ((eps if r == c else 0.0) + d[r] * d[c] / (term.length * length))
            block[r, c] += kk
            block[r, 3 + c] -= kk
            block[3 + r, c] -= kk
            block[3 + r, 3 + c] += kk
    add_block(model, coords, block, ab)



def held_load_forces(scene: Scene, model: CableModel) -> np.ndarray:
    """The constant loads with a rigid load held at rest along the cable's initial direction.

    A load released at rest on a taut rope (Westin 2018, section 4.1) pulls at the moment
    of release with the component of its weight along the rope, ``m_L g . e`` (the rope
    and the load move as one pendulum then, with no speed and so no centripetal part);
    the holder carried the rest. Holding the load so is a static equilibrium: the weight
    at G less its component normal to ``e`` (shared by P and I as the weight is,
    W(138)). The statics with these loads start the run from the tension the load pulls
    with as it is let go.

    Parameters
    ----------
    scene
        A scene with a rigid ``[load]``; ``e`` is ``cable.initial.direction`` (inertial).
    model
        Its compiled model.

    Returns
    -------
    numpy.ndarray
        ``model.f_const`` with the holder's force added [N].
    """
    load = scene.load
    e = np.asarray(scene.cable.initial.direction, dtype=float)
    e = e / np.linalg.norm(e)
    weight = np.array([0.0, 0.0, -load.mass * scene.environment.gravity])
    hold = -(weight - (weight @ e) * e)  # the holder takes the weight's component normal to the rope
    kappa = load.length_pg / load.length_pi
    forces = model.f_const.copy()
    p, i = model.terms.rigid_load.index - 6, model.terms.rigid_load.index
    forces[p:p + 3] += (1.0 - kappa) * hold
    forces[i:i + 3] += kappa * hold
    return forces


class Hooks(TermHooks):
    """The load's outputs, computed in Python from the state, and the load held at rest in
    the statics (``load.held``)."""

    OUTPUTS = ("tension.load", "load.angle", "energy.load")

    def __init__(self, name: str, scene: Scene, sim: Any) -> None:
        super().__init__(name, scene, sim)
        self.outputs = self.OUTPUTS if scene.load is not None else ()
        #: the holder's loads for a model (a load held at rest until the run starts; None: not held)
        self._held = functools.partial(held_load_forces, scene) if scene.load is not None and scene.load.held else None

    def statics_loads(self, model: CableModel) -> np.ndarray | None:
        """The constant loads with the load held along the cable's initial direction
        (:func:`held_load_forces`), let go when the run starts."""
        return None if self._held is None else self._held(model)

    def values(self) -> list[float]:
        """Force the cable exerts on the load [N], its swing angle [rad] and its energy
        (kinetic and link strain) [J]."""
        load_term, st = self.term, self.sim.state
        i = load_term.index
        p = i - 6
        # the load's own equations summed over P and I: the link forces cancel, what remains
        # is the cable's pull = sum of (mass matrix x acceleration) minus the load's weight
        # (the load's mass m_L is the entry m_II of its mass matrix, W(138))
        pull = ((load_term.mass[0] + load_term.mass[1]) * st.a[p:p + 3] + (load_term.mass[1] + load_term.mass[2]) * st.a[i:i + 3])
        pull[2] += load_term.mass[2] * self.sim.model.gravity
        d = st.q[i:i + 3] - st.q[p:p + 3]
        vp, vi = st.v[p:p + 3], st.v[i:i + 3]
        kinetic = 0.5 * (load_term.mass[0] * vp @ vp + 2.0 * load_term.mass[1] * vp @ vi + load_term.mass[2] * vi @ vi)
        length, rest = float(np.linalg.norm(d)), load_term.length
        # the link force k (l - L)/L d of W(139) is central: its potential is a function of l alone
        link = load_term.k / rest * ((length**3 - rest**3) / 3.0 - rest * (length**2 - rest**2) / 2.0)
        return [float(np.linalg.norm(pull)), float(np.arctan2(d[0], -d[2])), float(kinetic + link)]
