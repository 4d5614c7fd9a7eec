"""The rigid 6-DOF towed body (towcable_fmu/hydro/rigid_body.py) on the nodal-position
cable, and on the ANCF cable (towcable_fmu/ancf/system.py, joined by a stiff link).

Each test compares with a closed form or an independent computation:

* free decay of a body on a short pendulum cable in air: the period of the
  compound-pendulum mode (2-DOF linearised closed form; the compound pendulum about the
  tow point as the cable length goes to 0), far from the simple pendulum;
* steady tow in a uniform current: the trim (pitch) where the moments of buoyancy,
  drag and the cable force about the CG balance, solved here by hand in the vertical
  plane from the settled cable force; and the force balance;
* a torque-free symmetric body: precession at the closed-form rate |L| / J_t with the
  angular momentum conserved;
* RK4 and generalised-alpha agree; the scene keys are validated;
* with the ANCF cable: the same free-decay period and steady-tow trim, the link
  stiffness has no visible effect, the ANCF and nodal cables agree on a small scene,
  and the iteration matrix holds the body's couplings (finite differences).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from towcable_fmu.common.errors import SceneError
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


def _two_dof_period(mass: float, jyy: float, d: float, length: float) -> float:
    """Period [s] of the slower mode of the pendulum's two DOF (cable angle, body angle),
    linearised: massless cable of length l, body on a spherical joint at distance d above
    its CG."""
    m = np.array([[mass * length**2, mass * length * d], [mass * length * d, mass * d * d + jyy]])
    k = np.diag([mass * G * length, mass * G * d])
    return 2.0 * math.pi / math.sqrt(min(np.linalg.eigvals(np.linalg.solve(m, k)).real))


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
    low = _two_dof_period(mass, jyy, d, length)
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
@pytest.mark.parametrize("formulation", ["nodal_position", "ancf"])
def test_steady_tow_settles_at_the_trim_its_forces_imply(formulation, statics):
    """From the statics, or from a straight cable and a level body after 120 s of towing:
    the forces on the body balance and its pitch is the hand trim of the moments about
    the CG. Nodal cable: its last node is the tow point; ANCF cable: a stiff link
    (k = 100 EA/L_e) joins them and stretches T/k."""
    from towcable_fmu.models import simulation_for

    table = _tow_table() if formulation == "nodal_position" else _ancf(_tow_table())
    table["statics"] = {"enabled": statics}
    sim = simulation_for(scene_from_table(table))
    start = sim.initialize()
    if statics:
        out = start
    else:   # from the straight cable and a level body: let the tow settle
        series = sim.run(120.0, interval=0.5)
        tail = {k: v[-20:] for k, v in series.items()}
        assert np.ptp(tail["towbody.pitch"]) < 1e-4 and np.ptp(tail["towbody.x"]) < 1e-3
        out = {k: float(v[-1]) for k, v in series.items()}
    body = sim.body_state()
    force = body["cable_force"]   # the cable's pull on the body
    assert np.linalg.norm(force) == pytest.approx(out["tension.towbody"], rel=1e-12)
    if formulation == "nodal_position":
        nodes = sim.node_positions()
        along = (nodes[-2] - nodes[-1]) / np.linalg.norm(nodes[-2] - nodes[-1])
        assert np.degrees(math.acos(force @ along / np.linalg.norm(force))) < 2.0   # nearly along the last element
    else:
        assert body["link_stretch"] == pytest.approx(np.linalg.norm(force) / sim.model.terms.rigid_link.k, rel=1e-3)
        assert body["link_stretch"] < 2e-5
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
    scene_from_table(table)     # the ANCF cable carries the rigid body too (see the ANCF tests below)
    table = _tow_table(tow_point=[0.0, 0.0])
    with pytest.raises(SceneError, match="towbody.rigid.tow_point"):
        scene_from_table(table)


@pytest.mark.parametrize("formulation", ["nodal_position", "ancf"])
def test_sea_trial_rigid_scene_hangs_where_its_moments_balance(formulation):
    """The built-in scene (with either cable): the hanging statics put the CG where the
    moments of the (vertical) cable force at the tow point and the buoyancy at the CB
    cancel, and a short run from there starts the tow."""
    from towcable_fmu.models import simulation_for

    sim = simulation_for(load_scene("sea_trial_turn_rigid", {"model": formulation}))
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


@pytest.mark.parametrize("formulation", ["nodal_position", "ancf"])
def test_a_body_towed_backwards_flips_and_the_error_names_the_singularity(formulation):
    """Tow point downstream of the CG (current along the body's +x): the body turns
    round, through pitch -pi/2, where its Euler angles are singular: a clear error."""
    from towcable_fmu.common.errors import SolverError
    from towcable_fmu.models import simulation_for

    table = _tow_table()
    if formulation == "ancf":
        table = _ancf(table)
    table["statics"] = {"enabled": False}
    table["water"]["current"]["velocity"] = [1.5, 0.0, 0.0]
    table["cable"]["initial"]["direction"] = [0.3, 0.0, -1.0]
    with pytest.raises(SolverError, match="singular at"):
        simulation_for(scene_from_table(table)).run(60.0, interval=1.0)


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
    n = sim.state.q.size
    q = sim.state.q + 0.01 * rng.standard_normal(n)
    v, a = 0.3 * rng.standard_normal(n), rng.standard_normal(n)
    q[:3], v[:3], a[:3] = sim.state.q[:3], 0.0, 0.0
    ca, cv, cq = 1.0, 0.05, 0.001
    r0 = np.empty(n)
    residual(m, q, v, a, 0.0, r0)
    kl = bandwidth(m)
    ab = np.empty((n - 3, 3 * kl + 1))
    iteration_matrix(m, q, v, a, 0.0, ca, cv, cq, 1e-6, r0, ab, np.empty((4, n)))
    banded = np.zeros((n - 3, n - 3))
    for j in range(n - 3):
        for i in range(max(0, j - kl), min(n - 3, j + kl + 1)):
            banded[i, j] = ab[j, 2 * kl + i - j]
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


# ------------------------------------------------------------------ the ANCF cable
def _ancf(table: dict) -> dict:
    """The same scene with the ANCF cable (EI 1 N m^2: the nodal cable has none; here it
    only keeps the free end's slopes determinate)."""
    table["cable"]["formulation"] = "ancf"
    for seg in table["cable"]["segments"]:
        seg["EI"] = max(seg["EI"], 1.0 if seg["length"] > 1.0 else 1e-6)
    return table


def test_ancf_free_decay_period_is_the_compound_pendulum():
    from towcable_fmu.ancf.simulation import Simulation

    mass, jyy, d, length = 50.0, 10.0, 0.8, 0.02
    table = _ancf(_pendulum_table(0.0, length, mass, jyy, d))
    table["statics"] = {"enabled": True}
    sim = Simulation(scene_from_table(table))
    sim.initialize()
    assert sim.model.kl == 11 and sim.model.free_idx.size == 6 * 3 + 6   # the body widens no band
    w0 = 0.15
    sim.set_body_motion(velocity=[-w0 * d, 0.0, 0.0], angular_velocity=[0.0, w0, 0.0])
    out = sim.run(20.0, interval=0.002)
    measured = _crossing_period(out["time"][1:], out["towbody.pitch"][1:])
    low = _two_dof_period(mass, jyy, d, length)
    # as the nodal test: period error of the scheme < 1e-5, nonlinear lengthening 1.6e-4;
    # the link (k = 100 EA/L_e = 1e11 N/m) stretches 5e-9 m under the body's weight
    assert measured == pytest.approx(low, rel=5e-4)       # measured 1.6e-4
    p = out["towbody.pitch"]
    # no fluid, no damping: the energy (cable, link and body) stays that of the release,
    # 1/2 (J + m d^2) w0^2 = 0.47 J, within 1e-4 (measured 3e-5: Newton's tolerance), and the
    # amplitude within 3e-3 (measured 1.9e-3: the small cable-swing mode rides on the pitch)
    energy = out["energy.kinetic"] + out["energy.strain"] + out["energy.gravity"]
    assert np.abs(energy - energy[0]).max() < 1e-4 * 0.5 * (jyy + mass * d * d) * w0**2
    assert np.abs(p[-1000:]).max() == pytest.approx(np.abs(p[:1000]).max(), rel=3e-3)
    assert np.abs(p).max() == pytest.approx(w0 * measured / (2.0 * math.pi), rel=0.03)
    assert np.abs(out["towbody.roll"]).max() < 1e-9 and np.abs(out["towbody.y"]).max() < 1e-9
    assert sim.body_state()["link_stretch"] < 1e-8


def _kicked_in_air(table: dict) -> dict:
    """The tow scene in air and without the cable's internal damping (the two
    formulations define it differently: W(55) damps the rotation of the ANCF cable's
    tangent, the nodal damping only its stretching), step 5 ms: the body hangs at rest,
    then turns at (0.05, 0.3, 0.1) rad/s (body axes)."""
    del table["water"], table["towbody"]["parts"], table["towbody"]["volume"]
    table["solver"]["time_step"] = 0.005
    table["cable"]["segments"][0]["damping"] = 0.0
    return table


def _kick_run(sim, duration: float = 3.0) -> dict:
    sim.initialize()
    sim.set_body_motion(angular_velocity=[0.05, 0.3, 0.1])
    return sim.run(duration, interval=0.02)


_KICK_NAMES = ("towbody.pitch", "towbody.roll", "towbody.yaw", "towbody.x", "towbody.y", "towbody.z")


def test_ancf_link_stiffness_does_not_change_the_results():
    """Ten times stiffer or softer link (k = 10 .. 1000 EA/L_e instead of 100): the swing
    of a kicked body moves by the change of the link's stretch T/k (3.5e-5 m at the
    nominal k here, 3.5e-4 m at the softest), far below the tolerances of the ANCF tests,
    and the hanging trim not at all."""
    from towcable_fmu.ancf.simulation import Simulation

    runs = {}
    for factor in (0.1, 1.0, 10.0):
        sim = Simulation(scene_from_table(_ancf(_kicked_in_air(_tow_table()))))
        link = sim.model.terms.rigid_link
        link = link._replace(k=link.k * factor, c=link.c * math.sqrt(factor))
        sim.model = sim.model._replace(terms=sim.model.terms._replace(rigid_link=link))
        runs[factor] = _kick_run(sim)
        stretch = np.linalg.norm(sim.body_state()["cable_force"]) / sim.model.terms.rigid_link.k
        assert stretch < 4e-4
    base = runs[1.0]
    for factor in (0.1, 10.0):
        run = runs[factor]
        assert abs(run["towbody.pitch"][0] - base["towbody.pitch"][0]) < 1e-6    # the hanging trim (statics tolerance)
        for name in ("towbody.pitch", "towbody.roll", "towbody.yaw"):   # measured <= 7.6e-5 rad
            assert np.abs(run[name] - base[name]).max() < 2e-4, (factor, name)
        for name in ("towbody.x", "towbody.y", "towbody.z"):            # measured <= 3.8e-4 m (T/k)
            assert np.abs(run[name] - base[name]).max() < 5e-4, (factor, name)
        # measured 10.5 N (k / 10) and 1.4 N (10 k) of about 5.9 kN
        assert np.abs(run["tension.towbody"] - base["tension.towbody"]).max() < 3e-3 * base["tension.towbody"][0]


def test_ancf_and_nodal_rigid_bodies_agree():
    """The same body with each cable formulation (10 elements over 30 m).

    Hanging in the current (statics): the trim and the cable force agree to the solver
    tolerance (the cable's drag is the same law), the CG's position to the difference of
    the two cables' shapes (cubic ANCF elements against straight ones: 0.6 mm in x,
    1.7 mm in z at 10 elements, four times less at 20). Kicked in air (no damping): the
    swing over 3 s, measured within 8e-5 rad and 6e-5 m of each other, the tension
    within 5 N of 5.9 kN (the cables' own transverse modes, which the two meshes place
    differently)."""
    from towcable_fmu.ancf.simulation import Simulation

    table = _tow_table()
    nodal = NodalSimulation(scene_from_table(table)).initialize()
    ancf = Simulation(scene_from_table(_ancf(_tow_table()))).initialize()
    assert ancf["towbody.pitch"] == pytest.approx(nodal["towbody.pitch"], abs=1e-7)
    assert ancf["tension.towbody"] == pytest.approx(nodal["tension.towbody"], rel=1e-6)
    assert ancf["towbody.x"] == pytest.approx(nodal["towbody.x"], abs=2e-3)
    assert ancf["towbody.z"] == pytest.approx(nodal["towbody.z"], abs=5e-3)
    nodal = _kick_run(NodalSimulation(scene_from_table(_kicked_in_air(_tow_table()))))
    ancf = _kick_run(Simulation(scene_from_table(_ancf(_kicked_in_air(_tow_table())))))
    assert np.ptp(ancf["towbody.pitch"]) > 0.3 and np.ptp(ancf["towbody.yaw"]) > 0.4   # it does swing
    for name in ("towbody.pitch", "towbody.roll", "towbody.yaw"):
        assert np.abs(ancf[name] - nodal[name]).max() < 3e-4, name
    for name in ("towbody.x", "towbody.y", "towbody.z"):
        assert np.abs(ancf[name] - nodal[name]).max() < 3e-4, name
    assert np.abs(ancf["tension.towbody"] - nodal["tension.towbody"]).max() < 2e-3 * nodal["tension.towbody"][0]


def test_ancf_iteration_matrix_holds_the_body_couplings():
    """Columns of the body's six coordinates and of the last node's position, and the
    body's rows, against central differences of the whole residual (acceleration zero:
    the body block leaves out the attitude derivative of its inertia forces)."""
    from towcable_fmu.ancf.system import iteration_matrix, residual
    from towcable_fmu.numerics.banded import band_storage
    from towcable_fmu.ancf.simulation import Simulation

    table = _ancf(_tow_table())
    table["cable"]["segments"][0]["elements"] = 4
    sim = Simulation(scene_from_table(table))
    sim.initialize()
    m = sim.model
    rng = np.random.default_rng(2)
    q = sim.state.q.copy()
    free = m.free_dofs
    q[free] += 1e-3 * rng.standard_normal(free.size)
    v = np.zeros_like(q)
    v[free] = 0.2 * rng.standard_normal(free.size)
    a = np.zeros_like(q)
    ship = np.zeros((3, 6))
    ca, cv, cq = 1.0, 0.05, 0.001
    n = free.size
    ab = band_storage(n, m.kl, m.ku)
    iteration_matrix(m, q, v, 0.0, ship, ca, cv, cq, ab)
    i = m.terms.rigid_link.index
    cols = list(range(i - 6, i - 3)) + list(range(i, i + 6))
    rp, rm = np.zeros_like(q), np.zeros_like(q)
    for j in cols:
        h = 1e-3     # q moves by cq h = 1e-6 m: round-off 1e-9 of the column, truncation below it
        for sign, r in ((1.0, rp), (-1.0, rm)):
            qq, vv, aa = q.copy(), v.copy(), a.copy()
            qq[j] += sign * cq * h
            vv[j] += sign * cv * h
            aa[j] += sign * ca * h
            residual(m, qq, vv, aa, 0.0, ship, r)
        column = (rp - rm)[free] / (2.0 * h)
        fc = m.free_idx[j]
        banded = np.array([ab[fc, m.kl + m.ku + fr - fc] if abs(fr - fc) <= m.kl else 0.0 for fr in range(n)])
        assert np.abs(banded - column).max() < 1e-7 * np.abs(column).max(), j    # measured <= 1e-9
    # the body's rows hold nothing outside the band (columns of the other coordinates)
    for j in free:
        if j in cols:
            continue
        qq = q.copy()
        qq[j] += 1e-6
        residual(m, qq, v, a, 0.0, ship, rp)
        residual(m, q, v, a, 0.0, ship, rm)
        assert np.abs(rp[i:i + 6] - rm[i:i + 6]).max() == 0.0



def test_ancf_rigid_state_round_trip_continues_bit_identically():
    """get_state/set_state carry the body's coordinates (they are integrator coordinates)."""
    from towcable_fmu.ancf.simulation import Simulation

    table = _ancf(_tow_table())
    table["statics"] = {"enabled": False}
    sim = Simulation(scene_from_table(table))
    sim.initialize()
    sim.advance(1.0)
    saved = sim.get_state()
    first = sim.advance(2.0)
    sim.set_state(saved)
    again = sim.advance(2.0)
    assert first == again
    assert {"towbody.roll", "towbody.pitch", "towbody.yaw", "tension.towbody"} <= set(first)
    assert abs(first["towbody.pitch"] - saved["fields"]["q"][sim.model.terms.rigid_link.index + 4]) > 1e-4   # it moved


@pytest.mark.parametrize("formulation", ["nodal_position", "ancf"])
def test_set_body_motion_returns_the_outputs_of_the_new_state(formulation):
    """Both cables answer set_body_motion alike: the outputs in the new state, the body's
    new velocity among them."""
    from towcable_fmu.models import simulation_for

    table = _pendulum_table(0.0, 0.02, 50.0, 10.0, 0.8)
    if formulation == "ancf":
        table = _ancf(table)
    sim = simulation_for(scene_from_table(table))
    sim.initialize()
    out = sim.set_body_motion(velocity=[0.1, 0.0, 0.0])
    assert out == sim.outputs()
    assert out["towbody.vx"] == pytest.approx(0.1, abs=1e-12)
