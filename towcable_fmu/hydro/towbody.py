"""Hydrodynamic forces on the lumped towed body, W(85)-(92).

While the body is below the surface: buoyancy ``rho V g``; drag per axis
``1/2 rho (sum C_D A)_i |V_i| V_i`` of the relative flow ``V = V_f - V_b`` W(87); a lift
of constant direction ``1/2 rho A C_L (V . axis)^2`` (section 5.2); the inertia force
``rho V (C_m,b + 1) dV_f/dt`` W(88); and the added mass ``rho V C_m,b`` per axis W(89),
which enters the residual with the body's acceleration and the iteration matrix as a
mass W(92). Above the surface only its weight acts (part of the constant loads).

A body of height ``h > 0`` (``towbody.height``) passes through the surface over that
height: all of these forces grow linearly with its submerged fraction
``clip((z_s - z) / h + 1/2, 0, 1)`` of its centre's depth below the surface ``z_s``
(a body of upright sides); the iteration matrix leaves out the fraction's change with
depth (rho V g / h, small beside the cable's axial stiffness). ``h = 0``: a point, wet
or dry all at once.

In waves (:mod:`towcable_fmu.hydro.waves`) the surface is the instantaneous one above the
body's centre, the relative flow includes the waves' particle velocity and the inertia
force their acceleration, all at the centre (Wheeler-stretched; the body is small
against the wave length, so neither its diffraction of the waves nor the variation of
the kinematics over it is modelled, nor the slamming impulse as it enters the water).
The iteration matrix leaves out how the waves' kinematics and surface change with the
body's position (of order rho C_D A |V| k omega a, small beside the cable's axial
stiffness); the residual is exact, so Newton converges to the same solution.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..jit.kernel_cache import njit
from .water import WaterModel
from .waves import flow_at, surface_height


class BodyHydro(NamedTuple):
    """Towed-body data for the kernels (``enabled`` False: no body in water)."""

    enabled: bool
    index: int              #: first coordinate of the body's position
    volume: float           #: V [m^3]
    height: float           #: h [m] over which it passes through the surface (0: a point)
    added_mass: np.ndarray  #: (3,) rho V C_m,b [kg]
    inertia: np.ndarray     #: (3,) rho V (C_m,b + 1) [kg]
    cda: np.ndarray         #: (3,) sum of C_D A per axis [m^2]
    lift_k: float           #: 1/2 rho A C_L [kg/m]
    lift_dir: np.ndarray    #: (3,) unit direction of the lift
    lift_axis: np.ndarray   #: (3,) unit flow direction that makes lift
    calls: np.ndarray       #: (1,) int64 counter of evaluations (to verify skipping)


def no_body() -> BodyHydro:
    """The body data of a scene without a body in water."""
    return BodyHydro(False, 0, 0.0, 0.0, np.zeros(3), np.zeros(3), np.zeros(3), 0.0, np.zeros(3), np.zeros(3),
                     np.zeros(1, dtype=np.int64))


@njit(cache=True, inline="always")
def submerged(w: WaterModel, b: BodyHydro, r: np.ndarray, t: float) -> float:
    """Submerged fraction [-] of the body with its centre at ``r`` [m] at time ``t`` [s]."""
    surface = surface_height(w, r[0], r[1], t)[0]
    if b.height <= 0.0:
        return 1.0 if r[2] < surface else 0.0
    return min(max((surface - r[2]) / b.height + 0.5, 0.0), 1.0)


@njit(cache=True)
def body_force(w: WaterModel, b: BodyHydro, r: np.ndarray, rv: np.ndarray, ra: np.ndarray, t: float,
               out: np.ndarray) -> bool:
    """Hydrodynamic force on the body [N] (including its added-mass inertia) into ``out``.

    Returns False (and zero force) when the body is out of the water.
    """
    out[:] = 0.0
    wet = submerged(w, b, r, t)
    if wet == 0.0:
        return False
    b.calls[0] += 1
    vf = np.empty(3)
    af = np.empty(3)
    flow_at(w, r, t, vf, af)
    rel = vf - rv
    out[2] += w.density * b.volume * w.gravity
    along = 0.0
    for k in range(3):
        out[k] += 0.5 * w.density * b.cda[k] * abs(rel[k]) * rel[k]
        out[k] += b.inertia[k] * af[k] - b.added_mass[k] * ra[k]
        along += rel[k] * b.lift_axis[k]
    for k in range(3):
        out[k] = wet * (out[k] + b.lift_k * along * along * b.lift_dir[k])
    return True


# IR-inlined into its only caller (ancf.system): a kernel of its own would be one more library for the
# caller to link and optimise again, with all the code beneath it.
@njit(cache=True, inline="always")
def add_residual(w: WaterModel, b: BodyHydro, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float,
                 out: np.ndarray) -> None:
    """Subtract the body's hydrodynamic force from the residual."""
    i0 = b.index
    f = np.empty(3)
    if body_force(w, b, q[i0:i0 + 3], v[i0:i0 + 3], a[i0:i0 + 3], t, f):
        for k in range(3):
            out[i0 + k] -= f[k]


@njit(cache=True, inline="always")  # (as add_residual)
def add_jacobian(w: WaterModel, b: BodyHydro, q: np.ndarray, v: np.ndarray, t: float, ca: float, cv: float,
                 block: np.ndarray) -> bool:
    """The body's part of ``ca M + cv C`` (3x3, added to ``block``); False out of the water."""
    i0 = b.index
    wet = submerged(w, b, q[i0:i0 + 3], t)
    if wet == 0.0:
        return False
    vf = np.empty(3)
    af = np.empty(3)
    flow_at(w, q[i0:i0 + 3], t, vf, af)
    rel = vf - v[i0:i0 + 3]
    along = 0.0
    for k in range(3):
        along += rel[k] * b.lift_axis[k]
    for k in range(3):
        block[k, k] += wet * (ca * b.added_mass[k] + cv * w.density * b.cda[k] * abs(rel[k]))
        for m in range(3):
            block[k, m] += wet * cv * 2.0 * b.lift_k * along * b.lift_dir[k] * b.lift_axis[m]
    return True
