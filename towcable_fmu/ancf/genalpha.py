"""Generalised-alpha time integration with modified Newton on a banded Jacobian, compiled.

Scheme: Chung & Hulbert's generalised-alpha in the form of Arnold & Bruls (2007) for
``M(q) a + F(q, v, t) = 0`` with an auxiliary acceleration ``abar``:

    (1 - am) abar_{n+1} + am abar_n = (1 - af) a_{n+1} + af a_n
    q_{n+1} = q_n + h v_n + h^2 ((1/2 - beta) abar_n + beta abar_{n+1})
    v_{n+1} = v_n + h ((1 - gamma) abar_n + gamma abar_{n+1})
    R(q_{n+1}, v_{n+1}, a_{n+1}, t_{n+1}) = 0

with am = (2 rho - 1)/(rho + 1), af = rho/(rho + 1), gamma = 1/2 + af - am,
beta = (gamma + 1/2)^2 / 4 for the spectral radius ``rho = rho_inf``: second order,
unconditionally stable, high frequencies damped as set by ``rho_inf``. Equilibrium is
enforced at t_{n+1}, so forces need no mid-point evaluation.

Newton iterates on ``a_{n+1}`` with the iteration matrix ``M + gamma' C + beta' K``
(``gamma' = h gamma (1-af)/(1-am)``, ``beta' = h^2 beta (1-af)/(1-am)``), factorised
and reused over steps while it stays accurate (modified Newton). It is refreshed at
the start of a step when it is too old, when the step size changed by more than 5 %,
or when the last step's contraction rate theta exceeded ``THETA_REUSE`` (the rule of
Hairer & Wanner's RADAU5 for costly Jacobians). A matrix from an earlier step that
contracts worse than ``THETA_REFRESH`` is refreshed inside the step at the current
iterate, and the following steps factorise afresh without trying a reuse: 1, 3, 7, 15
steps after consecutive misses (at most ``MAX_BACKOFF``), halved by every successful
reuse. A cable sliding over a rolling sheave changes its contact set every step and
settles at a fresh matrix per step; a cable without contact keeps one for a hundred.

At the kink of a tension-only law (``compression = false``) a matrix from the other side
of the kink sends modified Newton into a 2-cycle (the slack point's zero stiffness) or a
crawl (the taut point's): the residual and the matrix report the Gauss points they saw
taut (``CableModel.el_taut``), and the matrix is refactorised at the current iterate
where they differ (semi-smooth Newton). A step in which a tension-only element went
taut or slack is taken again, shortened to end just past that instant
(:func:`~towcable_fmu.ancf.slack.crossing_fraction`, ``locate_events``).

Predictor: ``a_{n+1} = a_n + r (a_n - a_{n-1})`` per coordinate, with the ratio
``r = (a_n - a_{n-1}) / (a_{n-1} - a_{n-2})`` of the last two changes clipped to [-1, 0]:
a mode the step does not resolve alternates, damped by about ``-rho_inf`` a step, and is
followed; a smooth trend (r > 0) is not extrapolated. Used in fixed-step runs where a step
is shorter than the nominal one because the caller's interval ends sooner (a co-simulation's
communication step), after two accepted steps of the same size (the history ``a_hist``,
``h_hist`` is part of the state). At a run's own step it does not pay: it moved Newton's
contraction estimate and cost factorisations and cut steps (``docs/design.md``).

Convergence test (Hairer & Wanner): the estimated remaining error
``theta/(1-theta) * |dq|`` is below ``newton_tol``, with the contraction rate theta of
the previous step used on the first iteration; ``|dq|`` is the largest correction
with positions divided by the adjacent element length (a strain-like, scale-free
measure: the tension error it allows is about EA * newton_tol).

Local error estimate (Zienkiewicz & Xie): ``e = h^2 |beta - 1/6| |abar_{n+1} - abar_n|``,
weighted by ``atol + rtol l`` for a position (l: its element's length) and ``rtol + atol``
for a slope; it drives the step size in adaptive mode and is
reported as a statistic otherwise. A step whose Newton iteration fails is retried
with a fresh Jacobian, then with half the step; below ``min_time_step`` the call
returns a failure code and leaves the state at the last accepted step.

The winch rotation obeys the PD law W(136) and is integrated with the same scheme
(exactly: the equation is linear); it does not depend on the cable, so it is solved
first and then drives the cable end on the drum.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..jit.kernel_cache import njit
from .feed import apply_feed, feed_event
from .prescribed import apply_prescribed
from .model import TAUT_MATRIX, TAUT_RESIDUAL, CableModel
from .slack import crossing_fraction
from .system import iteration_matrix, residual
from ..runtime.drive import evaluate_drive
from ..numerics.alpha_scheme import scheme_coefficients
from ..numerics.arrays import copy_into
from ..numerics.banded import band_lu, band_solve, band_storage

# results of advance
OK = 0
FAILED_MIN_STEP = 1
#: an accepted step left the fed element of a spool end out of its band
#: (:func:`~towcable_fmu.ancf.feed.feed_event`): the caller splits or merges it and goes on
FEED_EVENT = 2

# results of one step attempt (_try_step)
STEP_ACCEPTED = 0
STEP_NOT_CONVERGED = 1  #: Newton did not converge (or the factorisation failed)
STEP_ERROR_TOO_LARGE = 2  #: adaptive steps: the local error estimate exceeds 1

# fields of IntegratorState.clock
CLOCK_TIME = 0  #: time [s]
CLOCK_STEP = 1  #: current step size [s]
CLOCK_ERROR = 2  #: last local error estimate [-]
CLOCK_STEPS_SINCE_CUT = 3  #: accepted steps since the last step-size cut

# indices into IntegratorState.stats
STAT_STEPS = 0
STAT_REJECTED = 1
STAT_NEWTON = 2
STAT_RESIDUALS = 3
STAT_JACOBIANS = 4
STAT_SINGULAR = 5
STAT_NAMES = ("steps", "rejected_steps", "newton_iterations", "residual_evaluations",
              "jacobian_factorisations", "singular_jacobians")

# indices into IntegratorState.jac
JAC_VALID = 0
JAC_H = 1
JAC_AGE = 2
JAC_T = 3
JAC_ETA = 4
JAC_SKIP = 5
JAC_BACKOFF = 6
#: winch rotation, rate and acceleration at the factorisation (the fed element's matrices follow them)
JAC_PHI = 7
JAC_FIELDS = 10

#: contraction rate above which a matrix from an earlier step is refreshed within the step
THETA_REFRESH = 0.5
#: contraction rate above which a matrix is not reused at the next step
THETA_REUSE = 0.1
#: longest run of steps that factorise afresh after reused matrices kept failing
MAX_BACKOFF = 16.0
#: refactorisations within one step because tension-only points went slack or taut
MAX_SWITCH_REFRESH = 4
#: a step in which a tension-only element went taut or slack before this fraction of it is
#: taken again, shortened to end just past that instant (by EVENT_OVERSHOOT of the new step)
EVENT_LAND = 0.9
EVENT_OVERSHOOT = 0.02
#: the shortest such step, as a fraction of the step it replaces
EVENT_MIN_FRACTION = 0.02


class SolverOptions(NamedTuple):
    """Integrator settings (see :class:`~towcable_fmu.scene.model.SolverSettings`)."""

    h_max: float
    rho_inf: float
    adaptive: bool
    rtol: float
    atol: float
    newton_tol: float
    max_iter: int
    jac_max_age: int
    h_min: float
    winch_kp: float
    winch_kd: float
    locate_events: bool


class IntegratorState(NamedTuple):
    """The whole integrator state; every field is an array so it can be saved and restored."""

    q: np.ndarray        #: (nf,) coordinates
    v: np.ndarray        #: (nf,) velocities
    a: np.ndarray        #: (nf,) accelerations
    abar: np.ndarray     #: (nf,) auxiliary accelerations of the scheme
    phi: np.ndarray      #: (4,) winch rotation, rate, acceleration, auxiliary acceleration
    clock: np.ndarray    #: (4,) the CLOCK_* fields: time [s], step size [s], last error estimate [-], steps since a cut
    jac: np.ndarray      #: (JAC_FIELDS,) valid, step size, age, time, Newton contraction estimate, steps left to factorise afresh, backoff length, winch state (3)
    jac_q: np.ndarray    #: (nf,) coordinates at which the Jacobian was evaluated
    jac_v: np.ndarray    #: (nf,) velocities at which the Jacobian was evaluated
    jac_ship: np.ndarray  #: (3, 6) ship state at which the Jacobian was evaluated
    stats: np.ndarray    #: (6,) int64 counters (see STAT_NAMES)
    taut: np.ndarray     #: (ne,) int64 taut Gauss points of the tension-only elements (bit masks) at the clock's time
    a_hist: np.ndarray   #: (2, nf) accelerations at the starts of the last two accepted steps (the predictor's history)
    h_hist: np.ndarray   #: (2,) the sizes of those steps [s] (0: none yet, e.g. after a start or a remeshing)


class Workspace(NamedTuple):
    """Scratch arrays and the factorised iteration matrix (rebuilt from the state on restore)."""

    ab: np.ndarray       #: band storage of the factorised iteration matrix
    ipiv: np.ndarray     #: pivots
    r: np.ndarray        #: (nf,) residual
    dx: np.ndarray       #: (n,) Newton increment
    q0: np.ndarray       #: (nf,) saved state at the start of a step
    v0: np.ndarray
    a0: np.ndarray
    abar0: np.ndarray
    ship: np.ndarray     #: (3, 6) ship state at the step end
    phi0: np.ndarray     #: (4,) winch state at the start of a step
    step_start: np.ndarray  #: (1,) time at the start of the last accepted step [s] (NaN: none yet)
    qs: np.ndarray       #: (nf,) a state between two step ends (interpolated sampling)
    vs: np.ndarray
    as_: np.ndarray
    phis: np.ndarray     #: (4,)
    ships: np.ndarray    #: (3, 6)


def new_state(model: CableModel) -> IntegratorState:
    """A zero integrator state for ``model``."""
    nf = model.free_idx.shape[0]
    return IntegratorState(np.zeros(nf), np.zeros(nf), np.zeros(nf), np.zeros(nf), np.zeros(4), np.zeros(4),
                           np.zeros(JAC_FIELDS), np.zeros(nf), np.zeros(nf), np.zeros((3, 6)),
                           np.zeros(len(STAT_NAMES), dtype=np.int64),
                           np.zeros(model.el_len.shape[0], dtype=np.int64), np.zeros((2, nf)), np.zeros(2))


def new_workspace(model: CableModel) -> Workspace:
    """Scratch arrays sized for ``model``."""
    nf = model.free_idx.shape[0]
    n = model.free_dofs.shape[0]
    return Workspace(band_storage(n, model.kl, model.ku), np.zeros(n, dtype=np.int64), np.zeros(nf),
                     np.zeros(n), np.zeros(nf), np.zeros(nf), np.zeros(nf), np.zeros(nf), np.zeros((3, 6)),
                     np.zeros(4), np.full(1, np.nan), np.zeros(nf), np.zeros(nf), np.zeros(nf), np.zeros(4),
                     np.zeros((3, 6)))


@njit(cache=True, inline="always")
def _factorize(model, opt, st, ws, t, h, am, af, gamma, beta):
    """Evaluate and factorise the iteration matrix at the current q, v; record where."""
    scale = (1.0 - af) / (1.0 - am)
    iteration_matrix(model, st.q, st.v, t, ws.ship, 1.0, h * gamma * scale, h * h * beta * scale, ws.ab)
    n = model.free_dofs.shape[0]
    info = band_lu(ws.ab, n, model.kl, model.ku, ws.ipiv)
    st.stats[STAT_JACOBIANS] += 1
    copy_into(st.jac_q, st.q)
    copy_into(st.jac_v, st.v)
    copy_into(st.jac_ship, ws.ship)
    st.jac[JAC_H] = h
    st.jac[JAC_AGE] = 0.0
    st.jac[JAC_T] = t
    for k in range(3):
        st.jac[JAC_PHI + k] = st.phi[k]
    if info != 0:
        st.stats[STAT_SINGULAR] += 1
        st.jac[JAC_VALID] = 0.0
        return False
    st.jac[JAC_VALID] = 1.0
    return True


def refactorize_from_state(model: CableModel, opt: SolverOptions, st: IntegratorState, ws: Workspace) -> None:
    """Rebuild the factorised Jacobian recorded in a restored state (bit-identical).

    The factorisation is not part of the saved state; the point where it was evaluated
    is, so a restored run continues exactly as the original one. (Python calling the
    kernels: as a kernel of its own it would link and optimise their code once more.)
    """
    if st.jac[JAC_VALID] == 0.0:
        return
    am, af, gamma, beta = scheme_coefficients(opt.rho_inf)
    h = st.jac[JAC_H]
    scale = (1.0 - af) / (1.0 - am)
    ws.ship[:, :] = st.jac_ship
    apply_feed(model, st.jac[JAC_PHI:JAC_PHI + 3])
    iteration_matrix(model, st.jac_q, st.jac_v, st.jac[JAC_T], ws.ship, 1.0, h * gamma * scale,
                     h * h * beta * scale, ws.ab)
    apply_feed(model, st.phi)
    n = model.free_dofs.shape[0]
    if band_lu(ws.ab, n, model.kl, model.ku, ws.ipiv) != 0:
        st.jac[JAC_VALID] = 0.0


def initial_acceleration(model: CableModel, opt: SolverOptions, st: IntegratorState, ws: Workspace, t: float,
                         drive_t: np.ndarray, drive_x: np.ndarray) -> bool:
    """Set prescribed kinematics at t and solve ``M a = -F`` for consistent accelerations.

    The winch's acceleration is that of its PD law W(136) at t,
    ``k1 (phi_sp - phi) + k2 (phi_sp_rate - phi_rate)`` with the drive's set-point: a drum
    started off its set-point, or at rest under a moving one, accelerates from the first
    instant, and the cable end on it with it (generalised-alpha needs consistent initial
    accelerations for its second order). Also invalidates the Jacobian. Python calling
    the kernels, once per start: as a kernel of its own it would link and optimise the
    residual and Jacobian code once more.

    Returns
    -------
    bool
        False if the mass matrix is singular or the forces are not finite.
    """
    sp, sp_rate = evaluate_drive(drive_t, drive_x, t, ws.ship)
    st.phi[2] = opt.winch_kp * (sp - st.phi[0]) + opt.winch_kd * (sp_rate - st.phi[1])
    apply_prescribed(model.att_index, model.att_kind, model.att_vec, model.att_radius, ws.ship, st.phi,
                     st.q, st.v, st.a)
    apply_feed(model, st.phi)
    st.a[model.free_dofs] = 0.0
    residual(model, st.q, st.v, st.a, t, ws.ship, ws.r)
    st.taut[:] = model.el_taut[TAUT_RESIDUAL]
    n = model.free_dofs.shape[0]
    ws.dx[:] = -ws.r[model.free_dofs]
    if not np.all(np.isfinite(ws.dx)):
        return False
    iteration_matrix(model, st.q, st.v, t, ws.ship, 1.0, 0.0, 0.0, ws.ab)
    st.jac[JAC_VALID] = 0.0
    if band_lu(ws.ab, n, model.kl, model.ku, ws.ipiv) != 0:
        return False
    band_solve(ws.ab, n, model.kl, model.ku, ws.ipiv, ws.dx)
    st.a[model.free_dofs] = ws.dx
    st.abar[:] = st.a
    st.phi[3] = st.phi[2]
    st.clock[CLOCK_TIME] = t
    st.h_hist[:] = 0.0
    return True


@njit(cache=True, inline="always")
def _switched(model):
    """True where the last residual saw a tension-only point slack that the matrix saw taut, or the reverse."""
    taut = model.el_taut
    for e in range(taut.shape[1]):
        if taut[TAUT_RESIDUAL, e] != taut[TAUT_MATRIX, e]:
            return True
    return False


@njit(cache=True, inline="always")
def _winch_step(opt, st, h, sp, sp_rate, am, af, gamma, beta):
    """Advance the winch PD law W(136) one step with the same scheme (linear: exact)."""
    phi, dphi, ddphi, bar = st.phi[0], st.phi[1], st.phi[2], st.phi[3]
    scale = (1.0 - af) / (1.0 - am)
    bar_new = (ddphi - am * bar) / (1.0 - am)
    p = phi + h * dphi + h * h * ((0.5 - beta) * bar + beta * bar_new)
    dp = dphi + h * ((1.0 - gamma) * bar + gamma * bar_new)
    acc = ddphi
    r = acc - opt.winch_kp * (sp - p) - opt.winch_kd * (sp_rate - dp)
    delta = -r / (1.0 + opt.winch_kd * h * gamma * scale + opt.winch_kp * h * h * beta * scale)
    st.phi[0] = p + h * h * beta * scale * delta
    st.phi[1] = dp + h * gamma * scale * delta
    st.phi[2] = acc + delta
    st.phi[3] = bar_new + scale * delta


@njit(cache=True, inline="always")
def _predicting(opt, st, h):
    """True when the predictor extrapolates the accelerations into a step of size h [s]
    (else a_{n+1} = a_n): in a fixed-step run, a step shorter than the current nominal one
    (it ends at the caller's time, a co-simulation's communication step), after two accepted
    steps of the size h (to 1 %)."""
    return (not opt.adaptive and h < 0.99 * st.clock[CLOCK_STEP]
            and abs(st.h_hist[0] - h) <= 0.01 * h and abs(st.h_hist[1] - h) <= 0.01 * h)


@njit(cache=True, inline="always")
def _try_step(model, opt, st, ws, h, drive_t, drive_x, am, af, gamma, beta):
    """One step attempt of size h: STEP_ACCEPTED, STEP_NOT_CONVERGED or STEP_ERROR_TOO_LARGE."""
    t1 = st.clock[CLOCK_TIME] + h
    sp, sp_rate = evaluate_drive(drive_t, drive_x, t1, ws.ship)
    _winch_step(opt, st, h, sp, sp_rate, am, af, gamma, beta)
    scale = (1.0 - af) / (1.0 - am)
    bp = h * h * beta * scale
    gp = h * gamma * scale
    n = model.free_dofs.shape[0]
    predict = _predicting(opt, st, h)
    for i in range(n):
        k = model.free_dofs[i]
        if not predict:  # a_{n+1} = a_n
            bar_new = (st.a[k] - am * st.abar[k]) / (1.0 - am)
        else:  # an alternation the step does not resolve, continued: the last change of a_n
            # again, scaled by the ratio r of the last two changes where r < 0 (a trend, r > 0, is not extrapolated)
            d1 = st.a[k] - st.a_hist[0, k]
            d0 = st.a_hist[0, k] - st.a_hist[1, k]
            ratio = min(max(d1 / d0, -1.0), 0.0) if d0 != 0.0 else 0.0
            guess = st.a[k] + ratio * d1
            bar_new = ((1.0 - af) * guess + af * st.a[k] - am * st.abar[k]) / (1.0 - am)
            st.a[k] = guess
        st.q[k] += h * st.v[k] + h * h * ((0.5 - beta) * st.abar[k] + beta * bar_new)
        st.v[k] += h * ((1.0 - gamma) * st.abar[k] + gamma * bar_new)
        st.abar[k] = bar_new
    apply_prescribed(model.att_index, model.att_kind, model.att_vec, model.att_radius, ws.ship, st.phi,
                     st.q, st.v, st.a)
    apply_feed(model, st.phi)
    reused = not (st.jac[JAC_VALID] == 0.0 or abs(h / st.jac[JAC_H] - 1.0) > 0.05
                  or st.jac[JAC_AGE] >= opt.jac_max_age or st.jac[JAC_SKIP] > 0.0)
    if not reused:
        st.jac[JAC_SKIP] = max(st.jac[JAC_SKIP] - 1.0, 0.0)
        if not _factorize(model, opt, st, ws, t1, h, am, af, gamma, beta):
            return STEP_NOT_CONVERGED
    eta = max(st.jac[JAC_ETA], 1e-4) ** 0.8
    prev = 0.0
    theta = 0.0  # contraction rate of the current factorisation (0: not measured yet)
    since = 0    # iterations with the current factorisation
    switches = 0  # refactorisations for points of the tension-only law that went slack or taut
    refresh = False  # refactorise at the current iterate before the next solve
    converged = False
    for it in range(opt.max_iter):
        residual(model, st.q, st.v, st.a, t1, ws.ship, ws.r)
        st.stats[STAT_RESIDUALS] += 1
        st.stats[STAT_NEWTON] += 1
        if switches < MAX_SWITCH_REFRESH and _switched(model):
            # the law's kink lies between the matrix and the iterate: a matrix with the other
            # side's stiffness sends modified Newton into a 2-cycle or a crawl
            switches += 1
            refresh = True
        if refresh:
            refresh = False
            reused = False
            if not _factorize(model, opt, st, ws, t1, h, am, af, gamma, beta):
                return STEP_NOT_CONVERGED
            since = 0
            theta = 0.0
            eta = 1.0
        finite = True
        for i in range(n):
            ws.dx[i] = -ws.r[model.free_dofs[i]]
            if not math.isfinite(ws.dx[i]):
                finite = False
        if not finite:
            break
        band_solve(ws.ab, n, model.kl, model.ku, ws.ipiv, ws.dx)
        dnorm = 0.0
        for i in range(n):
            k = model.free_dofs[i]
            d = ws.dx[i]
            st.a[k] += d
            st.abar[k] += scale * d
            st.v[k] += gp * d
            st.q[k] += bp * d
            e = abs(bp * d) * model.free_scale[i]
            if not e <= dnorm:  # (not max(): a NaN correction must not pass as converged)
                dnorm = e
        if not math.isfinite(dnorm):
            break
        if since > 0:
            theta = dnorm / max(prev, 1e-300)
            if theta < 1.0:
                eta = theta / (1.0 - theta)
        if theta < 1.0 and (eta * dnorm <= opt.newton_tol or dnorm <= 1e-3 * opt.newton_tol):
            converged = True
            break
        if theta > THETA_REFRESH:
            if reused:
                # a matrix from an earlier step contracts slowly: refresh it here and go on,
                # and factorise afresh for the next steps (twice as many as after the last miss)
                st.jac[JAC_BACKOFF] = min(2.0 * st.jac[JAC_BACKOFF] + 1.0, MAX_BACKOFF)
                st.jac[JAC_SKIP] = st.jac[JAC_BACKOFF]
                refresh = True
                continue
            if theta >= 1.0:
                break  # diverging with a fresh matrix: the caller retries with a smaller step
        prev = dnorm
        since += 1
    if not converged:
        return STEP_NOT_CONVERGED
    st.jac[JAC_ETA] = eta
    st.jac[JAC_AGE] += 1.0
    if reused:
        st.jac[JAC_BACKOFF] = math.floor(0.5 * st.jac[JAC_BACKOFF])
    if theta > THETA_REUSE:
        # the matrix is not accurate enough to be reused: refresh it at the next step
        st.jac[JAC_AGE] = opt.jac_max_age
    # local error estimate (Zienkiewicz-Xie), weighted max norm over free coordinates: a
    # position against atol + rtol times its element's length, a slope against rtol + atol
    c = h * h * abs(beta - 1.0 / 6.0)
    err = 0.0
    for i in range(n):
        k = model.free_dofs[i]
        w = model.free_scale[i]
        e = c * abs(st.abar[k] - ws.abar0[k]) * w / (opt.rtol + opt.atol * w)
        err = max(err, e)
    st.clock[CLOCK_ERROR] = err
    if opt.adaptive and err > 1.0:
        return STEP_ERROR_TOO_LARGE
    st.clock[CLOCK_TIME] = t1
    return STEP_ACCEPTED


@njit(cache=True, inline="always")
def _restore(st, ws):
    copy_into(st.q, ws.q0)
    copy_into(st.v, ws.v0)
    copy_into(st.a, ws.a0)
    copy_into(st.abar, ws.abar0)
    copy_into(st.phi, ws.phi0)


# A kernel of its own (not IR-inlined into towcable_fmu.ancf.output_kernel.advance_recording):
# the first run compiles it in parallel with the output kernel (towcable_fmu.jit.parallel_compile).
@njit(cache=True)
def advance(model: CableModel, opt: SolverOptions, st: IntegratorState, ws: Workspace, t_end: float,
            drive_t: np.ndarray, drive_x: np.ndarray, one_step: bool) -> int:
    """Integrate from the state's time to ``t_end`` (landing on it exactly), or with
    ``one_step`` take one accepted step of the current size towards it (the last one
    shortened to land on ``t_end``).

    Parameters
    ----------
    model, opt
        The system and the solver options.
    st, ws
        Integrator state (modified) and workspace.
    t_end
        Target time [s].
    drive_t, drive_x
        Drive table (see :func:`evaluate_drive`) covering the interval.
    one_step
        Return after one accepted step; ``ws.q0``, ``v0``, ``a0``, ``phi0`` and
        ``step_start`` then hold its start (for interpolated outputs).

    Returns
    -------
    int
        ``OK``; ``FAILED_MIN_STEP`` when a step failed at the minimum step size (the state
        is then the last accepted step, at a time before ``t_end``); or ``FEED_EVENT`` after
        an accepted step that took a spool end's fed element out of its band (the caller
        remeshes and calls again).
    """
    am, af, gamma, beta = scheme_coefficients(opt.rho_inf)
    while True:
        t = st.clock[CLOCK_TIME]
        remaining = t_end - t
        if remaining <= 1e-12 * max(1.0, abs(t_end)):
            st.clock[CLOCK_TIME] = t_end
            return OK
        h = min(st.clock[CLOCK_STEP], opt.h_max)
        # (the clock sums thousands of steps: no extra step for its round-off)
        nrem = math.ceil(remaining / h - 1e-6)
        # one step: the current size, the last two steps before t_end split evenly
        h_try = h if one_step and nrem > 2 else remaining / nrem
        copy_into(ws.q0, st.q)
        copy_into(ws.v0, st.v)
        copy_into(ws.a0, st.a)
        copy_into(ws.abar0, st.abar)
        copy_into(ws.phi0, st.phi)
        retried = False  # with a fresh Jacobian
        located = False  # the step was shortened to end at a tension-only element's kink
        while True:  # (one call site of the inlined _try_step)
            status = _try_step(model, opt, st, ws, h_try, drive_t, drive_x, am, af, gamma, beta)
            if status == STEP_NOT_CONVERGED and st.jac[JAC_AGE] > 0.0 and not retried:
                # stale Jacobian: retry the same step with a fresh one
                _restore(st, ws)
                st.jac[JAC_VALID] = 0.0
                st.jac[JAC_ETA] = 1.0
                retried = True
                continue
            if status == STEP_ACCEPTED and opt.locate_events and not located:
                s_event = crossing_fraction(model, ws.q0, st.q, st.taut, model.el_taut[TAUT_RESIDUAL])
                if s_event < EVENT_LAND:
                    # an element went taut or slack inside the step: end the step just past it
                    _restore(st, ws)
                    st.clock[CLOCK_TIME] = t
                    h_try *= max(s_event * (1.0 + EVENT_OVERSHOOT), EVENT_MIN_FRACTION)
                    located = True
                    continue
            break
        if status == STEP_ACCEPTED:
            ws.step_start[0] = t
            copy_into(st.a_hist[1], st.a_hist[0])
            copy_into(st.a_hist[0], ws.a0)
            st.h_hist[1] = st.h_hist[0]
            st.h_hist[0] = h_try
            copy_into(st.taut, model.el_taut[TAUT_RESIDUAL])
            st.stats[STAT_STEPS] += 1
            st.clock[CLOCK_STEPS_SINCE_CUT] += 1.0
            if opt.adaptive:
                err = st.clock[CLOCK_ERROR]
                factor = 0.9 * max(err, 1e-10) ** (-1.0 / 3.0)
                st.clock[CLOCK_STEP] = min(opt.h_max, h_try * min(2.0, max(0.5, factor)))
                if nrem > 1 and st.clock[CLOCK_STEP] > h_try and st.clock[CLOCK_STEP] < 1.2 * h_try:
                    st.clock[CLOCK_STEP] = h_try  # avoid re-factorising for a marginal gain
            elif st.clock[CLOCK_STEPS_SINCE_CUT] >= 8.0 and st.clock[CLOCK_STEP] < opt.h_max:
                # fixed-step mode after a cut: return to the nominal step by doublings
                st.clock[CLOCK_STEP] = min(opt.h_max, 2.0 * st.clock[CLOCK_STEP])
                st.clock[CLOCK_STEPS_SINCE_CUT] = 0.0
            if feed_event(model):
                return FEED_EVENT
            if one_step:
                return OK
            continue
        _restore(st, ws)
        st.stats[STAT_REJECTED] += 1
        st.clock[CLOCK_STEPS_SINCE_CUT] = 0.0
        if status == STEP_ERROR_TOO_LARGE:
            factor = 0.9 * st.clock[CLOCK_ERROR] ** (-1.0 / 3.0)
            h_new = h_try * min(0.9, max(0.2, factor))
        else:
            h_new = 0.5 * h_try
            st.jac[JAC_ETA] = 1.0
        if h_new < opt.h_min:
            apply_feed(model, st.phi)  # the fed element of the last accepted step
            return FAILED_MIN_STEP
        st.clock[CLOCK_STEP] = h_new
