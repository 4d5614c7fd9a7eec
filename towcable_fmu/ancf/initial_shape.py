"""Rough initial cable shapes handed to the statics solver."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def straight(top: np.ndarray, direction: np.ndarray, node_arc: np.ndarray, stretch: float = 1.0) -> np.ndarray:
    """Straight cable from ``top`` along ``direction``.

    Parameters
    ----------
    top
        Position of the first node [m].
    direction
        Direction of the cable (normalised here).
    node_arc
        Unstretched arc length of each node [m], shape (nn,).
    stretch
        Ratio of laid-out to unstretched length (1: unstretched; < 1: compressed).

    Returns
    -------
    ndarray, shape (6 nn,)
        Nodal coordinates.
    """
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    x = np.zeros((node_arc.size, 2, 3))
    x[:, 0, :] = top[None, :] + stretch * node_arc[:, None] * d[None, :]
    x[:, 1, :] = stretch * d
    return x.ravel()


def sag(top: np.ndarray, bottom: np.ndarray, sag_direction: np.ndarray, node_arc: np.ndarray) -> np.ndarray:
    """A parabola of the cable's length hung between two points.

    The parabola lies in the plane of the chord and ``sag_direction`` and bulges
    towards ``sag_direction``; its depth is chosen so that its arc length equals the
    cable length. A cable shorter than the chord is laid along the chord (stretched).

    Returns
    -------
    ndarray, shape (6 nn,)
        Nodal coordinates at the unstretched arc positions of the nodes.
    """
    total = float(node_arc[-1])
    chord = np.asarray(bottom, dtype=float) - np.asarray(top, dtype=float)
    span = float(np.linalg.norm(chord))
    if span == 0.0:
        raise ValueError("the two ends coincide: cannot lay a sagging cable between them")
    ex = chord / span
    w = np.asarray(sag_direction, dtype=float)
    w = w - (w @ ex) * ex
    if np.linalg.norm(w) < 1e-12:  # sag direction along the chord: pick any normal
        w = np.cross(ex, [0.0, 1.0, 0.0] if abs(ex[1]) < 0.9 else [1.0, 0.0, 0.0])
    ey = w / np.linalg.norm(w)
    if total <= span:
        return straight(top, ex, node_arc, span / total)

    u_fine = np.linspace(0.0, 1.0, 2001)

    def arc(depth: float) -> np.ndarray:
        # y(u) = 4 depth u (1 - u), x(u) = span u
        dy = 4.0 * depth * (1.0 - 2.0 * u_fine)
        speed = np.sqrt(span**2 + dy**2)
        return np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(u_fine))])

    depth = brentq(lambda h: arc(h)[-1] - total, 0.0, total)
    s_fine = arc(depth)
    u_nodes = np.interp(node_arc, s_fine, u_fine)
    x = np.zeros((node_arc.size, 2, 3))
    pos_x = span * u_nodes
    pos_y = 4.0 * depth * u_nodes * (1.0 - u_nodes)
    x[:, 0, :] = top[None, :] + pos_x[:, None] * ex[None, :] + pos_y[:, None] * ey[None, :]
    tx = np.full_like(u_nodes, span)
    ty = 4.0 * depth * (1.0 - 2.0 * u_nodes)
    norm = np.hypot(tx, ty)
    x[:, 1, :] = (tx / norm)[:, None] * ex[None, :] + (ty / norm)[:, None] * ey[None, :]
    return x.ravel()


def _lay(node_arc: np.ndarray, pieces: list, tail_dir: np.ndarray) -> np.ndarray:
    """Nodes along a path of lines and circular arcs, then straight along ``tail_dir``.

    Pieces: ``("line", p0, p1)`` or ``("arc", centre, radius, a0, a1)``: a circle in the
    XZ plane through ``centre``, angle psi measured from +Z towards +X (point
    ``centre + radius (sin psi, 0, cos psi)``), travelled from a0 to a1.
    """
    x = np.zeros((node_arc.size, 2, 3))
    start = 0.0
    tail = None
    for piece in pieces:
        if piece[0] == "arc":
            _, c, rad, a0, a1 = piece
            sign = 1.0 if a1 >= a0 else -1.0
            length = rad * abs(a1 - a0)
            sel = (node_arc >= start) & (node_arc <= start + length)
            ang = a0 + sign * (node_arc[sel] - start) / rad
            zero = np.zeros_like(ang)
            x[sel, 0, :] = c + rad * np.column_stack([np.sin(ang), zero, np.cos(ang)])
            x[sel, 1, :] = sign * np.column_stack([np.cos(ang), zero, -np.sin(ang)])
            tail = c + rad * np.array([np.sin(a1), 0.0, np.cos(a1)])
        else:
            _, p0, p1 = piece
            length = float(np.linalg.norm(p1 - p0))
            sel = (node_arc >= start) & (node_arc <= start + length)
            if length > 0.0:
                direction = (p1 - p0) / length
                x[sel, 0, :] = p0 + (node_arc[sel] - start)[:, None] * direction
                x[sel, 1, :] = direction
            tail = p1
        start += length
    sel = node_arc > start
    x[sel, 0, :] = tail + (node_arc[sel] - start)[:, None] * tail_dir
    x[sel, 1, :] = tail_dir
    return x.ravel()


def _leave_angle(direction: np.ndarray, increasing: bool) -> float:
    """Angle on a circle where the tangent of travel equals ``direction`` (XZ components)."""
    if increasing:
        return float(np.arctan2(-direction[2], direction[0]))
    return float(np.arctan2(direction[2], -direction[0]))


def wrapped(node_arc: np.ndarray, drum_center: np.ndarray, drum_radius: float, phi0: float,
            departure: np.ndarray, sheave_center: np.ndarray | None = None,
            sheave_radius: float = 0.0) -> np.ndarray:
    """Cable wound on the drum, over the sheave (if any), then straight: ship-frame coordinates.

    The path, in the ship's XZ plane, starts at the cable end on the drum (angle ``phi0``
    from the top towards +X), follows the drum with decreasing angle to the upper common
    tangent with the sheave, runs along it, follows the sheave over its top to the point
    where the cable direction equals ``departure``, and continues straight. Without a
    sheave it leaves the drum where its direction equals ``departure``. Radii are those of
    the cable centreline (surface radius plus cable radius).

    Parameters
    ----------
    node_arc
        Unstretched arc length of each node from the drum end [m].
    drum_center, drum_radius, phi0
        Drum centre (ship frame) [m], centreline radius [m], angle of the cable end [rad].
    departure
        Direction of the cable after the last contact (ship frame).
    sheave_center, sheave_radius
        Sheave centre (ship frame) [m] and centreline radius [m], or None.

    Returns
    -------
    ndarray, shape (6 nn,)
        Nodal positions and unit slopes in the ship frame.
    """
    u = np.asarray(departure, dtype=float)
    u = u / np.linalg.norm(u)
    angle_out = _leave_angle(u, increasing=False)
    c1 = np.asarray(drum_center, dtype=float)
    if sheave_center is None:
        return _lay(node_arc, [("arc", c1, drum_radius, phi0, angle_out)], u)
    c2 = np.asarray(sheave_center, dtype=float)
    chord = np.array([c2[0] - c1[0], c2[2] - c1[2]])
    dist = float(np.hypot(*chord))
    d = chord / dist
    up = np.array([d[1], -d[0]]) if -d[0] >= 0 else np.array([-d[1], d[0]])
    if up[1] < 0:
        up = -up
    sin_a = (drum_radius - sheave_radius) / dist
    n = np.sqrt(1.0 - sin_a**2) * up + sin_a * d
    tangent_angle = float(np.arctan2(n[0], n[1]))
    p1 = c1 + drum_radius * np.array([n[0], 0.0, n[1]])
    p2 = c2 + sheave_radius * np.array([n[0], 0.0, n[1]])
    p1[1], p2[1] = c1[1], c2[1]
    return _lay(node_arc, [("arc", c1, drum_radius, phi0, tangent_angle), ("line", p1, p2),
                           ("arc", c2, sheave_radius, tangent_angle, angle_out)], u)


def draped(node_arc: np.ndarray, start: np.ndarray, center: np.ndarray, radius: float,
           departure: np.ndarray) -> np.ndarray:
    """Cable from ``start`` over a pulley, then straight along ``departure``.

    From ``start`` the cable runs along the upper tangent to the circle (centreline
    radius ``radius`` about ``center``, in the XZ plane), over the top towards the side the
    start is not on, and leaves where its direction equals ``departure``.

    Returns
    -------
    ndarray, shape (6 nn,)
        Nodal positions and unit slopes (frame of the arguments).
    """
    p = np.asarray(start, dtype=float)
    c = np.array([center[0], p[1], center[2]], dtype=float)
    u = np.asarray(departure, dtype=float)
    u = u / np.linalg.norm(u)
    increasing = p[0] < c[0]  # coming from -X: over the top towards +X
    a0, touch = _touch_point(p, c, radius, increasing, "the start of a draped cable lies inside the pulley")
    return _lay(node_arc, [("line", p, touch), ("arc", c, radius, a0, _leave_angle(u, increasing))], u)


def _touch_point(p: np.ndarray, c: np.ndarray, radius: float, increasing: bool, inside: str) -> tuple:
    """Where the upper tangent from ``p`` meets the circle (centre ``c`` at p's Y, centreline
    radius ``radius`` [m], XZ plane) when the cable goes over the top towards +X
    (``increasing``) or towards -X: its angle from +Z towards +X [rad] and the point [m].

    Raises
    ------
    ValueError
        With the message ``inside`` when ``p`` lies inside the circle.
    """
    w = np.array([p[0] - c[0], p[2] - c[2]])
    dist = float(np.hypot(*w))
    if dist <= radius:
        raise ValueError(inside)
    spread = float(np.arccos(radius / dist))
    psi_w = float(np.arctan2(w[0], w[1]))
    a0 = psi_w + spread if increasing else psi_w - spread
    return a0, c + radius * np.array([np.sin(a0), 0.0, np.cos(a0)])


def over_pulleys(node_arc: np.ndarray, start: np.ndarray, centers: list[np.ndarray], radii: list[float],
                 departure: np.ndarray) -> np.ndarray:
    """Cable from ``start`` over a row of pulleys (in order, towards +X), then along ``departure``.

    From ``start`` (on the -X side of the first pulley) the cable runs along the upper
    tangent to the first circle, over the top of each pulley and along the upper common
    tangent to the next (circles in the XZ plane at the start's Y), and leaves the last
    one where its direction equals ``departure``. With one pulley this is :func:`draped`.

    Parameters
    ----------
    node_arc
        Unstretched arc length of each node [m].
    start
        First node [m].
    centers, radii
        Pulley centres [m] and centreline radii [m] (surface radius plus cable radius),
        with increasing X and not overlapping.
    departure
        Direction of the cable after the last pulley.

    Returns
    -------
    ndarray, shape (6 nn,)
        Nodal positions and unit slopes (frame of the arguments).
    """
    p = np.asarray(start, dtype=float)
    u = np.asarray(departure, dtype=float)
    u = u / np.linalg.norm(u)
    cs = [np.array([c[0], p[1], c[2]], dtype=float) for c in centers]
    a0, touch = _touch_point(p, cs[0], radii[0], True, "the start of a draped cable lies inside the first pulley")
    pieces: list = [("line", p, touch)]
    angle = a0
    for c1, r1, c2, r2 in zip(cs[:-1], radii[:-1], cs[1:], radii[1:]):
        chord = np.array([c2[0] - c1[0], c2[2] - c1[2]])
        gap = float(np.hypot(*chord))
        if gap <= abs(r1 - r2):
            raise ValueError("two pulleys of the row overlap")
        d = chord / gap
        up = np.array([-d[1], d[0]])  # left of the travel towards +X: upwards
        sin_a = (r1 - r2) / gap
        n = np.sqrt(1.0 - sin_a**2) * up + sin_a * d
        tangent = float(np.arctan2(n[0], n[1]))
        pieces.append(("arc", c1, r1, angle, tangent))
        pieces.append(("line", c1 + r1 * np.array([n[0], 0.0, n[1]]), c2 + r2 * np.array([n[0], 0.0, n[1]])))
        angle = tangent
    pieces.append(("arc", cs[-1], radii[-1], angle, _leave_angle(u, increasing=True)))
    return _lay(node_arc, pieces, u)
