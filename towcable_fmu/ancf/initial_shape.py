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
