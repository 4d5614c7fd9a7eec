"""Force term: contact of the cable with the winch drum and the sheave (and its idlers).

Penalty contact of the cable's surface with the faces of each surface (a cylinder, or
a grooved sheave's two walls and rim), integrated along each element
(:mod:`towcable_fmu.ancf.forces.contact_quadrature`); the surfaces move with the ship.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...jit.kernel_cache import njit
from . import contact_quadrature as cable_contact
from .contact_quadrature import new_summary, surface_summary
from ...contact.surfaces import CYLINDER, RIM, SHEAVE, WALL_MINUS, WALL_PLUS, WINCH, ContactModel, no_contact
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from .hooks import TermHooks
from .term import add_element_block

NAME = "contact"
#: The scene tables this term models (absent in a scene: the term is disabled).
TABLES = ("winch", "sheave")
Data = ContactModel


def build(scene: Scene, mesh: Mesh, model: CableModel) -> ContactModel:
    """Contact faces of the drum and the sheave (disabled when the scene has neither)."""
    return build_contact(scene)


def build_contact(scene: Scene) -> ContactModel:
    """The faces of the drum, the sheave and its idlers as the kernels read them."""
    faces = []  # (surface, kind, centre, radius, depth, cos, sin, opening, rim width, law)
    if scene.winch is not None:
        w = scene.winch
        faces.append((WINCH, CYLINDER, w.position, w.radius, 0.0, 1.0, 0.0, 0.0, 0.0, w.contact))
    # the sheave, then each idler as a surface of its own (ids 2, 3, ...: its own reach test;
    # the outputs summarise the winch and the sheave only)
    sheaves = [] if scene.sheave is None else [scene.sheave, *scene.idlers]
    for surface, sh in enumerate(sheaves, start=SHEAVE):
        if sh.shape == "cylinder":
            faces.append((surface, CYLINDER, sh.position, sh.radius, 0.0, 1.0, 0.0, 0.0, 0.0, sh.contact))
        else:
            half = np.radians(sh.throat_angle) / 2.0
            opening = sh.groove_depth * np.tan(half)
            for kind in (WALL_PLUS, WALL_MINUS, RIM):
                faces.append((surface, kind, sh.position, sh.radius, sh.groove_depth, np.cos(half), np.sin(half),
                              opening, sh.rim_width, sh.contact))
    if not faces:
        return no_contact()

    def column(k: int) -> np.ndarray:
        return np.array([f[k] for f in faces], dtype=float)

    return ContactModel(
        True, np.array([f[0] for f in faces], dtype=np.int64), np.array([f[1] for f in faces], dtype=np.int64),
        column(2), column(3), column(4), column(5), column(6), column(7), column(8),
        np.array([f[9].stiffness for f in faces]), np.array([f[9].exponent for f in faces]),
        np.array([f[9].damping for f in faces]), np.zeros(1, dtype=np.int64))


@njit(cache=True, inline="always")
def elements(model: CableModel) -> cable_contact.Elements:
    """The cable's elements as the contact kernels read them."""
    return cable_contact.Elements(model.el_len, model.el_d, model.el_npts)


# IR-inlined into the assembly: a kernel of its own would be one more library for the
# assembly to link and optimise again, with all the code beneath it.
@njit(cache=True, inline="always")
def residual(term: ContactModel, model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
             out: np.ndarray) -> None:
    """Subtract the contact forces of the elements ``first`` to ``stop - 1``."""
    cable_contact.add_residual(term, elements(model), motion.q, motion.v, motion.ship, first, stop, out)


@njit(cache=True, inline="always")  # (as residual)
def tangent(term: ContactModel, model: CableModel, motion: Motion, ca: float, cv: float, cq: float,
            ab: np.ndarray) -> None:
    """The contact part of ``cv C + cq K``: a 12x12 block per element a face acts on
    (:func:`~towcable_fmu.ancf.forces.contact_quadrature.add_jacobian`)."""
    ne = model.el_len.shape[0]
    blocks = np.empty((ne, 12, 12))
    touched = np.empty(ne, dtype=np.bool_)
    cable_contact.add_jacobian(term, elements(model), motion.q, motion.v, motion.ship, cv, cq, blocks, touched)
    for e in range(ne):
        if touched[e]:
            add_element_block(model, e, blocks[e], ab)


class Hooks(TermHooks):
    """The contact outputs (in the compiled output kernel), the contact state (the
    simulation's ``contact_state``) and the cable wound on the drum."""

    OUTPUTS = ("contact.winch_force", "contact.sheave_force", "energy.contact", "tension.winch", "sheave_angle",
               "tension.sheave", "contact.wrap_angle", "contact.detached")

    def __init__(self, name: str, scene: Scene, sim: Any) -> None:
        super().__init__(name, scene, sim)
        self._winch = scene.winch is not None and self.term.enabled
        if self.term.enabled:
            winch, sheave = scene.winch is not None, scene.sheave is not None
            self.outputs = (self.OUTPUTS[:3] + (self.OUTPUTS[3:4] if winch else ())
                            + (self.OUTPUTS[4:5] if winch or sheave else ()) + (self.OUTPUTS[5:] if sheave else ()))

    def wound_length(self) -> float | None:
        """The unstretched cable from its end to where it leaves the drum [m] (None: no drum contact)."""
        if not self._winch:
            return None
        ends = self.contact_state()["ends"]
        e = int(ends[WINCH, 2])
        mesh = self.sim.mesh
        return 0.0 if e < 0 else float(mesh.node_arc[e] + ends[WINCH, 3] * mesh.lengths[e])

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
        m, st = self.sim.model, self.sim.state
        out = new_summary(4 * int(m.el_npts.sum()))
        rows = surface_summary(self.term, elements(m), st.q, st.v, self.sim.workspace.ship, out)
        return {"force": out.force, "span": out.span, "ends": out.ends, "lowest": out.lowest, "energy": out.energy,
                "distribution": out.dist[:rows]}
