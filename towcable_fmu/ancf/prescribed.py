"""Prescribed (eliminated) coordinates: the ends that move with the ship, the winch or nothing.

A prescribed end is handled by exact kinematic elimination: its coordinates are not
unknowns; their position, velocity and acceleration are set from the ship motion at
the time of evaluation, and the residual rows they would have carried are the
reaction forces. This replaces the Baumgarte-stabilised constraint W(113)-(122) of
the reference; with the constraint satisfied exactly the two formulations describe
the same motion (the constraint form is implemented in the reference path,
:func:`towcable_fmu.ancf.reference_ivp.integrate_reference`, and the tests compare
the two).

Attachment kinds (``kind`` column of the attachment table):

=====  =====================================================================
0      position fixed in the inertial frame (``vec`` = point [m])
1      position fixed in the ship frame (``vec`` = body coordinates [m])
2      slope fixed in the inertial frame (``vec`` = unit direction)
3      slope fixed in the ship frame (``vec`` = unit direction, body frame)
4      point on the winch drum, W(120): ``s_w + R_y(phi) r_w k`` with ``vec`` = s_w
       [m] and ``radius`` = r_w [m]; phi is the winch rotation state
=====  =====================================================================
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from ..numerics.kinematics import rotation_derivatives

FIXED_POINT = 0
SHIP_POINT = 1
FIXED_SLOPE = 2
SHIP_SLOPE = 3
WINCH_POINT = 4


@njit(cache=True)
def drum_point(center: np.ndarray, radius: float, phi: np.ndarray) -> np.ndarray:
    """Body-frame position, velocity and acceleration of the cable end on the drum.

    Parameters
    ----------
    center
        Winch centre s_w in the ship body frame [m].
    radius
        Winch radius r_w [m].
    phi
        Winch rotation, rate and acceleration [rad, rad/s, rad/s^2], shape (3,).

    Returns
    -------
    ndarray, shape (3, 3)
        Rows: s, ds/dt, d2s/dt2 in the body frame.
    """
    c, s = np.cos(phi[0]), np.sin(phi[0])
    out = np.zeros((3, 3))
    # R_y(phi) k = [sin phi, 0, cos phi]
    out[0, 0] = center[0] + radius * s
    out[0, 1] = center[1]
    out[0, 2] = center[2] + radius * c
    out[1, 0] = radius * c * phi[1]
    out[1, 2] = -radius * s * phi[1]
    out[2, 0] = radius * (-s * phi[1] * phi[1] + c * phi[2])
    out[2, 2] = radius * (-c * phi[1] * phi[1] - s * phi[2])
    return out


@njit(cache=True)
def apply_prescribed(att_index: np.ndarray, att_kind: np.ndarray, att_vec: np.ndarray, att_radius: np.ndarray,
                     ship: np.ndarray, phi: np.ndarray, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> None:
    """Write the prescribed coordinates into the full q, v, a vectors.

    Parameters
    ----------
    att_index
        First global coordinate index of each attachment (3 consecutive coordinates).
    att_kind, att_vec, att_radius
        Attachment table (see module docstring).
    ship
        Ship state (3, 6) at the evaluation time.
    phi
        Winch state [rad, rad/s, rad/s^2].
    q, v, a
        Full coordinate, velocity and acceleration vectors, modified in place.
    """
    r, r1, r2 = rotation_derivatives(ship)
    for k in range(att_index.shape[0]):
        i0 = att_index[k]
        kind = att_kind[k]
        vec = att_vec[k]
        if kind == FIXED_POINT or kind == FIXED_SLOPE:
            for c in range(3):
                q[i0 + c] = vec[c]
                v[i0 + c] = 0.0
                a[i0 + c] = 0.0
        elif kind == SHIP_POINT or kind == SHIP_SLOPE:
            base = 1.0 if kind == SHIP_POINT else 0.0  # a point moves with the ship's CG, a slope only turns
            for c in range(3):
                p0 = p1 = p2 = 0.0
                for j in range(3):
                    p0 += r[c, j] * vec[j]
                    p1 += r1[c, j] * vec[j]
                    p2 += r2[c, j] * vec[j]
                q[i0 + c] = base * ship[0, c] + p0
                v[i0 + c] = base * ship[1, c] + p1
                a[i0 + c] = base * ship[2, c] + p2
        else:  # WINCH_POINT
            s = drum_point(vec, att_radius[k], phi)
            for c in range(3):
                p0 = p1 = p2 = 0.0
                for j in range(3):
                    p0 += r[c, j] * s[0, j]
                    p1 += r1[c, j] * s[0, j] + r[c, j] * s[1, j]
                    p2 += r2[c, j] * s[0, j] + 2.0 * r1[c, j] * s[1, j] + r[c, j] * s[2, j]
                q[i0 + c] = ship[0, c] + p0
                v[i0 + c] = ship[1, c] + p1
                a[i0 + c] = ship[2, c] + p2
