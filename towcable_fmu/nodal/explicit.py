"""Explicit time stepping of the nodal-position cable: lumped masses and leapfrog.

* Masses (MoorDyn's lumping, the row sums of the consistent matrices): node i carries half
  of each adjacent element's mass mu L0, the last node also the end mass (the lumped towed
  body, a bottom mass); the cable's added mass C_a rho A (I - u u^T) of each element goes to
  its two nodes by the same row sums of its two-point quadrature (the submerged Gauss points
  only, as :func:`towcable_fmu.hydro.cable.point_load` applies it), the body's added mass
  rho V C_m,b (its submerged fraction) to the last node. The 3x3 mass of a node is refreshed
  at every step (the added mass follows the elements' directions) and solved in closed form.
* Forces: :func:`towcable_fmu.nodal.explicit_kernel.cable_forces`, once per step: the
  implicit path's element and body laws (its residual at zero acceleration, tested), with
  the model's constants read once per call and nothing allocated per step.
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
from .explicit_kernel import cable_forces, explicit_outputs, lumped_cable, lumped_forces, solve_accelerations
from .integrators import (CLOCK_TIME, STAT_RESIDUALS, STAT_STEPS, Interpolant, NodalOptions, NodalState,
                          interpolate_step, prescribe_top_with)
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
def lumped_accelerations(m: NodalModel, mass: np.ndarray, q: np.ndarray, v: np.ndarray, f: np.ndarray,
                         added: np.ndarray, a: np.ndarray) -> None:
    """Accelerations [m/s^2] of the free nodes into ``a`` (node 0's entries kept): the forces
    at positions ``q`` [m] and velocities ``v`` [m/s] (:func:`.explicit_kernel.cable_forces`)
    through the lumped masses ``mass`` [kg] (:func:`node_masses`) and the cable's and body's
    added masses. ``f`` (q.size) and ``added`` (n_nodes, 6) are scratch."""
    lumped_forces(m, mass, q, v, f, added)
    solve_accelerations(m.water.enabled, mass, 1.0 / mass, f, added, a)


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
    The constants are read out of ``m`` once (:func:`.explicit_kernel.lumped_cable`) and
    nothing is allocated in the loop.

    Returns
    -------
    int
        Number of samples reached (fewer when an output is not finite: a blown-up run; the
        state is then not a valid one and the caller rolls back).
    """
    q, v, a, clock, stats = state.q, state.v, state.x, state.clock, state.stats
    n = q.size
    c = lumped_cable(m, mass)
    n_nodes, wet, body_on, closed, water = c.n_nodes, c.wet, c.body_on, c.closed, c.water
    gravity, end_mass = c.gravity, c.end_mass
    elements, hydro, kind, flow, body, inv_mass = c.elements, c.hydro, c.kind, c.flow, c.body, c.inv_mass
    f = np.empty(n)
    added = np.zeros((n_nodes, 6))
    ship, basis = np.empty((3, 6)), np.empty((6, 3))
    on_ship, top_point = m.top_on_ship, m.top_point
    start, state_t, t0 = ip.start, ip.state, ip.t0
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
                for i in range(n):
                    start[0, i], start[1, i], start[2, i] = q[i], v[i], a[i]
                t0[0] = t
            half = 0.5 * h
            for i in range(3, n):
                v[i] += half * a[i]
                q[i] += h * v[i]
            prescribe_top_with(on_ship, top_point, drive_t, drive_x, t + h, q, v, a, ship, basis)
            if closed:  # (two copies of the loop: the closed-form drag's has no call)
                cable_forces(n_nodes, wet, body_on, True, water, gravity, end_mass, elements, hydro, kind, flow, body,
                             q, v, f, added)
            else:
                cable_forces(n_nodes, wet, body_on, False, water, gravity, end_mass, elements, hydro, kind, flow,
                             body, q, v, f, added)
            solve_accelerations(wet, mass, inv_mass, f, added, a)
            for i in range(3, n):
                v[i] += half * a[i]
            clock[CLOCK_TIME] = t + h
            stats[STAT_STEPS] += 1
            stats[STAT_RESIDUALS] += 1
        row = values[s]
        t = clock[CLOCK_TIME]
        if target >= t - tol:
            explicit_outputs(wet, water, flow, elements, hydro, kind, q, v, a, row)
        else:
            interpolate_step(on_ship, top_point, start, t0[0], state_t, q, v, a, t, target, drive_t, drive_x, ship,
                             basis)
            explicit_outputs(wet, water, flow, elements, hydro, kind, state_t[0], state_t[1], state_t[2], row)
        for k in range(row.size):
            if not math.isfinite(row[k]):
                return s
    return samples.size
