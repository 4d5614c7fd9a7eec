"""Dynamics against closed forms, conservation laws and an independent integrator."""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import cable_scene, segment
from scipy.optimize import brentq

from towcable_fmu.common.errors import SceneError, SolverError
from towcable_fmu.ancf.reference_ivp import integrate_reference

G = 9.81


def _zero_crossing_period(t: np.ndarray, y: np.ndarray) -> float:
    """Mean period from upward zero crossings (linear interpolation)."""
    y = y - y.mean()
    idx = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    times = t[idx] - y[idx] * (t[idx + 1] - t[idx]) / (y[idx + 1] - y[idx])
    assert times.size >= 3, "too few oscillations recorded"
    return float(np.mean(np.diff(times)))


@pytest.mark.parametrize("mode", [1, 2, 3])
def test_taut_cable_transverse_frequencies(make_sim, mode):
    """Free vibration of a taut cable: f_n = n / (2 L) sqrt(T / mu) (stretched length and
    mass per stretched length), gravity off, no damping, no numerical damping."""
    L0, stretch, mu, ea = 10.0, 1.01, 0.1, 1e5
    span = L0 * stretch
    table = cable_scene([segment(L0, 24, mu=mu, EA=ea, EI=1e-6)],
                        top={"type": "pinned", "position": [0.0, 0.0, 0.0]},
                        bottom={"type": "pinned", "position": [span, 0.0, 0.0]},
                        environment={"gravity": 0.0}, solver={"time_step": 5e-4, "rho_inf": 1.0})
    sim = make_sim(table)
    sim.initialize()
    tension = sim.outputs()["tension.top"]
    assert tension == pytest.approx(ea * 0.5 * (stretch**2 - 1) * stretch, rel=1e-6)  # EA eps lambda
    # release from the mode shape: y = A sin(n pi x / span), amplitude 1 mm
    q = sim.state.q.copy().reshape(-1, 2, 3)
    x = q[:, 0, 0]
    k = mode * np.pi / span
    amp = 1e-3
    q[:, 0, 1] = amp * np.sin(k * x)
    q[:, 1, 1] = stretch * amp * k * np.cos(k * x)
    sim.set_coordinates(q.ravel())
    probe = int(np.argmin(np.abs(x - span / (2 * mode))))  # an antinode
    f_exact = mode / (2 * span) * np.sqrt(tension / (mu / stretch))
    duration = 6.0 / f_exact
    times, ys = [], []
    for t_out in np.linspace(0, duration, 600)[1:]:
        sim.advance(t_out)
        times.append(t_out)
        ys.append(sim.state.q[6 * probe + 1])
    period = _zero_crossing_period(np.array(times), np.array(ys))
    assert 1.0 / period == pytest.approx(f_exact, rel=2e-3)


def test_hanging_mass_axial_frequency(make_sim):
    """Axial oscillation of a mass on an elastic cable: the exact fixed-free bar with an
    end mass, beta tan(beta) = mu L / m, omega = beta sqrt(EA/mu) / L (close to the
    Rayleigh estimate sqrt(EA / (L (m + mu L / 3))))."""
    L, mu, ea, m = 10.0, 0.1, 1e6, 10.0  # static strain 1e-4: the linear bar applies
    table = cable_scene([segment(L, 10, mu=mu, EA=ea, EI=1e-4)],
                        top={"type": "pinned", "position": [0.0, 0.0, 0.0]}, towbody={"mass": m},
                        solver={"time_step": 2e-4, "rho_inf": 1.0})
    sim = make_sim(table)
    sim.initialize()
    z_eq = sim.outputs()["towbody.z"]
    # kick: a velocity profile growing linearly along the cable (close to the first mode)
    v = np.zeros_like(sim.state.q).reshape(-1, 2, 3)
    v[:, 0, 2] = -0.05 * sim.mesh.node_arc / L
    sim.set_coordinates(sim.state.q, v.ravel())
    res = sim.run(0.7, interval=4e-4)  # about ten periods
    beta = brentq(lambda b: b * np.tan(b) - mu * L / m, 1e-6, np.pi / 2 - 1e-9)
    omega_exact = beta * np.sqrt(ea / mu) / L
    period = _zero_crossing_period(res["time"], res["towbody.z"] - z_eq)
    assert 2 * np.pi / period == pytest.approx(omega_exact, rel=2e-3)
    omega_rayleigh = np.sqrt(ea / (L * (m + mu * L / 3)))
    assert omega_exact == pytest.approx(omega_rayleigh, rel=1e-3)


def test_towed_body_force_counts_the_body_alone_below_an_end_mass(make_sim):
    """A 30 kg end mass and a 20 kg body on the last node of a light cable (in air) hung
    from a ship heaving 1 m at 3 s (up to 0.45 g; from the top of the heave, at rest): the
    node's two masses share one acceleration, so the cable pulls the pair with
    (m_end + m_body) |a + g| and the end mass passes on m_body |a + g| to the body:
    tension.towbody is m_body / (m_end + m_body) = 0.4 of the force in the cable at its end
    (from its strain; within 1 %, the light last element's own inertia), in statics and
    throughout the heave."""
    m_end, m_body = 30.0, 20.0
    table = cable_scene([segment(10.0, 10, mu=0.1, EA=1e6, EI=1e-4, damping=50.0)],
                        top={"type": "pinned", "frame": "ship", "position": [0.0, 0.0, 0.0]},
                        bottom={"type": "free", "mass": m_end}, towbody={"mass": m_body},
                        motion={"type": "regular", "heave": {"amplitude": 1.0, "period": 3.0, "phase": 90.0}},
                        solver={"time_step": 5e-3})
    table["cable"]["initial"] = {"direction": [0.0, 0.0, -1.0]}
    sim = make_sim(table)
    out = sim.initialize()
    assert out["tension.towbody"] == pytest.approx(m_body * G, rel=1e-7)  # statics tolerance
    res = sim.run(6.0, interval=0.05)
    assert np.ptp(res["tension.bottom"]) > 0.5 * (m_end + m_body) * G  # the heave does shake the masses
    np.testing.assert_allclose(res["tension.towbody"], m_body / (m_end + m_body) * res["tension.bottom"], rtol=0.01)


def _pendulum(make_sim, damping: float, rho_inf: float):
    table = cable_scene([segment(5.0, 6, mu=0.5, EA=2e5, EI=1e-2, damping=damping)],
                        top={"type": "pinned", "position": [0.0, 0.0, 0.0]}, towbody={"mass": 2.0},
                        solver={"time_step": 2e-3, "rho_inf": rho_inf})
    table["cable"]["initial"] = {"direction": [np.sin(0.5), 0.0, -np.cos(0.5)]}
    sim = make_sim(table)
    sim.initialize(statics=False)  # released from a straight, unstretched cable 29 deg off vertical
    return sim


def test_energy_is_conserved_without_damping(make_sim):
    sim = _pendulum(make_sim, damping=0.0, rho_inf=1.0)
    res = sim.run(45.0, interval=0.01)  # about ten pendulum periods
    energy = res["energy.kinetic"] + res["energy.strain"] + res["energy.gravity"]
    swing = np.ptp(res["energy.gravity"])  # energy exchanged per swing
    assert swing > 10.0
    assert np.abs(energy - energy[0]).max() < 0.01 * swing


def test_energy_decreases_with_damping(make_sim):
    sim = _pendulum(make_sim, damping=5.0, rho_inf=0.8)
    res = sim.run(10.0, interval=0.01)
    energy = res["energy.kinetic"] + res["energy.strain"] + res["energy.gravity"]
    assert np.all(np.diff(energy) <= 1e-9 * np.abs(energy).max())
    assert energy[-1] < energy[0] - 1.0


def test_fast_integrator_agrees_with_scipy_radau(make_sim):
    """Same scene, same equations: generalised-alpha (small step) against solve_ivp(Radau)."""
    table = cable_scene([segment(6.0, 4, mu=0.3, EA=5e4, EI=0.05, damping=0.5)],
                        top={"type": "pinned", "frame": "ship", "position": [0.0, 0.0, 0.0]},
                        towbody={"mass": 1.0}, solver={"time_step": 1e-3, "newton_tol": 1e-11},
                        motion={"type": "regular", "ramp": 0.5, "heave": {"amplitude": 0.3, "period": 1.5},
                                "surge": {"amplitude": 0.5, "period": 2.0}})
    sim = make_sim(table)
    sim.initialize()
    t_eval = np.linspace(0.25, 2.0, 8)
    ref = integrate_reference(sim, 2.0, t_eval, rtol=1e-9, atol=1e-11)
    for k, t in enumerate(t_eval):
        sim.advance(t)
        np.testing.assert_allclose(sim.state.q, ref[k], atol=2e-5)


WINCH = {"position": [1.0, 0.0, 0.5], "radius": 0.3, "phi_nom": 0.5, "kp": 200.0, "kd": 20.0,
         "contact": {"stiffness": 1e6, "exponent": 1.5, "damping": 0.0}}


@pytest.mark.slow  # three Radau integrations per case at rtol 1e-9, each rhs from Python: 2-6 min in all
@pytest.mark.parametrize("top, extra", [
    ({"type": "pinned", "frame": "ship", "position": [1.0, 0.0, 0.5]}, {}),
    ({"type": "clamped", "frame": "ship", "position": [1.0, 0.0, 0.5], "slope": [0.6, 0.0, -0.8]}, {}),
    ({"type": "winch"}, {"winch": WINCH}),
], ids=["pinned", "clamped", "winch"])
def test_baumgarte_constraint_agrees_with_elimination(make_sim, top, extra):
    """W(113)-(118): the prescribed end held by a Baumgarte-stabilised constraint (the
    reference's way) moves the cable exactly as the elimination does; a violated
    constraint decays as C'' + 2 alpha C' + beta^2 C = 0 prescribes. The winch end is
    W(120): the cable's end fixed on the drum (rotation held), moving with the ship."""
    table = cable_scene([segment(6.0, 4, mu=0.3, EA=5e4, EI=0.05, damping=0.5)], top=top,
                        towbody={"mass": 1.0}, **extra,
                        motion={"type": "regular", "ramp": 0.5, "heave": {"amplitude": 0.3, "period": 1.5},
                                "pitch": {"amplitude": 3.0, "period": 2.0}, "roll": {"amplitude": 4.0, "period": 2.5}})
    sim = make_sim(table)
    sim.initialize()
    t_eval = np.linspace(0.1, 1.0, 10)
    exact = integrate_reference(sim, 1.0, t_eval, rtol=1e-9, atol=1e-11)
    stabilised = integrate_reference(sim, 1.0, t_eval, rtol=1e-9, atol=1e-11, constraints="baumgarte")
    np.testing.assert_allclose(stabilised, exact, atol=1e-7)

    held = np.flatnonzero(sim.model.free_idx < 0)
    beta = 20.0
    sim.state.q[held] += 1e-3  # start off the constraint, at rest relative to it
    off = integrate_reference(sim, 1.0, t_eval, rtol=1e-9, atol=1e-11, constraints="baumgarte",
                              baumgarte=(beta, beta))
    decay = 1e-3 * (1.0 + beta * t_eval) * np.exp(-beta * t_eval)  # critically damped: alpha = beta
    np.testing.assert_allclose(off[:, held] - exact[:, held], decay[:, None] * np.ones(held.size),
                               rtol=1e-3, atol=1e-10)


def test_state_round_trip_continues_bit_identically(make_sim):
    table = cable_scene([segment(20.0, 8, mu=0.5, EA=1e5, EI=0.1, damping=1.0)],
                        top={"type": "pinned", "frame": "ship", "position": [0.0, 0.0, 0.0]},
                        towbody={"mass": 5.0},
                        motion={"type": "regular", "heave": {"amplitude": 0.5, "period": 3.0}})
    sim = make_sim(table)
    sim.initialize()
    sim.run(1.0)
    saved = json.loads(json.dumps(sim.get_state()))
    first = [sim.advance(1.0 + 0.1 * k) for k in range(1, 11)]
    sim.set_state(saved)
    second = [sim.advance(1.0 + 0.1 * k) for k in range(1, 11)]
    assert first == second


def test_failed_step_leaves_state_unchanged(make_sim):
    table = cable_scene([segment(20.0, 8, mu=0.5, EA=1e5, EI=0.1)],
                        top={"type": "pinned", "frame": "ship", "position": [0.0, 0.0, 0.0]},
                        towbody={"mass": 5.0}, solver={"max_newton_iterations": 1, "min_time_step": 0.009})
    sim = make_sim(table)
    sim.initialize()
    before = sim.get_state()
    ship = np.zeros((3, 6))
    ship[2, 2] = 1e6  # an absurd vertical acceleration of the support
    with pytest.raises(SolverError):
        sim.step(0.01, ship)
    assert sim.get_state() == before
    with pytest.raises(SceneError, match="ship"):
        ship[0, 0] = np.nan
        sim.step(0.01, ship)
    with pytest.raises(SceneError, match="dt"):
        sim.step(-0.01, np.zeros((3, 6)))
    assert sim.get_state() == before


def _driven_cable(make_sim, solver):
    """The ship-driven cable of test_fast_integrator_agrees_with_scipy_radau (there the
    fixed-step integrator is checked against Radau at 2e-5 with h = 1e-3)."""
    table = cable_scene([segment(6.0, 4, mu=0.3, EA=5e4, EI=0.05, damping=0.5)],
                        top={"type": "pinned", "frame": "ship", "position": [0.0, 0.0, 0.0]},
                        towbody={"mass": 1.0}, solver=solver,
                        motion={"type": "regular", "ramp": 0.5, "heave": {"amplitude": 0.3, "period": 1.5},
                                "surge": {"amplitude": 0.5, "period": 2.0}})
    sim = make_sim(table)
    sim.initialize()
    return sim


def test_adaptive_step_control_tighter_tolerance_more_steps_smaller_error(make_sim):
    """solver.adaptive: the step follows the local error estimate h^2 |beta - 1/6| |dabar|
    weighted by atol + rtol l for a position (l: its element's length) and rtol + atol
    for a slope. Two tolerances 100x apart, against a fine fixed-step
    reference (h = 2.5e-4: 16x below the error of h = 1e-3, itself 2e-5 from Radau):
    (a) the tighter tolerance takes more steps, about 100^(1/3) = 4.6x for a local error
    of order h^3 (measured 4.3x); (b) its error is smaller, about 100^(2/3) = 21x for a
    second-order global error (measured 15x), and within the order the tolerance allows:
    an error-per-step control commits at most one weighted tolerance per accepted step,
    so the weighted global error stays below the number of steps (measured 132 against
    481 steps, tight; 18 against 113, loose)."""
    t_eval = np.linspace(0.15, 1.5, 10)
    ref_sim = _driven_cable(make_sim, {"time_step": 2.5e-4, "newton_tol": 1e-11})
    ref = []
    for t in t_eval:
        ref_sim.advance(t)
        ref.append(ref_sim.state.q.copy())
    results = {}
    for rtol, atol in [(1e-3, 1e-4), (1e-5, 1e-6)]:
        sim = _driven_cable(make_sim, {"time_step": 0.05, "adaptive": True, "rtol": rtol, "atol": atol,
                                       "newton_tol": 1e-10})
        err = 0.0
        weighted = 0.0
        scale = sim.model.free_scale  # 1 / element length for positions, 1 for slopes
        for k, t in enumerate(t_eval):
            sim.advance(t)
            diff = np.abs(sim.state.q - ref[k])[sim.model.free_dofs]
            err = max(err, diff.max())
            weighted = max(weighted, (diff * scale / (rtol + atol * scale)).max())
        stats = sim.statistics()
        assert stats["solver.last_error_estimate"] <= 1.0
        results[rtol] = (stats["solver.steps"], err, weighted)
    steps_loose, err_loose, w_loose = results[1e-3]
    steps_tight, err_tight, w_tight = results[1e-5]
    assert steps_loose > 1.5 / 0.05  # the loose run is adaptive too, not capped by h_max
    assert steps_tight > 3.0 * steps_loose
    assert err_tight < err_loose / 8.0
    assert w_loose < steps_loose and w_tight < steps_tight
    assert err_tight < 1e-3  # absolute: 0.2 mm on a 6 m cable moving +-0.5 m


def _per_step(sim) -> tuple[float, float]:
    """Newton iterations and Jacobian factorisations per accepted step."""
    stats = sim.statistics()
    steps = stats["solver.steps"]
    return stats["solver.newton_iterations"] / steps, stats["solver.jacobian_factorisations"] / steps


def test_jacobian_reuse_policy_keeps_a_good_matrix_and_drops_a_failing_one():
    """Without contact one factorisation serves many steps. With the cable sliding over
    a rolling sheave the contact set changes from step to step and a reused matrix often
    fails; the policy must then cost no more than a fresh matrix forced at every step.
    Cost in residual evaluations: an iteration is one (plus a back-solve), a
    factorisation about four (Jacobian and LU, benchmarks/results/profile.md). The
    earlier policy, which reused until a step failed, needed 5.6 iterations per step here."""
    from towcable_fmu.ancf.simulation import Simulation

    calm = Simulation.from_scene("hanging_cable", {"solver.time_step": 0.01})  # (a predictor good to one iteration)
    calm.run(10.0)
    iterations, factorisations = _per_step(calm)
    assert factorisations < 0.05 and iterations < 1.1

    motion = {"type": "regular", "ramp": 10.0, "heave": {"amplitude": 1.0, "period": 9.0},
              "roll": {"amplitude": 5.0, "period": 10.0}}
    cost = {}
    for max_age in (100, 1):
        sim = Simulation.from_scene("full_scale", {"motion": motion, "solver.time_step": 0.04,
                                                   "solver.jacobian_max_age": max_age})
        sim.run(20.0, interval=0.1)
        iterations, factorisations = _per_step(sim)
        assert iterations < 3.0
        cost[max_age] = iterations + 4.0 * factorisations
    assert cost[100] <= cost[1], cost
