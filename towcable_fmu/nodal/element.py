"""One straight two-node element in nodal positions: its loads on the residual.

With linear shape functions N = [(1 - xi) I, xi I] (eq. 5), unit direction
u = (X_2 - X_1)/L and current length L:

* strain from current against original length, eqs. 7-11: eps = L/L0 - 1 = B X - 1 with
  B = [-u, u]/L0;
* elastic force, eq. 13: K X - F0 = EA L B^T eps = EA (L/L0) eps [-u, u], a tension
  EA eps L/L0 = EA eps (1 + eps) as the paper writes it (the derivative of the strain
  energy EA L0 eps^2 / 2 with respect to the current length is EA eps: they differ at
  O(eps^2)); a tension-only material sets the elastic part to 0 when eps < 0;
* material damping C = c K, eqs. 14-15: C Xdot = BA (L/L0) epsdot [-u, u] with
  BA = c EA [N s] (the scene's segment ``damping``) and epsdot = u . (V_2 - V_1)/L0;
  it acts also in a slack element, as in the peers' Kelvin-Voigt law. With the segment's
  ``axial_law = "kelvin_voigt"`` the force is the peers' law itself,
  N = EA max(eps, 0) + BA epsdot, without the factor L/L0 (which stiffens the paper's law
  by 2 eps: 0.1 % at the snapping case's static strain);
* consistent mass, eq. 12: M = mu L0/6 [[2I, I], [I, 2I]] (constant);
* gravity and buoyancy, eqs. 24-25, and the fluid loads, eqs. 16-23: drag with the
  segment's loading functions, added mass C_a rho A (I - u u^T) acting on the normal
  acceleration, fluid inertia. These are evaluated per unit unstretched length at the
  two Gauss points of the element by the same point kernel as the ANCF cable
  (:func:`towcable_fmu.hydro.cable.point_load`).

Deviations from the paper, and why:

* Quadrature. The paper integrates the drag with the matrices A_1, A_2 of eq. 22, i.e.
  exactly for a drag quadratic in the linearly interpolated velocity with one angle of
  attack and one sign per element; two Gauss points integrate the same cubic
  integrands exactly (tested), and evaluate the angle and the sign at each point. The
  added-mass matrix of eq. 18 (integrand quadratic in xi) is also exact.
* Fluid inertia. Eq. 18d, F_a = M_a dV_f/dt, has only the added-mass part; the
  Froude-Krylov part rho A dV_f,n/dt of an accelerating flow is included (as in the
  ANCF cable; docs/design.md on W(69b)). It vanishes in still water.
* Lengths. The fluid loads are per unstretched length (eq. 22 uses the current length;
  the difference is the strain, below 0.5 % for steel).
"""

from __future__ import annotations

import math

import numpy as np

from ..jit.kernel_cache import njit
from ..hydro.cable import Section, point_load
from .model import NodalModel

#: Gauss points on [0, 1] (two points, weights 1/2): exact for cubic integrands.
_G0 = 0.5 - 0.5 / math.sqrt(3.0)
_G1 = 0.5 + 0.5 / math.sqrt(3.0)


@njit(cache=True, inline="always")
def axial_force(m: NodalModel, e: int, q: np.ndarray, v: np.ndarray) -> tuple:
    """Axial force N [N] (tension positive) of element ``e``, its current length L [m]
    and unit direction u (3 floats), from positions ``q`` [m] and velocities ``v`` [m/s]."""
    i = 3 * e
    dx, dy, dz = q[i + 3] - q[i], q[i + 4] - q[i + 1], q[i + 5] - q[i + 2]
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    # an element collapsed to a point (a diverging Newton iterate) has no direction: NaN,
    # which rejects the step (the compiled division would raise ZeroDivisionError instead)
    inv = 1.0 / length if length > 0.0 else math.nan
    ux, uy, uz = dx * inv, dy * inv, dz * inv
    l0 = m.L0[e]
    eps = length / l0 - 1.0
    eps_rate = (ux * (v[i + 3] - v[i]) + uy * (v[i + 4] - v[i + 1]) + uz * (v[i + 5] - v[i + 2])) / l0
    elastic = m.EA[e] * (max(eps, 0.0) if m.tension_only[e] else eps)
    factor = 1.0 if m.kelvin_voigt[e] else length / l0
    return factor * (elastic + m.BA[e] * eps_rate), length, ux, uy, uz


@njit(cache=True, inline="always")
def add_element(m: NodalModel, e: int, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float,
                r: np.ndarray) -> None:
    """Add element ``e``'s part of the residual r = M a + f_int - f_ext [N] (full vector).

    Parameters
    ----------
    q, v, a
        Nodal positions [m], velocities [m/s] and accelerations [m/s^2] of all nodes.
    t
        Time [s] (turbulence-free flow; kept for the flow kernels).
    """
    i = 3 * e
    n, _, ux, uy, uz = axial_force(m, e, q, v)
    ms = m.mu[e] * m.L0[e] / 6.0
    _add_pair(r, i, ms * (2.0 * a[i] + a[i + 3]) - n * ux, ms * (2.0 * a[i + 1] + a[i + 4]) - n * uy,
              ms * (2.0 * a[i + 2] + a[i + 5]) - n * uz + 0.5 * m.mu[e] * m.L0[e] * m.gravity, 1.0, 0.0)
    _add_pair(r, i, ms * (a[i] + 2.0 * a[i + 3]) + n * ux, ms * (a[i + 1] + 2.0 * a[i + 4]) + n * uy,
              ms * (a[i + 2] + 2.0 * a[i + 5]) + n * uz + 0.5 * m.mu[e] * m.L0[e] * m.gravity, 0.0, 1.0)
    w = m.water
    if not w.enabled:
        return
    section = Section(m.kind[e], m.d[e], m.area[e], m.cd[e], m.g_amp[e], m.cm[e], m.cdt[e])
    for g in range(2):
        xi = _G0 if g == 0 else _G1
        pz = (1.0 - xi) * q[i + 2] + xi * q[i + 5]
        if pz >= w.surface_z:
            continue
        vx = (1.0 - xi) * v[i] + xi * v[i + 3]
        vy = (1.0 - xi) * v[i + 1] + xi * v[i + 4]
        vz = (1.0 - xi) * v[i + 2] + xi * v[i + 5]
        ax = (1.0 - xi) * a[i] + xi * a[i + 3]
        ay = (1.0 - xi) * a[i + 1] + xi * a[i + 4]
        az = (1.0 - xi) * a[i + 2] + xi * a[i + 5]
        fx, fy, fz = point_load(w, section, t, pz, (ux, uy, uz), (vx, vy, vz), (ax, ay, az))
        wt = 0.5 * m.L0[e]
        _add_pair(r, i, -wt * fx, -wt * fy, -wt * fz, 1.0 - xi, xi)


@njit(cache=True, inline="always")
def _add_pair(r: np.ndarray, i: int, fx: float, fy: float, fz: float, c0: float, c1: float) -> None:
    """Add c0 (fx, fy, fz) to the node at coordinate i and c1 times it to the next node."""
    r[i] += c0 * fx
    r[i + 1] += c0 * fy
    r[i + 2] += c0 * fz
    r[i + 3] += c1 * fx
    r[i + 4] += c1 * fy
    r[i + 5] += c1 * fz
