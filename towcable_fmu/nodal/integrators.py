"""Time integration of the nodal-position cable: generalised-alpha and the paper's RK4.

* Generalised-alpha (Arnold & Bruls form, the coefficients of
  :func:`towcable_fmu.numerics.alpha_scheme.scheme_coefficients`): the unknowns are the
  accelerations of the free nodes at the end of the step, found by Newton's method
  (:func:`towcable_fmu.numerics.alpha_newton.alpha_step`, with this module's overloads of
  its protocol for :class:`NodalModel`) with the banded iteration matrix ``M + gamma' C + beta' K`` (by coloured differences,
  :func:`.assembly.iteration_matrix`; formed at the start of each step, and at every
  iteration when the first ``max_iter`` iterations do not converge, which happens when
  an element crosses between slack and taut) and the banded LU of
  :mod:`towcable_fmu.numerics.banded`. A step whose Newton iteration fails is halved.
* RK4: the classical explicit fourth-order Runge-Kutta method on (X, Xdot), as the paper
  (section 3): at each stage the accelerations solve (M + M_a) Xddot = F with the same
  banded LU. Its step must resolve the highest axial frequency of the mesh.

The top node is prescribed (exact elimination): its position, velocity and
acceleration follow the ship point at every stage from the drive table
(:mod:`towcable_fmu.runtime.drive`). The integrator's settings travel as one
:class:`NodalOptions`, its state as one :class:`NodalState`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..jit.kernel_cache import njit
from ..numerics.alpha_newton import (NewtonPolicy, alpha_step, model_correct, model_factorize, model_residual,
                                     model_solve, model_start, overload_for)
from ..numerics.kinematics import ship_point_kinematics
from ..numerics.banded import band_lu, band_solve
from ..numerics.hermite import step_weights
from ..runtime.drive import evaluate_drive_with
from .assembly import bandwidth, cable_residual, expand, iteration_matrix, residual
from .element import add_element, axial_force
from .model import NodalModel
from ..hydro.rigid_body import attitude_ok

# fields of the integrator's clock
CLOCK_TIME = 0  #: time [s]
CLOCK_STEP = 1  #: current step size [s]

GENALPHA = 0
RK4 = 1
LEAPFROG = 2  #: explicit, lumped masses: :mod:`.explicit`
INTEGRATORS = {"genalpha": GENALPHA, "rk4": RK4, "leapfrog": LEAPFROG}
# fields of the integrator's counters (NodalState.stats), named in STAT_NAMES
STAT_STEPS = 0
STAT_NEWTON = 1
STAT_JACOBIANS = 2
STAT_RESIDUALS = 3
STAT_REJECTED = 4
STAT_NAMES = ("steps", "newton_iterations", "jacobian_factorisations", "residual_evaluations", "rejected_steps")


class NodalOptions(NamedTuple):
    """Integrator settings (from the scene's ``[solver]`` table)."""

    method: int          #: GENALPHA or RK4
    h_max: float         #: largest (and first) step [s]
    h_min: float         #: smallest step [s]: a failure below it ends the run
    coef: np.ndarray     #: generalised-alpha (alpha_m, alpha_f, gamma, beta)
    newton_tol: float    #: Newton's position tolerance, relative to the shortest element
    max_iter: int        #: Newton iterations per attempt


class NodalState(NamedTuple):
    """The whole integrator state; every field is an array so it can be saved and restored."""

    q: np.ndarray        #: (n,) coordinates [m, rad]
    v: np.ndarray        #: (n,) their rates
    x: np.ndarray        #: (n,) accelerations (generalised-alpha: the scheme's a at the step end)
    acc: np.ndarray      #: (n,) the scheme's acceleration-like variable
    clock: np.ndarray    #: (2,) the CLOCK_* fields: time [s], current step [s]
    stats: np.ndarray    #: (5,) int64 counters, the STAT_* fields


def new_state(n: int, h: float) -> NodalState:
    """A zero state for ``n`` coordinates at t = 0 with the step ``h`` [s]."""
    return NodalState(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n), np.array([0.0, h]),
                      np.zeros(len(STAT_NAMES), dtype=np.int64))


@njit(cache=True)
def prescribe_top(m: NodalModel, drive_t: np.ndarray, drive_x: np.ndarray, t: float, q: np.ndarray,
                  v: np.ndarray, a: np.ndarray) -> None:
    """Set node 0's position [m], velocity [m/s] and acceleration [m/s^2] at time t [s]."""
    prescribe_top_with(m.top_on_ship, m.top_point, drive_t, drive_x, t, q, v, a, np.empty((3, 6)),
                       np.empty((6, 3)))


@njit(cache=True, inline="always")
def prescribe_top_with(top_on_ship: bool, top_point: np.ndarray, drive_t: np.ndarray, drive_x: np.ndarray, t: float,
                       q: np.ndarray, v: np.ndarray, a: np.ndarray, ship: np.ndarray, basis: np.ndarray) -> None:
    """:func:`prescribe_top` of the model's ``top_on_ship`` and ``top_point`` with the scratch
    ``ship`` (3, 6) and ``basis`` (6, 3): nothing allocated unless the ship rotates (and the
    model not passed: a tuple of arrays is reference-counted field by field wherever it goes)."""
    if top_on_ship:
        evaluate_drive_with(drive_t, drive_x, t, ship, basis)
        if ship[:, 3:].any():
            k = ship_point_kinematics(ship, top_point)
            for c in range(3):
                q[c], v[c], a[c] = k[0, c], k[1, c], k[2, c]
        else:  # a ship that does not rotate (now) carries the point with its origin: the same values
            for c in range(3):
                q[c], v[c], a[c] = ship[0, c] + top_point[c], ship[1, c], ship[2, c]
    else:
        for c in range(3):
            q[c], v[c], a[c] = top_point[c], 0.0, 0.0


@njit(cache=True)
def _factor(ab: np.ndarray, kl: int, ipiv: np.ndarray) -> bool:
    return band_lu(ab, ab.shape[0], kl, kl, ipiv) == 0


class AlphaIterate(NamedTuple):
    """One generalised-alpha step's iterate and scratch: the ``step`` of the protocol of
    :mod:`towcable_fmu.numerics.alpha_newton`, whose overloads for :class:`NodalModel`
    follow."""

    start: NodalState    #: the state at the step's start (q, v, x, acc; its counters)
    out: np.ndarray      #: (4, n): q, v, x, acc at the step's end (the iterate)
    drive_t: np.ndarray  #: the drive table
    drive_x: np.ndarray
    t1: float            #: the step's end [s]
    h: float             #: the step [s]
    coef: np.ndarray     #: (am, af, gamma, beta)
    ca: float            #: the changes of acc, v and q per change of x: (1 - af)/(1 - am), gamma', beta'
    cv: float
    cq: float
    kl: int              #: the iteration matrix's half-bandwidth
    r: np.ndarray        #: (n,) residual
    d: np.ndarray        #: (n - 3,) Newton correction
    ab: np.ndarray       #: band storage of the factorised iteration matrix
    ipiv: np.ndarray     #: its pivots
    work: np.ndarray     #: (4, n) scratch of the matrix's differences


@overload_for(model_start, NodalModel)
def _start(model, step):
    """The scheme's start: x1 = x (and the acc and q, v it gives), the top node at t1."""
    x, acc = step.start.x, step.start.acc
    q1, v1, x1, a1 = step.out[0], step.out[1], step.out[2], step.out[3]
    am, af, gamma, beta, h = step.coef[0], step.coef[1], step.coef[2], step.coef[3], step.h
    x1[:] = x
    a1[:] = (af * x - am * acc + (1.0 - af) * x1) / (1.0 - am)
    q1[:] = step.start.q + h * step.start.v + h * h * ((0.5 - beta) * acc + beta * a1)
    v1[:] = step.start.v + h * ((1.0 - gamma) * acc + gamma * a1)
    prescribe_top(model, step.drive_t, step.drive_x, step.t1, q1, v1, x1)


@overload_for(model_residual, NodalModel)
def _residual(model, step):
    residual(model, step.out[0], step.out[1], step.out[2], step.t1, step.r)
    step.start.stats[STAT_RESIDUALS] += 1


@overload_for(model_factorize, NodalModel)
def _factorize(model, step):
    stats, cq = step.start.stats, step.cq
    stats[STAT_RESIDUALS] += iteration_matrix(model, step.out[0], step.out[1], step.out[2], step.t1, 1.0,
                                              step.cv, cq, 1e-7 * model.L0.min() / cq, step.r, step.ab,
                                              step.work)
    stats[STAT_JACOBIANS] += 1
    return _factor(step.ab, step.kl, step.ipiv)


@overload_for(model_solve, NodalModel)
def _solve(model, step):
    """The correction of the free coordinates (checked for finite values by :func:`_correct`)."""
    d = step.d
    d[:] = -step.r[3:]
    band_solve(step.ab, d.size, step.kl, step.kl, step.ipiv, d)
    step.start.stats[STAT_NEWTON] += 1


@overload_for(model_correct, NodalModel)
def _correct(model, step):
    """The iterate moved by the correction; its norm: the largest position change [m] (NaN:
    a correction not finite, not applied)."""
    d = step.d
    if not np.all(np.isfinite(d)):
        return np.nan
    q1, v1, x1, a1 = step.out[0], step.out[1], step.out[2], step.out[3]
    x1[3:] += d
    a1[3:] += step.ca * d
    q1[3:] += step.cq * d
    v1[3:] += step.cv * d
    return step.cq * np.abs(d).max()


@njit(cache=True)
def genalpha_step(m: NodalModel, options: NodalOptions, h: float, t: float, drive_t: np.ndarray,
                  drive_x: np.ndarray, state: NodalState, out: np.ndarray) -> bool:
    """One generalised-alpha step of size h [s] from t (the state's q, v, x, acc), by
    :func:`towcable_fmu.numerics.alpha_newton.alpha_step`.

    Newton forms the iteration matrix at the first iterate and keeps it for
    ``options.max_iter`` iterations, then forms it at every iterate for as many more; it
    stops when the position correction is below ``options.newton_tol`` times the shortest
    element. ``out`` (4, n) receives q, v, x, acc at t + h (valid when True is returned);
    the state's arrays are not changed except its counters.
    """
    coef = options.coef
    am, af, gamma, beta = coef[0], coef[1], coef[2], coef[3]
    ca = (1.0 - af) / (1.0 - am)
    n = state.q.size
    kl = bandwidth(m)
    step = AlphaIterate(state, out, drive_t, drive_x, t + h, h, coef, ca, h * gamma * ca, h * h * beta * ca, kl,
                        np.empty(n), np.empty(n - 3), np.empty((n - 3, 3 * kl + 1)), np.empty(n - 3, dtype=np.int64),
                        np.empty((4, n)))
    policy = NewtonPolicy(2 * options.max_iter, options.max_iter, options.newton_tol * m.L0.min())
    return alpha_step(m, step, policy) and (not m.rigid.enabled or attitude_ok(out[0][n - 6:]))


@njit(cache=True)
def accelerations(m: NodalModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float,
                  stats: np.ndarray) -> bool:
    """Solve (M + M_a) Xddot = F for the free nodes into ``a`` (node 0's entries are kept)."""
    n = q.size
    a[3:] = 0.0
    r = np.empty(n)
    residual(m, q, v, a, t, r)
    kl = bandwidth(m)
    ab = np.empty((n - 3, 3 * kl + 1))
    ipiv = np.empty(n - 3, dtype=np.int64)
    work = np.empty((4, n))
    stats[STAT_RESIDUALS] += 1 + iteration_matrix(m, q, v, a, t, 1.0, 0.0, 0.0, 1.0, r, ab, work)
    if m.rigid.enabled and not attitude_ok(q[n - 6:]):
        return False
    if not _factor(ab, kl, ipiv):
        return False
    d = -r[3:]
    band_solve(ab, n - 3, kl, kl, ipiv, d)
    a[3:] = d
    return bool(np.all(np.isfinite(d)))


@njit(cache=True)
def rk4_step(m: NodalModel, h: float, t: float, drive_t: np.ndarray, drive_x: np.ndarray, q: np.ndarray,
             v: np.ndarray, out: np.ndarray, stats: np.ndarray) -> bool:
    """One classical RK4 step of size h [s] from (q, v) at t; the result (q, v, Xddot) at
    t + h goes to out[0], out[1], out[2]."""
    n = q.size
    kq = np.zeros((4, n))
    kv = np.zeros((4, n))
    qs = np.empty(n)
    vs = np.empty(n)
    a = np.zeros(n)
    for s in range(4):
        c = 0.0 if s == 0 else (0.5 if s < 3 else 1.0)
        qs[:] = q
        vs[:] = v
        if s > 0:
            qs += c * h * kq[s - 1]
            vs += c * h * kv[s - 1]
        prescribe_top(m, drive_t, drive_x, t + c * h, qs, vs, a)
        if not accelerations(m, qs, vs, a, t + c * h, stats):
            return False
        kq[s] = vs
        kv[s] = a
    q1, v1, x1 = out[0], out[1], out[2]
    q1[:] = q + h / 6.0 * (kq[0] + 2.0 * kq[1] + 2.0 * kq[2] + kq[3])
    v1[:] = v + h / 6.0 * (kv[0] + 2.0 * kv[1] + 2.0 * kv[2] + kv[3])
    prescribe_top(m, drive_t, drive_x, t + h, q1, v1, x1)
    return accelerations(m, q1, v1, x1, t + h, stats)


@njit(cache=True)
def output_values(m: NodalModel, q: np.ndarray, v: np.ndarray, x: np.ndarray, t: float, out: np.ndarray) -> None:
    """Outputs at one instant into ``out`` (see :data:`.simulation.OUTPUT_NAMES`): the top
    reaction's magnitude [N] and angle from the vertical [rad], the largest and smallest
    element axial force [N], the last node's (towed body's) position [m] and velocity [m/s];
    with a rigid body its CG's position and velocity, then the force of the cable on the
    body [N] and the body's roll, pitch and yaw [rad] (:data:`.simulation.RIGID_NAMES`)."""
    nq = 3 * m.n_nodes
    qn, vn, an = np.empty(nq), np.empty(nq), np.empty(nq)
    expand(m, q, v, x, qn, vn, an)
    r = np.zeros(6)  # the top node's residual: the first element's part of it (no other reaches it)
    add_element(m, 0, qn, vn, an, t, r)
    out[0] = math.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2)
    out[1] = math.acos(min(max(abs(r[2]) / max(out[0], 1e-300), 0.0), 1.0))
    hi, lo = -np.inf, np.inf
    for e in range(m.n_nodes - 1):
        n = axial_force(m, e, qn, vn)[0]
        hi = max(hi, n)
        lo = min(lo, n)
    out[2], out[3] = hi, lo
    i = nq - 3
    for k in range(3):
        out[4 + k] = q[i + k]
        out[7 + k] = v[i + k]
    if m.rigid.enabled:
        rn = np.empty(nq)
        cable_residual(m, qn, vn, an, t, rn)
        out[10] = math.sqrt(rn[i] ** 2 + rn[i + 1] ** 2 + rn[i + 2] ** 2)
        for k in range(3):
            out[11 + k] = q[i + 3 + k]


class Interpolant(NamedTuple):
    """The start of the last accepted step, for outputs at times inside it."""

    #: Coordinates, rates and accelerations (rows q, v, x) at the step's start, (3, n).
    start: np.ndarray
    #: The step's start time [s], (1,).
    t0: np.ndarray
    #: Scratch: the interpolated q, v, x, (3, n).
    state: np.ndarray


def new_interpolant(n: int) -> Interpolant:
    """An interpolant for ``n`` coordinates."""
    return Interpolant(np.zeros((3, n)), np.zeros(1), np.zeros((3, n)))


@njit(cache=True)
def _interpolate(m: NodalModel, ip: Interpolant, q: np.ndarray, v: np.ndarray, x: np.ndarray, t1: float,
                 t: float, drive_t: np.ndarray, drive_x: np.ndarray) -> None:
    """:func:`interpolate_step` with its scratch allocated here."""
    interpolate_step(m.top_on_ship, m.top_point, ip.start, ip.t0[0], ip.state, q, v, x, t1, t, drive_t, drive_x,
                     np.empty((3, 6)), np.empty((6, 3)))


@njit(cache=True, inline="always")
def interpolate_step(top_on_ship: bool, top_point: np.ndarray, start: np.ndarray, t0: float, state: np.ndarray,
                     q: np.ndarray, v: np.ndarray, x: np.ndarray, t1: float, t: float, drive_t: np.ndarray,
                     drive_x: np.ndarray, ship: np.ndarray, basis: np.ndarray) -> None:
    """The state at time t [s] inside the last step (from ``start`` (rows q, v, x) at ``t0``
    [s] to q, v, x at t1) into ``state`` (3, n): cubic Hermite in the coordinates from their
    values and rates at both ends (error O(h^4), below the schemes' own order), rates its
    derivative, accelerations linear; the top node follows the ship exactly
    (:func:`prescribe_top_with`, with its arguments)."""
    h = t1 - t0
    s = (t - t0) / h
    h00, h10, h01, h11, d00, d10, d01, d11 = step_weights(s, h)
    for i in range(q.size):
        q0, v0 = start[0, i], start[1, i]
        state[0, i] = h00 * q0 + h10 * h * v0 + h01 * q[i] + h11 * h * v[i]
        state[1, i] = d00 * q0 + d10 * v0 + d01 * q[i] + d11 * v[i]
        state[2, i] = (1.0 - s) * start[2, i] + s * x[i]
    prescribe_top_with(top_on_ship, top_point, drive_t, drive_x, t, state[0], state[1], state[2], ship, basis)


@njit(cache=True)
def advance_recording(m: NodalModel, options: NodalOptions, state: NodalState, samples: np.ndarray,
                      drive_t: np.ndarray, drive_x: np.ndarray, values: np.ndarray, ip: Interpolant,
                      interpolate: bool, t_land: float) -> int:
    """Step to each time in ``samples`` [s] and record :func:`output_values` in ``values``.

    Steps are ``state.clock[CLOCK_STEP]`` [s] long (at most ``options.h_max``; halved
    after a failed generalised-alpha step, doubled back after a success). Without
    ``interpolate`` they are shortened to land on every sample. With it the integrator
    keeps its own steps and never passes ``t_land`` [s] (the last two steps before it
    split evenly): a sample inside a step reads the state interpolated in that step
    (:func:`_interpolate`, from ``ip``), so the output interval does not change the steps;
    the state may then end up to one step past the last sample (the next call's drive
    table must start at ``ip.t0``).

    Returns
    -------
    int
        Number of samples reached (fewer than ``samples.size`` when a step failed below
        h_min or produced non-finite values; the state is then the last accepted one).
    """
    q, v, x, clock, stats = state.q, state.v, state.x, state.clock, state.stats
    out = np.empty((4, q.size))
    for s in range(samples.size):
        target = samples[s]
        while clock[CLOCK_TIME] < target - 1e-12 * max(1.0, abs(target)):
            t = clock[CLOCK_TIME]
            h = clock[CLOCK_STEP]
            if interpolate:
                remaining = t_land - t
                # (the clock sums thousands of steps: no extra step for its round-off)
                n_rem = math.ceil(remaining / h - 1e-6)
                h = h if n_rem > 2 else remaining / n_rem
            else:
                h = min(h, target - t)
            if options.method == GENALPHA:
                ok = genalpha_step(m, options, h, t, drive_t, drive_x, state, out)
            else:
                ok = rk4_step(m, h, t, drive_t, drive_x, q, v, out, stats)
            ok = ok and np.all(np.isfinite(out[0])) and np.all(np.isfinite(out[1]))
            if not ok:
                stats[STAT_REJECTED] += 1
                clock[CLOCK_STEP] *= 0.5
                if clock[CLOCK_STEP] < options.h_min or options.method == RK4:
                    return s
                continue
            ip.start[0, :], ip.start[1, :], ip.start[2, :] = q, v, x
            ip.t0[0] = t
            q[:], v[:], x[:] = out[0], out[1], out[2]
            if options.method == GENALPHA:
                state.acc[:] = out[3]
            clock[CLOCK_TIME] += h
            stats[STAT_STEPS] += 1
            if h == clock[CLOCK_STEP]:
                clock[CLOCK_STEP] = min(2.0 * clock[CLOCK_STEP], options.h_max)
        if not record_sample(m, ip, q, v, x, clock[CLOCK_TIME], target, drive_t, drive_x, values[s]):
            return s
    return samples.size


@njit(cache=True, inline="always")
def record_sample(m: NodalModel, ip: Interpolant, q: np.ndarray, v: np.ndarray, x: np.ndarray, t: float,
                  target: float, drive_t: np.ndarray, drive_x: np.ndarray, row: np.ndarray) -> bool:
    """:func:`output_values` at the sample time ``target`` [s] into ``row``: of the state (at
    time ``t`` [s]) when the step landed there, else interpolated inside the last step
    (:func:`_interpolate`); whether they are finite."""
    if target >= t - 1e-12 * max(1.0, abs(target)):
        output_values(m, q, v, x, t, row)
    else:
        _interpolate(m, ip, q, v, x, t, target, drive_t, drive_x)
        output_values(m, ip.state[0], ip.state[1], ip.state[2], target, row)
    return bool(np.all(np.isfinite(row)))
