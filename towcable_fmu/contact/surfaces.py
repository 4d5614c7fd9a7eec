"""Contact surfaces of the winch drum and the sheave, and their penalty law.

Surfaces are fixed in the ship and rotate about the ship's Y axis. A cable point is
described by its ship-frame position relative to the surface centre ``(X, Y, Z)``; rotating
it about Y into the YZ plane (W(94)-(96)) gives the radial distance ``rho = sqrt(X^2 +
Z^2)`` and the axial offset ``Y``. With ``R_c = r + d/2`` (surface radius plus cable
radius, W(98)) and ``h = rho - R_c`` the height of the centreline above its seated
position:

* drum (a cylinder, W(99)): penetration ``delta = -h``, normal ``e_rho``;
* groove wall on the +Y side: ``delta = Y cos(theta_g/2) - h sin(theta_g/2)``, normal
  ``-cos(theta_g/2) e_Y + sin(theta_g/2) e_rho``; on the -Y side with ``-Y`` (W(100);
  the reference prints the normals with an X component, which in the YZ plane of W(96)
  is the Y component). A wall pushes while the cable's contact point on it, the foot of
  the normal through the centreline at height ``h_w = h + delta sin(theta_g/2)``, lies
  below the groove top ``h_g`` (W(101), W(105): no force once the cable has climbed
  above the top). There is no sideways limit: a cable that the soft penalty lets sink
  below its seat (Table 9's k_N = 1e6: about 68 mm on ``full_scale``) and that is pushed
  sideways keeps both walls, which hold it up to a sideways/radial load ratio of
  ``cot(theta_g/2)``;
* the rims (flange tops) beside the groove, for a cable that has climbed out (its
  contact point on the wall of its side above the groove top, ``h_w > h_g``) and lies
  within ``Y_o + w`` of the groove centre (``Y_o = h_g tan(theta_g/2)`` the half-opening,
  w the rim width): ``delta = h_g - h``, normal ``e_rho``. Deviation: the reference has
  no rims; with them a cable that has climbed out lands on the flange top and can be
  carried back into the groove, or slides off the sheave's side (no rim beyond
  ``Y_o + w``).

Where the contact point on a wall passes the groove top the wall hands over to the rim
(the two never act on the same point; there the rim's penetration is sin(theta_g/2)
times the wall's, so the handover is not continuous and a cable crossing the corner
does not keep its contact energy exactly), and :func:`groove_exit` measures how far a
point is out of the groove with the same geometry. The walls also reach a cable that
sank so deep that its centreline lies beside the sheave (beyond ``Y_o + w``) while its
contact point is still on the wall: only the soft penalty puts it there, and the
reference's walls carry it.

Force per unit length after Hunt and Crossley W(93): ``k delta^n (1 + D d(delta)/dt)``
along the normal, never pulling (the bracket is clipped at zero). Each face reports an
indicator ``g`` (active where g > 0: ``delta`` and, for a wall, ``h_g - h_w``; for a
rim, ``h_w - h_g`` and the distance to the rim's outer edge) for the partial-element
quadrature.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..jit.kernel_cache import njit

CYLINDER = 0
WALL_PLUS = 1
WALL_MINUS = 2
RIM = 3

WINCH = 0
SHEAVE = 1

_ZERO9 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


class ContactModel(NamedTuple):
    """Contact faces for the kernels (``enabled`` False: nothing to touch)."""

    enabled: bool
    face_surface: np.ndarray  #: (nf,) WINCH, SHEAVE, or 2 + k for idler k: which surface a face belongs to
    face_kind: np.ndarray     #: (nf,) CYLINDER, WALL_PLUS, WALL_MINUS
    face_center: np.ndarray   #: (nf, 3) centre in the ship body frame [m]
    face_radius: np.ndarray   #: (nf,) drum radius or groove root radius [m]
    face_depth: np.ndarray    #: (nf,) groove depth h_g [m] (0 for a cylinder)
    face_cos: np.ndarray      #: (nf,) cos(theta_g / 2)
    face_sin: np.ndarray      #: (nf,) sin(theta_g / 2)
    face_open: np.ndarray     #: (nf,) half-opening of the groove at its top Y_o [m] (the rims start there)
    face_rim: np.ndarray      #: (nf,) rim width beyond the opening [m] (rim faces end at Y_o + width)
    face_k: np.ndarray        #: (nf,) stiffness k_N
    face_n: np.ndarray        #: (nf,) exponent n
    face_damping: np.ndarray  #: (nf,) D [s/m]
    calls: np.ndarray         #: (1,) int64 counter of point evaluations (to verify skipping)


def no_contact() -> ContactModel:
    """The contact data of a scene without winch or sheave."""
    z = np.zeros(0)
    return ContactModel(False, np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros((0, 3)), z, z,
                        z, z, z, z, z, z, z, np.zeros(1, dtype=np.int64))


@njit(cache=True, inline="always")
def wall_contact_height(h: float, y: float, ca: float, sa: float) -> float:
    """Height above the seat of a point's contact point on the groove wall of its side [m].

    The foot of the normal from the centreline at ``(y, h)`` onto the wall of the side of
    ``y`` (the +Y wall for y >= 0), W(100): ``h + delta sin(theta_g/2)`` with that wall's
    penetration ``delta = |y| cos(theta_g/2) - h sin(theta_g/2)``.

    Parameters
    ----------
    h
        Height of the centreline above its seated position [m].
    y
        Axial offset from the groove centre [m].
    ca, sa
        cos(theta_g / 2), sin(theta_g / 2).
    """
    return h + (abs(y) * ca - h * sa) * sa


@njit(cache=True, inline="always")
def groove_exit(c: ContactModel, f: int, h: float, y: float) -> float:
    """How far a point is out of face f's groove [m]: positive above the groove top, or
    with its contact point on the wall of its side above the top (climbed out).

    ``max(h, h_w) - h_g``, :func:`wall_contact_height`; the faces of a groove switch with
    the same geometry (walls where it is negative, rims where the contact point is above).
    """
    return max(h, wall_contact_height(h, y, c.face_cos[f], c.face_sin[f])) - c.face_depth[f]


@njit(cache=True, inline="always")
def _polar(c: ContactModel, f: int, half_d: float, x: float, z: float, vx: float, vz: float) -> tuple:
    """``(1/rho [1/m], e_rho's x and z, h [m], d(rho)/dt [m/s])`` of a point relative to face f."""
    rho = math.sqrt(x * x + z * z)
    inv = 1.0 / max(rho, 1e-12)
    return inv, x * inv, z * inv, rho - (c.face_radius[f] + half_d), (x * vx + z * vz) * inv


@njit(cache=True, inline="always")
def face_force(c: ContactModel, f: int, half_d: float, x: float, y: float, z: float, vx: float, vy: float,
               vz: float) -> tuple:
    """Force per unit length (ship frame) of face f on a cable point, and its indicator.

    Parameters
    ----------
    c, f
        Contact data and face index.
    half_d
        Cable radius d/2 [m].
    x, y, z
        Point relative to the surface centre, ship frame [m].
    vx, vy, vz
        Its velocity relative to the ship, ship frame [m/s].

    Returns
    -------
    (fx, fy, fz, g, e)
        Force [N/m] (the force when active, evaluated even where g <= 0 so that a
        crossing point gets the value of the active side), the indicator g [m] and the
        elastic energy stored per unit length k delta^(n+1) / (n+1) [J/m].
    """
    inv, ex, ez, h, rho_dot = _polar(c, f, half_d, x, z, vx, vz)
    kind = c.face_kind[f]
    if kind == CYLINDER:
        delta = -h
        ddelta = -rho_dot
        nx, ny, nz = ex, 0.0, ez
        g = delta
    elif kind == RIM:
        delta = c.face_depth[f] - h
        ddelta = -rho_dot
        nx, ny, nz = ex, 0.0, ez
        climbed = wall_contact_height(h, y, c.face_cos[f], c.face_sin[f]) - c.face_depth[f]
        g = min(delta, min(climbed, c.face_open[f] + c.face_rim[f] - abs(y)))
    else:
        ca, sa = c.face_cos[f], c.face_sin[f]
        sign = 1.0 if kind == WALL_PLUS else -1.0
        delta = sign * y * ca - h * sa
        ddelta = sign * vy * ca - rho_dot * sa
        nx, ny, nz = sa * ex, -sign * ca, sa * ez
        g = min(delta, c.face_depth[f] - (h + delta * sa))
    if delta <= 0.0:
        return 0.0, 0.0, 0.0, g, 0.0
    n = c.face_n[f]
    elastic = c.face_k[f] * (delta * math.sqrt(delta) if n == 1.5 else delta ** n)
    mag = elastic * max(1.0 + c.face_damping[f] * ddelta, 0.0)
    return mag * nx, mag * ny, mag * nz, g, elastic * delta / (n + 1.0)


@njit(cache=True, inline="always")
def face_tangent(c: ContactModel, f: int, half_d: float, x: float, y: float, z: float, vx: float, vy: float,
                 vz: float) -> tuple:
    """The force of :func:`face_force` (ship frame), its indicator and their exact derivatives.

    Arguments as :func:`face_force`.

    Returns
    -------
    (force, g, df_dx, df_dv, dg_dx)
        Force per unit length [N/m] (3-tuple); the indicator g [m]; the force's derivatives
        with respect to the point's position [N/m^2] and velocity [N s/m^2] (9-tuples,
        row-major); the indicator's gradient [-] (3-tuple; where g is a minimum, that of
        the smallest term). Zero force derivatives where the face does not push
        (delta <= 0), and the damping term's where its bracket is clipped at zero.
    """
    inv, ex, ez, h, rho_dot = _polar(c, f, half_d, x, z, vx, vz)
    # d e_rho/ds = (I - e e^T)/rho in the XZ plane; d rho_dot/ds = (e_z, 0, -e_x) tdot
    exx, exz, ezz = ez * ez * inv, -ex * ez * inv, ex * ex * inv
    tdot = (vx * ez - vz * ex) * inv
    kind = c.face_kind[f]
    dn = (exx, 0.0, exz, 0.0, 0.0, 0.0, exz, 0.0, ezz)  # d normal / ds, rows x, y, z
    if kind == WALL_PLUS or kind == WALL_MINUS:
        ca, sa = c.face_cos[f], c.face_sin[f]
        sign = 1.0 if kind == WALL_PLUS else -1.0
        delta = sign * y * ca - h * sa
        ddelta = sign * vy * ca - rho_dot * sa
        nx, ny, nz = sa * ex, -sign * ca, sa * ez
        d_delta = (-sa * ex, sign * ca, -sa * ez)
        d_rate_dx = (-sa * ez * tdot, 0.0, sa * ex * tdot)
        d_rate_dv = d_delta
        dn = (sa * exx, 0.0, sa * exz, 0.0, 0.0, 0.0, sa * exz, 0.0, sa * ezz)
        top = c.face_depth[f] - (h + delta * sa)
        g = min(delta, top)
        dg = d_delta if delta <= top else (-ex - sa * d_delta[0], -sa * d_delta[1], -ez - sa * d_delta[2])
    else:
        delta = (c.face_depth[f] if kind == RIM else 0.0) - h
        ddelta = -rho_dot
        nx, ny, nz = ex, 0.0, ez
        d_delta = (-ex, 0.0, -ez)
        d_rate_dx = (-ez * tdot, 0.0, ex * tdot)
        d_rate_dv = d_delta
        g = delta
        dg = d_delta
        if kind == RIM:
            ca, sa = c.face_cos[f], c.face_sin[f]
            sy = 1.0 if y >= 0.0 else -1.0
            climbed = wall_contact_height(h, y, ca, sa) - c.face_depth[f]
            edge = c.face_open[f] + c.face_rim[f] - abs(y)
            if climbed < g:
                g = climbed
                dg = (ex * ca * ca, sy * ca * sa, ez * ca * ca)
            if edge < g:
                g = edge
                dg = (0.0, -sy, 0.0)
    if delta <= 0.0:
        return (0.0, 0.0, 0.0), g, _ZERO9, _ZERO9, dg
    n = c.face_n[f]
    root = math.sqrt(delta)
    elastic = c.face_k[f] * (delta * root if n == 1.5 else delta ** n)
    slope = c.face_k[f] * n * (root if n == 1.5 else delta ** (n - 1.0))  # d elastic / d delta
    bracket = 1.0 + c.face_damping[f] * ddelta
    k_rate = elastic * c.face_damping[f] if bracket > 0.0 else 0.0
    bracket = max(bracket, 0.0)
    mag = elastic * bracket
    normal = (nx, ny, nz)
    dmag_dx = (slope * bracket * d_delta[0] + k_rate * d_rate_dx[0], slope * bracket * d_delta[1]
               + k_rate * d_rate_dx[1], slope * bracket * d_delta[2] + k_rate * d_rate_dx[2])
    df_dx = (normal[0] * dmag_dx[0] + mag * dn[0], normal[0] * dmag_dx[1] + mag * dn[1],
             normal[0] * dmag_dx[2] + mag * dn[2], normal[1] * dmag_dx[0] + mag * dn[3],
             normal[1] * dmag_dx[1] + mag * dn[4], normal[1] * dmag_dx[2] + mag * dn[5],
             normal[2] * dmag_dx[0] + mag * dn[6], normal[2] * dmag_dx[1] + mag * dn[7],
             normal[2] * dmag_dx[2] + mag * dn[8])
    df_dv = (normal[0] * k_rate * d_rate_dv[0], normal[0] * k_rate * d_rate_dv[1], normal[0] * k_rate * d_rate_dv[2],
             normal[1] * k_rate * d_rate_dv[0], normal[1] * k_rate * d_rate_dv[1], normal[1] * k_rate * d_rate_dv[2],
             normal[2] * k_rate * d_rate_dv[0], normal[2] * k_rate * d_rate_dv[1], normal[2] * k_rate * d_rate_dv[2])
    return (mag * nx, mag * ny, mag * nz), g, df_dx, df_dv, dg
