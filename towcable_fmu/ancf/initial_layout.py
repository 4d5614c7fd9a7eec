"""Where the ANCF cable starts: what the initial shape needs of a scene, read once, and the
rough initial coordinates it gives (handed to the statics).

:func:`layout_from_scene` picks the pieces when the simulation is built;
:func:`initial_coordinates` lays the cable out from them at initialisation: wrapped on the
winch and over the sheave, draped over the sheave (and its idlers), straight, or sagging
between two prescribed ends; then a rigid load along the cable's end, or a rigid towed body
at its initial attitude with its tow point on the last node.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..numerics.kinematics import rotation_matrix
from ..hydro.rigid_body import hanging_coordinates
from ..scene.model import Scene
from . import initial_shape
from .mesh import winch_radius
from .model import CableModel, Mesh
from .prescribed import apply_prescribed


class InitialLayout(NamedTuple):
    """What the initial shape needs of a scene (lengths [m], directions unit-free)."""

    top_type: str                   #: ``cable.top.type``
    top_start: np.ndarray | None    #: (3,) where a free top end starts (inertial) [m]; None: at the origin
    bottom_free: bool               #: the bottom end is free
    shape: str                      #: ``cable.initial.shape``: auto, straight or sag
    direction: np.ndarray           #: (3,) ``cable.initial.direction`` (inertial)
    sag_direction: np.ndarray       #: (3,) ``cable.initial.sag_direction``
    winch_center: np.ndarray        #: (3,) drum centre (ship frame) [m]; zeros without a winch
    winch_radius: float             #: centreline wrap radius r_w + d/2 [m]
    #: a spool end on the drum's centreline circle (ship frame, within SPOOL_ON_DRUM): its
    #: angle from the top towards +X in [0, 2 pi) [rad], the cable laid out wrapped from
    #: there with decreasing angle as from a winch end; else None
    spool_angle: float | None
    pulley_centers: np.ndarray      #: (k, 3) sheave then idlers (ship frame) [m]; k = 0 without a sheave
    pulley_radii: np.ndarray        #: (k,) centreline radii over them [m]
    load_length: float              #: a rigid load's link length L_PI [m] (0: no load)
    body_attitude: np.ndarray       #: (3,) a rigid towed body's initial roll, pitch, yaw [rad]


#: distance [m] within which a spool end counts as lying on the drum (the layout wraps from it)
SPOOL_ON_DRUM = 1e-3


def _spool_angle(scene: Scene) -> float | None:
    """The angle of a spool end on the drum (see :attr:`InitialLayout.spool_angle`)."""
    if scene.cable.top.type != "spool" or scene.cable.top.frame != "ship":
        return None
    offset = np.array(scene.cable.top.position, dtype=float) - np.array(scene.winch.position, dtype=float)
    if abs(np.hypot(offset[0], offset[2]) - winch_radius(scene)) > SPOOL_ON_DRUM:
        return None
    return float(np.arctan2(offset[0], offset[2]) % (2.0 * np.pi))  # as phi_nom: in [0, 2 pi)


def layout_from_scene(scene: Scene) -> InitialLayout:
    """The pieces of ``scene`` the initial shape uses."""
    cable = scene.cable
    half_d = 0.5 * cable.segments[0].diameter
    pulleys = [] if scene.sheave is None else [scene.sheave, *scene.idlers]
    winch = scene.winch
    body = scene.towbody
    return InitialLayout(
        top_type=cable.top.type,
        top_start=None if cable.top.position is None else np.array(cable.top.position, dtype=float),
        bottom_free=cable.bottom.type == "free", shape=cable.initial.shape,
        direction=np.array(cable.initial.direction, dtype=float),
        sag_direction=np.array(cable.initial.sag_direction, dtype=float),
        winch_center=np.zeros(3) if winch is None else np.array(winch.position, dtype=float),
        winch_radius=0.0 if winch is None else winch_radius(scene),
        spool_angle=_spool_angle(scene),
        pulley_centers=np.array([p.position for p in pulleys], dtype=float).reshape(-1, 3),
        pulley_radii=np.array([p.radius + half_d for p in pulleys], dtype=float),
        load_length=0.0 if scene.load is None else float(scene.load.length_pi),
        body_attitude=np.zeros(3) if body is None or body.rigid is None else np.array(body.rigid.attitude, dtype=float))


def initial_coordinates(layout: InitialLayout, mesh: Mesh, model: CableModel, ship0: np.ndarray,
                        phi: np.ndarray) -> np.ndarray:
    """Rough initial coordinates (full vector) of the cable and what hangs on it.

    Parameters
    ----------
    layout
        The scene's initial layout (:func:`layout_from_scene`).
    mesh, model
        The cable's mesh and compiled model.
    ship0
        Ship state (3, 6) at the start (pose [m, rad] and its rates).
    phi
        Winch state (angle [rad], rate [rad/s]).
    """
    x = _cable_shape(layout, mesh, model, ship0, phi)
    link = model.terms.rigid_link
    if link.enabled:
        return np.concatenate([x, hanging_coordinates(link.body, x[-6:-3], layout.body_attitude)])
    if not model.terms.rigid_load.enabled:
        return x
    direction = x[-3:] / np.linalg.norm(x[-3:])
    return np.concatenate([x, x[-6:-3] + layout.load_length * direction])


def _cable_shape(layout: InitialLayout, mesh: Mesh, model: CableModel, ship0: np.ndarray,
                 phi: np.ndarray) -> np.ndarray:
    """Wrapped on the winch and over the sheave, draped over the sheave, straight, or sagging."""
    arc = mesh.node_arc
    if layout.top_type == "winch" or layout.spool_angle is not None:
        start = float(phi[0]) if layout.spool_angle is None else layout.spool_angle
        return _in_ship_frame(ship0, lambda rot: initial_shape.wrapped(
            arc, layout.winch_center, layout.winch_radius, start, rot.T @ layout.direction,
            layout.pulley_centers[0] if layout.pulley_centers.size else None,
            float(layout.pulley_radii[0]) if layout.pulley_radii.size else 0.0))
    q = np.zeros(model.free_idx.size)
    apply_prescribed(model.att_index, model.att_kind, model.att_vec, model.att_radius, ship0, phi, q,
                     np.zeros_like(q), np.zeros_like(q))
    if layout.top_type == "free" and layout.top_start is not None:
        q[0:3] = layout.top_start
    top = q[0:3].copy()
    if layout.pulley_centers.size and layout.shape == "auto":
        return _draped(layout, arc, ship0, top)
    if layout.bottom_free:
        return initial_shape.straight(top, layout.direction, arc)
    last = 6 * (mesh.n_nodes - 1)
    bottom = q[last:last + 3].copy()
    if layout.shape == "straight":  # along the chord, compressed or stretched to fit
        chord = bottom - top
        return initial_shape.straight(top, chord, arc, float(np.linalg.norm(chord)) / arc[-1])
    return initial_shape.sag(top, bottom, layout.sag_direction, arc)


def _draped(layout: InitialLayout, arc: np.ndarray, ship0: np.ndarray, top: np.ndarray) -> np.ndarray:
    """From the top end over the sheave (and each idler in turn), then along the initial
    direction (inertial)."""
    def shape(rot: np.ndarray) -> np.ndarray:
        start = rot.T @ (top - ship0[0, :3])
        departure = rot.T @ layout.direction
        if len(layout.pulley_radii) > 1:
            return initial_shape.over_pulleys(arc, start, list(layout.pulley_centers), list(layout.pulley_radii),
                                              departure)
        return initial_shape.draped(arc, start, layout.pulley_centers[0], float(layout.pulley_radii[0]), departure)
    return _in_ship_frame(ship0, shape)


def _in_ship_frame(ship0: np.ndarray, shape) -> np.ndarray:
    """``shape(R)`` (nodal coordinates in the ship frame, R: ship -> inertial) moved to the
    inertial frame with the ship's pose."""
    rot = rotation_matrix(ship0[0, 3], ship0[0, 4], ship0[0, 5])
    x = shape(rot).reshape(-1, 2, 3)
    x[:, 0, :] = x[:, 0, :] @ rot.T + ship0[0, :3]
    x[:, 1, :] = x[:, 1, :] @ rot.T
    return x.ravel()
