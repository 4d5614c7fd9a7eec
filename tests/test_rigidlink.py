"""Verification of the rigid-link tug-tow model (towcable_fmu.rigidlink).

Each test compares the model with something computed independently of it: the
mechanical energy from the points' own velocities and heights, Newton's law of the tug
alone, the elastic catenary in closed form (tests/reference/catenary.py) and the
integral of the trapezoidal thrust rate.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from reference.catenary import solve_elastic_catenary

from towcable_fmu.cli import main
from towcable_fmu.common.errors import SceneError
from towcable_fmu.rigidlink.dynamics import accelerations, end_tensions, link_forces
from towcable_fmu.scene.rigid_link import Thrust
from towcable_fmu.rigidlink.simulation import RigidLinkSimulation
from towcable_fmu.rigidlink.statics import solve_statics
from towcable_fmu.rigidlink.thrust import thrust_at
from towcable_fmu.scene import load_scene

G = 9.81


def _sim(overrides: dict | None = None) -> RigidLinkSimulation:
    return RigidLinkSimulation(load_scene("tug_tow", overrides or {}))


def _energy(sim: RigidLinkSimulation, y: np.ndarray) -> tuple[float, float]:
    """Kinetic and potential (gravity, joint springs, heave springs) energy [J], from the points.

    Independent of the model's mass matrix: each point's velocity is differentiated
    here from its position along the chain. The vessels' weight is balanced by their
    buoyancy (their net potential is only the heave spring about the reference height).
    """
    n = sim.l.size
    q, qd = y[: n + 2], y[n + 2:]
    theta, omega = q[2:], qd[2:]
    step = sim.l[:, None] * np.column_stack((np.cos(theta), np.sin(theta)))
    step_rate = sim.l[:, None] * omega[:, None] * np.column_stack((-np.sin(theta), np.cos(theta)))
    nodes = q[:2] + np.vstack(([0.0, 0.0], np.cumsum(step, axis=0)))
    node_v = qd[:2] + np.vstack(([0.0, 0.0], np.cumsum(step_rate, axis=0)))
    mid = 0.5 * (nodes[:-1] + nodes[1:])
    mid_v = 0.5 * (node_v[:-1] + node_v[1:])
    z0 = sim.scene.layout.height
    kinetic = 0.5 * (sim.tug[0] * node_v[0] @ node_v[0] + sim.towed[0] * node_v[-1] @ node_v[-1]
                     + np.sum(sim.m * np.sum(mid_v ** 2, axis=1)))
    potential = (np.sum(sim.m * G * mid[:, 1]) + 0.5 * np.sum(sim.k * np.diff(theta) ** 2)
                 + 0.5 * sim.tug[1] * (nodes[0, 1] - z0) ** 2 + 0.5 * sim.towed[1] * (nodes[-1, 1] - z0) ** 2)
    return float(kinetic), float(potential)


def test_thrust_is_the_integral_of_a_trapezoidal_rate():
    spec = Thrust(maximum=320e3, ramp_time=80.0, rise_fraction=0.25)
    t = np.linspace(0.0, 100.0, 200001)
    a, T = 20.0, 80.0
    rate = np.clip(np.minimum(t / a, (T - t) / a), 0.0, 1.0)  # trapezoid of height 1
    rate *= 320e3 / np.trapezoid(rate, t)
    integral = np.concatenate(([0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))))
    model = np.array([thrust_at(x, spec) for x in t])
    assert np.max(np.abs(model - integral)) < 1e-3 * 320e3
    assert thrust_at(80.0, spec) == pytest.approx(320e3, rel=1e-12)
    assert thrust_at(40.0, spec) == pytest.approx(160e3, rel=1e-12)  # symmetric ramp
    assert thrust_at(-1.0, spec) == 0.0 and thrust_at(500.0, spec) == 320e3


def test_energy_is_conserved_without_damping_and_thrust():
    """Start off equilibrium (the parabola) with heave springs, joint springs, gravity:
    the total energy stays constant while about 1e3 J swing between its parts."""
    sim = _sim({"cable.links": 8, "cable.bending_damping": 0.0, "cable.EI": 5e4, "thrust.maximum": 0.0,
                "tug.heave_kd": 0.0, "towed.heave_kd": 0.0, "tug.resistance": 0.0, "towed.resistance": 0.0,
                "tug.wave_amplitude": 0.0, "towed.wave_amplitude": 0.0, "tug.mass": 2e3, "towed.mass": 5e3,
                "tug.heave_kp": 2e4, "towed.heave_kp": 5e4,
                "solver.method": "DOP853", "solver.rtol": 1e-11, "solver.atol": 1e-12})
    e0 = sum(_energy(sim, sim.y))
    kinetic, total = [], []
    for _ in range(20):
        sim.run(0.5, interval=0.5)
        k, p = _energy(sim, sim.y)
        kinetic.append(k)
        total.append(k + p)
    kinetic_peak = max(kinetic)
    drift = max(abs(e - e0) for e in total)
    assert drift < 1e-7 * kinetic_peak


def test_tension_at_the_tug_matches_the_tugs_own_newton_law():
    """The link-by-link force at node 0 equals thrust + resistance + heave force + weight - M a."""
    sim = _sim()
    rng = np.random.default_rng(1)
    n = sim.l.size
    q = sim.y[: n + 2] + np.concatenate(([0.3, -0.2], 0.05 * rng.standard_normal(n)))
    qd = np.concatenate(([1.5, 0.4], 0.2 * rng.standard_normal(n)))
    refs = np.array([3.1, 0.2, 2.9, -0.3])
    qdd, ft, fb = accelerations(q, qd, sim.l, sim.m, sim.k, sim.c, sim.tug, sim.towed, 2e5, refs, G)
    F = link_forces(q, qd, qdd, sim.l, sim.m, sim.towed[0], fb, G)
    tug_on_cable = ft + np.array([0.0, -sim.tug[0] * G]) - sim.tug[0] * qdd[:2]
    assert np.allclose(F[0], tug_on_cable, rtol=1e-9, atol=1e-6 * np.abs(tug_on_cable).max())
    # and the axial component is what end_tensions reports at the tug
    e1 = np.array([math.cos(q[2]), math.sin(q[2])])
    assert end_tensions(q, F)[0] == pytest.approx(-tug_on_cable @ e1, rel=1e-9)


@pytest.mark.parametrize("links", [4, 8, 16, 32, 64])
def test_static_tension_is_tensile_everywhere_and_agrees_with_the_recursion(links):
    """Without bending stiffness a hanging chain carries tension only; the statics'
    support forces and Newton's law link by link (zero acceleration) agree."""
    sim = _sim({"cable.links": links, "cable.EI": 0.0})
    eq = solve_statics(sim.theta0, sim.l, sim.m, sim.k, 30.0, G, force0=(-5e3, 1.4e3))
    n = links
    q = np.concatenate(([30.0, 0.0], eq.theta))
    F = link_forces(q, np.zeros(n + 2), np.zeros(n + 2), sim.l, sim.m, 0.0, eq.force_towed, G)
    e = np.column_stack((np.cos(eq.theta), np.sin(eq.theta)))
    tensions = np.concatenate((-np.einsum("ij,ij->i", F[:-1], e), -np.einsum("ij,ij->i", F[1:], e)))
    assert tensions.min() > 0.0
    assert -F[0] @ e[0] == pytest.approx(eq.tension_tug, rel=1e-9)
    assert -F[-1] @ e[-1] == pytest.approx(eq.tension_towed, rel=1e-9)


def test_static_sag_converges_to_the_catenary_as_links_grow():
    """Sag and end tension of the chain tend to the catenary of the same cable (length
    n l, weight per length) at second order in 1/n. The links are rigid, so the limit
    is the elastic catenary with EA -> infinity; the tug_tow wire (EA = 1.05e8 N)
    would stretch by T/EA = 5e-5 and deepen the sag by about 4 mm more, a difference
    the test also states."""
    errors = []
    for links in (5, 10, 20, 40, 80):
        sim = _sim({"cable.links": links, "cable.EI": 0.0})
        w = sim.scene.cable.mass_per_length * G
        eq = solve_statics(sim.theta0, sim.l, sim.m, sim.k, 30.0, G, force0=(-w * 900 / 16, 0.5 * w * sim.length))
        cat = solve_elastic_catenary(sim.length, 1e15, w, 30.0, 0.0)
        errors.append((abs(eq.sag - cat.sag) / cat.sag, abs(eq.tension_tug - cat.tension_A) / cat.tension_A))
    errors = np.array(errors)
    assert errors[-1, 0] < 2e-4 and errors[-1, 1] < 2e-4
    order = np.log2(errors[:-1] / errors[1:])  # observed order between successive meshes
    assert np.all(order > 1.7)
    elastic = solve_elastic_catenary(sim.length, 1.05e8, w, 30.0, 0.0)
    assert 1e-3 < elastic.sag - cat.sag < 1e-2  # the stretch the rigid links leave out [m]


def test_run_from_the_cli_writes_tensions_and_positions(tmp_path):
    out = tmp_path / "tug_tow.csv"
    assert main(["run", "tug_tow", "--duration", "2", "--output", str(out), "--quiet",
                 "--set", "cable.links=6"]) == 0
    with open(out, encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 21
    for name in ("time", "tension.top", "tension.towbody", "ship.x", "ship.z", "towbody.x", "towbody.z",
                 "cable.taut"):
        assert name in rows[0]
    first = rows[0]
    # the reference's start: fairleads 30 m apart at the scene's height, at rest
    assert float(first["ship.x"]) - float(first["towbody.x"]) == pytest.approx(30.0, abs=1e-12)
    assert float(first["ship.z"]) == pytest.approx(3.0, abs=1e-12)
    assert float(first["ship.vx"]) == 0.0 and float(first["towbody.vz"]) == 0.0
    assert all(float(r["tension.top"]) > 0.0 and float(r["cable.taut"]) == 0.0 for r in rows)


def test_static_command_reports_the_catenary_tension(capsys):
    assert main(["static", "tug_tow", "--json", "--set", "cable.EI=0", "--set", "cable.links=80"]) == 0
    import json

    out = json.loads(capsys.readouterr().out)
    sim = _sim({"cable.links": 80})
    cat = solve_elastic_catenary(sim.length, 1e15, 9.2 * G, 30.0, 0.0)
    assert out["tension.top"] == pytest.approx(cat.tension_A, rel=1e-3)
    assert out["cable.sag"] == pytest.approx(cat.sag, rel=1e-3)


@pytest.mark.parametrize("key, value, fragment", [
    ("model", "lumped_mass", "'ancf', 'rigid_link'"),
    ("cable.links", 1, ">= 2"),
    ("tug.mass", -5.0, "> 0"),
    ("layout.sag", 20.0, "< span / 2"),
    ("cable.elements", 10, "one of the keys"),
])
def test_bad_rigid_link_input_names_key_value_and_allowed(key, value, fragment):
    with pytest.raises(SceneError) as info:
        load_scene("tug_tow", {key: value})
    assert info.value.key == key and info.value.value == value and fragment in str(info.value)


def test_steady_tow_tension_is_the_barge_resistance():
    """At full thrust in calm water the pair settles at the speed where thrust equals the
    total resistance, u = sqrt(F / (c_tug + c_towed)) = 4 m/s, and the cable carries the
    barge's resistance c_towed u^2 = 256 kN (plus nothing: no waves, constant speed).
    Lighter vessels (a tenth) make the approach fast enough for a unit test."""
    sim = _sim({"cable.links": 6, "tug.mass": 6e4, "towed.mass": 2e5, "tug.wave_amplitude": 0.0,
                "towed.wave_amplitude": 0.0, "tug.heave_kp": 2.1e5, "tug.heave_kd": 4.5e4,
                "towed.heave_kp": 1.09e6, "towed.heave_kd": 1.9e5})
    series = sim.run(110.0, interval=0.1)
    u = math.sqrt(320e3 / (4000.0 + 16000.0))
    last = series["time"] >= 100.0  # means over 10 s: a lightly damped chain mode (about 2 % of T) rings on
    assert series["towbody.vx"][last].mean() == pytest.approx(u, rel=1e-4)
    assert series["tension.towbody"][last].mean() == pytest.approx(16000.0 * u ** 2, rel=1e-3)
    assert np.all(series["cable.taut"][last] == 1.0)


def test_ancf_twin_has_the_same_cable():
    """tug_tow_ancf's cable is the rigid-link cable: same wire, and its length is the arc
    length of the reference's parabola (which the rigid chain's length tends to)."""
    from scipy.integrate import quad

    ancf = load_scene("tug_tow_ancf")
    rigid = load_scene("tug_tow")
    seg = ancf.cable.segments[0]
    D, d = rigid.layout.span, rigid.layout.sag
    arc = quad(lambda x: math.sqrt(1.0 + (4.0 * d / D * (1.0 - 2.0 * x / D)) ** 2), 0.0, D, epsabs=1e-12)[0]
    assert seg.length == pytest.approx(arc, abs=1e-3)
    assert _sim({"cable.links": 200}).length == pytest.approx(arc, rel=1e-5)
    assert (seg.mass_per_length, seg.EA, seg.EI) == (rigid.cable.mass_per_length, rigid.cable.EA, rigid.cable.EI)
    assert ancf.cable.top.position[2] == rigid.layout.height
