"""Changing the mesh of a running cable without disturbing it: an element split in two.

An element's coordinates ``[r(0), r_p(0), r(L), r_p(L)]`` (slopes ``r_p = dr/dp`` with
respect to the unstretched arc parameter) interpolate a cubic in p. A new node at
``p* = xi* L`` with the cubic's own value and slope there, ``r(p*)`` and ``r_p(p*)``,
makes two elements of lengths ``p*`` and ``L - p*`` that interpolate the same cubic on
each side: the geometry is that of the old element exactly. The slopes need no
rescaling (they are per metre of cable, not per element). Coordinates, velocities,
accelerations and the integrator's auxiliary accelerations are linear in the element's
coordinates, so each is split the same way. What depends on the cubic alone is unchanged:
mass, momentum, kinetic, bending and gravity energy. The axial strain is not the
cubic's own: the decoupled strain of :mod:`towcable_fmu.ancf.axial` interpolates each
element's stretch from its end slopes and arc length, so the split elements carry a
finer interpolant and the tension changes by the old one's error (in full_scale's free
span 1e-5 of the strain energy). Loads integrated on each element's grid of points
(contact, fluid) change by their quadrature error, now on the finer grid.

Merging two elements of one segment into one (:func:`merge_mesh`) drops the node between
them: exact when the two form one cubic (a split undone), otherwise the merged element
misses the dropped node by :func:`merge_defect` (for a smooth shape, O(L^4) of the merged
length L). Both are the remeshing a deploying and recovering winch needs (issue 20).
"""

from __future__ import annotations

import numpy as np

from . import element
from .model import Mesh


def _check(mesh: Mesh, e: int, xi: float) -> None:
    if not (isinstance(e, (int, np.integer)) and 0 <= e < mesh.n_elements):
        raise ValueError(f"element = {e!r} is not an element of this mesh (0 ... {mesh.n_elements - 1})")
    if not (np.isfinite(xi) and 0.0 < xi < 1.0):
        raise ValueError(f"xi = {xi!r} must lie inside the element, in (0, 1)")


def split_mesh(mesh: Mesh, e: int, xi: float = 0.5, first_segment: int | None = None) -> Mesh:
    """``mesh`` with element ``e`` split at normalised position ``xi`` in (0, 1): two
    elements of lengths ``xi L`` and ``(1 - xi) L`` [m], in the same segment (or the first
    in ``first_segment``: a split at a section boundary of cable paid out from a drum).

    Raises
    ------
    ValueError
        If ``e`` is not an element of the mesh or ``xi`` is not inside (0, 1).
    """
    _check(mesh, e, xi)
    length = mesh.lengths[e]
    lengths = np.concatenate([mesh.lengths[:e], [xi * length, (1.0 - xi) * length], mesh.lengths[e + 1:]])
    segments = np.insert(mesh.segment_of_element, e,
                         mesh.segment_of_element[e] if first_segment is None else first_segment)
    arc = np.insert(mesh.node_arc, e + 1, mesh.node_arc[e] + xi * length)
    return Mesh(lengths, segments, arc)


def split_coordinates(x: np.ndarray, mesh: Mesh, e: int, xi: float = 0.5) -> np.ndarray:
    """Coordinate vector ``x`` of ``mesh`` (or its velocities, accelerations: anything
    linear in the nodal coordinates; the coordinates of a load or body after the last
    node follow unchanged) with the node of :func:`split_mesh` inserted: the value and
    slope of element ``e``'s cubic at ``xi``.

    Raises
    ------
    ValueError
        As :func:`split_mesh`, or if ``x`` is shorter than the mesh's nodes.
    """
    _check(mesh, e, xi)
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.shape[0] < 6 * mesh.n_nodes:
        raise ValueError(f"coordinate vector of shape {x.shape} does not cover the {mesh.n_nodes} nodes of the mesh")
    length = mesh.lengths[e]
    nodal = x[6 * e: 6 * e + 12].reshape(4, 3)  # r(0), r_p(0), r(L), r_p(L)
    value = element.shape_functions(xi, length) @ nodal
    slope = element.shape_derivatives(xi, length) @ nodal
    return np.concatenate([x[:6 * (e + 1)], value, slope, x[6 * (e + 1):]])


def _check_pair(mesh: Mesh, e: int, across: bool = False) -> None:
    if not (isinstance(e, (int, np.integer)) and 0 <= e < mesh.n_elements - 1):
        raise ValueError(f"element = {e!r} has no next element to merge with (0 ... {mesh.n_elements - 2})")
    if not across and mesh.segment_of_element[e] != mesh.segment_of_element[e + 1]:
        raise ValueError(f"elements {e} and {e + 1} belong to different segments (their properties differ)")


def merge_mesh(mesh: Mesh, e: int, across: bool = False) -> Mesh:
    """``mesh`` with elements ``e`` and ``e + 1`` (of one segment) merged into one; with
    ``across``, also two of different segments, the merged element in the second's (the
    short last piece of a section hauled onto a drum).

    Raises
    ------
    ValueError
        If ``e + 1`` is not an element or the two belong to different segments (without ``across``).
    """
    _check_pair(mesh, e, across)
    lengths = np.concatenate([mesh.lengths[:e], [mesh.lengths[e] + mesh.lengths[e + 1]], mesh.lengths[e + 2:]])
    return Mesh(lengths, np.delete(mesh.segment_of_element, e), np.delete(mesh.node_arc, e + 1))


def merge_coordinates(x: np.ndarray, mesh: Mesh, e: int) -> np.ndarray:
    """Coordinate vector ``x`` of ``mesh`` without the node between elements ``e`` and
    ``e + 1`` (see :func:`merge_mesh`): the merged element keeps the outer nodes, so it is
    the two elements exactly when they form one cubic (:func:`merge_defect`)."""
    _check_pair(mesh, e, across=True)
    x = np.asarray(x, dtype=float)
    return np.concatenate([x[:6 * (e + 1)], x[6 * (e + 2):]])


def merge_defect(x: np.ndarray, mesh: Mesh, e: int) -> tuple[float, float]:
    """How far the merged element of :func:`merge_coordinates` misses the node it drops:
    the distance [m] between the node's position and the merged cubic there, and the
    norm [-] of the difference of the slopes (0, 0 when the two elements form one cubic)."""
    _check_pair(mesh, e, across=True)
    x = np.asarray(x, dtype=float)
    length = mesh.lengths[e] + mesh.lengths[e + 1]
    xi = mesh.lengths[e] / length
    nodal = np.concatenate([x[6 * e: 6 * e + 6], x[6 * (e + 2): 6 * (e + 2) + 6]]).reshape(4, 3)
    node = x[6 * (e + 1): 6 * (e + 1) + 6]
    value = element.shape_functions(xi, length) @ nodal
    slope = element.shape_derivatives(xi, length) @ nodal
    return float(np.linalg.norm(value - node[:3])), float(np.linalg.norm(slope - node[3:]))
