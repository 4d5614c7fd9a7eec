"""The nodal-position cable as the compiled kernels see it, built from a scene.

Nodes run from the top (node 0, prescribed by the ship motion) to the bottom (the last
node, free, carrying the lumped towed body). Coordinates are the nodal positions
``X = (X_0, Y_0, Z_0, X_1, ...)`` [m], three per node. With a rigid towed body
(:mod:`.rigid_body`) the last node is the body's tow point, eliminated: the
coordinates are those of nodes 0 .. n_nodes - 2, then the body's CG [m] and Euler
angles [rad] (:func:`n_coordinates`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..common.errors import SceneError
from ..hydro.loading import LOADINGS
from ..hydro.scene_data import build_body, build_water
from ..hydro.towbody import BodyHydro, no_body
from ..hydro.water import WaterModel
from ..scene.model import Scene
from ..hydro.rigid_body import NDOF, RigidBodyModel, build_rigid_body
from ..runtime.tables import reject_unmodelled


class NodalModel(NamedTuple):
    """Element properties, end conditions, water and body for the kernels."""

    n_nodes: int
    L0: np.ndarray          #: (ne,) unstretched element length [m]
    EA: np.ndarray          #: (ne,) axial stiffness [N]
    BA: np.ndarray          #: (ne,) axial damping c EA of eq. 14-15 [N s]
    tension_only: np.ndarray  #: (ne,) bool: no elastic force in compression
    kelvin_voigt: np.ndarray  #: (ne,) bool: N = EA eps + BA epsdot (else the paper's (L/L0) times it)
    mu: np.ndarray          #: (ne,) mass per unstretched length [kg/m]
    kind: np.ndarray        #: (ne,) loading functions (hydro.loading codes)
    d: np.ndarray           #: (ne,) hydrodynamic diameter [m]
    area: np.ndarray        #: (ne,) pi d^2 / 4 [m^2]
    cd: np.ndarray          #: (ne,) constant C_D, or 0 for C_D(Re)
    g_amp: np.ndarray       #: (ne,) drag amplification G
    cm: np.ndarray          #: (ne,) normal added-mass coefficient C_a
    cdt: np.ndarray         #: (ne,) tangential C_Dt on pi d (loading normal_tangential only)
    gravity: float          #: g [m/s^2]
    water: WaterModel
    body: BodyHydro
    end_mass: float         #: lumped mass at the last node (towed body or bottom mass) [kg]
    top_point: np.ndarray   #: (3,) attachment of node 0 (ship frame or inertial) [m]
    top_on_ship: bool       #: True: top_point moves with the ship
    rigid: RigidBodyModel   #: rigid towed body at the last node (``enabled`` False: none)


def n_coordinates(m: NodalModel) -> int:
    """Length of the coordinate vector: 3 per node, or with a rigid body 3 per node but
    the last, plus the body's 6."""
    return 3 * m.n_nodes + (NDOF - 3 if m.rigid.enabled else 0)


#: The scene tables the nodal-position cable models; any other optional table is refused
#: (:func:`towcable_fmu.runtime.tables.reject_unmodelled`).
TABLES = ("water", "towbody", "towbody.lift", "towbody.rigid", "motion")


def check_scene(scene: Scene) -> None:
    """Reject what the nodal-position formulation does not model.

    Raises
    ------
    SceneError
        Naming the key, its value and what this formulation allows.
    """
    cable = scene.cable
    if cable.top.type != "pinned":
        raise SceneError("cable.top.type", cable.top.type, "'pinned' with formulation = 'nodal_position'")
    if cable.bottom.type != "free":
        raise SceneError("cable.bottom.type", cable.bottom.type, "'free' with formulation = 'nodal_position'")
    if cable.initial.shape == "sag":
        raise SceneError("cable.initial.shape", "sag", "'straight' or 'auto' with formulation = 'nodal_position'")
    reject_unmodelled(scene, TABLES, "nodal_position")
    if scene.solver.adaptive:
        raise SceneError("solver.adaptive", True, "false with formulation = 'nodal_position' (fixed steps)")


def build_nodal_model(scene: Scene) -> NodalModel:
    """Element arrays, water, body and top attachment of a validated scene."""
    check_scene(scene)
    segs = [s for s in scene.cable.segments for _ in range(s.elements)]

    def col(name: str) -> np.ndarray:
        return np.array([getattr(s, name) for s in segs], dtype=float)

    d = col("diameter")
    ne = len(segs)
    top = scene.cable.top
    rigid = build_rigid_body(scene)
    lumped = scene.towbody is not None and not rigid.enabled
    end_mass = scene.cable.bottom.mass + (scene.towbody.mass if lumped else 0.0)
    return NodalModel(
        n_nodes=ne + 1, L0=np.array([s.length / s.elements for s in segs]), EA=col("EA"),
        BA=col("damping"), tension_only=np.array([not s.compression for s in segs]),
        kelvin_voigt=np.array([s.axial_law == "kelvin_voigt" for s in segs]),
        mu=col("mass_per_length"), kind=np.array([LOADINGS[s.loading] for s in segs], dtype=np.int64),
        d=d, area=np.pi * d**2 / 4.0, cd=np.array([s.drag_coefficient or 0.0 for s in segs]),
        g_amp=col("drag_amplification"), cm=col("added_mass_coefficient"),
        cdt=np.array([s.tangential_drag_coefficient or 0.0 for s in segs]),
        gravity=scene.environment.gravity, water=build_water(scene),
        body=build_body(scene, 3 * ne) if lumped else no_body(), end_mass=end_mass,
        top_point=np.array(top.position, dtype=float), top_on_ship=top.frame == "ship", rigid=rigid)
