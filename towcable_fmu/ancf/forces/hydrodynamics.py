"""Force term: Morison hydrodynamics on the cable (drag, buoyancy, inertia, added mass).

The loads of :mod:`towcable_fmu.hydro.cable` integrated along each submerged element
(:mod:`.hydro_quadrature`, in waves :mod:`.wave_quadrature`: the water's component
table chooses one at each call, so still water runs the code it ran before waves
existed); the elements of segments with ``fluid_loads = false`` and every element of a
dry scene carry none.
"""

from __future__ import annotations

import numpy as np

from typing import Any

from ...jit.kernel_cache import njit
from ...hydro.loading import LOADINGS
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from . import hydro_quadrature as cable_hydro
from . import wave_quadrature as wave_hydro
from .hooks import TermHooks
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
    npts = np.array([p.integration_points for p in props], dtype=np.int64)
    return CableHydro(
        enabled=wet,
        el_on=np.array([wet and p.fluid_loads for p in props], dtype=bool),
        el_kind=np.array([LOADINGS[p.loading] for p in props], dtype=np.int64),
        el_d=d, el_area=np.pi * d**2 / 4.0,
        el_cd=np.array([p.drag_coefficient or 0.0 for p in props]),
        el_cdt=np.array([p.tangential_drag_coefficient or 0.0 for p in props]),
        el_g=np.array([p.drag_amplification for p in props]),
        el_cm=np.array([p.added_mass_coefficient for p in props]),
        el_npts=npts,
        calls=np.zeros(1, dtype=np.int64),
        **dict(zip(("wave_ref", "wave_stamp", "wave_clock"),
                   wave_hydro.wave_cache(npts.size, int(npts.max(initial=2)), model.water.waves.shape[0] > 0))),
    )


# IR-inlined into the assembly: a kernel of its own would be one more library for the
# assembly to link and optimise again, with all the code beneath it.
@njit(cache=True, inline="always")
def residual(term: CableHydro, model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
             out: np.ndarray) -> None:
    """Subtract the hydrodynamic forces (and add the added-mass inertia) of the elements
    ``first`` to ``stop - 1`` (none while the model's water is disabled)."""
    if not model.water.enabled:
        return
    if model.water.waves.shape[0] == 0:
        cable_hydro.add_residual(model.water, term, model.el_len, motion.q, motion.v, a, motion.t, first, stop,
                                 out)
    else:
        wave_hydro.add_residual(model.water, term, model.el_len, motion.q, motion.v, a, motion.t, first, stop, out)


@njit(cache=True, inline="always")  # (as residual)
def tangent(term: CableHydro, model: CableModel, motion: Motion, ca: float, cv: float, cq: float,
            ab: np.ndarray) -> None:
    """Added mass, drag and waterline-crossing tangents: every element's block from one
    call of the quadrature chosen by the water (as :func:`residual`), then the wet ones added."""
    if not model.water.enabled:
        return
    ne = model.el_len.shape[0]
    blocks = np.empty((ne, 12, 12))
    wet = np.empty(ne, dtype=np.bool_)
    if model.water.waves.shape[0] == 0:
        cable_hydro.add_jacobians(model.water, term, model.el_len, motion.q, motion.v, motion.t, ca, cv, cq, blocks,
                                  wet)
    else:
        wave_hydro.add_jacobians(model.water, term, model.el_len, motion.q, motion.v, motion.t, ca, cv, cq, blocks,
                                 wet)
    for e in range(ne):
        if wet[e]:
            add_element_block(model, e, blocks[e], ab)


class Hooks(TermHooks):
    """The waves' references of a time step (:mod:`.wave_quadrature`) are forgotten when a
    run starts (a run that starts again meets the times of the last one)."""

    def reset(self) -> None:
        """Forget the references (the next residual evaluates the waves afresh)."""
        self.term.wave_clock[0] = np.nan

