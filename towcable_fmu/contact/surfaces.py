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
  is the Y component); no force when ``h > h_g`` (W(101));
* the rims (flange tops) beside the groove opening ``|Y| > Y_o = h_g tan(theta_g/2)``, out
  to ``Y_o + w`` (rim width w): ``delta = h_g - h``, normal ``e_rho``. Deviation: the
  reference's walls extend sideways without end, so a cable that has climbed out of the
  groove and is pulled down beside it meets an ever deeper penetration and is thrown back
  violently; with the rims it lands on the flange top or slides off the sheave's side
  (no contact beyond the rim), and the walls act only within the opening.

Force per unit length after Hunt and Crossley W(93): ``k delta^n (1 + D d(delta)/dt)``
along the normal, never pulling (the bracket is clipped at zero). Each face reports an
indicator ``g`` (active where g > 0: ``delta`` and, for a wall, ``h_g - h``) for the
partial-element quadrature.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

CYLINDER = 0
WALL_PLUS = 1
WALL_MINUS = 2
RIM = 3

WINCH = 0
SHEAVE = 1


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
    face_open: np.ndarray     #: (nf,) half-opening of the groove at its top Y_o [m] (wall faces are active within)
    face_rim: np.ndarray      #: (nf,) rim width beyond the opening [m] (rim faces are active there)
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
    rho = math.sqrt(x * x + z * z)
    inv = 1.0 / max(rho, 1e-12)
    ex = x * inv
    ez = z * inv
    h = rho - (c.face_radius[f] + half_d)
    rho_dot = (x * vx + z * vz) * inv
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
        side = abs(y) - c.face_open[f]
        g = min(delta, min(side, c.face_rim[f] - side))
    else:
        ca, sa = c.face_cos[f], c.face_sin[f]
        sign = 1.0 if kind == WALL_PLUS else -1.0
        delta = sign * y * ca - h * sa
        ddelta = sign * vy * ca - rho_dot * sa
        nx, ny, nz = sa * ex, -sign * ca, sa * ez
        g = min(delta, min(c.face_depth[f] - h, c.face_open[f] - abs(y)))
    if delta <= 0.0:
        return 0.0, 0.0, 0.0, g, 0.0
    n = c.face_n[f]
    elastic = c.face_k[f] * (delta * math.sqrt(delta) if n == 1.5 else delta ** n)
    mag = elastic * max(1.0 + c.face_damping[f] * ddelta, 0.0)
    return mag * nx, mag * ny, mag * nz, g, elastic * delta / (n + 1.0)
