"""Force term: a rigid load hanging from the cable's last node, W(138)-(139).

The load's point P is the last node; its centre of inertia I has three coordinates of
its own (``index``, after the cable's). Its mass matrix W(138) couples P and I; a stiff
link of rest length L_PI joins them, W(139). The load's weight is in the model's
constant load (``f_const``, see :func:`towcable_fmu.ancf.mesh.build_model`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...kernel_cache import njit
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
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

