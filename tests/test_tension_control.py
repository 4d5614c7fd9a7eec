"""The constant-tension winch (issue 20, deliverable 2): the sampled law of
controllers/tension.py against its limits worked out by hand, and the whole model (cable,
drum contact, PD drive, controller) in regular heave against the closed form of the
linearised loop."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmu_util import open_fmu, outputs, set_inputs

from controllers import SetpointConfig, TensionControl, setpoint_config_from_table
from towcable_fmu.common.errors import SceneError
from towcable_fmu.ancf.simulation import Simulation

R_W = 0.30  # drum radius to the cable centreline [m]
PHI_NOM = 3.8  # [rad]
SCENE = Path(__file__).parent / "data" / "winch_to_anchor.toml"


def control(**overrides) -> TensionControl:
    params = dict(algorithm="constant_tension", reference_point=(0.0, 0.0, 0.0), winch_radius=R_W, phi_nom=PHI_NOM,
                  theta_nom=0.0, tension_target=1000.0, tension_gain=1e-4)
    params.update(overrides)
    return TensionControl(SetpointConfig(**params))


# ---------------------------------------------------------------- the sampled law
def test_rate_follows_the_tension_error_one_interval_later():
    ctl = control()
    sp = ctl.advance(1500.0, 0.1)  # 500 N above the target: pay out at 0.05 m/s from now on
    assert ctl.payout == 0.0 and sp.payout_rate == pytest.approx(0.05)
    assert sp.phi_sp_rate == pytest.approx(-0.05 / R_W)
    sp = ctl.advance(1000.0, 0.1)  # at the target: the rate held so far moved the payout, now stop
    assert sp.payout == pytest.approx(0.005) and sp.payout_rate == 0.0
    assert sp.phi_sp == pytest.approx(PHI_NOM - 0.005 / R_W)
    assert ctl.setpoint() == sp  # the set-point is the state's: reading it changes nothing


def test_speed_and_acceleration_limits():
    ctl = control(max_winch_speed=0.5, max_winch_acceleration=1.0)  # 0.15 m/s, 0.3 m/s^2
    rates = [ctl.advance(1e6, 0.1).payout_rate for _ in range(8)]
    np.testing.assert_allclose(rates, [0.03, 0.06, 0.09, 0.12, 0.15, 0.15, 0.15, 0.15])
    assert ctl.advance(1e6, 0.1).rate_clipped
    # the payout integrates the rates held: 0.1 s x (0 + 0.03 + ... + 0.15 x 4); the last not yet
    assert ctl.payout == pytest.approx(0.1 * sum(rates))


def test_payout_limit_is_reached_not_passed():
    ctl = control(max_payout=0.1)
    for _ in range(40):
        sp = ctl.advance(1e5, 0.1)  # would pay out at 9.9 m/s
        assert abs(sp.payout) <= 0.1 + 1e-15
    assert sp.payout == pytest.approx(0.1) and sp.payout_rate == pytest.approx(0.0, abs=1e-12)
    assert sp.payout_clipped
    ctl.advance(0.0, 0.1)  # far below the target: haul in again
    assert ctl.rate < 0.0


def test_longer_interval_than_planned_sets_the_payout_back_to_the_limit():
    ctl = control(max_payout=0.1)
    ctl.advance(1e5, 0.1)  # rate planned to land on the limit after 0.1 s
    assert ctl.payout + ctl.rate * 0.1 == pytest.approx(0.1)
    sp = ctl.advance(1e5, 0.3)
    assert sp.payout == 0.1


def test_state_round_trip_continues_identically():
    a = control(max_winch_acceleration=2.0)
    for tension in (1200.0, 900.0, 1300.0):
        a.advance(tension, 0.05)
    b = control(max_winch_acceleration=2.0)
    b.set_state(a.get_state())
    for tension in (1100.0, 800.0):
        assert a.advance(tension, 0.05) == b.advance(tension, 0.05)


@pytest.mark.parametrize("tension, dt", [(math.nan, 0.1), (math.inf, 0.1), (1000.0, 0.0), (1000.0, -0.1)])
def test_bad_measurement_or_interval_changes_nothing(tension, dt):
    ctl = control()
    ctl.advance(1100.0, 0.1)
    before = ctl.get_state()
    with pytest.raises(ValueError, match="tension|interval"):
        ctl.advance(tension, dt)
    assert ctl.get_state() == before


@pytest.mark.parametrize("field, value", [("tension_target", 0.0), ("tension_target", -5.0),
                                          ("tension_gain", 0.0), ("max_winch_acceleration", -1.0),
                                          ("max_winch_speed", -1.0), ("tension_target", math.nan)])
def test_bad_setting_names_the_key(field, value):
    with pytest.raises(SceneError) as err:
        control(**{field: value})
    assert err.value.key == f"compensation.{field}" and str(err.value).startswith(f"compensation.{field} = {value!r}")


@pytest.mark.parametrize("missing", ["tension_target", "tension_gain"])
def test_constant_tension_needs_target_and_gain(missing):
    table = {"algorithm": "constant_tension", "reference_point": [0.0, 0.0, 0.0], "winch_radius": R_W,
             "phi_nom": PHI_NOM, "theta_nom": 0.0, "tension_target": 1000.0, "tension_gain": 1e-4}
    del table[missing]
    with pytest.raises(SceneError, match=f"compensation.{missing}.*required"):
        setpoint_config_from_table(table)


# ------------------------------------------------------ the whole model in heave
OMEGA = 2.0 * math.pi / 5.0  # the scene's heave [rad/s]
HEAVE = 0.05  # [m]


def _tension_phasor(overrides: dict) -> tuple[complex, float]:
    """Complex amplitude of tension.winch at the heave frequency (sin -> real part) over
    20-40 s (the heave's ramp ends at 10 s), and its mean [N]."""
    sim = Simulation.from_scene(str(SCENE), overrides)
    out = sim.run(40.0, 0.01)
    keep = out["time"] > 20.0
    t = out["time"][keep]
    basis = np.column_stack([np.ones_like(t), np.sin(OMEGA * t), np.cos(OMEGA * t)])
    c = np.linalg.lstsq(basis, out["tension.winch"][keep], rcond=None)[0]
    return complex(c[1], c[2]), float(c[0])


def test_constant_tension_winch_in_heave_follows_the_linearised_loop():
    """With the winch held, the taut cable to the anchor is a spring: T = k X, k the
    whole cable's EA / L (the wrap stretches too). With the controller, the closed form
    of controllers/tension.py for a fixed far end, T / X = k s / (s + g W(s) k e^{-1.5 s h})
    (W the PD drive's response, h = 0.01 s the control interval), gives amplitude and
    phase; the mean tension is the target (integral action)."""
    fixed, _ = _tension_phasor({})
    k = abs(fixed) / HEAVE
    assert k == pytest.approx(1.0e6 / 12.5, rel=0.02)
    assert abs(np.angle(fixed)) < 1e-3  # in phase with the heave
    target = Simulation.from_scene(str(SCENE), {}).initialize()["tension.winch"]  # the static tension
    kp, kd, h = 250.0, 50.0, 0.01
    s = 1j * OMEGA
    drive = (kd * s + kp) / (s * s + kd * s + kp)
    for gain in (2.5e-5, 1e-4):  # bandwidths g k = 2 and 8 rad/s against the heave's 1.26
        phasor, mean = _tension_phasor({"compensation.algorithm": "constant_tension",
                                           "compensation.tension_target": target,
                                           "compensation.tension_gain": gain})
        closed = k * s / (s + gain * k * drive * np.exp(-1.5 * s * h)) * HEAVE
        assert abs(phasor) == pytest.approx(abs(closed), rel=0.01), gain
        assert abs(np.angle(phasor / closed)) < 0.01, gain
        assert mean == pytest.approx(target, rel=1e-4)
    assert abs(phasor) < 0.2 * abs(fixed)


def test_state_of_a_constant_tension_run_restores_bit_identically():
    overrides = {"compensation.algorithm": "constant_tension", "compensation.tension_target": 7000.0,
                 "compensation.tension_gain": 1e-4}
    sim = Simulation.from_scene(str(SCENE), overrides)
    sim.run(12.0, 0.01)
    saved = sim.get_state()
    first = sim.run(1.0, 0.01)
    other = Simulation.from_scene(str(SCENE), overrides)
    other.set_state(saved)
    second = other.run(1.0, 0.01)
    for name in ("tension.winch", "winch.payout"):
        np.testing.assert_array_equal(first[name], second[name])
    assert np.ptp(first["winch.payout"]) > 0.0


# ------------------------------------------------------------ the FMU and the master
CT_PARAMETERS = {"algorithm": "constant_tension", "winch_radius": R_W, "phi_nom": PHI_NOM, "tension_target": 1000.0,
                 "tension_gain": 1e-4, "max_winch_acceleration": 2.0}


def test_heave_compensation_fmu_is_the_controller_stepped_by_the_master(fmu_paths):
    """Outputs: the controller's state (setting the tension changes nothing before the
    step); each step moves it with the tension at the step's start; a non-finite tension
    is refused with fmi2Discard and changes nothing; FMU state get/set rolls back."""

    fmu = open_fmu(fmu_paths, "HeaveCompensation", CT_PARAMETERS)
    fmu.exit_initialization()
    ctl = control(max_winch_acceleration=2.0)
    t = 0.0
    for tension, dt in ((1500.0, 0.1), (700.0, 0.05), (1200.0, 0.1)):
        before = outputs(fmu)
        set_inputs(fmu, {"tension.winch": tension})
        assert outputs(fmu) == before  # no feedthrough
        fmu.fmu.doStep(t, dt)
        t += dt
        sp = ctl.advance(tension, dt)
        out = outputs(fmu)
        assert (out["winch.phi_sp"], out["winch.phi_sp_rate"]) == (sp.phi_sp, sp.phi_sp_rate)
    state = fmu.fmu.getFMUstate()
    set_inputs(fmu, {"tension.winch": math.nan})
    mark = len(fmu.messages)
    with pytest.raises(FMICallException):
        fmu.fmu.doStep(t, 0.1)
    assert "tension.winch" in fmu.log_text(mark) and outputs(fmu) == out
    set_inputs(fmu, {"tension.winch": 2000.0})
    fmu.fmu.doStep(t, 0.1)
    moved = outputs(fmu)
    fmu.fmu.setFMUstate(state)  # (the inputs too, as FMI has it)
    assert outputs(fmu) == out
    set_inputs(fmu, {"tension.winch": 2000.0})
    fmu.fmu.doStep(t, 0.1)
    assert outputs(fmu) == moved
    fmu.fmu.freeFMUstate(state)
    fmu.free()


@pytest.mark.parametrize("params, text", [({"tension_target": 0.0}, "tension_target = 0.0"),
                                          ({"tension_gain": 0.0}, "tension_gain = 0.0")])
def test_heave_compensation_fmu_without_target_or_gain_fails_initialisation(fmu_paths, params, text):

    fmu = open_fmu(fmu_paths, "HeaveCompensation", {**CT_PARAMETERS, **params})
    mark = len(fmu.messages)
    with pytest.raises(FMICallException):
        fmu.fmu.exitInitializationMode()
    assert text in fmu.log_text(mark) and "constant_tension" in fmu.log_text(mark), fmu.log_text(mark)
    fmu.free()


def test_cosimulated_constant_tension_winch_follows_the_linearised_loop(fmu_paths):
    """The main job's way: ShipMotion, HeaveCompensation (constant_tension, the tension fed
    back from TowCable) and TowCable at a 0.01 s communication step, against the same
    closed form as the standalone run (k from a standalone run with the winch held)."""
    from towcable_fmu.cosim import CosimConfig, run_cosim

    fixed, _ = _tension_phasor({})
    k = abs(fixed) / HEAVE
    target = Simulation.from_scene(str(SCENE), {}).initialize()["tension.winch"]
    gain = 1e-4
    result = run_cosim(CosimConfig(scene=str(SCENE), compensation="constant_tension", duration=40.0, step=0.01,
                                   controller_parameters={"tension_target": target, "tension_gain": gain}),
                       echo=False, fmus=fmu_paths)
    series = result.series
    keep = series["time"] > 20.0
    t = series["time"][keep]
    basis = np.column_stack([np.ones_like(t), np.sin(OMEGA * t), np.cos(OMEGA * t)])
    c = np.linalg.lstsq(basis, series["tension.winch"][keep], rcond=None)[0]
    phasor = complex(c[1], c[2])
    s = 1j * OMEGA
    drive = (50.0 * s + 250.0) / (s * s + 50.0 * s + 250.0)
    closed = k * s / (s + gain * k * drive * np.exp(-1.5 * s * 0.01)) * HEAVE
    assert abs(phasor) == pytest.approx(abs(closed), rel=0.02)
    assert abs(np.angle(phasor / closed)) < 0.02
    assert c[0] == pytest.approx(target, rel=1e-3)


# ---------------------------------------------------- more payout than the drum holds
def test_an_unstable_tension_loop_stops_at_the_drum_instead_of_running_away():
    """A gain far above the sampled loop's stability limit (full_scale: bandwidth g k
    ~ 75 rad/s against a 10 ms control interval) makes the payout diverge; the run stops
    with an error naming winch.payout and the gain as soon as the payout passes the cable
    wound on the drum, instead of reeling out kilometres of cable the drum does not have."""
    from towcable_fmu.common.errors import SolverError

    sim = Simulation.from_scene("full_scale", {"compensation.algorithm": "constant_tension",
                                               "compensation.tension_target": 3951.4,
                                               "compensation.tension_gain": 5e-3})
    with pytest.raises(SolverError, match=r"winch.payout = .* exceeds the 1.0\d* m the drum holds.*tension_gain"):
        sim.run(60.0, 0.01)
    assert sim.time < 10.0


def test_a_step_beyond_the_drum_is_refused_and_changes_nothing():
    from towcable_fmu.common.errors import SolverError

    sim = Simulation.from_scene("full_scale", {"compensation.algorithm": "none"})
    start = sim.initialize()
    ship = sim.motion.evaluate(0.0)
    radius = sim.output_scene.payout_radius
    with pytest.raises(SolverError, match="winch.payout"):
        sim.step(0.5, ship, (PHI_NOM - 3.0 / radius, -1.0 / radius))  # 3 m out in half a second
    assert sim.time == 0.0 and sim.outputs() == start
    out = sim.step(0.5, ship, (PHI_NOM - 0.5 / radius, 0.0))  # towards 0.5 m: on the drum
    assert 0.2 < out["winch.payout"] < 0.51


def test_towcable_fmu_discards_a_step_beyond_the_drum(fmu_paths):
    """fmi2Discard with the message; the outputs keep their values."""
    from fmu_util import SMALL_SCENE, ship_inputs

    fmu = open_fmu(fmu_paths, "TowCable", {"scene": str(SMALL_SCENE)})
    fmu.exit_initialization()
    before = outputs(fmu)
    set_inputs(fmu, {"winch.phi_sp": before["winch.phi"] - 40.0, "winch.phi_sp_rate": -80.0})
    mark = len(fmu.messages)
    with pytest.raises(FMICallException):
        fmu.fmu.doStep(0.0, 0.5)
    assert "winch.payout" in fmu.log_text(mark), fmu.log_text(mark)
    assert outputs(fmu) == before
    fmu.free()
