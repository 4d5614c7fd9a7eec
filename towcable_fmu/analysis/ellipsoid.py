"""Calnan's enclosing ellipsoid of a towed-body track (Westin 2018, sections 2.1 and 4.3.3).

The measure of how much a towed body moves: an ellipsoid that contains a given fraction
(95 %) of the recorded positions. The fit follows the reference:

1. the ellipsoid frame is centred at the centroid of the points;
2. ``X_E`` lies along the best-fit line and ``X_E``, ``Y_E`` span the best-fit plane
   (least squares in the orthogonal sense), i.e. the principal axes of the point cloud,
   ordered by decreasing spread; ``Z_E`` is the plane's normal;
3. the radii are proportional to the spread along each axis and scaled by one common
   factor until the wanted fraction of the points is inside.

The reference says the radii are "proportional to the variance"; we use the standard
deviation, which keeps the radii in metres and gives the ellipsoid the shape of the
cloud's covariance (for normally distributed positions the fit is then the 95 %
confidence ellipsoid; with variances it would be stretched along the long axis).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

#: An axis whose standard deviation is at most this fraction of the largest is degenerate
#: (zero radius; the cloud is flat or collinear up to rounding).
DEGENERATE_RTOL = 1e-9

#: ... or at most this many machine epsilons times the largest coordinate magnitude (the
#: rounding level of the centroid and the differences to it).
ROUNDING_ULPS = 1000.0


@dataclasses.dataclass(frozen=True, eq=False)
class Ellipsoid:
    """An ellipsoid ``sum_i ((p - centre) . axes[i] / radii[i])^2 <= 1``.

    Attributes
    ----------
    centre
        (3,) centroid of the points [m].
    axes
        (3, 3) unit principal directions as rows (``X_E``, ``Y_E``, ``Z_E``), a
        right-handed orthonormal basis, ordered by decreasing spread.
    radii
        (3,) semi-axes along ``axes`` [m], non-increasing; 0 along a degenerate axis.
    volume
        ``4/3 pi a b c`` [m^3] (0 for a flat or collinear cloud).
    fraction_inside
        Fraction of the fitted points inside or on the surface [-].
    """

    centre: np.ndarray
    axes: np.ndarray
    radii: np.ndarray
    volume: float
    fraction_inside: float


def enclosing_ellipsoid(points: np.ndarray, fraction: float = 0.95) -> Ellipsoid:
    """Fit Calnan's ellipsoid containing ``fraction`` of ``points``.

    Parameters
    ----------
    points
        (n, 3) positions [m], n >= 4, all finite.
    fraction
        Share of the points the ellipsoid must contain, in (0, 1] [-]. The scale is the
        smallest that puts at least ``ceil(fraction * n)`` points inside or on the surface.

    Returns
    -------
    Ellipsoid
        Centre, principal axes, radii [m], volume [m^3] and the fraction inside.

    Raises
    ------
    ValueError
        ``points`` not of shape (n, 3), fewer than 4 points, a non-finite coordinate, or
        ``fraction`` outside (0, 1]; the message names the offending value.

    Notes
    -----
    The radii are ``k * s_i`` with ``s_i`` the (population) standard deviation of the
    points along principal axis ``i`` and ``k`` the common scale. A degenerate cloud does
    not fail: along an axis with ``s_i <= DEGENERATE_RTOL * s_max`` or below the rounding
    level ``ROUNDING_ULPS * eps * max|p|`` (points in a plane or on a line, up to rounding)
    the radius is 0, that coordinate is left out when counting the points inside, and the
    volume is 0. If all points coincide every radius is 0.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points must have shape (n, 3), got {pts.shape}")
    n = pts.shape[0]
    if n < 4:
        raise ValueError(f"points: need at least 4 points, got {n}")
    bad = np.flatnonzero(~np.isfinite(pts).all(axis=1))
    if bad.size:
        raise ValueError(f"points: non-finite coordinates in row {bad[0]}: {pts[bad[0]].tolist()} "
                         f"({bad.size} rows in all)")
    if not (math.isfinite(fraction) and 0.0 < fraction <= 1.0):
        raise ValueError(f"fraction must be in (0, 1], got {fraction}")

    centre = pts.mean(axis=0)
    rel = pts - centre
    _, singular, vt = np.linalg.svd(rel, full_matrices=False)
    axes = _right_handed(vt)
    spread = singular / math.sqrt(n)  # standard deviation along each principal axis [m]
    floor = max(DEGENERATE_RTOL * spread[0], ROUNDING_ULPS * np.finfo(float).eps * float(np.max(np.abs(pts))))
    active = spread > floor
    local = rel @ axes[active].T
    distance2 = np.sum((local / spread[active]) ** 2, axis=1)  # squared Mahalanobis distance
    needed = max(1, math.ceil(fraction * n - 1e-9))  # points that must be inside (1e-9: rounding of f n)
    scale2 = np.sort(distance2)[needed - 1]
    radii = np.where(active, math.sqrt(scale2) * spread, 0.0)
    inside = float(np.count_nonzero(distance2 <= scale2)) / n
    volume = 4.0 / 3.0 * math.pi * float(np.prod(radii))
    return Ellipsoid(centre=centre, axes=axes, radii=radii, volume=volume, fraction_inside=inside)


def _right_handed(vt: np.ndarray) -> np.ndarray:
    """Principal directions with a fixed sign (largest component of X_E and Y_E positive)
    and Z_E = X_E x Y_E."""
    first = vt[0] * np.sign(vt[0][np.argmax(np.abs(vt[0]))])
    second = vt[1] * np.sign(vt[1][np.argmax(np.abs(vt[1]))])
    return np.array([first, second, np.cross(first, second)])


def projected_outline(ellipsoid: Ellipsoid, dims: tuple[int, int], n: int = 181) -> np.ndarray:
    """Outline of the ellipsoid's orthogonal projection onto two inertial coordinates.

    Parameters
    ----------
    ellipsoid
        The ellipsoid.
    dims
        The two coordinate indices (0 = x, 1 = y, 2 = z) spanning the projection plane.
    n
        Number of outline points (the first equals the last).

    Returns
    -------
    numpy.ndarray
        (n, 2) outline points [m], relative to the ellipsoid's centre.

    Notes
    -----
    The ellipsoid is ``{c + M^(1/2) w : |w| <= 1}`` with ``M = axes^T diag(radii^2) axes``;
    its projection is the ellipse of the 2 x 2 block of ``M`` on ``dims`` (a segment or a
    point when that block is singular).
    """
    m = ellipsoid.axes.T @ np.diag(ellipsoid.radii ** 2) @ ellipsoid.axes
    block = m[np.ix_(dims, dims)]
    values, vectors = np.linalg.eigh(block)
    angle = np.linspace(0.0, 2.0 * math.pi, n)
    circle = np.stack([np.cos(angle), np.sin(angle)])
    return (vectors @ (np.sqrt(np.clip(values, 0.0, None))[:, None] * circle)).T
