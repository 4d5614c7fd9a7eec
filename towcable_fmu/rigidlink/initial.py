"""Initial configuration: the links laid along the parabola of the reference.

The reference starts from rest with the cable on ``z = -4 d (x/D)(1 - x/D)`` between
the fairleads (span ``D``, sag ``d``, its section "Simulations"). Here the ``n`` nodes
lie on that parabola with equal chords (so every node is exactly on the curve and the
links are equal); the cable length is ``n`` times that chord, which tends to the
parabola's arc length as ``n`` grows.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from ..scene.rigid_link import Layout


def _parabola(x: float, layout: Layout) -> float:
    D, d = layout.span, layout.sag
    return layout.height - 4.0 * d * (x / D) * (1.0 - x / D)


def _next_node(x: float, chord: float, layout: Layout) -> float:
    """x of the point on the parabola at distance ``chord`` behind (smaller x) the point at ``x``."""
    z = _parabola(x, layout)

    def gap(xn: float) -> float:
        return math.hypot(x - xn, z - _parabola(xn, layout)) - chord

    return brentq(gap, x - chord, x, xtol=1e-14, rtol=1e-15)


def _end_x(chord: float, n: int, layout: Layout) -> float:
    x = layout.span
    for _ in range(n):
        x = _next_node(x, chord, layout)
    return x


def parabola_angles(n: int, layout: Layout) -> tuple[np.ndarray, float]:
    """Link angles [rad] and the common link length [m] of the initial parabola.

    Node 0 (the tug's fairlead) is at ``(D, z0)``, node ``n`` (the towed vessel's) at
    ``(0, z0)``.

    Returns
    -------
    theta, length
        Elevation angles of the n links (measured from +x; about pi, the cable points
        back from the tug; unwrapped, so neighbours differ by less than pi) and the link
        length.
    """
    D = layout.span
    if layout.sag == 0.0:
        return np.full(n, math.pi), D / n
    upper = D / n * (1.0 + 8.0 * (layout.sag / D) ** 2)  # above the arc length / n (chords are shorter)
    chord = brentq(lambda c: _end_x(c, n, layout), D / n, upper, xtol=1e-14, rtol=1e-15)
    x = D
    theta = np.empty(n)
    for i in range(n):
        xn = _next_node(x, chord, layout)
        theta[i] = math.atan2(_parabola(xn, layout) - _parabola(x, layout), xn - x)
        x = xn
    return np.unwrap(theta), chord  # continuous across pi: the joint springs see differences
