"""Force term: the transport terms of the cable flowing from a spool point.

The elements of the gear (``winch.gear_segments``) and the fed element after them carry
material that moves through them (:mod:`towcable_fmu.ancf.feed`): their inertia gains
``G de/dt + H e`` (Coriolis, transport and feed acceleration).
:func:`~towcable_fmu.ancf.feed.apply_feed` computes the 4x4 factors from the winch state
and the lengths; this term applies them.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ...common.errors import SceneError, SolverError
from ...jit.kernel_cache import njit
from ...scene.model import Scene
from .. import element
from ..feed import (BOUNDARY_BAND, MERGE_FACTOR, SPLIT_FACTOR, boundary_above, feed_event, fed_length,
                    material_rates, section_boundaries)
from ..model import CableModel, Mesh, Motion
from .hooks import TermHooks
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


class Hooks(TermHooks):
    """A spool end's fed element in a run: its length follows the winch, the mesh it
    reached is part of the state, and it is split or merged when it leaves its band
    (:meth:`handle_event`); the payout it starts from is checked."""

    OUTPUTS = ("winch.deployed",)

    def __init__(self, name: str, scene: Scene, sim: Any) -> None:
        super().__init__(name, scene, sim)
        enabled = bool(self.term.enabled)
        self.MOVES_MESH = enabled
        self.outputs = self.OUTPUTS if enabled else ()
        #: the scene's cable sections (their lengths [m]) and the gear's segment count
        self._segments = scene.cable.segments
        self._gear = scene.winch.gear_segments if enabled else 0
        #: the scene's mesh and its winch rotation [rad] (a run starts from them)
        self._scene_mesh = sim._mesh
        self._phi_nom = float(scene.winch.phi_nom) if enabled else 0.0

    def reset(self) -> None:
        """The winch remeshed the cable in an earlier run: start from the scene's mesh (a
        split asked for by the caller, without a spool end, stays)."""
        if self.term.enabled and self.sim._mesh is not self._scene_mesh:
            self.sim._remodel(self._scene_mesh, self._phi_nom)

    def start(self, phi: float) -> None:
        """A spool end starts on the scene's mesh: its fed element must lie inside the band
        where it is neither split nor merged.

        Raises
        ------
        SceneError
            Naming the initial winch rotation and the payouts the scene can start from.
        """
        feed = self.term
        if not feed.enabled:
            return
        shortest, longest = MERGE_FACTOR * feed.length_nom, SPLIT_FACTOR * feed.length_nom
        if shortest < fed_length.py_func(feed, phi) < longest:  # (in Python: no kernel to compile for it)
            return
        payout = (shortest - feed.ref[0], longest - feed.ref[0])   # from phi_ref = phi_nom
        raise SceneError("winch.phi_sp (initial)", phi,
                         f"a rotation with a payout in ({payout[0]:.6g}, {payout[1]:.6g}) m, "
                         f"phi in ({feed.ref[1] - payout[1] / feed.radius:.6g}, "
                         f"{feed.ref[1] - payout[0] / feed.radius:.6g}) rad: a spool end starts from the scene's "
                         "deployed length (its fed element between "
                         f"{MERGE_FACTOR:g} and {SPLIT_FACTOR:g} nominal lengths); give the scene that length instead")

    def rebuilt(self, model: Any, lengths: np.ndarray, phi_ref: float) -> None:
        feed = getattr(model.terms, self.name)
        feed.ref[:] = (lengths[feed.element], phi_ref)

    def save(self) -> Any:
        """The mesh the run reached (its lengths and segments) and the fed element's reference rotation."""
        feed = self.term
        if not feed.enabled:
            return None
        mesh = self.sim._mesh
        return {"lengths": mesh.lengths.tolist(), "segments": mesh.segment_of_element.tolist(),
                "phi_ref": float(feed.ref[1])}

    def adopt(self, saved: Any) -> None:
        """Rebuild the model for the mesh of a saved state when it is not the current one."""
        feed = self.term
        if saved is None or not feed.enabled:
            return
        lengths = np.asarray(saved["lengths"], dtype=float)
        segments = np.asarray(saved["segments"], dtype=np.int64)
        phi_ref = float(saved["phi_ref"])
        mesh = self.sim._mesh
        if (lengths.shape == mesh.lengths.shape and np.array_equal(lengths, mesh.lengths)
                and np.array_equal(segments, mesh.segment_of_element) and feed.ref[1] == phi_ref):
            return
        self.sim._remodel(Mesh(lengths, segments, np.concatenate([[0.0], np.cumsum(lengths)])), phi_ref)

    def restore(self, saved: Any) -> None:
        self.adopt(saved)

    def new_node_rates(self, element: int, xi: float) -> tuple[np.ndarray, np.ndarray] | None:
        """The fed element gives a new node the material's velocity and acceleration there
        (:func:`~towcable_fmu.ancf.feed.material_rates`): the node is material from then on."""
        feed, st = self.term, self.sim.state
        if not feed.enabled or element != feed.element:
            return None
        u, du = -feed.radius * st.phi[1], -feed.radius * st.phi[2]
        span = slice(6 * element, 6 * element + 12)
        return material_rates(st.q[span], st.v[span], st.a[span], self.sim.mesh.lengths[element], xi, u, du)

    def handle_event(self) -> bool:
        """After a step reported a feed event, remesh the fed element: split it where the
        next section's cable came in (``BOUNDARY_BAND`` nominal lengths past a section
        boundary: the downstream piece keeps its section, the fed element takes the new
        one); split it when it has grown to SPLIT_FACTOR nominal lengths (one nominal
        element downstream, the rest upstream, where the cable comes in); or merge it with
        the next when it has shrunk to MERGE_FACTOR (with the next section's element when
        its own section is all hauled in: the merged element takes the next section, and
        the last piece of the fed one, at most MERGE_FACTOR of a nominal length, with it).
        False if there is no event (the step failed).

        Raises
        ------
        SolverError
            If the winch hauls in the whole cable, or a section whose cable differs from the
            gear's (it cannot pass over drum and sheave).
        """
        sim = self.sim
        if not self.term.enabled or not feed_event(sim.model):
            return False
        feed = self.term
        fed, length, nominal = feed.element, float(sim.model.el_len[feed.element]), feed.length_nom
        mesh = sim.mesh
        if length >= feed.boundary + BOUNDARY_BAND * nominal:
            boundaries = section_boundaries(np.array([seg.length for seg in self._segments]), self._gear)
            upper = int(np.argmin(np.abs(boundaries - (np.sum(mesh.lengths[fed + 1:]) + feed.boundary))))
            # the piece downstream, up to the boundary, keeps its section
            sim._split(fed, (length - feed.boundary) / length, self._gear + upper)
        elif length >= SPLIT_FACTOR * nominal:
            sim._split(fed, (length - nominal) / length)
        elif mesh.n_elements > fed + 1 and mesh.segment_of_element[fed + 1] == mesh.segment_of_element[fed]:
            sim._merge(fed)
        elif mesh.n_elements > fed + 1:
            self._check_passes_the_gear(int(mesh.segment_of_element[fed + 1]))
            sim._merge(fed, across=True)
        else:
            raise SolverError(f"winch.payout = {sim._payout():.6g} m at t = {sim.time:.6g} s "
                              f"hauls in the whole cable: the deployed length cannot go below "
                              f"{float(mesh.node_arc[fed]) + MERGE_FACTOR * nominal:.6g} m (the gear and "
                              f"{MERGE_FACTOR:g} of the last element); limit the winch's set-point")
        return True

    def _check_passes_the_gear(self, segment: int) -> None:
        """A section hauled in passes over drum and sheave on the gear's mesh: its cable must
        be the gear's.

        Raises
        ------
        SolverError
            Naming the first property that differs.
        """
        segments, gear = self._segments, self._gear
        name = segments[segment].cable_difference(segments[gear])
        if name is not None:
            raise SolverError(f"winch.payout = {self.sim._payout():.6g} m at t = {self.sim.time:.6g} s "
                              f"hauls cable.segments[{segment}] onto the drum, but its {name} = "
                              f"{getattr(segments[segment], name)!r} differs from the gear's "
                              f"{getattr(segments[gear], name)!r}: it cannot pass over drum and sheave on "
                              "their mesh; limit the winch's set-point")
