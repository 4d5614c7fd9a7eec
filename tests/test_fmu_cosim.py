"""The co-simulation master, the command line, and the SSP file run by libcosim and fmpy.ssp."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from fmu_util import SMALL_SCENE
from towcable_fmu.common import contract
from towcable_fmu.cosim import CosimConfig, run_cosim

WAVES = """type = "regular"
ramp = 0.0
heave = { amplitude = 0.8, period = 6.0 }
pitch = { amplitude = 2.0, period = 7.0 }
"""


def cosim(fmu_paths, **kw):
    config = CosimConfig(scene=str(SMALL_SCENE), duration=kw.pop("duration", 0.3), step=kw.pop("step", 0.01), **kw)
    return run_cosim(config, echo=False, fmus=fmu_paths)


@pytest.fixture(scope="module")
def moving(fmu_paths):
    """A master run with a moving ship and the rigorous sheave algorithm."""
    return cosim(fmu_paths, motion=WAVES, compensation="rigorous_sheave", duration=0.4)


def test_still_ship_cable_equals_the_simulation(fmu_paths):
    """With the ship at rest, the co-simulated cable gives what Simulation gives directly."""
    from towcable_fmu.ancf.simulation import Simulation

    result = cosim(fmu_paths, motion="none", compensation="none", duration=0.5)
    s = result.series
    sim = Simulation.from_scene(SMALL_SCENE)
    phi_nom = result.geometry["phi_nom"]
    rows = [sim.initialize(0.0, np.zeros((3, 6)), (phi_nom, 0.0))]
    for k in range(50):
        rows.append(sim.step(0.01, np.zeros((3, 6)), (phi_nom, 0.0)))
    for name in ("tension.top", "tension.towbody", "towbody.x", "towbody.z", "angle.top"):
        assert s[name].tolist() == [r[name] for r in rows], name
    assert np.all(s["winch.phi_sp"] == phi_nom) and np.all(s["winch.phi_sp_rate"] == 0.0)
    assert np.all(s["ship.z"] == 0.0)
    # sane: a towed cable at 1.5 m/s streams aft and down, tension decreasing towards the body
    assert s["towbody.z"][-1] < -50.0 and s["towbody.x"][-1] < -40.0
    assert s["tension.top"][-1] > s["tension.towbody"][-1] > 0.0


def test_order_ship_then_controller_then_cable(fmu_paths, moving):
    """The cable is initialised with the nominal set-point and steps with the ship state at
    the start of the step; the set-point at t_k uses the ship at t_k and the sheave angle
    the cable gave at t_k (one step of delay)."""
    from controllers import SetpointAlgorithm, SetpointConfig
    from ship_motion import motion_from_config
    from towcable_fmu.ancf.simulation import Simulation
    import tomllib

    s = moving.series
    t = s["time"]
    source = motion_from_config(tomllib.loads(WAVES))
    ships = source.evaluate_many(t)
    names = [n for n in contract.signals() if n.startswith("ship.")]
    assert np.array_equal(np.stack([s[n] for n in names], axis=1), ships.reshape(len(t), 18))
    cfg = SetpointConfig(algorithm="rigorous_sheave", reference_point=moving.geometry["reference_point"],
                         winch_radius=moving.geometry["winch_radius"], phi_nom=moving.geometry["phi_nom"],
                         theta_nom=moving.geometry["theta_nom"])
    algo = SetpointAlgorithm(cfg)
    for k in range(len(t)):
        ship = ships[k].copy()
        ship[2] = 0.0
        sp = algo.compute(ship, s["sheave_angle"][k])
        assert (s["winch.phi_sp"][k], s["winch.phi_sp_rate"][k]) == (sp.phi_sp, sp.phi_sp_rate)
    sim = Simulation.from_scene(SMALL_SCENE)
    # the master initialises the cable with the nominal set-point (the controller needs
    # the cable's static angle first), then steps it with the controller's
    ref = [sim.initialize(0.0, ships[0], (moving.geometry["phi_nom"], 0.0))]
    for k in range(len(t) - 1):
        ref.append(sim.step(t[k + 1] - t[k], ships[k], (s["winch.phi_sp"][k], s["winch.phi_sp_rate"][k])))
    assert s["tension.top"].tolist() == [r["tension.top"] for r in ref]
    assert moving.geometry["source"]["theta_nom"].startswith("static sheave_angle")


def test_same_run_twice_is_bit_identical(fmu_paths, moving):
    again = cosim(fmu_paths, motion=WAVES, compensation="rigorous_sheave", duration=0.4)
    assert again.series.keys() == moving.series.keys()
    for name in moving.series:
        assert np.array_equal(again.series[name], moving.series[name]), name


def test_timing_and_overhead_are_reported(moving):
    t = moving.timing
    assert t["steps"] == 40 and 0.0 < t["model"] < t["wall"]
    assert 0.0 < t["overhead_share"] < 1.0
    parts = [t[f"model.{name}"] for name in ("ShipMotion", "HeaveCompensation", "TowCable")]
    assert min(parts) > 0.0 and sum(parts) == pytest.approx(t["model"], rel=1e-12)
    assert t["realtime_factor"] == pytest.approx(0.4 / t["wall"], rel=1e-12)


def test_command_line_writes_csv_summary_and_plot(fmu_paths, tmp_path):
    from towcable_fmu.cli import main

    out = tmp_path / "run"
    code = main(["cosim", "--scene", str(SMALL_SCENE), "--duration", "0.2", "--step", "0.02", "--output", str(out),
                 "--fmus", str(fmu_paths["TowCable"].parent), "--compensation", "simplified_sheave",
                 "--motion", "none", "--theta-nom", "0.5", "--quiet"])
    assert code == 0
    with open(out / "cosim.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    assert header[0] == "time" and len(rows) == 12
    expected = [n for name in contract.system()["components"] for n in contract.fmu(name).names("output")
                if not contract.signals()[n].diagnostic]
    assert header[1:] == expected
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["HeaveCompensation"]["theta_nom"] == 0.5
    assert summary["units"]["tension.top"] == "N"
    assert (out / "cosim.png").stat().st_size > 10_000


def test_command_line_reports_a_bad_scene(fmu_paths, tmp_path, capsys):
    from towcable_fmu.cli import main

    code = main(["cosim", "--scene", "no_such_scene", "--duration", "0.1", "--output", str(tmp_path),
                 "--fmus", str(fmu_paths["TowCable"].parent), "--quiet"])
    assert code == 2 and "no_such_scene" in capsys.readouterr().err


# ------------------------------------------------------------------ SSP
@pytest.fixture(scope="module")
def steady(fmu_paths):
    """A master run with a moving ship and no compensation: the set-point stays at phi_nom,
    so the order in which a tool exchanges it does not matter."""
    return cosim(fmu_paths, motion=WAVES, compensation="none", duration=0.4)


@pytest.fixture(scope="module")
def ssp_file(fmu_paths, steady, tmp_path_factory):
    from towcable_fmu.fmu_build.ssp import write_ssp

    return write_ssp(tmp_path_factory.mktemp("ssp") / "TowedCableSystem.ssp", fmu_paths, steady.parameters,
                     stop_time=0.4)


def test_ssd_is_schema_valid_and_follows_the_contract(ssp_file):
    from fmpy.ssp.ssd import find_components, get_connections, read_ssd

    ssd = read_ssd(str(ssp_file))  # validates against the SSP 1.0 schema
    assert [c.name for c in find_components(ssd.system)] == contract.system()["components"]
    assert len(get_connections(ssd.system)) == len(contract.connections())


def test_libcosim_runs_the_ssp_like_the_master(ssp_file, steady):
    """libcosim (OSP) exchanges values after all FMUs stepped (Jacobi): the ship and the
    cable see the same inputs as with the master (the set-point would reach the cable one
    step later, which does not show here: it is constant)."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.ERROR)
    execution = CosimExecution.from_ssp_file(str(ssp_file), step_size=int(round(0.01 * 1e9)))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    index = {s.name.decode(): s.index for s in execution.slave_infos()}
    refs = {name: {v.name.decode(): v.reference for v in execution.slave_variables(i)} for name, i in index.items()}
    cable_names = ["tension.top", "tension.towbody", "towbody.x", "towbody.z", "angle.top"]
    ship_names = ["ship.z", "ship.pitch", "ship.vz", "ship.az"]
    s = steady.series
    for k in range(1, len(s["time"])):
        execution.step(1)
        # libcosim counts time in integer nanoseconds: its communication points differ from
        # the master's t0 + k h in the last bits, and so do time-dependent results
        got = observer.last_real_values(index["TowCable"], [refs["TowCable"][n] for n in cable_names])
        np.testing.assert_allclose(got, [s[n][k] for n in cable_names], rtol=1e-9, atol=1e-9, err_msg=str(k))
        got = observer.last_real_values(index["ShipMotion"], [refs["ShipMotion"][n] for n in ship_names])
        np.testing.assert_allclose(got, [s[n][k] for n in ship_names], rtol=1e-12, atol=1e-12, err_msg=str(k))
    assert execution.status().current_time == int(round(0.4e9))


def test_fmpy_ssp_runs_the_ssp(ssp_file):
    """fmpy.ssp runs the file, within its limits (README, "SSP"): it applies neither the
    SSD's parameter bindings nor any String parameter, sets every connection to 0.0
    before the first step and exchanges nothing during initialisation. The FMUs hence run
    with their defaults (default sea, compensation none, scene full_scale), and the cable
    starts from zero inputs, so only the ship and the set-point are compared."""
    from fmpy.ssp.simulation import simulate_ssp
    from ship_motion import DEFAULT_SEA, motion_from_config

    result = simulate_ssp(str(ssp_file), stop_time=0.03, step_size=0.01)
    t = result["time"]
    assert len(t) == 3
    sea = motion_from_config(DEFAULT_SEA).evaluate_many(t + 0.01)  # rows hold the values after the step
    names = [n for n in contract.signals() if n.startswith("ship.")]
    got = np.stack([result[f"ShipMotion.{n}"] for n in names], axis=1)
    np.testing.assert_allclose(got, sea.reshape(len(t), 18), rtol=1e-12, atol=1e-15)  # fmpy adds up the time
    assert np.all(result["HeaveCompensation.winch.phi_sp"] == contract.fmu("HeaveCompensation")
                  .variable("phi_nom").start)
    assert np.all(np.isfinite(result["TowCable.tension.top"]))


def test_a_step_refused_mid_run_names_the_fmu_the_call_and_its_message(fmu_paths, tmp_path):
    """The compiled loop stops at the refused step: the error names the FMU, fmi2DoStep, the
    step's time and the FMU's own log message (a ship record that ends at 0.2 s)."""
    from towcable_fmu.cosim import CosimError

    record = tmp_path / "short.csv"
    rows = ["t [s],vx [m/s],vy [m/s],vz [m/s],roll [deg],pitch [deg],yaw [deg]"]
    rows += [f"{0.025 * i:.3f},0,0,{0.1 * i:.1f},0,0,0" for i in range(9)]
    record.write_text("\n".join(rows) + "\n")
    motion = f'type = "time_series"\nfile = "{record}"'
    with pytest.raises(CosimError) as info:
        cosim(fmu_paths, motion=motion, compensation="none", duration=0.5)
    text = str(info.value)
    assert text.startswith("ShipMotion: fmi2DoStep from t = 0.2 s by 0.01 s failed"), text
    assert "0.21" in text and "0.2" in text  # TimeRangeError names t and the record's range
