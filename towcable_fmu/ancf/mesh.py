"""Build the compiled cable model from a scene: mesh, constant matrices, end conditions.

Everything constant is computed here once (mass, bending and damping matrices,
gravity loads, the map from coordinates to unknowns and the band widths), so the
compiled kernels only do per-step work.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..hydro.scene_data import build_water
from ..hydro.rigid_body import NDOF as RIGID_NDOF
from ..scene.model import End, Scene, Segment
from . import element
from .forces import build_terms
from .forces.rigid_link import RIGID_LINK_FACTOR
from .model import CableModel, Mesh
from .prescribed import FIXED_POINT, FIXED_SLOPE, SHIP_POINT, SHIP_SLOPE, WINCH_POINT

#: Gauss points per element for the axial force (exact for its polynomial integrands).
AXIAL_GAUSS_POINTS = 5


def build_mesh(segments: Sequence[Segment]) -> Mesh:
    """Equal elements within each segment (``cable.segments``: length [m], elements), segments
    from the top end down."""
    lengths, seg = [], []
    for i, s in enumerate(segments):
        lengths += [s.length / s.elements] * s.elements
        seg += [i] * s.elements
    lengths_arr = np.array(lengths)
    return Mesh(lengths_arr, np.array(seg, dtype=np.int64), np.concatenate([[0.0], np.cumsum(lengths_arr)]))


def _attachments(end: End, node: int, sign: float, winch_center: np.ndarray | None = None
                 ) -> list[tuple[int, int, np.ndarray]]:
    """(first coordinate, kind, vector) triples of one end condition."""
    out: list[tuple[int, int, np.ndarray]] = []
    if end.type == "free":
        return out
    if end.type == "winch":
        return [(6 * node, WINCH_POINT, winch_center)]
    # a spool end is a point like a pinned one; the winch feeds the first element (ancf/feed.py)
    ship = end.frame == "ship"
    out.append((6 * node, SHIP_POINT if ship else FIXED_POINT, np.array(end.position, dtype=float)))
    if end.type == "clamped":
        direction = np.array(end.slope, dtype=float)
        direction = sign * direction / np.linalg.norm(direction)
        out.append((6 * node + 3, SHIP_SLOPE if ship else FIXED_SLOPE, direction))
    return out


def _band_width(free_idx: np.ndarray, n_elements: int, rigid: bool = False) -> int:
    width = 6 if free_idx.size % 6 else 0  # a rigid load couples the last node with 3 extra coordinates
    if rigid:  # a rigid body's 6 coordinates couple with the last node's position
        last = 6 * n_elements
        width = int(free_idx[-1] - free_idx[last])
    for e in range(n_elements):
        idx = free_idx[6 * e: 6 * e + 12]
        idx = idx[idx >= 0]
        if idx.size:
            width = max(width, int(idx.max() - idx.min()))
    return width


def build_model(scene: Scene, mesh: Mesh) -> CableModel:
    """Compile-ready arrays for ``scene`` meshed as ``mesh``."""
    segs = scene.cable.segments
    ne, nn = mesh.n_elements, mesh.n_nodes
    rigid = scene.load
    rigid_body = scene.towbody is not None and scene.towbody.model == "rigid"  # six coordinates of its own
    nf = 6 * nn + (3 if rigid is not None else 0) + (RIGID_NDOF if rigid_body else 0)
    g = scene.environment.gravity
    el_len = mesh.lengths.copy()
    props = [segs[i] for i in mesh.segment_of_element]
    el_ea = np.array([p.EA for p in props])
    el_tension_only = np.array([not p.compression for p in props])
    el_engineering = np.array([p.axial_law == "kelvin_voigt" for p in props])
    el_mass = np.stack([element.mass_matrix(L, p.mass_per_length) for L, p in zip(el_len, props)])
    el_bend = np.stack([element.bending_matrix(L, p.EI) for L, p in zip(el_len, props)])
    el_damp = np.stack([element.damping_matrix(L, p.damping) for L, p in zip(el_len, props)])

    f_const = np.zeros(nf)
    for e, (L, p) in enumerate(zip(el_len, props)):
        load = element.load_vector(L) * (-p.mass_per_length * g)
        for i in range(4):
            f_const[6 * e + 3 * i + 2] += load[i]
    node_mass = np.zeros((nn, 3))
    node_mass[0, :] += scene.cable.top.mass
    node_mass[-1, :] += scene.cable.bottom.mass
    if scene.towbody is not None and not rigid_body:
        node_mass[-1, :] += scene.towbody.mass
    f_const[2:6 * nn:6] -= node_mass[:, 2] * g
    if rigid is not None:
        kappa = rigid.length_pg / rigid.length_pi
        f_const[6 * (nn - 1) + 2] -= rigid.mass * g * (1.0 - kappa)  # weight at G, shared by P and I
        f_const[6 * nn + 2] -= rigid.mass * g * kappa

    winch_center = None if scene.winch is None else np.array(scene.winch.position, dtype=float)
    att = _attachments(scene.cable.top, 0, 1.0, winch_center) + _attachments(scene.cable.bottom, nn - 1, -1.0)
    prescribed = np.zeros(nf, dtype=bool)
    for i0, _, _ in att:
        prescribed[i0:i0 + 3] = True
    free_dofs = np.flatnonzero(~prescribed)
    free_idx = np.full(nf, -1, dtype=np.int64)
    free_idx[free_dofs] = np.arange(free_dofs.size)
    width = _band_width(free_idx, ne, rigid_body)
    node_length = np.minimum(np.concatenate([el_len[:1], el_len]), np.concatenate([el_len, el_len[-1:]]))
    node_length = np.append(node_length, node_length[-1])  # the load's point I scales like the last node
    scale = np.where(free_dofs % 6 < 3, 1.0 / node_length[np.minimum(free_dofs // 6, nn)], 1.0)
    if rigid_body:
        # Newton's corrections of the link's ends, measured by the force they make in the
        # link (k dq against EA newton_tol, as for the elements): the last node's position
        # and the CG RIGID_LINK_FACTOR times stricter, the angles by the tow point's arm
        arm = float(np.linalg.norm(scene.towbody.rigid.tow_point))
        ends = (free_dofs >= 6 * (nn - 1)) & (free_dofs % 6 < 3)     # last node's position, body's CG
        scale[ends] = RIGID_LINK_FACTOR / el_len[-1]
        scale[free_dofs >= 6 * nn + 3] = max(1.0, RIGID_LINK_FACTOR * arm / el_len[-1])   # body's angles

    gx, gw = element.gauss_legendre(AXIAL_GAUSS_POINTS)
    model = CableModel(
        el_len=el_len, el_ea=el_ea, el_tension_only=el_tension_only, el_engineering=el_engineering,
        el_mass=el_mass, el_bend=el_bend,
        el_damp=el_damp, el_d=np.array([p.diameter for p in props]),
        el_npts=np.array([p.integration_points for p in props], dtype=np.int64),
        f_const=f_const, node_mass=node_mass,
        gauss_dn=element.shape_derivatives(gx, 1.0), gauss_w=gw,
        free_idx=free_idx, free_dofs=free_dofs.astype(np.int64), free_scale=scale, kl=width, ku=width,
        att_index=np.array([a[0] for a in att], dtype=np.int64),
        att_kind=np.array([a[1] for a in att], dtype=np.int64),
        att_vec=np.array([a[2] for a in att], dtype=float).reshape(-1, 3),
        att_radius=np.array([winch_radius(scene) if kind == WINCH_POINT else 0.0 for _, kind, _ in att]),
        water=build_water(scene), gravity=g, terms=(), el_taut=np.zeros((2, ne), dtype=np.int64),
    )
    return model._replace(terms=build_terms(scene, mesh, model))


def winch_radius(scene: Scene) -> float:
    """Radius at which the cable centreline wraps the drum: r_w + d/2 of the first segment [m].

    W(120) places the cable end at r_w; the contact surface for the centreline is offset
    by the cable radius (W(98)), so we fix the end there too: the end then rests on the
    drum instead of inside it, and the payout per radian of winch rotation is r_w + d/2.
    """
    return scene.winch.radius + 0.5 * scene.cable.segments[0].diameter
