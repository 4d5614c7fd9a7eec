"""Every model runs in the TowCable FMU (issue 7): the nodal-position cable and the
rigid-link tug-tow scene, next to the ANCF scenes the other FMU tests use.

Checks: the FMU's statics equal the hand-computed wet weight; an FMU run with the
scene's own ship motion as inputs follows the simulation's own run (the two drive the
top differently - constant-acceleration extrapolation per communication step against
quintic knots - so they agree to that drive error, not bit for bit); FMU states roll back
exactly.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fmu_util import open_fmu, outputs, set_inputs, ship_inputs


def towcable(paths, scene: str):
    fmu = open_fmu(paths, "TowCable", {"scene": scene})
    return fmu


def run(fmu, motion, t0: float, n: int, dt: float) -> tuple[float, list[dict[str, float]]]:
    """n communication steps of dt [s], ship inputs from ``motion`` (None: left alone)."""
    t, rows = t0, []
    for _ in range(n):
        if motion is not None:
            set_inputs(fmu, ship_inputs(motion.evaluate(t)))
        fmu.fmu.doStep(t, dt)  # fmpy raises on a status other than OK
        t = round(t + dt, 12)
        rows.append(outputs(fmu))
    return t, rows


# ------------------------------------------------------------- nodal-position cable
@pytest.fixture(scope="module")
def nodal_scene():
    from towcable_fmu.scene import load_scene

    return load_scene("snapping_cable_nodal")


def test_nodal_scene_in_the_fmu_starts_at_the_wet_weight(fmu_paths, nodal_scene):
    seg, body, rho = nodal_scene.cable.segments[0], nodal_scene.towbody, nodal_scene.water.density
    G = nodal_scene.environment.gravity
    wet_cable = (seg.mass_per_length - rho * math.pi / 4 * seg.diameter ** 2) * seg.length * G
    wet_body = (body.mass - rho * body.volume) * G
    fmu = towcable(fmu_paths, "snapping_cable_nodal")
    still = np.zeros((3, 6))
    still[0, 2] = -2.0  # the ship at rest 2 m down: the top at z = -3 m
    set_inputs(fmu, ship_inputs(still))
    fmu.exit_initialization()
    out = outputs(fmu)
    fmu.free()
    assert out["tension.top"] == pytest.approx(wet_cable + wet_body, rel=1e-4)
    stretch = (wet_body + 0.5 * wet_cable) * seg.length / seg.EA  # integral of T / EA along the cable
    assert out["towbody.z"] == pytest.approx(-3.0 - seg.length - stretch, abs=1e-4)


def test_nodal_scene_in_the_fmu_follows_the_simulations_own_run(fmu_paths, nodal_scene):
    from towcable_fmu.nodal.simulation import NodalSimulation
    from towcable_fmu.runtime.ship_input import motion_source

    motion = motion_source(nodal_scene)
    fmu = towcable(fmu_paths, "snapping_cable_nodal")
    set_inputs(fmu, ship_inputs(motion.evaluate(0.0)))
    fmu.exit_initialization()
    _, rows = run(fmu, motion, 0.0, 100, 0.01)
    fmu.free()
    ref = NodalSimulation(nodal_scene).run(1.0, 0.01)
    got_z = np.array([r["towbody.z"] for r in rows])
    got_t = np.array([r["tension.top"] for r in rows])
    # the sphere's motion: the top moves 0.05 m; the drive difference is O(dt^3) (measured 2e-5 m)
    assert np.max(np.abs(got_z - ref["towbody.z"][1:])) < 1e-4
    # tension through the slack-taut snaps: within 1 % of the peak (measured 0.7 %, 2.1 N of 295 N)
    assert np.max(np.abs(got_t - ref["tension.top"][1:])) < 0.01 * np.max(ref["tension.top"])
    assert np.max(got_t) > 3.0 * ref["tension.top"][0]  # it snaps (Tmax/T0 about 5.4 over a longer run)


@pytest.mark.parametrize("scene", ["snapping_cable_nodal", "sea_trial_turn_rigid", "tug_tow"])
def test_fmu_state_of_the_other_models_rolls_back_exactly(fmu_paths, scene):
    fmu = towcable(fmu_paths, scene)
    fmu.exit_initialization()
    t1, _ = run(fmu, None, 0.0, 5, 0.01)
    state = fmu.fmu.getFMUstate()
    data = fmu.fmu.serializeFMUstate(state)
    _, first = run(fmu, None, t1, 7, 0.01)
    fmu.fmu.setFMUstate(state)
    _, second = run(fmu, None, t1, 7, 0.01)
    assert second == first
    fresh = towcable(fmu_paths, scene)
    fresh.exit_initialization()
    fresh.fmu.setFMUstate(fresh.fmu.deSerializeFMUstate(data))
    _, third = run(fresh, None, t1, 7, 0.01)
    assert third == first
    fmu.fmu.freeFMUstate(state)
    fmu.free()
    fresh.free()


# ------------------------------------------------------------- rigid-link tug-tow
def test_rigid_link_scene_in_the_fmu_follows_the_simulations_own_run(fmu_paths):
    from towcable_fmu.rigidlink.simulation import RigidLinkSimulation
    from towcable_fmu.scene import load_scene

    fmu = towcable(fmu_paths, "tug_tow")
    fmu.exit_initialization()
    _, rows = run(fmu, None, 0.0, 40, 0.05)
    fmu.free()
    sim = RigidLinkSimulation(load_scene("tug_tow"))
    sim.initialize()
    ref = sim.run(2.0, 0.05)
    got_x = np.array([r["towbody.x"] for r in rows])
    got_t = np.array([r["tension.towbody"] for r in rows])
    # two runs of the same ODE by the scene's solver (its rtol): one restarted at every
    # communication point, one not (measured: 1e-8 m and 4e-4 N of 5.8 kN)
    assert np.max(np.abs(got_x - ref["towbody.x"][1:])) < 1e-6
    assert np.max(np.abs(got_t - ref["tension.towbody"][1:])) < 1e-5 * np.max(np.abs(ref["tension.towbody"]))


def test_rigid_body_attitude_reaches_the_fmu_outputs(fmu_paths):
    """The rigid towed body's CG and attitude are exported (a lumped body's attitude is 0)."""
    from towcable_fmu.models import simulation_for
    from towcable_fmu.scene import load_scene

    still = np.zeros((3, 6))
    fmu = towcable(fmu_paths, "sea_trial_turn_rigid")
    set_inputs(fmu, ship_inputs(still))
    fmu.exit_initialization()
    got = outputs(fmu)
    fmu.free()
    ref = simulation_for(load_scene("sea_trial_turn_rigid")).initialize(0.0, still, (0.0, 0.0))
    for name in ("towbody.x", "towbody.z", "towbody.roll", "towbody.pitch", "towbody.yaw", "tension.towbody"):
        assert got[name] == ref[name], name
    assert abs(got["towbody.pitch"]) > 1e-3  # the hanging body trims where its moments balance
