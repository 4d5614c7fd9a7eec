"""Force term: Morison hydrodynamics on the cable (drag, buoyancy, inertia, added mass).

The loads of :mod:`towcable_fmu.hydro.cable` integrated along each submerged element
(:mod:`.hydro_quadrature`); the elements of segments with ``fluid_loads = false`` and
every element of a dry scene carry none.
"""

from __future__ import annotations

import numpy as np

from ...kernel_cache import njit
from ...hydro.loading import LOADINGS
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from . import hydro_quadrature as cable_hydro
from .hydro_quadrature import CableHydro
from .term import add_element_block

NAME = "hydrodynamics"
#: The scene tables this term models (absent in a scene: the term is disabled).
TABLES = ("water",)
Data = CableHydro


def build(scene: Scene, mesh: Mesh, model: CableModel) -> CableHydro:
    """Per-element hydrodynamic properties (disabled, every element off, in a dry scene)."""
    wet = bool(model.water.enabled)
    props = [scene.cable.segments[i] for i in mesh.segment_of_element]
    d = np.array([p.diameter for p in props])
    return CableHydro(
        enabled=wet,
        el_on=np.array([wet and p.fluid_loads for p in props], dtype=bool),
        el_kind=np.array([LOADINGS[p.loading] for p in props], dtype=np.int64),
        el_d=d, el_area=np.pi * d**2 / 4.0,
        el_cd=np.array([p.drag_coefficient or 0.0 for p in props]),
        el_cdt=np.array([p.tangential_drag_coefficient or 0.0 for p in props]),
        el_g=np.array([p.drag_amplification for p in props]),
        el_cm=np.array([p.added_mass_coefficient for p in props]),
        el_npts=np.array([p.integration_points for p in props], dtype=np.int64),
        calls=np.zeros(1, dtype=np.int64),
    )


# IR-inlined into the assembly: a kernel of its own would be one more library for the
# assembly to link and optimise again, with all the code beneath it.
@njit(cache=True, inline="always")
def residual(term: CableHydro, model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
             out: np.ndarray) -> None:
    """Subtract the hydrodynamic forces (and add the added-mass inertia) of the elements
    ``first`` to ``stop - 1`` (none while the model's water is disabled)."""
    if model.water.enabled:
        cable_hydro.add_residual(model.water, term, model.el_len, motion.q, motion.v, a, motion.t, first, stop,
                                 out)


@njit(cache=True, inline="always")  # (as residual)
def tangent(term: CableHydro, model: CableModel, motion: Motion, ca: float, cv: float, cq: float,
            ab: np.ndarray) -> None:
    """Added mass, drag and waterline-crossing tangents, element by element."""
    if not model.water.enabled:
        return
    ke = np.empty((12, 12))
    for e in range(model.el_len.shape[0]):
        ke[:, :] = 0.0
        if cable_hydro.add_jacobian(model.water, term, model.el_len, motion.q, motion.v, motion.t, e, ca, cv, cq,
                                    ke):
            add_element_block(model, e, ke, ab)

