"""The three FMUs on fmpy's low-level FMI 2.0 interface: state machine, FMU state, bad input.

Independent checks: the TowCable FMU against the Simulation driven directly with the same
inputs (bit-identical), the ShipMotion FMU against the motion source, the
HeaveCompensation FMU against SetpointAlgorithm.
"""

from __future__ import annotations

import json
import math

import pytest
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException

from fmu_misuse import envelope
from fmu_util import SMALL_SCENE, all_finite, open_fmu, outputs, set_inputs, ship_inputs

from towcable_fmu.common import contract

DISCARD, ERROR = 2, 3


def regular_motion():
    from ship_motion import motion_from_config

    return motion_from_config({"type": "regular", "ramp": 0.0, "heave": {"amplitude": 0.8, "period": 6.0},
                               "pitch": {"amplitude": 2.0, "period": 7.0}})


def cable(paths, instance=None, **params):
    return open_fmu(paths, "TowCable", {"scene": str(SMALL_SCENE), **params}, instance=instance)


def run_cable(fmu, t0: float, steps, motion=None):
    """Step the TowCable FMU with ship inputs from ``motion`` at the start of each step."""
    t = t0
    for dt in steps:
        if motion is not None:
            set_inputs(fmu, ship_inputs(motion.evaluate(t)))
        fmu.fmu.doStep(t, dt)
        t += dt
    return t, outputs(fmu)


# ------------------------------------------------------------------ independent check
def test_towcable_fmu_equals_the_simulation_driven_directly(fmu_paths):
    """Variable communication steps, a moving ship: the FMU gives bit for bit what
    Simulation.step gives with the same inputs."""
    from towcable_fmu.ancf.simulation import Simulation

    motion = regular_motion()
    steps = [0.01, 0.02, 0.005, 0.015, 0.01, 0.03]
    fmu = cable(fmu_paths)
    set_inputs(fmu, ship_inputs(motion.evaluate(0.0)))
    fmu.exit_initialization()
    first = outputs(fmu)
    _, out = run_cable(fmu, 0.0, steps, motion)
    fmu.free()

    sim = Simulation.from_scene(SMALL_SCENE)
    ref0 = sim.initialize(0.0, motion.evaluate(0.0), (0.0, 0.0))
    t = 0.0
    for dt in steps:
        ref = sim.step((t + dt) - t, motion.evaluate(t), (0.0, 0.0))
        t += dt
    for name, value in ref.items():
        if name in out:
            assert out[name] == value, name
    assert first["tension.top"] == ref0["tension.top"]
    # outputs the Simulation does not give for this scene are 0
    assert out["tension.sheave"] == 0.0 and out["contact.detached"] == 0.0


def test_ship_motion_fmu_outputs_the_source_at_the_end_of_each_step(fmu_paths):
    from ship_motion import DEFAULT_SEA, motion_from_config

    fmu = open_fmu(fmu_paths, "ShipMotion")
    fmu.exit_initialization()
    source = motion_from_config(DEFAULT_SEA)
    assert list(outputs(fmu).values()) == source.evaluate(0.0).ravel().tolist()
    t = 0.0
    for dt in (0.1, 0.25, 0.05):
        fmu.fmu.doStep(t, dt)
        t += dt
    assert list(outputs(fmu).values()) == source.evaluate(t).ravel().tolist()
    fmu.free()


def test_ship_motion_fmu_reads_an_rao_file_through_motion_config(fmu_paths):
    """motion.config naming a TOML file whose [motion.rao] is a Capytaine dataset (the worked
    example's short-crested sea): the FMU outputs that source; a missing RAO file is an error
    naming motion.rao.file."""
    pytest.importorskip("capytaine")
    import tomllib
    from pathlib import Path

    from ship_motion import motion_from_config

    scene = Path(__file__).resolve().parents[1] / "docs" / "examples" / "capytaine_barge" / "barge_sea.toml"
    fmu = open_fmu(fmu_paths, "ShipMotion", {"motion.config": str(scene)})
    fmu.exit_initialization()
    source = motion_from_config(tomllib.loads(scene.read_text())["motion"], base_dir=scene.parent)
    t = 0.0
    for dt in (0.1, 0.25):
        fmu.fmu.doStep(t, dt)
        t += dt
    assert list(outputs(fmu).values()) == source.evaluate(t).ravel().tolist()
    fmu.free()
    text = scene.read_text().replace("barge_capytaine.nc", "missing.nc")
    fmu = open_fmu(fmu_paths, "ShipMotion", {})
    mark = len(fmu.messages)
    with pytest.raises(FMICallException) as info:
        fmu.set_parameters({"motion.config": text})
        fmu.fmu.exitInitializationMode()
    assert info.value.status == ERROR and "motion.rao.file" in fmu.log_text(mark)
    fmu.free()


def test_heave_compensation_fmu_is_setpoint_algorithm_with_direct_feedthrough(fmu_paths):
    from controllers import SetpointAlgorithm, SetpointConfig

    params = {"algorithm": "rigorous_sheave", "theta_nom": 0.5, "winch_radius": 0.3, "phi_nom": 3.8}
    fmu = open_fmu(fmu_paths, "HeaveCompensation", params)
    fmu.exit_initialization()
    algo = SetpointAlgorithm(SetpointConfig(algorithm="rigorous_sheave", reference_point=(-36.8, 0.0, 3.7),
                                            winch_radius=0.3, phi_nom=3.8, theta_nom=0.5))
    motion = regular_motion()
    times = (0.0, 0.7, 1.9, 2.0)
    for k, t in enumerate(times[:-1]):
        ship = motion.evaluate(t)
        angle = 0.4 + 0.1 * k
        values = {n: v for n, v in ship_inputs(ship).items() if n in fmu.spec.names("input")}
        set_inputs(fmu, {**values, "sheave_angle": angle})
        out = outputs(fmu)  # read before the step: feedthrough
        ship_no_acc = ship.copy()
        ship_no_acc[2] = 0.0
        sp = algo.compute(ship_no_acc, angle)
        assert (out["winch.phi_sp"], out["winch.phi_sp_rate"]) == (sp.phi_sp, sp.phi_sp_rate)
        fmu.fmu.doStep(t, times[k + 1] - t)  # steps follow each other (FMI 2.0)
    fmu.free()


# ------------------------------------------------------------------ state machine
def test_state_machine_terminate_reset_and_run_again(fmu_paths):
    fmu = cable(fmu_paths)
    set_inputs(fmu, ship_inputs(regular_motion().evaluate(0.0)))
    fmu.exit_initialization()
    _, first = run_cable(fmu, 0.0, [0.01] * 5, regular_motion())
    fmu.fmu.terminate()
    fmu.fmu.reset()  # back to instantiated, with the default parameters
    fmu.fmu.setupExperiment(startTime=0.0)
    fmu.set_parameters({"scene": str(SMALL_SCENE)})
    fmu.fmu.enterInitializationMode()
    set_inputs(fmu, ship_inputs(regular_motion().evaluate(0.0)))
    fmu.exit_initialization()
    _, again = run_cable(fmu, 0.0, [0.01] * 5, regular_motion())
    assert again == first
    fmu.free()


def test_two_instances_in_one_process_do_not_interfere(fmu_paths):
    motion = regular_motion()
    alone = {}
    for mass in (150.0, 300.0):
        fmu = cable(fmu_paths, **{"towbody.mass": mass})
        fmu.exit_initialization()
        alone[mass] = run_cable(fmu, 0.0, [0.01] * 8, motion)[1]
        fmu.free()
    a = cable(fmu_paths, **{"towbody.mass": 150.0})
    b = cable(fmu_paths, instance="second", **{"towbody.mass": 300.0})
    a.exit_initialization()
    b.exit_initialization()
    t = 0.0
    for _ in range(8):
        for fmu in (a, b):
            set_inputs(fmu, ship_inputs(motion.evaluate(t)))
            fmu.fmu.doStep(t, 0.01)
        t += 0.01
    assert outputs(a) == alone[150.0] and outputs(b) == alone[300.0]
    assert alone[150.0]["tension.top"] != alone[300.0]["tension.top"]
    a.free()
    b.free()


def test_two_different_fmus_in_one_process(fmu_paths):
    """All three slaves share one interpreter: their entry modules must not collide."""
    fmus = [open_fmu(fmu_paths, "ShipMotion"), open_fmu(fmu_paths, "HeaveCompensation"), cable(fmu_paths)]
    for fmu in fmus:
        fmu.exit_initialization()
        fmu.fmu.doStep(0.0, 0.01)
        assert all_finite(outputs(fmu))
    for fmu in fmus:
        fmu.free()


# ------------------------------------------------------------------ FMU state
@pytest.mark.parametrize("name", ["TowCable", "ShipMotion", "HeaveCompensation"])
def test_get_state_run_set_state_run_again_is_identical(fmu_paths, name):
    motion = regular_motion()
    fmu = cable(fmu_paths) if name == "TowCable" else open_fmu(fmu_paths, name)
    fmu.exit_initialization()

    def run(t, n):
        for _ in range(n):
            if name != "ShipMotion":
                values = {k: v for k, v in ship_inputs(motion.evaluate(t)).items() if k in fmu.spec.names("input")}
                set_inputs(fmu, values)
            fmu.fmu.doStep(t, 0.01)
            t = round(t + 0.01, 10)
        return t, outputs(fmu)

    t1, _ = run(0.0, 5)
    state = fmu.fmu.getFMUstate()
    t2, first = run(t1, 7)
    fmu.fmu.setFMUstate(state)
    t2b, second = run(t1, 7)
    assert t2 == t2b and second == first
    fmu.fmu.freeFMUstate(state)
    fmu.free()


def test_serialized_state_continues_identically_in_a_fresh_instance(fmu_paths):
    motion = regular_motion()
    fmu = cable(fmu_paths)
    fmu.exit_initialization()
    t1, _ = run_cable(fmu, 0.0, [0.01] * 5, motion)
    state = fmu.fmu.getFMUstate()
    data = fmu.fmu.serializeFMUstate(state)
    fields = envelope(bytes(data))  # FMU, build and checksum around the JSON of the solver state
    assert fields["magic"] == b"TWCSTATE" and fields["crc_ok"]
    assert fields["name"] == "TowCable" and fields["guid"] == read_model_description(fmu_paths["TowCable"]).guid
    assert json.loads(fields["payload"].decode())["fmu"] == "TowCable"
    fmu.fmu.freeFMUstate(state)
    _, expected = run_cable(fmu, t1, [0.01] * 6, motion)

    fresh = open_fmu(fmu_paths, "TowCable", instance="fresh")  # default scene parameter
    fresh.exit_initialization()  # a different (default) scene first
    restored = fresh.fmu.deSerializeFMUstate(data)
    fresh.fmu.setFMUstate(restored)
    _, got = run_cable(fresh, t1, [0.01] * 6, motion)
    assert got == expected
    fresh.fmu.freeFMUstate(restored)
    fresh.free()
    fmu.free()


# ------------------------------------------------------------------ bad input
def expect_discard(fmu, t, dt, text):
    mark = len(fmu.messages)
    before = outputs(fmu)
    with pytest.raises(FMICallException) as info:
        fmu.fmu.doStep(t, dt)
    assert info.value.status == DISCARD
    assert text in fmu.log_text(mark), fmu.log_text(mark)
    after = outputs(fmu)
    assert after == before and all_finite(after)


def test_nan_input_zero_and_negative_step_are_discarded_with_a_message(fmu_paths):
    fmu = cable(fmu_paths)
    fmu.exit_initialization()
    fmu.fmu.doStep(0.0, 0.01)
    set_inputs(fmu, {"ship.z": math.nan})
    expect_discard(fmu, 0.01, 0.01, "ship.z")
    set_inputs(fmu, {"ship.z": 0.0, "winch.phi_sp": math.inf})
    expect_discard(fmu, 0.01, 0.01, "winch.phi_sp")
    set_inputs(fmu, {"winch.phi_sp": 0.0})
    expect_discard(fmu, 0.01, 0.0, "step size")
    expect_discard(fmu, 0.01, -0.01, "step size")
    expect_discard(fmu, 0.5, 0.01, "not the model time")
    fmu.fmu.doStep(0.01, 0.01)  # valid again: the refused steps changed nothing
    assert all_finite(outputs(fmu))
    fmu.free()


@pytest.mark.parametrize("name, params, text", [
    ("TowCable", {"scene": "no_such_scene"}, "no_such_scene"),
    ("TowCable", {"scene": str(SMALL_SCENE), "towbody.mass": -5.0}, "towbody.mass"),
    ("TowCable", {"scene": str(SMALL_SCENE), "solver.time_step": -0.01}, "solver.time_step"),
    ("TowCable", {"scene": str(SMALL_SCENE), "overrides": "water.density=-1"}, "water.density"),
    ("HeaveCompensation", {"winch_radius": -0.3}, "winch_radius"),
    ("HeaveCompensation", {"algorithm": "magic"}, "algorithm"),
    ("ShipMotion", {"motion.hs": -1.0}, "motion.hs"),
    ("ShipMotion", {"motion.type": "tsunami"}, "motion.type"),
])
def test_bad_scene_or_parameter_is_an_fmi2_error_with_a_message(fmu_paths, name, params, text):
    """A value outside the contract's declared range is refused by its setter; any other
    value the model cannot use, by fmi2ExitInitializationMode. Both return fmi2Error (the
    loader layer maps the logged error to the call's status), and a failed initialisation
    makes every later step an error too."""
    spec = contract.fmu(name)
    declared = all(spec.variable(k).min is None or v >= spec.variable(k).min for k, v in params.items()
                   if isinstance(v, float))
    fmu = open_fmu(fmu_paths, name, {})
    mark = len(fmu.messages)
    with pytest.raises(FMICallException) as info:
        fmu.set_parameters(params)
        assert declared, "a value outside the declared range was set"
        fmu.fmu.exitInitializationMode()
    assert info.value.status == ERROR
    errors = [m for s, m in fmu.messages[mark:] if s == ERROR]
    assert errors and text in errors[0], fmu.log_text(mark)
    if declared:
        mark = len(fmu.messages)
        with pytest.raises(FMICallException) as info:
            fmu.fmu.doStep(0.0, 0.01)
        assert info.value.status == ERROR and "initialisation failed" in fmu.log_text(mark)
    fmu.free()


def test_master_reports_a_failed_initialisation(fmu_paths):
    from towcable_fmu.cosim import CosimError

    fmu = open_fmu(fmu_paths, "TowCable", {"scene": "no_such_scene"})
    with pytest.raises(CosimError, match="no_such_scene") as info:
        fmu.exit_initialization()
    assert str(info.value).count("initialisation failed") == 1, str(info.value)
    fmu.free()


def test_heave_compensation_bad_inputs(fmu_paths):
    fmu = open_fmu(fmu_paths, "HeaveCompensation", {"algorithm": "rigorous_sheave"})
    fmu.exit_initialization()
    good = outputs(fmu)
    set_inputs(fmu, {"ship.z": math.nan})
    assert outputs(fmu) == good  # keeps the last valid set-point
    expect_discard(fmu, 0.0, 0.01, "ship.z")
    # a missing angle measurement is not an error: theta_nom is used, with a warning
    mark = len(fmu.messages)
    set_inputs(fmu, {"ship.z": 0.5, "sheave_angle": math.nan})
    fmu.fmu.doStep(0.0, 0.01)
    assert all_finite(outputs(fmu)) and outputs(fmu) != good
    assert "theta_nom" in fmu.log_text(mark)
    fmu.free()


def test_time_series_outside_its_record_is_discarded(fmu_paths):
    fmu = open_fmu(fmu_paths, "ShipMotion", {"motion.type": "time_series"})
    fmu.exit_initialization()
    fmu.fmu.doStep(0.0, 1.0)
    expect_discard(fmu, 1.0, 500.0, "t")
    fmu.free()


def test_solver_failure_inside_the_fmu_is_discarded_with_message_and_unchanged_outputs(fmu_paths):
    """A step the solver cannot take (at most three Newton iterations, no step below 9 ms,
    an absurd ship heave acceleration of 1e6 m/s^2 at the winch) comes back as
    fmi2Discard with the solver's message; the outputs keep their previous finite values,
    and the model is where it was: with sane inputs the same step then gives bit for bit
    what an instance that never saw the failed step gives. (The sane steps of this smooth,
    ramped motion need one or two Newton iterations at the full step.)"""
    from ship_motion import motion_from_config

    overrides = "solver.max_newton_iterations=3; solver.min_time_step=0.009"
    motion = motion_from_config({"type": "regular", "ramp": 5.0, "heave": {"amplitude": 0.8, "period": 6.0},
                                 "pitch": {"amplitude": 2.0, "period": 7.0}})

    def start(instance):
        f = cable(fmu_paths, instance=instance, overrides=overrides)
        set_inputs(f, ship_inputs(motion.evaluate(0.0)))
        f.exit_initialization()
        return f

    # the undisturbed run first
    twin = start("twin")
    t_twin, good_twin = run_cable(twin, 0.0, [0.01] * 4, motion)
    _, expected = run_cable(twin, t_twin, [0.01, 0.01], motion)
    twin.free()

    fmu = start(None)
    t, good = run_cable(fmu, 0.0, [0.01] * 4, motion)
    assert t == t_twin and good == good_twin and all_finite(good)
    violent = motion.evaluate(t).copy()
    violent[2, 2] = 1e6  # ship.az
    set_inputs(fmu, ship_inputs(violent))
    mark = len(fmu.messages)
    expect_discard(fmu, t, 0.01, "failed")
    log = fmu.log_text(mark)
    assert "Newton failed at the minimum step size" in log, log
    assert f"from t = {t:.6g} s" in log  # says where it happened
    assert outputs(fmu) == good

    # the discarded step left the model at t: the same step again, with sane inputs
    _, after = run_cable(fmu, t, [0.01, 0.01], motion)
    assert after == expected and after != good
    fmu.free()


def test_each_instance_receives_its_own_log_messages(fmu_paths):
    """fmpy's logger proxy keeps one process-wide logger; the master's router must still
    deliver each message to the instance that logged it."""
    first = cable(fmu_paths, instance="first")
    second = cable(fmu_paths, instance="second")
    try:
        first.exit_initialization()
        assert any("first:" in m for _, m in first.messages), first.messages
        assert not any("first:" in m for _, m in second.messages), second.messages
    finally:
        first.free()
        second.free()
