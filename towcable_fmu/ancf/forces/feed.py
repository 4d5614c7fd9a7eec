"""Force term: the transport terms of the cable flowing from a spool point.

The elements of the gear (``winch.gear_segments``) and the fed element after them carry
material that moves through them (:mod:`towcable_fmu.ancf.feed`): their inertia gains
``G de/dt + H e`` (Coriolis, transport and feed acceleration).
:func:`~towcable_fmu.ancf.feed.apply_feed` computes the 4x4 factors from the winch state
and the lengths; this term applies them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...kernel_cache import njit
from ...scene.model import Scene
from .. import element
from ..feed import boundary_above, section_boundaries
from ..model import CableModel, Mesh, Motion
from .term import add_element_block

NAME = "feed"
#: The scene tables this term models (absent in a scene: the term is disabled).
TABLES = ("winch",)

#: Gauss points of the transport integrals (their integrands are polynomials of degree <= 7)
GAUSS_POINTS = 5


class Data(NamedTuple):
    """The fed element's material and the state of its feed."""

    enabled: bool
    element: int             #: the fed element (after the gear's elements; its length follows the winch)
    ref: np.ndarray          #: (2,) length L_ref [m] at winch rotation phi_ref [rad] (updated at a remesh)
    radius: float            #: payout radius r_w + d/2 [m]
    length_nom: float        #: nominal element length of the fed element's segment [m]
    boundary: float          #: the fed element's length [m] at which the next section's cable comes in (inf: none)
    mass_per_length: float   #: [kg/m]
    ei: float                #: bending stiffness [N m^2]
    damping: float           #: internal damping coefficient c [N s]
    unit_mass: np.ndarray    #: (4, 4) int h^T h dxi
    unit_bend: np.ndarray    #: (4, 4) int h''^T h'' dxi
    unit_damp: np.ndarray    #: (4, 4) int h'^T h' dxi
    unit_load: np.ndarray    #: (4,) int h dxi
    base_load: np.ndarray    #: (4,) vertical constant loads of the fed element's rows without its own weight [N]
    gauss_x: np.ndarray      #: (k,) points on [0, 1]
    gauss_w: np.ndarray      #: (k,) weights
    gauss_h: np.ndarray      #: (k, 3, 4) h, dh/dxi, d2h/dxi2 there
    transport: np.ndarray    #: (element + 1, 2, 4, 4) G [kg/s...] and H [kg/s^2...] per element at the current winch state


def build(scene: Scene, mesh: Mesh, model: CableModel) -> Data:
    """The feed of a spool end (disabled for any other top end): the fed element is the
    first after the gear's (``winch.gear_segments``); its section is its segment's."""
    enabled = scene.cable.top.type == "spool"
    gear = scene.winch.gear_segments if enabled else 0
    fed = int(np.count_nonzero(mesh.segment_of_element < gear))
    seg = scene.cable.segments[int(mesh.segment_of_element[fed])]
    boundaries = section_boundaries(np.array([s.length for s in scene.cable.segments]), gear)
    x, w = element.gauss_legendre(GAUSS_POINTS)
    h = np.stack([element.shape_functions(x, 1.0), element.shape_derivatives(x, 1.0),
                  element.shape_second_derivatives(x, 1.0)], axis=1)
    length = float(mesh.lengths[fed])
    base = model.f_const[6 * fed + 2:6 * fed + 12:3].copy()
    base += seg.mass_per_length * scene.environment.gravity * element.load_vector(length)
    return Data(enabled=enabled, element=fed,
                ref=np.array([length, float(scene.winch.phi_nom) if enabled else 0.0]),
                radius=scene.winch.radius + 0.5 * seg.diameter if enabled else 0.0,
                length_nom=seg.length / seg.elements, boundary=boundary_above(boundaries, mesh.lengths, fed),
                mass_per_length=seg.mass_per_length, ei=seg.EI,
                damping=seg.damping, unit_mass=element.mass_matrix(1.0, 1.0),
                unit_bend=element.bending_matrix(1.0, 1.0), unit_damp=element.damping_matrix(1.0, 1.0),
                unit_load=element.load_vector(1.0), base_load=base, gauss_x=x, gauss_w=w, gauss_h=h,
                transport=np.zeros((fed + 1, 2, 4, 4)))


@njit(cache=True, inline="always")
def residual(term: Data, model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
             out: np.ndarray) -> None:
    """Add ``(G (x) I3) de/dt + (H (x) I3) e`` to the rows of the gear's and the fed element."""
    for e in range(first, min(stop, term.element + 1)):
        g, h = term.transport[e, 0], term.transport[e, 1]
        base = 6 * e
        for i in range(4):
            for c in range(3):
                acc = 0.0
                for j in range(4):
                    acc += g[i, j] * motion.v[base + 3 * j + c] + h[i, j] * motion.q[base + 3 * j + c]
                out[base + 3 * i + c] += acc


@njit(cache=True, inline="always")
def tangent(term: Data, model: CableModel, motion: Motion, ca: float, cv: float, cq: float,
            ab: np.ndarray) -> None:
    """``cv G + cq H`` over the gear's and the fed element."""
    block = np.zeros((12, 12))
    for e in range(term.element + 1):
        for i in range(4):
            for j in range(4):
                val = cv * term.transport[e, 0, i, j] + cq * term.transport[e, 1, i, j]
                for c in range(3):
                    block[3 * i + c, 3 * j + c] = val
        add_element_block(model, e, block, ab)
