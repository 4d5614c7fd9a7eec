"""Winch and sheave: contact statics, payout, detachment from the groove, energy, pulley scenes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import cable_scene, segment

from towcable_fmu.ancf.mesh import winch_radius
from towcable_fmu.contact.surfaces import WINCH
from towcable_fmu.scene import scene_from_table
from towcable_fmu.simulation import Simulation

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


def _winch_hoist(phi: float):
    table = cable_scene([segment(2.0, 20, mu=0.5, EA=1e7, EI=0.1, diameter=0.01),
                         segment(10.0, 10, mu=0.5, EA=1e7, EI=0.1, diameter=0.01)],
                        top={"type": "winch"}, towbody={"mass": 50.0},
                        winch={"position": [0.0, 0.0, 0.0], "radius": 0.3, "phi_nom": 3.0, "kp": 100.0,
                               "kd": 20.0, "contact": {"stiffness": 1e10}})
    table["cable"]["initial"] = {"direction": [0.0, 0.0, -1.0]}
    sim = Simulation(scene_from_table(table))
    return sim, sim.initialize(setpoint=(phi, 0.0))


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
    assert not sim.model.contact.enabled and sim.model.contact.calls[0] == 0
    # a winch without a sheave: the drum is the only surface there is to test
    flume = Simulation.from_scene("flume")
    assert set(flume.model.contact.face_surface.tolist()) == {WINCH}
