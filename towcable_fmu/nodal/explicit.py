"""Explicit time stepping of the nodal-position cable: lumped masses and leapfrog.

* Masses (MoorDyn's lumping, the row sums of the consistent matrices): node i carries half
  of each adjacent element's mass mu L0, the last node also the end mass (the lumped towed
  body, a bottom mass); the cable's added mass C_a rho A (I - u u^T) of each element goes to
  its two nodes by the same row sums of its two-point quadrature (the submerged Gauss points
  only, as :func:`towcable_fmu.hydro.cable.point_load` applies it), the body's added mass
  rho V C_m,b (its submerged fraction) to the last node. The 3x3 mass of a node is refreshed
  at every step (the added mass follows the elements' directions) and solved in closed form.
* Forces: the nodal residual (:func:`towcable_fmu.nodal.assembly.cable_residual`, the same
  element and body laws as the implicit path) at zero acceleration, once per step.
* Leapfrog, kick-drift-kick: v += h/2 a; q += h v; a = M^-1 F(q, v); v += h/2 a. The
  velocity-dependent forces (material damping, drag on cable and body) see the half-step
  velocity v_{n+1/2} = (q_{n+1} - q_n)/h: first order in h in the damping, one force
  evaluation per step, and the stability limit of
  :mod:`towcable_fmu.numerics.explicit_step` (exact for this lag; a predicted velocity,
  v_{n+1/2} + theta h a_n, halves the damping's error but lowers the limit, by 18 % at
  theta = 0.4 and the snapping cable's zeta = 0.27).
* The top node follows the ship from the drive table at the end of each step.

The state is (q, v, a) at the step's end (v the full-step velocity, a the accelerations the
next step's first kick uses): saved and restored bit for bit, and the run continues as if
uninterrupted. :func:`leapfrog_recording` runs a whole block of samples in one call,
sampling at the exact sample times (landing on them, or interpolated inside a step as the
implicit path does).
"""

from __future__ import annotations

import math

import numpy as np

from ..kernel_cache import njit
from ..hydro.towbody import submerged
from .assembly import cable_residual
from .element import _G0, _G1
from .integrators import (CLOCK_TIME, STAT_RESIDUALS, STAT_STEPS, Interpolant, NodalOptions, NodalState,
                          prescribe_top, record_sample)
from .model import NodalModel


def node_masses(m: NodalModel) -> np.ndarray:
    """Lumped structural mass of every node [kg] (n_nodes,): half of each adjacent element's
    mu L0, the end mass at the last node (added masses: :func:`lumped_accelerations`)."""
    half = 0.5 * m.mu * m.L0
    mass = np.zeros(m.n_nodes)
    mass[:-1] += half
    mass[1:] += half
    mass[-1] += m.end_mass
    return mass


@njit(cache=True, error_model="numpy")
def lumped_accelerations(m: NodalModel, mass: np.ndarray, q: np.ndarray, v: np.ndarray, t: float,
                         zero: np.ndarray, r: np.ndarray, added: np.ndarray, a: np.ndarray) -> None:
    """Accelerations [m/s^2] of the free nodes into ``a`` (node 0's entries kept): the forces
    at positions ``q`` [m] and velocities ``v`` [m/s] through the lumped masses ``mass`` [kg]
    (:func:`node_masses`) and the cable's and body's added masses.

    ``zero`` (zeros, q.size), ``r`` (q.size) and ``added`` (n_nodes, 6) are scratch.
    """
    cable_residual(m, q, v, zero, t, r)  # minus the forces (no inertia at a = 0)
    n_nodes = m.n_nodes
    added[:, :] = 0.0
    w = m.water
    if w.enabled:
        for e in range(n_nodes - 1):
            i = 3 * e
            s0, s1 = 0.0, 0.0  # row sums of the element's quadrature, submerged points only
            for g in range(2):
                xi = _G0 if g == 0 else _G1
                if (1.0 - xi) * q[i + 2] + xi * q[i + 5] < w.surface_z:
                    s0 += 0.5 * (1.0 - xi)
                    s1 += 0.5 * xi
            if s0 + s1 == 0.0:
                continue
            dx, dy, dz = q[i + 3] - q[i], q[i + 4] - q[i + 1], q[i + 5] - q[i + 2]
            inv2 = 1.0 / (dx * dx + dy * dy + dz * dz)
            c = m.cm[e] * w.density * m.area[e] * m.L0[e]
            _add_normal(added[e], c * s0 * inv2, dx, dy, dz, c * s0)
            _add_normal(added[e + 1], c * s1 * inv2, dx, dy, dz, c * s1)
        if m.body.enabled:
            last = n_nodes - 1
            wet = submerged(w, m.body, q[3 * last + 2])
            for k in range(3):
                added[last, k] += wet * m.body.added_mass[k]
    for node in range(1, n_nodes):
        i = 3 * node
        p = added[node]
        xx, yy, zz = mass[node] + p[0], mass[node] + p[1], mass[node] + p[2]
        xy, xz, yz = p[3], p[4], p[5]
        # the symmetric 3x3 inverse by cofactors (positive definite: mass plus a semi-definite part)
        c00, c11, c22 = yy * zz - yz * yz, xx * zz - xz * xz, xx * yy - xy * xy
        c01, c02, c12 = xz * yz - xy * zz, xy * yz - xz * yy, xy * xz - xx * yz
        inv_det = 1.0 / (xx * c00 + xy * c01 + xz * c02)
        fx, fy, fz = -r[i], -r[i + 1], -r[i + 2]
        a[i] = (c00 * fx + c01 * fy + c02 * fz) * inv_det
        a[i + 1] = (c01 * fx + c11 * fy + c12 * fz) * inv_det
        a[i + 2] = (c02 * fx + c12 * fy + c22 * fz) * inv_det


@njit(cache=True, inline="always")
def _add_normal(p: np.ndarray, k2: float, dx: float, dy: float, dz: float, k: float) -> None:
    """Add k (I - d d^T / |d|^2) [kg] to a node's symmetric 3x3 ``p`` (xx, yy, zz, xy, xz, yz);
    ``k2`` = k / |d|^2."""
    p[0] += k - k2 * dx * dx
    p[1] += k - k2 * dy * dy
    p[2] += k - k2 * dz * dz
    p[3] -= k2 * dx * dy
    p[4] -= k2 * dx * dz
    p[5] -= k2 * dy * dz


# error_model "numpy": a division by zero gives inf or NaN (the run stops at a non-finite
# output) instead of a Python exception, whose checks halve the speed of the force loop
@njit(cache=True, error_model="numpy")
def leapfrog_recording(m: NodalModel, mass: np.ndarray, options: NodalOptions, state: NodalState,
                       samples: np.ndarray, drive_t: np.ndarray, drive_x: np.ndarray, values: np.ndarray,
                       ip: Interpolant, interpolate: bool, t_land: float) -> int:
    """Leapfrog steps of ``options.h_max`` [s] to each time in ``samples`` [s], recording
    :func:`~towcable_fmu.nodal.integrators.output_values` in ``values``: the contract of
    :func:`~towcable_fmu.nodal.integrators.advance_recording` (landing on every sample, or with
    ``interpolate`` keeping the steps, never passing ``t_land`` [s], and reading samples inside
    a step from the cubic Hermite interpolant of its ends). ``mass``: :func:`node_masses`.

    Returns
    -------
    int
        Number of samples reached (fewer when an output is not finite: a blown-up run; the
        state is then not a valid one and the caller rolls back).
    """
    q, v, a, clock, stats = state.q, state.v, state.x, state.clock, state.stats
    n = q.size
    zero = np.zeros(n)
    r = np.empty(n)
    added = np.empty((m.n_nodes, 6))
    h_nom = options.h_max
    for s in range(samples.size):
        target = samples[s]
        tol = 1e-12 * max(1.0, abs(target))
        while clock[CLOCK_TIME] < target - tol:
            t = clock[CLOCK_TIME]
            h = h_nom
            if interpolate:
                # (the clock sums thousands of steps: no extra step for its round-off)
                n_rem = math.ceil((t_land - t) / h - 1e-6)
                h = h if n_rem > 2 else (t_land - t) / n_rem
            else:
                h = min(h, target - t)
            if t + h > target + tol:  # the sample falls inside this step: keep its start
                ip.start[0, :], ip.start[1, :], ip.start[2, :] = q, v, a
                ip.t0[0] = t
            half = 0.5 * h
            for i in range(3, n):
                v[i] += half * a[i]
                q[i] += h * v[i]
            prescribe_top(m, drive_t, drive_x, t + h, q, v, a)
            lumped_accelerations(m, mass, q, v, t + h, zero, r, added, a)
            for i in range(3, n):
                v[i] += half * a[i]
            clock[CLOCK_TIME] = t + h
            stats[STAT_STEPS] += 1
            stats[STAT_RESIDUALS] += 1
        if not record_sample(m, ip, q, v, a, clock[CLOCK_TIME], target, drive_t, drive_x, values[s]):
            return s
    return samples.size
