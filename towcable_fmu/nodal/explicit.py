"""Explicit time stepping of the nodal-position cable: lumped masses and leapfrog.

* Masses (MoorDyn's lumping, the row sums of the consistent matrices): node i carries half
  of each adjacent element's mass mu L0, the last node also the end mass (the lumped towed
  body, a bottom mass); the cable's added mass C_a rho A (I - u u^T) of each element goes to
  its two nodes by the same row sums of its two-point quadrature (the submerged Gauss points
  only, as :func:`towcable_fmu.hydro.cable.point_load` applies it), the body's added mass
  rho V C_m,b (its submerged fraction) to the last node. The 3x3 mass of a node is refreshed
  at every step (the added mass follows the elements' directions) and solved in closed form.
* Forces and accelerations: :func:`towcable_fmu.nodal.explicit_kernel.leapfrog_update`,
  once per step: the implicit path's element and body laws (its residual at zero
  acceleration, tested), with the model's constants read once per call, the state in
  vectorised rows and nothing allocated per step.
* Leapfrog, kick-drift-kick: v += h/2 a; q += h v; a = M^-1 F(q, v); v += h/2 a. The
  velocity-dependent forces (material damping, drag on cable and body) see the half-step
  velocity v_{n+1/2} = (q_{n+1} - q_n)/h: first order in h in the damping, one force
  evaluation per step, and the stability limit of
  :mod:`towcable_fmu.numerics.explicit_step` (exact for this lag; a predicted velocity,
  v_{n+1/2} + theta h a_n, halves the damping's error but lowers the limit, by 18 % at
  theta = 0.4 and the snapping cable's zeta = 0.27).
* The top node follows the ship from the drive table at the end of each step (while the
  ship does not rotate, from the power-basis quintics of the drive's current piece:
  :func:`prescribe_top_fast`).

The state is (q, v, a) at the step's end (v the full-step velocity, a the accelerations the
next step's first kick uses): saved and restored bit for bit, and the run continues as if
uninterrupted. :func:`leapfrog_recording` runs a whole block of samples in one call,
sampling at the exact sample times (landing on them, or interpolated inside a step as the
implicit path does).
"""

from __future__ import annotations

import math

import numpy as np

from ..jit.kernel_cache import njit
from .explicit_kernel import (STEP_FASTMATH, STRIDE, explicit_outputs, leapfrog_update, load_state, lumped_cable,
                              lumped_forces, new_work, set_top, store_state, update_with)
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
    at positions ``q`` [m] and velocities ``v`` [m/s] through the lumped masses ``mass`` [kg]
    (:func:`node_masses`) and the cable's and body's added masses
    (:func:`.explicit_kernel.lumped_forces`). ``f`` (q.size) and ``added`` (n_nodes, 6) are
    scratch."""
    lumped_forces(m, mass, q, v, f, added, a)


#: entries of a drive piece's record (:func:`_top_piece`): its index, the times it serves
#: (lo, hi], 1/dt [1/s], 1.0 if the top point moves with the ship's origin in it (no
#: rotation), then the top point's coordinates as quintics in s = (t - t_k)/dt (3 x 6)
_P_INDEX, _P_LO, _P_HI, _P_INV_DT, _P_PLAIN, _P_COEF = 0, 1, 2, 3, 4, 5
_PIECE_ENTRIES = 5 + 18


@njit(cache=True)
def new_top_piece() -> np.ndarray:
    """A drive piece's record that serves no time (the first use computes one)."""
    piece = np.zeros(_PIECE_ENTRIES)
    piece[_P_LO], piece[_P_HI] = np.inf, -np.inf
    return piece


@njit(cache=True)
def _top_piece(drive_t: np.ndarray, drive_x: np.ndarray, top_point: np.ndarray, t: float,
               piece: np.ndarray) -> None:
    """The record of the drive's piece at time ``t`` [s] into ``piece``: the piece
    :func:`~towcable_fmu.runtime.drive.evaluate_drive_with` uses at t (t_k < t <= t_k+1,
    the first and last piece beyond the table) and, where the ship does not rotate in it
    (every rotation channel's value, rate and acceleration 0 at both knots, so its quintic
    Hermite is 0), the power-basis coefficients of the top point's coordinates: the ship's
    quintic Hermite of the knots' values, rates and accelerations plus the top point [m]."""
    nk = drive_t.shape[0]
    k = min(max(np.searchsorted(drive_t, t) - 1, 0), nk - 2)
    dt = drive_t[k + 1] - drive_t[k]
    piece[_P_INDEX] = k
    piece[_P_LO] = -np.inf if k == 0 else drive_t[k]
    piece[_P_HI] = np.inf if k == nk - 2 else drive_t[k + 1]
    piece[_P_INV_DT] = 1.0 / dt
    plain = True
    for knot in (k, k + 1):
        for d in range(3):
            for c in range(3, 6):
                plain = plain and drive_x[knot, d, c] == 0.0
    piece[_P_PLAIN] = 1.0 if plain else 0.0
    for c in range(3):
        p0, b0, c0 = drive_x[k, 0, c], dt * drive_x[k, 1, c], dt * dt * drive_x[k, 2, c]
        p1, b1, c1 = drive_x[k + 1, 0, c], dt * drive_x[k + 1, 1, c], dt * dt * drive_x[k + 1, 2, c]
        i = _P_COEF + 6 * c
        piece[i] = p0 + top_point[c]
        piece[i + 1] = b0
        piece[i + 2] = 0.5 * c0
        piece[i + 3] = -10.0 * p0 - 6.0 * b0 - 1.5 * c0 + 10.0 * p1 - 4.0 * b1 + 0.5 * c1
        piece[i + 4] = 15.0 * p0 + 8.0 * b0 + 1.5 * c0 - 15.0 * p1 + 7.0 * b1 - c1
        piece[i + 5] = -6.0 * p0 - 3.0 * b0 - 0.5 * c0 + 6.0 * p1 - 3.0 * b1 + 0.5 * c1


@njit(cache=True)
def drive_is_plain(drive_x: np.ndarray) -> bool:
    """True if the ship rotates nowhere in the drive table: every rotation channel's value,
    rate and acceleration 0 at every knot (every piece plain, see :func:`_top_piece`)."""
    for knot in range(drive_x.shape[0]):
        for d in range(3):
            for c in range(3, 6):
                if drive_x[knot, d, c] != 0.0:
                    return False
    return True


@njit(cache=True, inline="always")
def _top_from_piece(piece: np.ndarray, drive_t: np.ndarray, t: float, q: np.ndarray, v: np.ndarray,
                    a: np.ndarray) -> None:
    """The top node's position [m], velocity [m/s] and acceleration [m/s^2] at time ``t`` [s]
    into ``q``, ``v``, ``a`` from the quintics of ``piece`` (a plain piece that serves t) by
    Horner's rule."""
    inv_dt = piece[_P_INV_DT]
    k = int(piece[_P_INDEX])
    s = (t - drive_t[k]) / (drive_t[k + 1] - drive_t[k])  # (as the drive computes it: the same s)
    for c in range(3):
        i = _P_COEF + 6 * c
        c0, c1, c2, c3, c4, c5 = piece[i], piece[i + 1], piece[i + 2], piece[i + 3], piece[i + 4], piece[i + 5]
        q[c] = c0 + s * (c1 + s * (c2 + s * (c3 + s * (c4 + s * c5))))
        v[c] = (c1 + s * (2.0 * c2 + s * (3.0 * c3 + s * (4.0 * c4 + s * 5.0 * c5)))) * inv_dt
        a[c] = (2.0 * c2 + s * (6.0 * c3 + s * (12.0 * c4 + s * 20.0 * c5))) * (inv_dt * inv_dt)


@njit(cache=True, inline="always")
def prescribe_top_fast(top_on_ship: bool, top_point: np.ndarray, drive_t: np.ndarray, drive_x: np.ndarray,
                       t: float, q: np.ndarray, v: np.ndarray, a: np.ndarray, ship: np.ndarray, basis: np.ndarray,
                       piece: np.ndarray) -> None:
    """:func:`~.integrators.prescribe_top_with` (the top node's position [m], velocity [m/s]
    and acceleration [m/s^2] at time ``t`` [s] into the first entries of ``q``, ``v``, ``a``)
    with the drive's piece kept in ``piece`` (:func:`new_top_piece`) while t stays in it:
    where the ship does not rotate, three quintics by Horner's rule (the same polynomial as
    the drive's Hermite basis, to round-off: :func:`_top_from_piece`) instead of the six
    channels' basis and the search for the piece at every step."""
    if not top_on_ship or drive_t.shape[0] < 2:
        prescribe_top_with(top_on_ship, top_point, drive_t, drive_x, t, q, v, a, ship, basis)
        return
    if not piece[_P_LO] < t <= piece[_P_HI]:
        _top_piece(drive_t, drive_x, top_point, t, piece)
    if piece[_P_PLAIN] == 0.0:
        prescribe_top_with(top_on_ship, top_point, drive_t, drive_x, t, q, v, a, ship, basis)
        return
    _top_from_piece(piece, drive_t, t, q, v, a)


@njit(cache=True, inline="always")
def _recording_with(plain: bool, stride: int, closed: bool, args: tuple) -> int:
    """:func:`leapfrog_recording`'s loop over the samples; ``args``: the cable's tables ``c``
    (:class:`~.explicit_kernel.LumpedCable`), its rows ``work`` (loaded), the model's
    ``top_on_ship`` and ``top_point``, the step ``h_nom`` [s], then leapfrog_recording's
    arguments from ``state`` on. ``plain`` (a literal): the top is on
    the ship and the ship rotates nowhere in the drive (the top node at every step from the
    kept piece's quintics, with no test for a rotating piece or for the general evaluation);
    ``stride``, ``closed``: the cable's (with ``plain`` literals: the step compiled for them,
    :func:`.explicit_kernel.update_with`; else the step dispatched on them,
    :func:`.explicit_kernel.leapfrog_update`)."""
    c, work, on_ship, top_point, h_nom, state, samples, drive_t, drive_x, values, ip, interpolate, t_land = args
    # (the fields in locals: a named tuple of arrays passed inside the loop is reference-counted field by field)
    n_nodes, wet, body_on, water, gravity = c.n_nodes, c.wet, c.body_on, c.water, c.gravity
    end_mass, flow, body, table = c.end_mass, c.flow, c.body, c.table
    elements, hydro, kind = c.elements, c.hydro, c.kind
    q, v, a, clock, stats = state.q, state.v, state.x, state.clock, state.stats
    n = q.size
    ship, basis = np.empty((3, 6)), np.empty((6, 3))
    top_q, top_v, top_a = np.empty(3), np.empty(3), np.empty(3)
    piece = new_top_piece()
    start, state_t, t0 = ip.start, ip.state, ip.t0
    # (the clock in a local, written at each sample: a store to an array in the loop made the
    # compiler reload the rows after it)
    t = clock[CLOCK_TIME]
    for s in range(samples.size):
        target = samples[s]
        tol = 1e-12 * max(1.0, abs(target))
        stop, inside = target - tol, target + tol
        steps = 0
        while t < stop:
            h = h_nom
            if interpolate:
                # (the clock sums thousands of steps: no extra step for its round-off; more than 3
                # steps from t_land n_rem > 3 and h stays h_nom: no division there)
                if t_land - t < 4.0 * h_nom:
                    n_rem = math.ceil((t_land - t) / h - 1e-6)
                    h = h if n_rem > 2 else (t_land - t) / n_rem
            else:
                h = min(h, target - t)
            if t + h > inside:  # the sample falls inside this step: keep its start
                store_state(work, stride, q, v, a)
                for i in range(n):
                    start[0, i], start[1, i], start[2, i] = q[i], v[i], a[i]
                t0[0] = t
            if plain:
                if not piece[_P_LO] < t + h <= piece[_P_HI]:
                    _top_piece(drive_t, drive_x, top_point, t + h, piece)
                _top_from_piece(piece, drive_t, t + h, top_q, top_v, top_a)
            else:
                prescribe_top_fast(on_ship, top_point, drive_t, drive_x, t + h, top_q, top_v, top_a, ship, basis,
                                   piece)
            set_top(work, stride, top_q, top_v, top_a)
            if plain:
                update_with(stride, closed, n_nodes, wet, body_on, water, gravity, end_mass, flow, body, hydro, kind,
                            table, work, h)
            else:
                leapfrog_update(n_nodes, closed, stride, wet, body_on, water, gravity, end_mass, flow, body, hydro,
                                kind, table, work, h)
            t = t + h
            steps += 1
        clock[CLOCK_TIME] = t
        stats[STAT_STEPS] += steps
        stats[STAT_RESIDUALS] += steps
        store_state(work, stride, q, v, a)
        row = values[s]
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


# the loop compiled twice, each its own function: one function holding the plain loop beside
# the general top's code made a step of the snapping cable about 50 ns slower (an earlier
# measurement)
@njit(cache=True, error_model="numpy", fastmath=STEP_FASTMATH)
def _recording_plain(args: tuple) -> int:
    """:func:`_recording_with` for a plain drive, closed-form drag and the compiled stride."""
    return _recording_with(True, STRIDE, True, args)


@njit(cache=True, error_model="numpy", fastmath=STEP_FASTMATH)
def _recording_general(args: tuple) -> int:
    """:func:`_recording_with` for any cable and drive (the step dispatched on the cable's
    stride and drag: :func:`.explicit_kernel.leapfrog_update`)."""
    c = args[0]
    return _recording_with(False, c.stride, c.closed, args)


# error_model "numpy": a division by zero gives inf or NaN (the run stops at a non-finite
# output) instead of a Python exception, whose checks halve the speed of the force loop
@njit(cache=True, error_model="numpy", fastmath=STEP_FASTMATH)
def leapfrog_recording(m: NodalModel, mass: np.ndarray, options: NodalOptions, state: NodalState,
                       samples: np.ndarray, drive_t: np.ndarray, drive_x: np.ndarray, values: np.ndarray,
                       ip: Interpolant, interpolate: bool, t_land: float) -> int:
    """Leapfrog steps of ``options.h_max`` [s] to each time in ``samples`` [s], recording
    :func:`~towcable_fmu.nodal.integrators.output_values` in ``values``: the contract of
    :func:`~towcable_fmu.nodal.integrators.advance_recording` (landing on every sample, or with
    ``interpolate`` keeping the steps, never passing ``t_land`` [s], and reading samples inside
    a step from the cubic Hermite interpolant of its ends). ``mass``: :func:`node_masses`.
    The constants are read out of ``m`` once (:func:`.explicit_kernel.lumped_cable`), the
    state is stepped in the kernel's rows (:func:`.explicit_kernel.leapfrog_update`) and
    written back at the samples, and nothing is allocated in the loop.

    Returns
    -------
    int
        Number of samples reached (fewer when an output is not finite: a blown-up run; the
        state is then not a valid one and the caller rolls back).
    """
    c = lumped_cable(m, mass)
    work = new_work(c)
    load_state(state.q, state.v, state.x, work, c.stride)
    args = (c, work, m.top_on_ship, m.top_point, options.h_max, state, samples, drive_t, drive_x, values, ip,
            interpolate, t_land)
    if m.top_on_ship and drive_t.shape[0] >= 2 and c.closed and c.stride == STRIDE and drive_is_plain(drive_x):
        return _recording_plain(args)
    return _recording_general(args)
