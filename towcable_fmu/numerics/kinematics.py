"""Ship rigid-body kinematics: rotation matrix W(24)-(25) and its time derivatives.

Conventions (docs/design.md): inertial frame z up; ship body frame X forward, Y port, Z up;
Euler angles yaw alpha, pitch beta, roll gamma with R = Rz(alpha) Ry(beta) Rx(gamma),
so that a point fixed in the ship at body coordinates ``s`` is at
``r = r_CG + R s`` in the inertial frame.

A ship state is a (3, 6) array: row k is the k-th time derivative (0 = value,
1 = rate, 2 = acceleration); columns are ``x, y, z`` [m] of the centre of gravity and
``roll, pitch, yaw`` [rad]. The angle rates are Euler-angle time derivatives, not body
angular velocities.

All functions are compiled with numba so the solver kernels can call them; they are
plain callables from Python too.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit

#: Column order of a ship state array.
SHIP_DOF_NAMES = ("x", "y", "z", "roll", "pitch", "yaw")


@njit(cache=True)
def _axis_rotations(roll: float, pitch: float, yaw: float):
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    cy, sy = np.cos(yaw), np.sin(yaw)
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    # first derivatives with respect to the angle
    drz = np.array([[-sy, -cy, 0.0], [cy, -sy, 0.0], [0.0, 0.0, 0.0]])
    dry = np.array([[-sp, 0.0, cp], [0.0, 0.0, 0.0], [-cp, 0.0, -sp]])
    drx = np.array([[0.0, 0.0, 0.0], [0.0, -sr, -cr], [0.0, cr, -sr]])
    # second derivatives with respect to the angle
    ddrz = np.array([[-cy, sy, 0.0], [-sy, -cy, 0.0], [0.0, 0.0, 0.0]])
    ddry = np.array([[-cp, 0.0, -sp], [0.0, 0.0, 0.0], [sp, 0.0, -cp]])
    ddrx = np.array([[0.0, 0.0, 0.0], [0.0, -cr, sr], [0.0, -sr, -cr]])
    return rz, ry, rx, drz, dry, drx, ddrz, ddry, ddrx


@njit(cache=True, inline="always")
def _add_product(a: np.ndarray, b: np.ndarray, c: np.ndarray, scale: float, out: np.ndarray) -> None:
    """out += scale * a @ b @ c for 3 x 3 matrices (loops: no BLAS call, no temporary)."""
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for k in range(3):
                ab = 0.0
                for m in range(3):
                    ab += a[i, m] * b[m, k]
                acc += ab * c[k, j]
            out[i, j] += scale * acc


@njit(cache=True)
def rotation_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Body-to-inertial rotation R = Rz(yaw) Ry(pitch) Rx(roll), W(24)-(25).

    Parameters
    ----------
    roll, pitch, yaw
        Euler angles [rad].

    Returns
    -------
    ndarray, shape (3, 3)
    """
    rz, ry, rx, _, _, _, _, _, _ = _axis_rotations(roll, pitch, yaw)
    r = np.zeros((3, 3))
    _add_product(rz, ry, rx, 1.0, r)
    return r


@njit(cache=True)
def rotation_derivatives(ship: np.ndarray):
    """Rotation matrix and its first and second time derivatives.

    Parameters
    ----------
    ship
        Ship state, shape (3, 6) (see module docstring).

    Returns
    -------
    R, Rdot, Rddot : ndarray, shape (3, 3) each
        R [-], dR/dt [1/s], d2R/dt2 [1/s^2].
    """
    roll, pitch, yaw = ship[0, 3], ship[0, 4], ship[0, 5]
    wr, wp, wy = ship[1, 3], ship[1, 4], ship[1, 5]
    ar, ap, ay = ship[2, 3], ship[2, 4], ship[2, 5]
    rz, ry, rx, drz, dry, drx, ddrz, ddry, ddrx = _axis_rotations(roll, pitch, yaw)
    r = np.zeros((3, 3))
    r1 = np.zeros((3, 3))
    r2 = np.zeros((3, 3))
    _add_product(rz, ry, rx, 1.0, r)
    # first derivative: one factor differentiated, times its angle's rate
    _add_product(drz, ry, rx, wy, r1)
    _add_product(rz, dry, rx, wp, r1)
    _add_product(rz, ry, drx, wr, r1)
    # second derivative: one factor twice (rate squared) or once (its acceleration), or two factors once
    _add_product(ddrz, ry, rx, wy * wy, r2)
    _add_product(drz, ry, rx, ay, r2)
    _add_product(rz, ddry, rx, wp * wp, r2)
    _add_product(rz, dry, rx, ap, r2)
    _add_product(rz, ry, ddrx, wr * wr, r2)
    _add_product(rz, ry, drx, ar, r2)
    _add_product(drz, dry, rx, 2.0 * wy * wp, r2)
    _add_product(drz, ry, drx, 2.0 * wy * wr, r2)
    _add_product(rz, dry, drx, 2.0 * wp * wr, r2)
    return r, r1, r2


@njit(cache=True)
def ship_point_kinematics(ship: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Position, velocity and acceleration of a point fixed in the ship.

    Parameters
    ----------
    ship
        Ship state, shape (3, 6).
    s
        Body-frame coordinates of the point [m], shape (3,).

    Returns
    -------
    ndarray, shape (3, 3)
        Rows: position [m], velocity [m/s], acceleration [m/s^2] in the inertial frame.
    """
    r, r1, r2 = rotation_derivatives(ship)
    out = np.empty((3, 3))
    for i in range(3):  # element loops: no shape checks (whose error formatting takes seconds to compile)
        out[0, i] = ship[0, i] + r[i, 0] * s[0] + r[i, 1] * s[1] + r[i, 2] * s[2]
        out[1, i] = ship[1, i] + r1[i, 0] * s[0] + r1[i, 1] * s[1] + r1[i, 2] * s[2]
        out[2, i] = ship[2, i] + r2[i, 0] * s[0] + r2[i, 1] * s[1] + r2[i, 2] * s[2]
    return out
