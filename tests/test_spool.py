"""A cable paid out and hauled in from a spool point (cable.top.type = "spool",
towcable_fmu/ancf/feed.py): the fed element's kinematics against time derivatives, a slow
veer against the closed form of a hanging cable, conservation of length and energy, no
impulse at the splits and merges, and the errors at the limits."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from towcable_fmu.ancf import element
from towcable_fmu.ancf.feed import MERGE_FACTOR, SPLIT_FACTOR, apply_feed, material_rates, material_rows
from towcable_fmu.common.errors import SceneError, SolverError
from towcable_fmu.ancf.simulation import Simulation

SCENE = str(Path(__file__).parent / "data" / "spool_hanging.toml")
MU, EA, MASS, G, LENGTH = 0.389, 6.786e6, 250.0, 9.81, 20.0  # the scene's wire, end mass and deployed length


def _ramp(t0: float, t1: float, p0: float, p1: float, knots: int = 1001) -> dict:
    """A payout program from p0 at t0 to p1 at t1 [m] with a smooth (cosine) speed, in
    many short linear pieces (each knot steps the drive's rate set-point a little)."""
    s = np.linspace(0.0, 1.0, knots)
    payout = p0 + (p1 - p0) * (s - np.sin(2 * np.pi * s) / (2 * np.pi))
    return {"winch.program_times": list(t0 + (t1 - t0) * s), "winch.program_payout": list(payout)}


def _run(overrides: dict, duration: float, interval: float = 0.01) -> tuple[Simulation, dict]:
    sim = Simulation.from_scene(SCENE, overrides)
    sim.initialize()
    return sim, sim.run(duration, interval)


@pytest.fixture(scope="module")
def veer() -> dict[int, tuple[Simulation, dict]]:
    """The scene veered slowly from 20 m to 40 m deployed (100 s), meshed in 4 and in 5 elements."""
    return {n: _run({**_ramp(1.0, 101.0, 0.0, 20.0), "cable.segments[0].elements": n}, 103.0) for n in (4, 5)}


def test_the_fed_element_has_the_element_matrices_of_its_length():
    """apply_feed rescales the unit matrices; element.py integrates them at that length."""
    sim = Simulation.from_scene(SCENE)
    model, feed = sim.model, sim.model.terms.feed
    phi = np.array([-7.3, 0.0, 0.0, 0.0])   # 7.3 rad paid out
    apply_feed(model, phi)
    length = 5.0 + feed.radius * 7.3
    assert model.el_len[0] == pytest.approx(length, rel=1e-14)
    np.testing.assert_allclose(model.el_mass[0], element.mass_matrix(length, MU), rtol=1e-12)
    np.testing.assert_allclose(model.el_bend[0], element.bending_matrix(length, 1.40), rtol=1e-12)
    np.testing.assert_allclose(model.el_damp[0], element.damping_matrix(length, 310.0), rtol=1e-12)
    # the cable's whole weight: the vertical loads of all position rows
    weight = model.f_const[2:6 * sim.mesh.n_nodes:6].sum()
    assert weight == pytest.approx(-(MU * (15.0 + length) + MASS) * G, rel=1e-12)
    np.testing.assert_array_equal(feed.transport, 0.0)   # at rest: no transport terms


def _rows(xi: float, length: float, grows: float, u: float, du: float) -> list[np.ndarray]:
    """N, B, dB/dt, N_p, B_p of material_rows at xi."""
    h = np.stack([element.shape_functions(xi, 1.0), element.shape_derivatives(xi, 1.0),
                  element.shape_second_derivatives(xi, 1.0)])
    rows = [np.empty(4) for _ in range(5)]
    material_rows(h, xi, length, grows, u, du, *rows)
    return rows


@pytest.mark.parametrize("grows", [1.0, 0.0])
def test_material_rates_are_the_time_derivatives_of_a_material_point(grows):
    """r(t) = N(xi(p, t); L(t)) e(t) at a fixed material point p, with material entering
    at a varying payout rate and the element growing with it (the fed element) or of fixed
    length (a gear element): N de/dt + B e and N d2e/dt2 + 2 B de/dt + dB/dt e are its
    first and second time derivatives (finite differences), and the slope's likewise."""
    rng = np.random.default_rng(3)
    c0, c1, c2 = rng.normal(size=(3, 12))          # e(t) = c0 + c1 t + c2 t^2
    length0, u0, du = 3.0, 1.3, -0.4              # fed: p0(t) = -(u0 t + du t^2 / 2), L(t) = L0 - p0(t)
    p = 1.1                                        # material coordinate at t = 0

    def at(t: float) -> tuple[np.ndarray, np.ndarray]:
        fed = u0 * t + 0.5 * du * t * t
        length = length0 + grows * fed
        xi = (p + fed) / length
        e = (c0 + c1 * t + c2 * t * t).reshape(4, 3)
        return element.shape_functions(xi, length) @ e, element.shape_derivatives(xi, length) @ e

    dt = 1e-4
    (r_m, s_m), (r_0, s_0), (r_p, s_p) = at(-dt), at(0.0), at(dt)
    n, b, bdot, n_p, b_p = _rows(p / length0, length0, grows, u0, du)
    e, de, dde = c0.reshape(4, 3), c1.reshape(4, 3), 2.0 * c2.reshape(4, 3)
    np.testing.assert_allclose(n @ de + b @ e, (r_p - r_m) / (2 * dt), rtol=1e-7, atol=1e-8)
    np.testing.assert_allclose(n_p @ de + b_p @ e, (s_p - s_m) / (2 * dt), rtol=1e-7, atol=1e-8)
    np.testing.assert_allclose(n @ dde + 2 * b @ de + bdot @ e, (r_p - 2 * r_0 + r_m) / dt**2, rtol=1e-5, atol=1e-5)
    if grows:   # what a split of the fed element gives its new node, the slope's acceleration included
        velocity, acceleration = material_rates(c0, c1, 2.0 * c2, length0, p / length0, u0, du)
        np.testing.assert_allclose(velocity[:3], (r_p - r_m) / (2 * dt), rtol=1e-7, atol=1e-8)
        np.testing.assert_allclose(velocity[3:], (s_p - s_m) / (2 * dt), rtol=1e-7, atol=1e-8)
        np.testing.assert_allclose(acceleration[:3], (r_p - 2 * r_0 + r_m) / dt**2, rtol=1e-5, atol=1e-5)
        np.testing.assert_allclose(acceleration[3:], (s_p - 2 * s_0 + s_m) / dt**2, rtol=1e-5, atol=1e-5)
    # where the material enters it moves with the element's start plus the feed along the cable
    n, b, *_ = _rows(0.0, length0, grows, u0, du)
    np.testing.assert_allclose(n @ de + b @ e, de[0] + u0 * e[1], rtol=1e-13)


def test_a_slow_veer_follows_the_hanging_cable_closed_form(veer):
    """Top tension (mu L + M) g and end depth -(L + g (M L + mu L^2 / 2) / EA) at every
    deployed length L = 20 m + payout, within 1 % (tension) and 1 mm (depth)."""
    for sim, rec in veer.values():
        length = LENGTH + rec["winch.payout"]
        tension = (MU * length + MASS) * G
        np.testing.assert_allclose(rec["tension.top"], tension, rtol=0.01)
        depth = -(length + G * (MASS * length + 0.5 * MU * length**2) / EA)
        np.testing.assert_allclose(rec["towbody.z"], depth, atol=1e-3)
        assert rec["winch.payout"][-1] == pytest.approx(20.0, abs=1e-3)


def test_the_mesh_grows_with_the_deployed_length_and_conserves_it(veer):
    """Deployed (the elements) plus stored cable is the scene's, and the cable's mass
    (from the element mass matrices) is mu times the deployed length."""
    for n, (sim, rec) in veer.items():
        nominal = LENGTH / n
        assert sim.mesh.n_elements == n + round(20.0 / nominal)   # 20 m more at the nominal length
        np.testing.assert_allclose(sim.mesh.lengths[1:], nominal, rtol=1e-12)
        deployed = sim.mesh.node_arc[-1]
        assert deployed == pytest.approx(LENGTH + float(sim.outputs()["winch.payout"]), rel=1e-13)
        # the output at every sample (inside steps too: the interpolated winch state)
        np.testing.assert_allclose(rec["winch.deployed"], LENGTH + rec["winch.payout"], rtol=1e-13)
        ones = np.array([1.0, 0.0, 1.0, 0.0])          # a unit translation of an element
        mass = sum(ones @ m @ ones for m in sim.model.el_mass)
        assert mass == pytest.approx(MU * deployed, rel=1e-12)
        assert MERGE_FACTOR * nominal < sim.mesh.lengths[0] < SPLIT_FACTOR * nominal


def test_splits_leave_no_impulse_in_the_tension(veer):
    """Meshed in 4 or 5 elements, the splits fall at other times (every 5 m or 4 m of
    payout): the two tension histories agree within 1 % of the range of the tension's
    dynamic part (its departure from the quasi-static closed form)."""
    (_, a), (_, b) = veer[4], veer[5]
    quasi_static = (MU * (LENGTH + a["winch.payout"]) + MASS) * G
    dynamic = a["tension.top"] - quasi_static
    assert np.max(np.abs(a["tension.top"] - b["tension.top"])) < 0.01 * np.ptp(dynamic)
    assert np.ptp(dynamic) > 5.0   # the veer's own dynamics: its acceleration and the wire's axial mode


def test_the_energy_balance_closes_through_a_veer(veer):
    """The change of kinetic, strain and potential energy equals the work of the cable on
    the spool, -T u, plus the strain energy the paid-out cable brings with it,
    u T^2 / (2 EA), within the internal damping's share (below 0.05 % of the work)."""
    sim, rec = veer[4]
    t, u = rec["time"], np.gradient(rec["winch.payout"], rec["time"])
    tension = rec["tension.top"]
    power = -tension * u + u * tension**2 / (2 * EA)
    work = np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(t))
    energy = rec["energy.kinetic"] + rec["energy.strain"] + rec["energy.gravity"]
    assert energy[-1] - energy[0] == pytest.approx(work, rel=5e-4)
    assert abs(work) > 4e4   # 20 m of a 2.5 kN pull


def test_out_and_back_restores_the_mesh_and_the_hanging_state():
    """Veer 20 m and haul it back: the merges undo the splits, the mesh is the scene's
    again, and the cable hangs as it did (to the wire's remaining axial oscillation)."""
    program = _ramp(1.0, 21.0, 0.0, 12.0, 201)
    back = _ramp(22.0, 42.0, 12.0, 0.0, 201)
    program = {k: program[k] + back[k] for k in program}
    sim, rec = _run(program, 44.0, 0.05)
    np.testing.assert_allclose(sim.mesh.lengths[1:], np.full(3, 5.0), rtol=1e-12)
    assert sim.mesh.lengths[0] == pytest.approx(5.0, abs=1e-6)   # to the drive's tracking error
    assert rec["winch.payout"][-1] == pytest.approx(0.0, abs=1e-6)
    assert rec["towbody.z"][-1] == pytest.approx(-(LENGTH + G * (MASS * LENGTH + 0.5 * MU * LENGTH**2) / EA), abs=1e-4)
    assert rec["tension.top"][-1] == pytest.approx((MU * LENGTH + MASS) * G, rel=0.01)


def test_a_state_saved_before_a_split_restores_and_repeats_the_run():
    """get_state at 1 m of payout, run across a split, set_state: the mesh of the saved
    state comes back, and the run repeats bit for bit."""
    sim = Simulation.from_scene(SCENE, _ramp(0.5, 10.5, 0.0, 6.0, 101))
    sim.initialize()
    sim.run(3.0, 0.1)
    saved, n = sim.get_state(), sim.mesh.n_elements
    first = sim.run(5.0, 0.1)
    assert sim.mesh.n_elements == n + 1
    sim.set_state(saved)
    assert sim.mesh.n_elements == n
    second = sim.run(5.0, 0.1)
    for name in ("tension.top", "towbody.z", "winch.payout"):
        np.testing.assert_array_equal(first[name], second[name])


def test_hauling_in_the_whole_cable_is_an_error():
    sim = Simulation.from_scene(SCENE, _ramp(0.5, 10.5, 0.0, -19.9, 101))
    sim.initialize()
    with pytest.raises(SolverError, match=r"winch.payout = .* deployed length cannot go below 0.75 m"):
        sim.run(12.0, 0.1)


def test_paying_out_more_than_the_drum_stores_is_an_error():
    with pytest.raises(SceneError, match=r"winch.program_payout.*<= winch.stored_length = 200 m"):
        Simulation.from_scene(SCENE, _ramp(0.5, 10.5, 0.0, 250.0, 11))
    sim = Simulation.from_scene(SCENE, {"winch.stored_length": 1.0})
    sim.initialize()
    phi = -2.0 / sim.model.terms.feed.radius   # 2 m of payout
    with pytest.raises(SolverError, match=r"winch.payout = .* exceeds the 1 m the drum holds"):
        for _ in range(100):
            sim.step(0.05, sim.motion.evaluate(sim.time), (phi, 0.0))


@pytest.mark.parametrize("overrides, key", [
    ({"winch.stored_length": None}, "winch.stored_length"),
    ({"cable.top.position": None}, "cable.top.position"),
    ({"winch.program_times": [0.0, 1.0], "winch.program_payout": [0.0]}, "winch.program_payout"),
    ({"winch.program_times": [1.0, 0.0], "winch.program_payout": [0.0, 1.0]}, "winch.program_times"),
])
def test_bad_spool_settings_are_named(overrides, key):
    with pytest.raises(SceneError, match=key.replace(".", r"\.")):
        Simulation.from_scene(SCENE, overrides)


def _as_shipped(scene: str, duration: float) -> tuple[Simulation, dict, int]:
    """A built-in scene run as shipped, recorded at every step (0.05 s), and its element count at the start."""
    sim = Simulation.from_scene(scene)
    sim.initialize()
    start = sim.n_elements
    return sim, sim.run(duration, 0.05), start


@pytest.fixture(scope="module")
def deploy() -> tuple[Simulation, dict, int]:
    """full_scale_deploy as shipped."""
    return _as_shipped("full_scale_deploy", 720.0)


def _events(rec: dict) -> np.ndarray:
    """Samples just after the fed bare segment (nominal 25 m, 25 m deployed at the start)
    split (its element reaching 37.5 m: payouts 12.5 + 25 k on the way out) or merged (down to
    3.75 m: payouts 278.75 - 25 k on the way back)."""
    t, p = rec["time"], rec["winch.payout"]
    out = []
    for k in range(12):
        up, down = 12.5 + 25.0 * k, 278.75 - 25.0 * k
        out += list(np.flatnonzero((p[:-1] < up) & (p[1:] >= up) & (t[1:] < 350.0)) + 1)
        out += list(np.flatnonzero((p[:-1] > down) & (p[1:] <= down) & (t[1:] > 350.0)) + 1)
    return np.array(sorted(out))


def test_the_deploy_scene_veers_and_hauls_back_300_m(deploy):
    """300 m out at 1 m/s and back while towing in the default sea: one element per 25 m
    out and back, the deployed length is the scene's plus the payout to round-off, and the
    cable stays on the drum and in the sheave's groove throughout."""
    sim, rec, start = deploy
    assert np.max(rec["winch.payout"]) == pytest.approx(300.0, abs=0.01)
    assert sim.n_elements == start
    np.testing.assert_allclose(rec["winch.deployed"] - rec["winch.payout"], rec["winch.deployed"][0], rtol=1e-13)
    assert len(_events(rec)) == 24
    assert np.min(rec["contact.winch_force"]) > 1000.0 and np.min(rec["contact.sheave_force"]) > 100.0
    assert not np.any(rec["contact.detached"])
    assert np.all(np.isfinite(rec["tension.top"])) and np.min(rec["tension.top"]) > 0.0


@pytest.mark.parametrize("name", ["tension.top", "tension.sheave"])
def test_splits_and_merges_leave_no_impulse_in_the_deploy_scene(deploy, name):
    """At each of the 24 events the tension departs from its quadratic extrapolation
    through the three samples before by less than 1 % of its range over the run, and no
    more than it does at 99 % of the other steps (the sea and the program's knots)."""
    _, rec, _ = deploy
    x = rec[name]
    jump = np.abs(x[3:] - (3 * x[2:-1] - 3 * x[1:-2] + x[:-3]))
    events = _events(rec) - 3
    others = np.delete(jump, events)
    assert np.max(jump[events]) < 0.01 * np.ptp(x)
    assert np.max(jump[events]) < np.percentile(others, 99)


def test_steps_shorter_than_the_solver_step_split_and_merge_the_fed_element():
    """Steps of half the scene's time step (a co-simulation's communication step below the
    solver's: every call one solver step, which reaches the caller's time) out through a
    split and back through the merge: after every step the fed element is within its band
    (MERGE_FACTOR to SPLIT_FACTOR nominal lengths), as in a run. A step that ends at the
    caller's time with the fed element out of its band used to leave it unmeshed: hauled
    in, it shrank through zero length (ZeroDivisionError in the kernels)."""
    program = {"winch.program_times": [0.5, 6.5, 12.5], "winch.program_payout": [0.0, 3.0, 0.0]}
    sim = Simulation.from_scene(SCENE, program)
    sim.initialize(0.0, np.zeros((3, 6)))
    feed, nominal = sim.model.terms.feed, LENGTH / 4
    h = 0.5 * sim.options.h_max
    counts = set()
    for k in range(int(round(13.0 / h))):
        sim.step((k + 1) * h - sim.time, np.zeros((3, 6)))
        length = sim.model.el_len[feed.element]
        assert MERGE_FACTOR * nominal < length < SPLIT_FACTOR * nominal, (sim.time, length)
        counts.add(sim.mesh.n_elements)
    assert counts == {4, 5}   # split on the way out, merged on the way back
    assert sim.mesh.n_elements == 4


def test_the_towcable_fmu_pays_out_across_a_split_and_restores_its_state(fmu_paths):
    """The TowCable FMU on the spool scene with a payout program: winch.deployed follows
    the program through a split, the outputs are the Simulation's bit for bit, an FMU
    state saved before the split restores across it, and a set-point beyond the drum's
    store is refused with fmi2Discard and a message naming winch.payout, and an initial
    set-point far from the scene's deployed length with fmi2Error."""
    from fmpy.fmi1 import FMICallException

    from fmu_util import open_fmu, outputs, set_inputs, ship_inputs

    program = "winch.program_times = [0.5, 8.5]; winch.program_payout = [0.0, 4.0]"
    fmu = open_fmu(fmu_paths, "TowCable", {"scene": SCENE, "overrides": program})
    still = ship_inputs(np.zeros((3, 6)))
    set_inputs(fmu, still)
    fmu.exit_initialization()
    sim = Simulation.from_scene(SCENE, {"winch.program_times": [0.5, 8.5], "winch.program_payout": [0.0, 4.0]})
    sim.initialize(0.0, np.zeros((3, 6)))

    def run(t: float, n: int) -> tuple[float, dict]:
        for _ in range(n):
            fmu.fmu.doStep(t, 0.05)
            t += 0.05
        return t, outputs(fmu)

    t, _ = run(0.0, 60)                       # 1.5 m out: before the split at 2.5 m
    state = fmu.fmu.getFMUstate()
    t_end, first = run(t, 100)                # 3.75 m out at 8 s
    t_sim = 0.0
    for _ in range(160):                      # the same communication points
        expected = sim.step((t_sim + 0.05) - t_sim, np.zeros((3, 6)))
        t_sim += 0.05
    for name in ("tension.top", "towbody.z", "winch.payout", "winch.deployed"):
        assert first[name] == expected[name], name
    assert first["winch.deployed"] == pytest.approx(LENGTH + 3.75, abs=1e-3)   # the program at 8 s
    fmu.fmu.setFMUstate(state)
    assert run(t, 100) == (t_end, first)
    fmu.fmu.freeFMUstate(state)
    fmu.free()

    small = open_fmu(fmu_paths, "TowCable", {"scene": SCENE, "overrides": "winch.stored_length = 1.0"},
                     instance="small drum")
    set_inputs(small, still)
    small.exit_initialization()
    radius = 0.3 + 0.005
    set_inputs(small, {"winch.phi_sp": -2.0 / radius})       # 2 m out of a drum storing 1 m
    t, mark = 0.0, len(small.messages)
    with pytest.raises(FMICallException) as info:
        for _ in range(100):
            small.fmu.doStep(t, 0.05)
            t += 0.05
    assert info.value.status == 2   # fmi2Discard
    assert "winch.payout" in small.log_text(mark) and "1 m the drum holds" in small.log_text(mark)
    small.free()

    far = open_fmu(fmu_paths, "TowCable", {"scene": SCENE}, instance="far out")
    set_inputs(far, {**still, "winch.phi_sp": -30.0 / radius})    # 30 m out at the start
    mark = len(far.messages)
    with pytest.raises(FMICallException) as info:
        far.fmu.exitInitializationMode()
    assert info.value.status == 3   # fmi2Error
    assert "winch.phi_sp (initial)" in far.log_text(mark), far.log_text(mark)
    far.free()


def test_a_slow_haul_follows_the_statics_at_each_deployed_length():
    """full_scale_recovery on a still ship, hauled 10 m in over 600 s (at most 0.033 m/s):
    at each of five deployed lengths the spool tension and the body's depth are those of
    the scene's statics with the bare segment that long (towcable static), within 1 %."""
    still = {"motion": {"type": "none"}}
    program = _ramp(10.0, 610.0, 0.0, -10.0, 601)
    sim = Simulation.from_scene("full_scale_recovery", {**still, **program})
    sim.initialize()
    rec = sim.run(612.0, 1.0)
    checked = 0
    for t in (10.0, 160.0, 310.0, 460.0, 612.0):
        k = int(np.argmin(np.abs(rec["time"] - t)))
        length = 30.0 + float(rec["winch.payout"][k])
        static = Simulation.from_scene("full_scale_recovery", {**still, "cable.segments[3].length": length})
        expected = static.initialize()
        assert rec["tension.top"][k] == pytest.approx(expected["tension.top"], rel=0.01), t
        assert rec["towbody.z"][k] == pytest.approx(expected["towbody.z"], rel=0.01), t
        checked += 1
    assert checked == 5 and rec["winch.payout"][-1] == pytest.approx(-10.0, abs=1e-3)


@pytest.fixture(scope="module")
def recovery() -> tuple[Simulation, dict, int]:
    """full_scale_recovery as shipped."""
    return _as_shipped("full_scale_recovery", 110.0)


def test_the_recovery_lifts_the_body_through_the_splash_zone(recovery):
    """29 m hauled in: the fed segment merges from six elements to one, the cable crosses
    the waterline as it shortens, and the body, 27 m deep at the start, leaves the water
    (its centre above the surface by more than its half height) after the haul."""
    sim, rec, start = recovery
    assert sim.n_elements == start - 5
    assert rec["towbody.z"][0] < -26.0
    after = rec["time"] > 85.0
    assert np.max(rec["towbody.z"][after]) > 0.3 + 1.0
    np.testing.assert_allclose(rec["winch.deployed"] - rec["winch.payout"], rec["winch.deployed"][0], rtol=1e-13)
    assert np.all(np.isfinite(rec["tension.top"])) and np.min(rec["tension.top"]) > 0.0


def test_merges_leave_no_impulse_in_the_recovery(recovery):
    """At the five merges (the fed element, nominal 5 m, down to 0.75 m: payouts
    -4.25 - 5 k) the spool tension departs from its quadratic extrapolation by less than 1 %
    of its range, and no more than at 99 % of the other steps."""
    _, rec, _ = recovery
    p, x = rec["winch.payout"], rec["tension.top"]
    events = np.array([int(np.flatnonzero((p[:-1] > v) & (p[1:] <= v))[0]) + 1 for v in -4.25 - 5.0 * np.arange(5)])
    jump = np.abs(x[3:] - (3 * x[2:-1] - 3 * x[1:-2] + x[:-3]))
    others = np.delete(jump, events - 3)
    assert np.max(jump[events - 3]) < 0.01 * np.ptp(x)
    assert np.max(jump[events - 3]) < np.percentile(others, 99)


def test_initialising_again_starts_from_the_scene_mesh():
    """After a veer the winch's splits are undone by a new initialisation: the scene's
    mesh, 20 m deployed and the same statics."""
    sim = Simulation.from_scene(SCENE, _ramp(0.5, 10.5, 0.0, 6.0, 101))
    first = sim.initialize()
    sim.run(11.0, 0.5)
    assert sim.n_elements == 5
    again = sim.initialize()
    assert sim.n_elements == 4 and again["winch.deployed"] == LENGTH
    assert again["tension.top"] == pytest.approx(first["tension.top"], rel=1e-9)


def test_an_initial_set_point_far_from_the_scene_length_is_an_error():
    """The cable starts on the scene's mesh: 30 m out at initialisation (the fed element
    would be 35 m of a nominal 5 m) is refused with the range of payouts allowed."""
    sim = Simulation.from_scene(SCENE)
    radius = sim.model.terms.feed.radius
    with pytest.raises(SceneError, match=r"winch.phi_sp \(initial\).*payout in \(-4.25, 2.5\) m"):
        sim.initialize(0.0, np.zeros((3, 6)), (-30.0 / radius, 0.0))
    assert sim.initialize(0.0, np.zeros((3, 6)), (-2.0 / radius, 0.0))["winch.deployed"] == pytest.approx(22.0)


def test_a_section_hauled_onto_the_drum_comes_back_off_it_in_place():
    """Two sections (20 m, then the lowest 10 m) of the same wire: hauled 25 m in, the fed
    element passes into the lower section (the last 0.75 m of the upper one with it); paid
    35 m out, the fed element is split exactly where the upper section's cable comes in
    again. The lower section is then 10 m long again, the upper 30 + 10 m, and the tension
    is that of the same 30 m of wire as one section (within 1 % of its range: the section
    events disturb nothing)."""
    two = str(Path(__file__).parent / "data" / "spool_two_sections.toml")
    haul, veer = _ramp(1.0, 121.0, 0.0, -25.0, 1201), _ramp(122.0, 282.0, -25.0, 10.0, 1601)
    program = {k: haul[k] + veer[k] for k in haul}
    sim = Simulation.from_scene(two, program)
    sim.initialize()
    rec = sim.run(284.0, 0.05)
    labels, lengths = sim.mesh.segment_of_element, sim.mesh.lengths
    assert np.sum(lengths[labels == 1]) == pytest.approx(10.0, rel=1e-12)
    assert np.sum(lengths[labels == 0]) == pytest.approx(20.0 + 10.0, rel=1e-6)   # (the drive's tracking error)
    assert np.min(rec["winch.deployed"]) == pytest.approx(5.0, abs=1e-3)          # 25 m in: 5 m of the lower left
    one = Simulation.from_scene(SCENE, {**program, "cable.segments[0].length": 30.0, "cable.segments[0].elements": 6})
    one.initialize()
    twin = one.run(284.0, 0.05)
    assert np.max(np.abs(rec["tension.top"] - twin["tension.top"])) < 0.01 * np.ptp(twin["tension.top"])


def test_a_section_of_other_cable_cannot_pass_the_gear():
    """The lower section 50 % heavier: hauling it onto the drum through the gear, whose mesh
    carries the fed segment's cable, is an error naming the section and the property."""
    two = str(Path(__file__).parent / "data" / "spool_two_sections.toml")
    sim = Simulation.from_scene(two, {**_ramp(1.0, 41.0, 0.0, -25.0, 401),
                                      "cable.segments[1].mass_per_length": 1.5 * MU})
    sim.initialize()
    with pytest.raises(SolverError, match=r"cable.segments\[1\] onto the drum, but its mass_per_length"):
        sim.run(42.0, 0.1)


def test_the_spool_pays_out_as_the_cable_pinned_on_the_drum_does():
    """full_scale (cable end pinned on the drum, wound by its rotation) against the same
    system paid out from a spool (full_scale_deploy meshed as full_scale: 300 m bare in 8,
    150 m faired in 6), a still ship, 1 m paid out over 20 s: the same statics, and the
    sheave tension, the pull on the body and its depth agree within 1 % of their ranges.
    The drum contact is made stiff (k_N = 1e8): the scene's soft drum lets the wound cable
    sink 5.5 cm, so the pinned model pays out about 15 % less cable than its payout."""
    common = {"motion": {"type": "none"}, "winch.contact.stiffness": 1e8, **_ramp(5.0, 25.0, 0.0, 1.0, 201)}
    pinned = Simulation.from_scene("full_scale", {**common, "compensation.algorithm": "none"})
    spool = Simulation.from_scene("full_scale_deploy", {
        **common, "cable.segments[3].length": 300.0, "cable.segments[3].elements": 8,
        "cable.segments[4].length": 150.0, "cable.segments[4].elements": 6})
    first, second = pinned.initialize(), spool.initialize()
    assert spool.n_elements == pinned.n_elements
    for name in ("tension.sheave", "towbody.z"):
        assert second[name] == pytest.approx(first[name], rel=1e-7)
    a, b = pinned.run(45.0, 0.05), spool.run(45.0, 0.05)
    for name in ("tension.sheave", "tension.towbody", "towbody.z"):
        assert np.max(np.abs(a[name] - b[name])) < 0.01 * np.ptp(a[name]), name
    assert np.ptp(a["towbody.z"]) > 1.0   # the body sank by the metre paid out


def test_frames_of_a_remeshed_cable_are_padded_with_its_end():
    """Animation snapshots across a split: one node more after it; the earlier frames
    repeat their bottom end up to the same number of rows."""
    from towcable_fmu.ancf.frames import run_with_frames

    sim = Simulation.from_scene(SCENE, _ramp(0.5, 10.5, 0.0, 6.0, 101))
    _, frames = run_with_frames(sim, 11.0, 0.5, 0.1)
    assert frames.nodes.shape[1] == 6 == sim.mesh.n_nodes
    first = frames.nodes[0]
    np.testing.assert_array_equal(first[4:], np.repeat(first[4:5], 2, axis=0))   # 5 nodes, the last twice
    np.testing.assert_array_equal(frames.nodes[-1], sim.node_positions())
