"""The rigid 6-DOF towed body on the nodal-position cable (towcable_fmu/nodal/rigid_body.py).

Each test compares with a closed form or an independent computation:

* free decay of a body on a short pendulum cable in air: the period of the
  compound-pendulum mode (2-DOF linearised closed form; the compound pendulum about the
  tow point as the cable length goes to 0), far from the simple pendulum;
* steady tow in a uniform current: the trim (pitch) where the moments of buoyancy,
  drag and the cable force about the CG balance, solved here by hand in the vertical
  plane from the settled cable force; and the force balance;
* a torque-free symmetric body: precession at the closed-form rate |L| / J_t with the
  angular momentum conserved;
* RK4 and generalised-alpha agree; the scene keys are validated.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from towcable_fmu.errors import SceneError
from towcable_fmu.nodal.simulation import NodalSimulation
from towcable_fmu.scene import load_scene
from towcable_fmu.scene.loader import scene_from_table

G = 9.81


def _pendulum_table(theta0: float, length: float, mass: float, jyy: float, d: float, **solver) -> dict:
    """A body of ``mass`` [kg] with J_yy [kg m^2], tow point ``d`` [m] above its CG, on a
    light stiff cable of ``length`` [m] from a fixed pin, in air, released from rest at
    pitch ``theta0`` with the cable along the tow point - CG line."""
    return {
        "cable": {"formulation": "nodal_position",
                  "segments": [{"length": length, "elements": 2, "diameter": 0.005, "mass_per_length": 1e-3,
                                "EA": 1e7, "EI": 0.0}],
                  "top": {"type": "pinned", "position": [0.0, 0.0, 0.0]}, "bottom": {"type": "free"},
                  "initial": {"shape": "straight", "direction": [-math.sin(theta0), 0.0, -math.cos(theta0)]}},
        "towbody": {"mass": mass, "model": "rigid",
                    "rigid": {"inertia": [0.8 * jyy, jyy, 0.6 * jyy], "tow_point": [0.0, 0.0, d],
                              "attitude": [0.0, theta0, 0.0]}},
        "statics": {"enabled": False},
        "solver": dict({"time_step": 0.002}, **solver),
    }


def _crossing_period(t: np.ndarray, y: np.ndarray) -> float:
    """Mean period [s] from the zero crossings of y (linear interpolation)."""
    i = np.where(np.sign(y[:-1]) * np.sign(y[1:]) < 0)[0]
    tc = t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])
    return 2.0 * float(np.mean(np.diff(tc)))


def test_free_decay_period_is_the_compound_pendulum():
    mass, jyy, d, length = 50.0, 10.0, 0.8, 0.02
    table = _pendulum_table(0.0, length, mass, jyy, d)
    table["statics"] = {"enabled": True}
    sim = NodalSimulation(scene_from_table(table))
    sim.initialize()    # hanging at rest; then a small swing about the tow point (the tow point at rest)
    w0 = 0.15
    sim.set_body_motion(velocity=[-w0 * d, 0.0, 0.0], angular_velocity=[0.0, w0, 0.0])
    out = sim.run(20.0, interval=0.002)
    measured = _crossing_period(out["time"][1:], out["towbody.pitch"][1:])
    # the pendulum's two DOF (cable angle, body angle), linearised: massless cable of
    # length l, body on a spherical joint at distance d above its CG
    m = np.array([[mass * length**2, mass * length * d], [mass * length * d, mass * d * d + jyy]])
    k = np.diag([mass * G * length, mass * G * d])
    low = 2.0 * math.pi / math.sqrt(min(np.linalg.eigvals(np.linalg.solve(m, k)).real))
    compound = 2.0 * math.pi * math.sqrt((jyy + mass * d * d) / (mass * G * d))  # about the tow point
    simple = 2.0 * math.pi * math.sqrt((length + d) / G)
    # time step 2 ms: generalised-alpha's period error ~ (omega h)^2 / 12 < 1e-5; amplitude
    # 0.05 rad: the nonlinear lengthening theta0^2 / 16 = 1.6e-4; cable mass 2e-5 kg
    assert measured == pytest.approx(low, rel=5e-4)
    # the cable of 2 cm adds about l / (2 d) = 1.2 % to the period of the compound pendulum
    assert measured == pytest.approx(compound, rel=0.015)
    assert abs(measured / simple - 1.0) > 0.08   # the body's inertia matters
    # no fluid, no damping: the swing keeps its amplitude (genalpha rho_inf = 0.8, h = 2 ms)
    p = out["towbody.pitch"]
    assert np.abs(p[-1000:]).max() == pytest.approx(np.abs(p[:1000]).max(), rel=2e-3)
    assert np.abs(p).max() == pytest.approx(w0 * measured / (2.0 * math.pi), rel=0.03)
    assert np.abs(out["towbody.roll"]).max() < 1e-9 and np.abs(out["towbody.y"]).max() < 1e-9


def test_rk4_and_genalpha_agree():
    table = _pendulum_table(0.1, 0.2, 50.0, 10.0, 0.8)
    table["cable"]["segments"][0].update(EA=1e4, mass_per_length=0.5)
    runs = {}
    for integrator, h in (("genalpha", 2e-4), ("rk4", 2e-4)):
        table["solver"] = {"time_step": h, "integrator": integrator}
        runs[integrator] = NodalSimulation(scene_from_table(table)).run(1.0, interval=0.01)
    for name in ("towbody.pitch", "towbody.x", "tension.towbody"):
        a, b = runs["genalpha"][name], runs["rk4"][name]
        assert np.abs(a - b).max() < 2e-3 * np.abs(b).max(), name


def _tow_table(**rigid) -> dict:
    body = {"inertia": [400.0, 1500.0, 1400.0], "tow_point": [0.6, 0.0, 0.4],
            "buoyancy_centre": [0.0, 0.0, 0.15], "drag_centre": [-0.5, 0.0, 0.0],
            "rotational_damping": [500.0, 2000.0, 2000.0], "rotational_drag": [200.0, 1000.0, 1000.0]}
    body.update(rigid)
    return {
        "water": {"density": 1025.0, "current": {"type": "uniform", "velocity": [-1.5, 0.0, 0.0]}},
        "cable": {"formulation": "nodal_position",
                  "segments": [{"length": 30.0, "elements": 10, "diameter": 0.02, "mass_per_length": 1.0,
                                "EA": 5e6, "EI": 0.0, "damping": 1e4, "drag_coefficient": 1.2}],
                  "top": {"type": "pinned", "position": [0.0, 0.0, -2.0]}, "bottom": {"type": "free"},
                  "initial": {"shape": "straight", "direction": [-0.3, 0.0, -1.0]}},
        "towbody": {"mass": 600.0, "volume": 0.4, "model": "rigid", "added_mass_coefficient": [0.1, 1.0, 1.0],
                    "parts": [{"area": [0.3, 1.2, 1.5], "drag_coefficient": [0.4, 1.0, 1.0]}], "rigid": body},
        "solver": {"time_step": 0.02},
    }


def _trim_by_hand(table: dict, cable_force: np.ndarray) -> float:
    """The pitch [rad] at which the moments about the CG of buoyancy (at the CB), drag (at
    the drag centre, the body at rest in the current) and the cable force (at the tow
    point) cancel, in the x-z plane. Pitch theta: body x = (cos, -sin) in (x, z)."""
    body, rb = table["towbody"], table["towbody"]["rigid"]
    rho, u = table["water"]["density"], table["water"]["current"]["velocity"][0]
    cda = np.array(body["parts"][0]["area"]) * np.array(body["parts"][0]["drag_coefficient"])
    buoy = rho * body["volume"] * G

    def moment(theta: float) -> float:
        c, s = math.cos(theta), math.sin(theta)
        to_body = lambda fx, fz: (c * fx - s * fz, s * fx + c * fz)  # noqa: E731  (R^T, x-z plane)
        ux, uz = to_body(u, 0.0)
        drag = (0.5 * rho * cda[0] * abs(ux) * ux, 0.5 * rho * cda[2] * abs(uz) * uz)
        total = 0.0
        for (px, pz), (fx, fz) in ((rb["buoyancy_centre"][::2], to_body(0.0, buoy)),
                                   (rb["drag_centre"][::2], drag),
                                   (rb["tow_point"][::2], to_body(cable_force[0], cable_force[2]))):
            total += pz * fx - px * fz   # y component of p x f
        return total

    return brentq(moment, -1.0, 1.0)


@pytest.mark.parametrize("statics", [True, False])
def test_steady_tow_settles_at_the_trim_its_forces_imply(statics):
    table = _tow_table()
    table["statics"] = {"enabled": statics}
    sim = NodalSimulation(scene_from_table(table))
    start = sim.initialize()
    if statics:
        out = start
    else:   # from the straight cable and a level body: let the tow settle
        series = sim.run(120.0, interval=0.5)
        tail = {k: v[-20:] for k, v in series.items()}
        assert np.ptp(tail["towbody.pitch"]) < 1e-4 and np.ptp(tail["towbody.x"]) < 1e-3
        out = {k: float(v[-1]) for k, v in series.items()}
    body = sim.body_state()
    force = body["cable_force"]   # the end tension and the last node's share of the cable's drag
    assert np.linalg.norm(force) == pytest.approx(out["tension.towbody"], rel=1e-12)
    nodes = sim.node_positions()
    along = (nodes[-2] - nodes[-1]) / np.linalg.norm(nodes[-2] - nodes[-1])
    assert np.degrees(math.acos(force @ along / np.linalg.norm(force))) < 2.0   # nearly along the last element
    # force balance in the current (body at rest): weight, buoyancy, drag, cable
    b = table["towbody"]
    rho, u = table["water"]["density"], table["water"]["current"]["velocity"][0]
    rot = body["rotation"]
    ub = rot.T @ np.array([u, 0.0, 0.0])
    cda = np.array(b["parts"][0]["area"]) * np.array(b["parts"][0]["drag_coefficient"])
    drag = rot @ (0.5 * rho * cda * np.abs(ub) * ub)
    net = force + drag + np.array([0.0, 0.0, (rho * b["volume"] - b["mass"]) * G])
    assert np.abs(net).max() < 1e-3 * np.linalg.norm(force)
    trim = _trim_by_hand(table, force)
    assert abs(out["towbody.pitch"] - trim) < 2e-4
    assert abs(trim) > 0.05      # a trim that the moments set, not level by symmetry
    assert abs(out["towbody.roll"]) < 1e-6 and abs(out["towbody.yaw"]) < 1e-6


def test_trim_moves_with_the_buoyancy_centre():
    """A wrong moment arm would not follow: the hand trim and the model move together."""
    pitches = []
    for cb in (0.0, 0.3):
        table = _tow_table(buoyancy_centre=[0.0, 0.0, cb])
        sim = NodalSimulation(scene_from_table(table))
        out = sim.initialize()
        trim = _trim_by_hand(table, sim.body_state()["cable_force"])
        assert abs(out["towbody.pitch"] - trim) < 2e-4
        pitches.append(out["towbody.pitch"])
    assert abs(pitches[1] - pitches[0]) > 0.02


def test_torque_free_symmetric_body_precesses_at_the_closed_form_rate():
    """No gravity, no fluid, tow point at the CG: no moment acts. A body symmetric about
    its x axis with angular momentum L along z: its x axis keeps its elevation (pitch
    constant) and turns about z at |L| / J_t (yaw rate)."""
    ja, jt, pitch0, lz = 2.0, 5.0, -0.4, 3.0
    table = {
        "environment": {"gravity": 0.0},
        "cable": {"formulation": "nodal_position",
                  "segments": [{"length": 1.0, "elements": 2, "diameter": 0.005, "mass_per_length": 0.01,
                                "EA": 1e5, "EI": 0.0, "compression": False}],
                  "top": {"type": "pinned", "position": [0.0, 0.0, 0.0]}, "bottom": {"type": "free"}},
        "towbody": {"mass": 10.0, "model": "rigid",
                    "rigid": {"inertia": [ja, jt, jt], "tow_point": [0.0, 0.0, 0.0], "attitude": [0.0, pitch0, 0.0]}},
        "statics": {"enabled": False},
        "solver": {"time_step": 0.002, "rho_inf": 1.0},
    }
    sim = NodalSimulation(scene_from_table(table))
    sim.initialize()
    s, c = math.sin(pitch0), math.cos(pitch0)
    sim.set_body_motion(angular_velocity=[-lz * s / ja, 0.0, lz * c / jt])   # J^-1 R^T (0, 0, L)
    l0 = sim.body_state()["angular_momentum"]
    assert l0 == pytest.approx([0.0, 0.0, lz], abs=1e-12)
    out = sim.run(8.0, interval=0.01)
    yaw = np.unwrap(out["towbody.yaw"])
    rate = np.polyfit(out["time"], yaw, 1)[0]
    assert rate == pytest.approx(lz / jt, rel=1e-4)
    assert np.abs(out["towbody.pitch"] - pitch0).max() < 1e-5
    assert np.abs(sim.body_state()["angular_momentum"] - l0).max() < 1e-5 * lz
    assert np.abs(out["tension.max"]).max() < 1e-9      # the cable never pulls


def test_torque_free_asymmetric_body_conserves_momentum_and_energy():
    """A general tumbling body (three different moments, products of inertia): the
    angular momentum about the CG (inertial axes) and the kinetic energy stay constant;
    the Euler-angle coordinates are integrated, so this checks the rate map G, its
    derivative and the gyroscopic term together."""
    table = {
        "environment": {"gravity": 0.0},
        "cable": {"formulation": "nodal_position",
                  "segments": [{"length": 1.0, "elements": 2, "diameter": 0.005, "mass_per_length": 0.01,
                                "EA": 1e5, "EI": 0.0, "compression": False}],
                  "top": {"type": "pinned", "position": [0.0, 0.0, 0.0]}, "bottom": {"type": "free"}},
        "towbody": {"mass": 10.0, "model": "rigid",
                    "rigid": {"inertia": [2.0, 5.0, 8.0], "inertia_products": [0.3, -0.2, 0.4],
                              "tow_point": [0.0, 0.0, 0.0], "attitude": [0.2, -0.1, 0.3]}},
        "statics": {"enabled": False},
        "solver": {"time_step": 0.002, "rho_inf": 1.0},
    }
    sim = NodalSimulation(scene_from_table(table))
    sim.initialize()
    sim.set_body_motion(angular_velocity=[2.0, 0.3, -0.2])
    j = sim.model.rigid.inertia
    start = sim.body_state()
    out = sim.run(10.0, interval=0.01)
    end = sim.body_state()
    assert np.abs(out["towbody.pitch"]).max() < 1.2       # tumbling, but clear of pitch = pi/2
    assert np.ptp(np.unwrap(out["towbody.roll"])) > 6.0    # several turns
    l0 = start["angular_momentum"]
    # genalpha (rho_inf = 1, h = 2 ms) on the Euler angles: errors O(h^2), measured 2e-6
    assert np.abs(end["angular_momentum"] - l0).max() < 2e-5 * np.linalg.norm(l0)
    energy = [0.5 * b["angular_velocity"] @ j @ b["angular_velocity"] for b in (start, end)]
    assert energy[1] == pytest.approx(energy[0], rel=1e-5)


def test_rigid_scene_keys_are_validated():
    table = _tow_table()
    table["towbody"]["rigid"]["inertia_products"] = [500.0, 0.0, 0.0]   # 500^2 < 400 x 1500: positive definite
    scene_from_table(table)
    table["towbody"]["rigid"]["inertia_products"] = [900.0, 0.0, 0.0]
    with pytest.raises(SceneError, match="towbody.rigid.inertia_products"):
        scene_from_table(table)
    table = _tow_table(attitude=[0.0, 1.5, 0.0])
    with pytest.raises(SceneError, match=r"towbody.rigid.attitude\[1\]"):
        scene_from_table(table)
    table = _tow_table()
    del table["towbody"]["rigid"]
    with pytest.raises(SceneError, match="towbody.rigid"):
        scene_from_table(table)
    table = _tow_table()
    table["cable"]["formulation"] = "ancf"
    with pytest.raises(SceneError, match="towbody.model"):
        scene_from_table(table)
    table = _tow_table(tow_point=[0.0, 0.0])
    with pytest.raises(SceneError, match="towbody.rigid.tow_point"):
        scene_from_table(table)


def test_sea_trial_rigid_scene_hangs_where_its_moments_balance():
    """The built-in scene: the hanging statics put the CG where the moments of the
    (vertical) cable force at the tow point and the buoyancy at the CB cancel, and a
    short run from there starts the tow."""
    sim = NodalSimulation(load_scene("sea_trial_turn_rigid"))
    out = sim.initialize()
    rb = sim.scene.towbody.rigid
    body = sim.body_state()
    force = body["cable_force"]
    assert abs(force[0]) < 1e-6 * abs(force[2])      # no current: the cable hangs straight
    buoy = 1025.0 * 6.25 * G
    (px, _, pz), (bx, _, bz) = rb.tow_point, rb.buoyancy_centre

    def moment(theta: float) -> float:   # y moment about the CG, body axes, pitch theta
        c, s = math.cos(theta), math.sin(theta)
        return pz * (-s * force[2]) - px * (c * force[2]) + bz * (-s * buoy) - bx * (c * buoy)

    assert out["towbody.pitch"] == pytest.approx(brentq(moment, -1.2, 1.2), abs=1e-6)
    assert force[2] == pytest.approx((9500.0 - 1025.0 * 6.25) * G, rel=1e-6)
    series = sim.run(20.0, interval=1.0)
    assert np.all(np.isfinite(series["towbody.pitch"])) and series["towbody.x"][-1] > series["towbody.x"][0]


def test_command_line_static_and_run(tmp_path, capsys):
    import csv
    import json

    from towcable_fmu.cli import main

    assert main(["static", "sea_trial_turn_rigid", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    for name in ("towbody.z", "towbody.pitch", "towbody.roll", "towbody.yaw", "tension.towbody", "tension.top"):
        assert math.isfinite(summary[name]), name
    out = tmp_path / "run.csv"
    assert main(["run", "sea_trial_turn_rigid", "--duration", "5", "--output", str(out), "--quiet"]) == 0
    with open(out, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    assert {"time", "towbody.x", "towbody.pitch", "tension.towbody"} <= set(rows[0]) and len(rows) == 7


def test_a_body_towed_backwards_flips_and_the_error_names_the_singularity():
    """Tow point downstream of the CG (current along the body's +x): the body turns
    round, through pitch -pi/2, where its Euler angles are singular: a clear error."""
    from towcable_fmu.errors import SolverError

    table = _tow_table()
    table["statics"] = {"enabled": False}
    table["water"]["current"]["velocity"] = [1.5, 0.0, 0.0]
    table["cable"]["initial"]["direction"] = [0.3, 0.0, -1.0]
    with pytest.raises(SolverError, match="singular at"):
        NodalSimulation(scene_from_table(table)).run(60.0, interval=1.0)


def test_banded_iteration_matrix_holds_every_coupling():
    """The coloured differences with the widened band give the same matrix as plain
    column-by-column differences of the whole residual (a missing coupling of the tow
    point would only slow Newton down, so it is checked here directly)."""
    from towcable_fmu.nodal.assembly import bandwidth, iteration_matrix, residual

    table = _tow_table()
    table["cable"]["segments"][0]["elements"] = 4
    sim = NodalSimulation(scene_from_table(table))
    sim.initialize()
    m = sim.model
    rng = np.random.default_rng(1)
    n = sim.q.size
    q = sim.q + 0.01 * rng.standard_normal(n)
    v, a = 0.3 * rng.standard_normal(n), rng.standard_normal(n)
    q[:3], v[:3], a[:3] = sim.q[:3], 0.0, 0.0
    ca, cv, cq = 1.0, 0.05, 0.001
    r0 = np.empty(n)
    residual(m, q, v, a, 0.0, r0)
    kl = bandwidth(m)
    ab = np.empty((3 * kl + 1, n - 3))
    iteration_matrix(m, q, v, a, 0.0, ca, cv, cq, 1e-6, r0, ab, np.empty((4, n)))
    banded = np.zeros((n - 3, n - 3))
    for j in range(n - 3):
        for i in range(max(0, j - kl), min(n - 3, j + kl + 1)):
            banded[i, j] = ab[2 * kl + i - j, j]
    dense = np.zeros((n - 3, n - 3))
    r = np.empty(n)
    for j in range(3, n):
        qp, vp, ap = q.copy(), v.copy(), a.copy()
        qp[j] += cq * 1e-6
        vp[j] += cv * 1e-6
        ap[j] += ca * 1e-6
        residual(m, qp, vp, ap, 0.0, r)
        dense[:, j - 3] = (r[3:] - r0[3:]) / 1e-6
    assert kl == 8
    assert np.abs(banded - dense).max() < 1e-9 * np.abs(dense).max()
