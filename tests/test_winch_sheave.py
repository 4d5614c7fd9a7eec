"""Winch and sheave: contact statics, payout, detachment from the groove, energy, pulley scenes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from conftest import cable_scene, segment

from towcable_fmu.ancf.mesh import winch_radius
from towcable_fmu.contact.surfaces import WINCH, face_force
from towcable_fmu.numerics.kinematics import rotation_matrix
from towcable_fmu.scene import scene_from_table
from towcable_fmu.ancf.simulation import Simulation

G = 9.81
MU = 1e-3  # [kg/m] of the two-mass pulley cable


def _two_masses(mass: float = 5.0):
    """A light 2 m cable over a frictionless pulley (r = 0.1 m) with equal masses on both
    ends (the cable's own weight would make the symmetric rest position unstable: keep it
    small); coarse elements where it hangs, 7 deg elements where it wraps the pulley."""
    table = cable_scene([segment(0.7, 7, mu=MU, EA=1e6, EI=1e-3, diameter=0.01),
                         segment(0.6, 48, mu=MU, EA=1e6, EI=1e-3, diameter=0.01),
                         segment(0.7, 7, mu=MU, EA=1e6, EI=1e-3, diameter=0.01)],
                        top={"type": "free", "position": [-0.105, 0.0, -0.835], "mass": mass},
                        bottom={"type": "free", "mass": mass},
                        sheave={"position": [0.0, 0.0, 0.0], "radius": 0.1, "shape": "cylinder",
                                "contact": {"stiffness": 1e9}})
    table["cable"]["initial"] = {"direction": [0.0, 0.0, -1.0]}
    return Simulation(scene_from_table(table))


def test_pulley_with_two_hanging_masses():
    """Equal tension on both sides, contact force per unit length T/R along the wrap, total
    contact force equal to the vector sum of the two tensions (the total weight here)."""
    mass, mu, length = 5.0, MU, 2.0
    sim = _two_masses(mass)
    sim.initialize()
    contact = sim.contact_state()
    total = contact["force"][1]
    weight = (2 * mass + mu * length) * G
    np.testing.assert_allclose(total, [0.0, 0.0, weight], rtol=1e-6, atol=1e-6 * weight)
    # the force carried by the elements just outside the wrap: the weight hanging below them
    # (the frictionless pulley has slid the cable into a position where the two sides
    # balance, so measure each side's hanging length)
    from towcable_fmu.ancf.measures import element_tension

    e0, xi0, e1, xi1 = contact["ends"][1]
    e0, e1 = int(e0), int(e1)
    arc = sim.mesh.node_arc
    mid_left = 0.5 * (arc[e0 - 1] + arc[e0])
    mid_right = 0.5 * (arc[e1 + 1] + arc[e1 + 2])
    left = element_tension(sim.model, sim.state.q, e0 - 1)
    right = element_tension(sim.model, sim.state.q, e1 + 1)
    assert left == pytest.approx(mass * G + mu * G * mid_left, rel=1e-3)
    assert right == pytest.approx(mass * G + mu * G * (length - mid_right), rel=1e-3)
    # carried on to where the cable meets and leaves the pulley (both at its sides), equal up
    # to the small cogging of a wrap discretised in 7 deg elements
    meet = left + mu * G * (arc[e0] + xi0 * sim.mesh.lengths[e0] - mid_left)
    leave = right + mu * G * (mid_right - arc[e1] - xi1 * sim.mesh.lengths[e1])
    assert meet == pytest.approx(leave, rel=1e-3)
    hanging = 0.5 * (length - math.pi * 0.105)
    # force per unit length along the wrap (away from its ends) equals T / R
    dist = contact["distribution"]
    angles = dist[:, 1]
    middle = np.abs(angles) < np.radians(60.0)
    tension_top = mass * G + mu * G * (hanging + 0.5 * math.pi * 0.105)
    np.testing.assert_allclose(dist[middle, 2], tension_top / 0.105, rtol=0.02)
    # the deflection between the first and the last touching point (located to a fraction of an element)
    assert np.degrees(sim.outputs()["contact.wrap_angle"]) == pytest.approx(180.0, abs=2.0)


def _winch_hoist(phi: float, rate: float = 0.0):
    table = cable_scene([segment(2.0, 20, mu=0.5, EA=1e7, EI=0.1, diameter=0.01),
                         segment(10.0, 10, mu=0.5, EA=1e7, EI=0.1, diameter=0.01)],
                        top={"type": "winch"}, towbody={"mass": 50.0},
                        winch={"position": [0.0, 0.0, 0.0], "radius": 0.3, "phi_nom": 3.0, "kp": 100.0,
                               "kd": 20.0, "contact": {"stiffness": 1e10}})
    table["cable"]["initial"] = {"direction": [0.0, 0.0, -1.0]}
    sim = Simulation(scene_from_table(table))
    return sim, sim.initialize(setpoint=(phi, rate))


def test_winch_rotation_pays_out_its_pitch_radius_times_the_angle():
    """Turning the drum back by d_phi lowers the load by (r_w + d/2) d_phi; the tension stays
    the weight (frictionless drum: the rotation only moves cable from the drum to the span)."""
    sim1, out1 = _winch_hoist(3.0)
    sim2, out2 = _winch_hoist(2.5)
    radius = winch_radius(sim1.scene)
    assert radius == pytest.approx(0.305)
    assert out1["towbody.z"] - out2["towbody.z"] == pytest.approx(0.5 * radius, rel=2e-3)
    assert out2["winch.payout"] - out1["winch.payout"] == pytest.approx(0.5 * radius, rel=1e-12)
    for phi, out in ((3.0, out1), (2.5, out2)):
        # off the drum where its tangent is vertical (angle -pi/2): the load and what hangs below
        hanging = 12.0 - radius * (phi + 0.5 * math.pi)
        assert out["tension.winch"] == pytest.approx((50.0 + 0.5 * hanging) * G, rel=1e-3)
    assert out1["tension.towbody"] == pytest.approx(out2["tension.towbody"], rel=1e-9)


def test_winch_follows_its_set_point_in_time():
    """The PD drive W(136) moves the drum to a new set-point; the load follows by the payout."""
    sim, out0 = _winch_hoist(3.0)
    ship = np.zeros((3, 6))
    for _ in range(300):
        out = sim.step(0.01, ship, (2.8, 0.0))
    assert out["winch.phi"] == pytest.approx(2.8, abs=1e-4)
    assert out0["towbody.z"] - out["towbody.z"] == pytest.approx(0.2 * 0.305, rel=0.02)


def test_winch_started_under_a_moving_set_point_follows_the_pd_law_from_the_first_step():
    """The drum at rest at phi = 3 rad while its set-point already moves at omega = 1 rad/s:
    W(136) accelerates it at once with k2 omega = 20 rad/s^2, and the initial state has
    that acceleration. With k1 = 100 and k2 = 20 (critically damped, 10 rad/s) the lag
    e = phi_sp - phi obeys e'' + k2 e' + k1 e = 0 from e = 0, e' = omega:
    e = omega t exp(-10 t), at most 0.037 rad. The drum follows it within 0.1 % of that
    (0.01 s steps); started with no acceleration it was up to 5 % off."""
    omega = 1.0
    sim, _ = _winch_hoist(3.0, omega)
    assert sim.state.phi[2] == pytest.approx(20.0 * omega, rel=1e-12)
    ship = np.zeros((3, 6))
    largest = omega / (10.0 * math.e)
    for _ in range(50):
        out = sim.step(0.01, ship, (3.0 + omega * sim.time, omega))
        t = sim.time
        assert out["winch.phi"] == pytest.approx(3.0 + omega * t * (1.0 - math.exp(-10.0 * t)), abs=1e-3 * largest)


def _lateral_pull(sway: float):
    """A taut cable between two fixed points, over a grooved sheave that the ship carries
    sideways (sway, period 20 s): the spans pull the cable across the groove. The cable
    wraps the sheave by 8 deg only, so the pressure that holds it in the groove is small."""
    table = cable_scene([segment(1.0, 40, mu=0.1, EA=1e5, EI=1e-2, damping=0.05, diameter=0.01)],
                        top={"type": "pinned", "position": [-0.5, 0.0, 0.17]},
                        bottom={"type": "pinned", "position": [0.5, 0.0, 0.17]},
                        sheave={"position": [0.0, 0.0, 0.0], "radius": 0.2, "shape": "groove",
                                "groove_depth": 0.01, "throat_angle": 60.0, "rim_width": 0.6,
                                "contact": {"stiffness": 1e8}},
                        motion={"type": "regular", "sway": {"amplitude": sway, "period": 20.0}},
                        solver={"time_step": 0.005})
    table["cable"]["initial"] = {"direction": [0.9976, 0.0, -0.0698]}
    return Simulation(scene_from_table(table))


def test_cable_climbs_the_groove_wall_detaches_and_reseats():
    """Carrying the sheave sideways pulls the cable up a groove wall and out of the groove
    (the detachment indicator switches); the cable then rests on the flange top beside the
    groove, and carrying the sheave back re-seats it. Nothing goes NaN and the contact force
    never pulls (its total always points from the sheave into the cable's wrap)."""
    sim = _lateral_pull(sway=0.4)
    out = sim.initialize()
    assert out["contact.detached"] == 0.0
    res = sim.run(20.0, interval=0.1)
    detached = res["contact.detached"] > 0.5
    assert not detached[0] and detached[40:60].all()  # around the largest sway (t = 5 s): out of the groove
    assert not detached[95:106].all()  # the sheave back under the cable (t = 10 s): in the groove again
    assert detached[140:160].all() and not detached[-1]  # the same on the other side, and back
    for name, values in res.items():
        assert np.all(np.isfinite(values)), name
    assert np.all(res["contact.sheave_force"] > 0.0)  # always resting on groove or rim


def test_small_sideways_pull_keeps_the_cable_seated():
    sim = _lateral_pull(sway=0.02)
    sim.initialize()
    res = sim.run(10.0, interval=0.1)
    assert np.all(res["contact.detached"] == 0.0)


# ------------------------------------------------------------------ the V-groove's walls
COT_HALF_THROAT = 1.0 / math.tan(math.radians(30.0))  # cot(theta_g / 2) of the 60 deg groove


def _groove_force(h: float, y: float) -> tuple[np.ndarray, float]:
    """Total force per unit length of full_scale's sheave faces on a cable point at height h
    above its seat and offset y from the groove centre, at the top of the sheave [N/m]
    (Y, radial), and the point's detachment measure [m]."""
    from towcable_fmu.ancf.forces.contact import build_contact
    from towcable_fmu.contact.surfaces import SHEAVE, groove_exit
    from towcable_fmu.scene import load_scene

    scene = load_scene("full_scale")
    c = build_contact(scene)
    half_d = 0.5 * scene.cable.segments[0].diameter
    rc = scene.sheave.radius + half_d
    total = np.zeros(2)
    faces = [f for f in range(c.face_kind.size) if c.face_surface[f] == SHEAVE]
    for f in faces:
        _, fy, fz, g, _ = face_force(c, f, half_d, 0.0, y, rc + h, 0.0, 0.0, 0.0)
        if g > 0.0:
            total += (fy, fz)
    return total, groove_exit(c, faces[0], h, y)


def test_sunk_cable_is_held_by_both_groove_walls_and_a_climbed_out_cable_by_the_flange_top():
    """full_scale's groove (10 mm deep, 60 deg throat, Table 9's k_N = 1e6): the static
    cable sits 68 mm below its seat. Shifted sideways by Y it still lies below both walls
    of W(100), and below the groove top (W(101)): each pushes with k delta^1.5 along its
    normal, delta = +-Y cos 30 + 68 mm sin 30, whether Y is inside the groove's
    half-opening Y_o = 5.77 mm or beyond it, and the flange top does not push; the point
    is in the groove (negative detachment measure). A point whose contact point on the
    wall of its side is above the groove top (climbed out) rests on the flange top alone,
    pushed straight up with k (h_g - h)^1.5; above the flange top nothing pushes; both are
    out of the groove."""
    k, ca, sa, depth = 1e6, math.cos(math.radians(30.0)), math.sin(math.radians(30.0)), 0.068
    for offset in (0.0, 0.003, 0.0057, 0.0058, 0.010, 0.015, 0.025):
        force, exit_height = _groove_force(-depth, offset)
        plus, minus = (max(s * offset * ca + depth * sa, 0.0) ** 1.5 for s in (1.0, -1.0))
        np.testing.assert_allclose(force, [-k * ca * (plus - minus), k * sa * (plus + minus)], rtol=1e-12,
                                   err_msg=f"Y = {offset} m")
        assert exit_height < 0.0
    h = 0.009
    for y in (0.009, -0.015):
        force, exit_height = _groove_force(h, y)
        np.testing.assert_allclose(force, [0.0, k * (0.010 - h) ** 1.5], rtol=1e-12)
        assert exit_height > 0.0
    force, exit_height = _groove_force(0.011, 0.0)
    assert np.all(force == 0.0) and exit_height > 0.0


_HOLD = {"radius": 2.0, "mass": 140.0, "EA": 1e6, "rho": 1026.0, "cd": 4.0, "d": 0.01, "span": 2.0}


def _v_limit_geometry(stiffness: float) -> tuple[float, float, float]:
    """Tension T [N], strain and centreline radius R_p [m] of the wrap of :func:`_held_by_current`
    at the V's holding limit: on one wall, which carries N / sin(theta_g/2) with the radial
    load N = T (1 + eps) / R_p per unit (unstretched) length, sunk by that wall's
    penetration (2 N / k)^(2/3) below the seat."""
    p = _HOLD
    tension = (p["mass"] + 1e-3 * p["span"]) * G  # the hanging mass and the light span below the wrap
    eps = tension / p["EA"]
    seat = p["radius"] + 0.5 * p["d"]
    radius = seat
    for _ in range(30):
        radius = seat - (2.0 * tension * (1.0 + eps) / (radius * stiffness)) ** (2.0 / 3.0)
    return tension, eps, radius


def _held_by_current(ratio: float, stiffness: float) -> Simulation:
    """Half a turn of cable round a large grooved sheave (r = 2 m; full_scale's groove:
    10 mm deep, 60 deg throat), pinned below one side, a 140 kg mass hanging from the other.
    A current along the sheave's axis loads only the wrapped, neutrally buoyant segment:
    a uniform sideways drag q = 1/2 rho C_D d U^2 per unit length (the bare-cable loading
    functions of the nodal-position paper are 1 across the flow and 0 along it); the spans
    carry no fluid loads. ``ratio`` is q over the V's holding limit cot(theta_g/2) N. The
    pinned span meets the wrap where the sunk cable does (radius R_p), so the radial load
    is uniform; on the 2 m sheave the uneven sinking changes the wrap's tension by 0.3 %."""
    p = _HOLD
    tension, eps, radius = _v_limit_geometry(stiffness)
    drag = ratio * COT_HALF_THROAT * tension * (1.0 + eps) / radius
    current = math.sqrt(drag / (0.5 * p["rho"] * p["cd"] * p["d"]))
    common = {"EA": p["EA"], "EI": 1e-3, "diameter": p["d"]}
    span = segment(p["span"], 10, mu=1e-3, fluid_loads=False, **common)
    wrap = segment(math.pi * radius / (1.0 + eps), 80, mu=p["rho"] * math.pi * p["d"] ** 2 / 4.0,
                   loading="sun2011_bare", drag_coefficient=p["cd"], **common)
    table = cable_scene([span, wrap, dict(span)],
                        top={"type": "pinned", "frame": "ship", "position": [-radius, 0.0, -p["span"]]},
                        bottom={"type": "free", "mass": p["mass"]},
                        sheave={"position": [0.0, 0.0, 0.0], "radius": p["radius"], "shape": "groove",
                                "groove_depth": 0.01, "throat_angle": 60.0, "contact": {"stiffness": stiffness}},
                        water={"density": p["rho"], "surface_z": 10.0,
                               "current": {"type": "uniform", "velocity": [0.0, current, 0.0]}},
                        solver={"time_step": 2e-3})
    table["cable"]["initial"] = {"direction": [0.0, 0.0, -1.0]}
    return Simulation(scene_from_table(table))


def _wrap_middle(sim: Simulation) -> tuple[np.ndarray, np.ndarray]:
    """Sideways offset and height above the seat [m] of the nodes within 45 deg of the top."""
    x = sim.node_positions()
    middle = (x[:, 2] > 0.0) & (np.abs(x[:, 0]) < math.sin(math.radians(45.0)) * np.hypot(x[:, 0], x[:, 2]))
    return x[middle, 1], np.hypot(x[middle, 0], x[middle, 2]) - (_HOLD["radius"] + 0.5 * _HOLD["d"])


@pytest.mark.parametrize("stiffness", [1e6, 1e8])
def test_sideways_load_is_held_by_the_v_groove_up_to_its_closed_form_limit(stiffness):
    """The lateral drag grows from half the V's limit to 99 % of it (statics, each from the
    last): the cable stays in the groove, where the two walls of W(100) balance the radial
    load N and the sideways load q = r cot(theta_g/2) N: they carry N (1 +- r) (at 30 deg
    the normal force is twice its radial part), so the penetrations are
    delta+- = (N (1 +- r) / k)^(2/3) and the centreline sits (delta+ - delta-) / (2 cos 30)
    sideways and (delta+ + delta-) below the seat (closed form, within 1.5 %: the
    sinking sets N). With Table 9's k_N = 1e6 that is 7 mm sideways, beyond the groove's
    half-opening of 5.8 mm. 1 % beyond the limit there is no equilibrium in the groove: the
    cable climbs the wall and out, and the flange top cannot hold it sideways."""
    tension, eps, _ = _v_limit_geometry(stiffness)
    sim = _held_by_current(0.5, stiffness)
    sim.initialize()
    for ratio in (0.9, 0.99):
        last = sim.state.q
        sim = _held_by_current(ratio, stiffness)
        out = sim.initialize(q0=last)
        assert out["contact.detached"] == 0.0
        y, h = _wrap_middle(sim)
        normal = tension * (1.0 + eps) / (_HOLD["radius"] + 0.5 * _HOLD["d"] + h)  # T / R per unit length
        delta = [(normal * (1.0 + s * ratio) / stiffness) ** (2.0 / 3.0) for s in (1.0, -1.0)]
        np.testing.assert_allclose(y, (delta[0] - delta[1]) / (2.0 * math.cos(math.radians(30.0))), rtol=0.015)
        np.testing.assert_allclose(h, -(delta[0] + delta[1]), rtol=0.015)
    if stiffness == 1e6:
        assert y.min() > 0.01 * math.tan(math.radians(30.0))  # beyond the opening, still held
    held = sim.state.q
    sim = _held_by_current(1.01, stiffness)
    sim.initialize(statics=False, q0=held)
    for _ in range(30):
        out = sim.advance(sim.time + 0.1)
        if out["contact.detached"]:
            break
    assert out["contact.detached"] == 1.0


def _rolled(roll: float) -> np.ndarray:
    """Ship state (3, 6) of a ship at rest at a steady roll [deg]."""
    ship = np.zeros((3, 6))
    ship[0, 3] = math.radians(roll)
    return ship


def _roll_ratio(roll: float, departure: float, rise: float) -> float:
    """Sideways over radial force the two tensions press on a sheave rolled by ``roll``
    [rad]: the cable comes in from the drum in the sheave's plane, rising by ``rise``
    [rad], and leaves at ``departure`` [rad] from the inertial vertical in the inertial
    x-z plane, which the roll tilts out of the sheave's plane by cos(departure) sin(roll)."""
    sideways = math.cos(departure) * math.sin(roll)
    return sideways / math.hypot(math.sin(departure) - math.cos(rise),
                                 math.cos(departure) * math.cos(roll) + math.sin(rise))


@pytest.mark.parametrize("stiffness", [1e6, 1e8])
def test_rolled_ship_keeps_the_cable_in_the_groove_up_to_the_v_limit(stiffness):
    """full_scale in statics with the ship at a steady roll, each roll solved from the
    last equilibrium (the ship rolling slowly): the cable stays in the groove from 0 to
    60 deg, with Table 9's k_N = 1e6 as with 1e8. The sheave's force balances the two
    tensions: its sideways/radial ratio follows the closed form of their directions
    (upright departure angle and the drum-to-sheave tangent, within 3 %). At 80 deg,
    beyond the roll at which that ratio reaches the V's cot(theta_g/2) (about 74 deg),
    the walls cannot hold the cable: it is off the sheave."""
    sim = Simulation.from_scene("full_scale", {"motion.type": "none", "compensation.algorithm": "none",
                                               "sheave.contact.stiffness": stiffness})
    out = sim.initialize()
    sc = sim.scene
    gap = np.subtract(sc.sheave.position, sc.winch.position)
    distance = math.hypot(gap[0], gap[2])
    rise = math.atan2(gap[2], -gap[0]) - math.asin((sc.winch.radius - sc.sheave.radius) / distance)
    departure = out["sheave_angle"]
    limit = math.degrees(brentq(lambda r: _roll_ratio(r, departure, rise) - COT_HALF_THROAT, 0.1, 1.5))
    assert 70.0 < limit < 78.0
    for roll in [*np.arange(2.0, 61.0, 2.0), 80.0]:  # steps of 2 deg move the sheave 13 cm sideways
        out = sim.initialize(ship=_rolled(roll), q0=sim.state.q.copy())
        if roll > limit:
            assert out["contact.detached"] == 1.0 and out["contact.sheave_force"] == 0.0
            continue
        assert out["contact.detached"] == 0.0, roll
        if roll % 10.0:
            continue
        force = rotation_matrix(*_rolled(roll)[0, 3:6]).T @ sim.contact_state()["force"][1]  # ship frame
        ratio = abs(force[1]) / math.hypot(force[0], force[2])
        assert ratio == pytest.approx(_roll_ratio(math.radians(roll), departure, rise), rel=0.03), roll


# ------------------------------------------------------------------ the sheave angle
def _leaving_tangent(sim: Simulation) -> np.ndarray:
    """The cable's tangent (inertial, unnormalised) where it leaves the sheave: the
    derivative of the element's Hermite interpolation at the last touching point."""
    from towcable_fmu.ancf import element

    e, xi = sim.contact_state()["ends"][1][2:]
    e = int(e)
    assert e >= 0
    x = sim.state.q[6 * e: 6 * e + 12].reshape(4, 3)
    return element.shape_derivatives(xi, sim.mesh.lengths[e]) @ x


def _pitched_about(point: np.ndarray, pitch: float) -> np.ndarray:
    """Ship state (3, 6) at rest, pitched by ``pitch`` [rad] about the ship-fixed
    ``point`` (body frame [m]), which stays where it is on the upright ship at the origin."""
    ship = np.zeros((3, 6))
    ship[0, 4] = pitch
    ship[0, :3] = point - rotation_matrix(0.0, pitch, 0.0) @ point
    return ship


def test_sheave_angle_is_measured_from_the_inertial_vertical():
    """full_scale at its upright equilibrium; then the ship pitched by 1 and -2 deg about
    the sheave's axis with the cable held where it is. The groove is round about that
    axis, so the cable touches it as before (same contact force). The departure angle
    from the inertial vertical, which W(1)-(2) combine with inertial displacements,
    stays that of the cable's own tangent where it leaves the sheave; measured from the
    ship's vertical it would follow the pitch one to one."""
    sim = Simulation.from_scene("full_scale", {"motion.type": "none", "compensation.algorithm": "none"})
    upright = sim.initialize()
    tangent = _leaving_tangent(sim)
    assert upright["sheave_angle"] == pytest.approx(math.atan2(-tangent[0], -tangent[2]), abs=1e-12)
    held = sim.state.q.copy()
    sheave = np.array(sim.scene.sheave.position)
    for pitch in (math.radians(1.0), math.radians(-2.0)):
        out = sim.initialize(ship=_pitched_about(sheave, pitch), statics=False, q0=held)
        assert out["contact.sheave_force"] == pytest.approx(upright["contact.sheave_force"], rel=1e-9)
        assert out["sheave_angle"] == pytest.approx(upright["sheave_angle"], abs=1e-9)


def test_rigorous_waterline_setpoint_on_a_pitched_ship():
    """full_scale at equilibrium on a ship pitched 2 deg (its stern and sheave 1.3 m up),
    with the rigorous waterline compensation and theta_nom = 1.25 rad. By hand, W(1):
    L = H / cos(theta) - H_nom / cos(theta_nom) with H the sheave centre's height above
    the waterline and theta the inertial angle of the cable's tangent where it leaves the
    sheave, and phi_sp = phi_nom - L / (r_w + d/2). The simulation drives the winch with
    that set-point (an angle measured from the ship's vertical, 2 deg off, would pay out
    2.5 m too much)."""
    pitch = math.radians(2.0)
    sim = Simulation.from_scene("full_scale", {"motion": {"type": "regular", "pitch": {"mean": 2.0}},
                                               "compensation": {"algorithm": "rigorous_waterline",
                                                                "theta_nom": 1.25}})
    sim.initialize()
    tangent = _leaving_tangent(sim)
    theta = math.atan2(-tangent[0], -tangent[2])
    s_ref = np.array(sim.scene.sheave.position)
    height = (rotation_matrix(0.0, pitch, 0.0) @ s_ref)[2]
    payout = height / math.cos(theta) - s_ref[2] / math.cos(1.25)
    phi_sp = sim.scene.winch.phi_nom - payout / winch_radius(sim.scene)
    sim.advance(0.02)  # the set-point over the step is computed with the angle measured at its start
    assert sim.get_state()["setpoint"][0] == pytest.approx(phi_sp, abs=1e-9)


def test_energy_of_a_swing_over_a_pulley_is_conserved_without_damping():
    """No internal, contact or numerical damping: kinetic + strain + gravity + contact energy
    stays constant (the penalty contact is conservative for D = 0)."""
    table = cable_scene([segment(0.3, 6, mu=0.1, EA=2e5, EI=1e-3, diameter=0.01),
                         segment(0.6, 12, mu=0.1, EA=2e5, EI=1e-3, diameter=0.01)],
                        top={"type": "pinned", "position": [-0.3, 0.0, 0.055]},
                        bottom={"type": "free", "mass": 2.0},
                        sheave={"position": [0.0, 0.0, 0.0], "radius": 0.05, "shape": "cylinder",
                                "contact": {"stiffness": 1e8, "damping": 0.0}},
                        statics={"enabled": False}, solver={"time_step": 2e-4, "rho_inf": 1.0})
    table["cable"]["initial"] = {"direction": [math.cos(0.5), 0.0, -math.sin(0.5)]}
    sim = Simulation(scene_from_table(table))
    sim.initialize()
    res = sim.run(3.0, interval=0.005)
    energy = res["energy.kinetic"] + res["energy.strain"] + res["energy.gravity"] + res["energy.contact"]
    swing = np.ptp(res["energy.gravity"])
    assert swing > 2.0
    assert np.abs(energy - energy[0]).max() < 0.02 * swing


@pytest.mark.parametrize("scene", ["pulley_static", "pulley_static_2", "pulley_static_3"])
def test_pulley_static_tension_is_the_same_on_both_sides(scene):
    """Frictionless pulley and a light rope (Table 1's three configurations): the pinned
    side pulls as hard as the load side, through the whole swing; the strain at the rope's
    end agrees with the load's own equation of motion (its weight component plus its
    inertia)."""
    sim = Simulation.from_scene(scene)
    sim.initialize()
    res = sim.run(2.0, interval=0.005)
    taut = res["tension.load"] > 20.0
    assert taut.mean() > 0.5
    ratio = res["tension.top"][taut] / res["tension.load"][taut]
    assert np.median(np.abs(ratio - 1.0)) < 0.02
    end = res["tension.bottom"][taut] / res["tension.load"][taut]
    assert np.median(np.abs(end - 1.0)) < 0.02
    if scene == "pulley_static":
        wrap = np.degrees(res["contact.wrap_angle"])
        assert wrap.min() < 40.0 and wrap.max() > 120.0  # the swing of Table 1's configuration 1


def test_moving_pulley_at_rest_carries_the_load_and_swings_both_sides_alike():
    """Table 2's arm at rest: the rope's end carries the load's weight and, over a
    frictionless pulley, T - w z is the same all along a perfectly flexible rope in
    statics (w: weight per length), so the tension at the pinned end is the load's weight
    plus w times the height between the two ends. With the arm rotating, the two sides
    still pull alike."""
    from towcable_fmu.scene import load_scene

    scene = load_scene("pulley_moving")
    weight = scene.load.mass * scene.environment.gravity
    w = scene.cable.segments[0].mass_per_length * scene.environment.gravity
    still = Simulation(load_scene("pulley_moving", {"motion.pitch.amplitude": 0.0}))
    out = still.initialize()
    z = still.node_positions()[:, 2]
    assert out["tension.load"] == pytest.approx(weight, rel=2e-3)
    assert out["tension.bottom"] == pytest.approx(weight, rel=2e-3)
    # bending (EI 8e-5 N m^2) shifts the axial force by up to EI kappa^2 on the bent piece
    seg = scene.cable.segments[0]
    bending = seg.EI / (scene.sheave.radius + 0.5 * seg.diameter) ** 2
    assert out["tension.top"] - out["tension.bottom"] == pytest.approx(w * (z[0] - z[-1]), abs=bending)
    sim = Simulation(scene)
    sim.initialize()
    res = sim.run(3.0, interval=0.005)
    late = res["time"] > 2.0  # after the 2 s ramp
    assert np.ptp(res["tension.load"][late]) > 0.05 * weight  # the arm does shake the load
    ratio = res["tension.top"][late] / res["tension.load"][late]
    assert np.median(np.abs(ratio - 1.0)) < 0.02


def test_scenes_without_a_sheave_or_winch_never_call_the_contact_kernels():
    sim = Simulation.from_scene("hanging_cable")
    sim.initialize()
    sim.run(0.5)
    assert not sim.model.terms.contact.enabled and sim.model.terms.contact.calls[0] == 0
    # a winch without a sheave: the drum is the only surface there is to test
    flume = Simulation.from_scene("flume")
    assert set(flume.model.terms.contact.face_surface.tolist()) == {WINCH}
