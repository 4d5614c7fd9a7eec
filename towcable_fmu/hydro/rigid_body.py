"""A rigid 6-DOF towed body at the end of the cable (nodal-position or ANCF).

The nodal-position paper (Sun et al., "Dynamic modeling of cable towed body using nodal
position finite element method", section 3.2) models the sea-trial body "as a rigid
body" and gives its mass, volume, length and principal inertias (Table 4) but no
equations; these are the standard Newton-Euler equations, written as residuals like the
cable's eq. 27.

Coordinates (six, appended after the free cable nodes): the centre of gravity (CG)
``r`` [m] (inertial) and the Euler angles ``(roll, pitch, yaw)`` [rad] of
R = Rz(yaw) Ry(pitch) Rx(roll) (docs/design.md, W(24)); body axes x forward, y port, z up.
The body angular velocity is ``w = G(angles) d(angles)/dt``. Euler angles are singular
at pitch = +-pi/2: the step fails there (|cos pitch| < 1e-3) and the scene check keeps
the initial pitch below 1.4 rad; a towed body trims at small pitch.

Residuals (generalised forces of the virtual work, zero at the solution):

* translation: ``m a + R A R^T a - R f_b - F_g - F_B + r_N``,
* rotation: ``G^T [(J + J_a) dw/dt + w x J w - tau]`` (body axes),

with ``A = diag(rho V C_m,b)`` the added mass and ``f_b`` the fluid force in body axes:
drag ``1/2 rho (C_D A)_i |u_i| u_i`` plus linear damping ``c_i u_i`` of the relative flow
``u = R^T (V_f - v - R (w x d))`` at the drag centre d, and the fluid inertia
``rho V (C_m,b + 1) (R^T dV_f/dt)_i``. Moments ``tau`` about the CG: buoyancy
``rho V g`` at the centre of buoyancy, the drag at d, rotational drag ``-k |w| w`` and
damping ``-c w``. Gravity acts at the CG. Below the surface (the CG below
``water.surface_z``, or in waves the instantaneous surface above it) the fluid terms act,
above it only gravity; in waves the flow includes their velocity and acceleration at
the CG (:mod:`towcable_fmu.hydro.waves`).

The cable: its last node N is the tow point p (a spherical joint), eliminated exactly:
``X_N = r + R p``, ``V_N = v + R (w x p)``, ``A_N = a + R (dw/dt x p + w x (w x p))``.
The cable's residual at node N, ``r_N`` (the force the body must exert on the cable end),
is carried to the body by the transpose of that map: ``r_N`` on the translation and
``G^T (p x R^T r_N)`` on the rotation. No link stiffness, so no new stiff mode (the
explicit RK4 keeps its step).

On the ANCF cable (:mod:`towcable_fmu.ancf.system`) the same :func:`body_residual`
is used, but the last node keeps its coordinates (its slopes must stay free and the
assembly is built around whole nodes): the body's six coordinates follow the cable's,
and a stiff spring-damper link ``f = k (X_N - p) + c (V_N - dp/dt)`` joins the node to
the tow point; ``r_N`` above is then ``-f``. The implicit integrator carries the link's
stiffness (k = 100 EA/L of the last element, ``towcable_fmu.ancf.forces.rigid_link.RIGID_LINK_FACTOR``).

Simplifications (the paper gives none of these terms): the added mass is diagonal
in body axes without the Munk moment or added-mass Coriolis terms; the rotational
added inertia carries no gyroscopic term; the flow is taken at the CG depth.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..jit.kernel_cache import njit
from .water import WaterModel
from .waves import flow_at, surface_height

if TYPE_CHECKING:
    from ..scene.model import Scene

#: Number of body coordinates.
NDOF = 6


class RigidBodyModel(NamedTuple):
    """Rigid towed body for the kernels (``enabled`` False: no rigid body).

    The per-axis data are the rows of one array (few arrays keep the model tuple that
    every kernel receives small; a larger one slows the whole cable down)."""

    enabled: bool
    mass: float               #: m [kg]
    volume: float             #: displaced volume V [m^3] (0 in a dry scene)
    inertia: np.ndarray       #: (3, 3) inertia tensor J about the CG, body axes [kg m^2]
    axes: np.ndarray          #: (NROWS, 3) per-axis data, rows indexed by the ``ROW_*`` constants


#: Rows of :attr:`RigidBodyModel.axes` (body axes): rotational added inertia [kg m^2],
#: added mass rho V C_m,b [kg], fluid inertia rho V (C_m,b + 1) [kg], tow point, centre of
#: buoyancy and drag centre relative to the CG [m], sum of C_D A [m^2], linear damping
#: [N s/m], rotational drag [N m s^2], rotational damping [N m s].
(ROW_ADDED_INERTIA, ROW_ADDED_MASS, ROW_FLUID_INERTIA, ROW_TOW, ROW_CB, ROW_DRAG_CENTRE, ROW_CDA,
 ROW_LINEAR_DAMPING, ROW_ROT_DRAG, ROW_ROT_DAMPING) = range(10)
NROWS = 10


def no_rigid_body() -> RigidBodyModel:
    """The (disabled) rigid-body data of a scene without one."""
    return RigidBodyModel(False, 0.0, 0.0, np.eye(3), np.zeros((NROWS, 3)))


@njit(cache=True)
def rotation(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """R = Rz(yaw) Ry(pitch) Rx(roll) (3, 3): body axes -> inertial axes."""
    cf, sf = math.cos(roll), math.sin(roll)
    ct, st = math.cos(pitch), math.sin(pitch)
    cp, sp = math.cos(yaw), math.sin(yaw)
    r = np.empty((3, 3))
    r[0, 0], r[0, 1], r[0, 2] = cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf
    r[1, 0], r[1, 1], r[1, 2] = sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf
    r[2, 0], r[2, 1], r[2, 2] = -st, ct * sf, ct * cf
    return r


@njit(cache=True)
def angular_kinematics(q: np.ndarray, v: np.ndarray, a: np.ndarray) -> tuple:
    """Rotation matrix, rate map G (w = G d(angles)/dt), body angular velocity w [rad/s]
    and acceleration dw/dt [rad/s^2] from the body coordinates (6 each: CG and angles)."""
    f, th = q[3], q[4]
    cf, sf, ct, st = math.cos(f), math.sin(f), math.cos(th), math.sin(th)
    fd, td, pd = v[3], v[4], v[5]
    fa, ta, pa = a[3], a[4], a[5]
    g = np.zeros((3, 3))
    g[0, 0], g[0, 2] = 1.0, -st
    g[1, 1], g[1, 2] = cf, ct * sf
    g[2, 1], g[2, 2] = -sf, ct * cf
    w = np.empty(3)
    w[0] = fd - pd * st
    w[1] = td * cf + pd * ct * sf
    w[2] = -td * sf + pd * ct * cf
    wd = np.empty(3)
    wd[0] = fa - pa * st - pd * td * ct
    wd[1] = ta * cf - td * fd * sf + pa * ct * sf - pd * td * st * sf + pd * fd * ct * cf
    wd[2] = -ta * sf - td * fd * cf + pa * ct * cf - pd * td * st * cf - pd * fd * ct * sf
    return rotation(q[3], q[4], q[5]), g, w, wd


@njit(cache=True, inline="always")
def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.empty(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


@njit(cache=True, inline="always")
def _mv(m: np.ndarray, x: np.ndarray) -> np.ndarray:
    """m x for 3x3 m (loops: BLAS costs more than the product)."""
    out = np.empty(3)
    for i in range(3):
        out[i] = m[i, 0] * x[0] + m[i, 1] * x[1] + m[i, 2] * x[2]
    return out


@njit(cache=True, inline="always")
def _mtv(m: np.ndarray, x: np.ndarray) -> np.ndarray:
    """m^T x for 3x3 m."""
    out = np.empty(3)
    for i in range(3):
        out[i] = m[0, i] * x[0] + m[1, i] * x[1] + m[2, i] * x[2]
    return out


@njit(cache=True)
def tow_point_state(b: RigidBodyModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, xn: np.ndarray,
                    vn: np.ndarray, an: np.ndarray) -> None:
    """Position [m], velocity [m/s] and acceleration [m/s^2] of the tow point (the cable's
    last node) from the body coordinates, into ``xn``, ``vn``, ``an`` (3 each)."""
    rot, _, w, wd = angular_kinematics(q, v, a)
    wp = _cross(w, b.axes[ROW_TOW])
    acc = _cross(wd, b.axes[ROW_TOW]) + _cross(w, wp)
    xb, vb, ab = _mv(rot, b.axes[ROW_TOW]), _mv(rot, wp), _mv(rot, acc)
    for c in range(3):  # (element-wise: a slice assignment compiles a shape-checking error path)
        xn[c] = q[c] + xb[c]
        vn[c] = v[c] + vb[c]
        an[c] = a[c] + ab[c]


@njit(cache=True)
def body_residual(w: WaterModel, b: RigidBodyModel, gravity: float, q: np.ndarray, v: np.ndarray,
                  a: np.ndarray, t: float, r_tow: np.ndarray, out: np.ndarray) -> None:
    """The six body residuals (module docstring) into ``out``.

    Parameters
    ----------
    q, v, a
        Body coordinates, their rates and accelerations (CG [m], angles [rad]).
    r_tow
        The cable's residual at its last node [N] (the force the body exerts on the cable).
    """
    rot, g, om, omd = angular_kinematics(q, v, a)
    force = np.zeros(3)      # inertial, on the body (without inertia of the body itself)
    moment = np.zeros(3)     # body axes, about the CG
    force[2] -= b.mass * gravity
    jeff = b.inertia.copy()
    if q[2] < surface_height(w, q[0], q[1], t)[0]:
        vf = np.empty(3)
        af = np.empty(3)
        flow_at(w, q[:3], t, vf, af)
        buoy = np.zeros(3)
        buoy[2] = w.density * b.volume * w.gravity
        force += buoy
        moment += _cross(b.axes[ROW_CB], _mtv(rot, buoy))
        u = _mtv(rot, vf - v[:3] - _mv(rot, _cross(om, b.axes[ROW_DRAG_CENTRE])))
        ab = _mtv(rot, a[:3])
        afb = _mtv(rot, af)
        fb = np.empty(3)
        for k in range(3):
            fb[k] = (0.5 * w.density * b.axes[ROW_CDA, k] * abs(u[k]) * u[k] + b.axes[ROW_LINEAR_DAMPING, k] * u[k])
        moment += _cross(b.axes[ROW_DRAG_CENTRE], fb)
        for k in range(3):
            fb[k] += b.axes[ROW_FLUID_INERTIA, k] * afb[k] - b.axes[ROW_ADDED_MASS, k] * ab[k]
            moment[k] -= b.axes[ROW_ROT_DRAG, k] * abs(om[k]) * om[k] + b.axes[ROW_ROT_DAMPING, k] * om[k]
            jeff[k, k] += b.axes[ROW_ADDED_INERTIA, k]
        force += _mv(rot, fb)
    for k in range(3):
        out[k] = b.mass * a[k] - force[k] + r_tow[k]
    moment -= _cross(b.axes[ROW_TOW], _mtv(rot, r_tow))
    e = _mv(jeff, omd) + _cross(om, _mv(b.inertia, om)) - moment
    moments = _mtv(g, e)
    for k in range(3):
        out[3 + k] = moments[k]


@njit(cache=True)
def attitude_ok(q: np.ndarray) -> bool:
    """False when the pitch q[4] is within 1e-3 of the Euler-angle singularity."""
    return abs(math.cos(q[4])) > 1e-3


def hanging_coordinates(b: RigidBodyModel, tow_point: np.ndarray, attitude: np.ndarray) -> np.ndarray:
    """The body's six coordinates (CG [m], roll, pitch, yaw [rad]) at ``attitude`` with its
    tow point at ``tow_point`` (inertial) [m]: where a cable's last node holds it at the start."""
    return np.concatenate([tow_point - rotation(*attitude) @ b.axes[ROW_TOW], attitude])


def build_rigid_body(scene: Scene) -> RigidBodyModel:
    """Rigid-body data of a scene (disabled unless ``towbody.model == "rigid"``)."""
    body = scene.towbody
    if body is None or body.model != "rigid":
        return no_rigid_body()
    rb = body.rigid
    jxx, jyy, jzz = rb.inertia
    jxy, jxz, jyz = rb.inertia_products
    inertia = np.array([[jxx, jxy, jxz], [jxy, jyy, jyz], [jxz, jyz, jzz]], dtype=float)
    w = scene.water
    volume = scene.towbody_volume()
    rho = w.density if w is not None else 0.0
    cm = np.array(body.added_mass_coefficient, dtype=float)
    cda = np.zeros(3)
    for part in body.parts:
        cda += np.array(part.area) * np.array(part.drag_coefficient)
    axes = np.zeros((NROWS, 3))
    axes[ROW_ADDED_INERTIA] = rb.added_inertia
    axes[ROW_ADDED_MASS] = rho * volume * cm
    axes[ROW_FLUID_INERTIA] = rho * volume * (cm + 1.0)
    axes[ROW_TOW] = rb.tow_point
    axes[ROW_CB] = rb.buoyancy_centre
    axes[ROW_DRAG_CENTRE] = rb.drag_centre
    axes[ROW_CDA] = cda
    axes[ROW_LINEAR_DAMPING] = rb.linear_damping
    axes[ROW_ROT_DRAG] = rb.rotational_drag
    axes[ROW_ROT_DAMPING] = rb.rotational_damping
    return RigidBodyModel(True, float(body.mass), float(volume), inertia, axes)
