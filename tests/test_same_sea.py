"""One sea for ShipMotion and TowCable (issue 42 item 4): the master and the SSP file give
ShipMotion a ``motion.config`` and TowCable the same text as the item ``motion = {...}`` of
its ``overrides``, and the realisation each FMU builds from its own parameters, by its own
code path, is the same sea.

Ship side: ShipMotion's parameters read as the FMU reads them
(:func:`ship_motion.fmu.motion_table`), the ship's elevation
:meth:`~ship_motion.irregular.IrregularSea.wave_elevation` and, away from the ship's
reference point, the Airy sum of its components written out here. Cable side: TowCable's
scene built as the FMU builds it (:func:`towcable_fmu.fmu.scene_overrides`), its wave
table (:func:`towcable_fmu.hydro.waves.scene_waves`) and the kernel's elevation.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from towcable_fmu.common.errors import SceneError

SCENE = "full_scale_recovery_waves"
TIMES = np.linspace(25.0, 400.0, 751)  # after the 20 s ramp
#: points of the mean frame [m]: the ship's reference point (its mean CG), the sheave, off to port
POINTS = ((0.0, 0.0), (-36.8, 0.0), (10.0, 40.0))


def ship_elevation(ship_params: dict, x: float, y: float, times: np.ndarray) -> np.ndarray:
    """The free-surface elevation [m] of ShipMotion's sea (not ramped): the ship's own
    ``wave_elevation`` at its reference point, the Airy sum of its components elsewhere."""
    from ship_motion import motion_from_config
    from towcable_fmu.cosim.sea import ship_motion_table

    table, base = ship_motion_table(ship_params)
    sea = motion_from_config(table, key="motion", base_dir=base)
    if x == 0.0 and y == 0.0:
        return sea.wave_elevation(times)
    w = sea.waves
    heading = np.full(w.omega.size, sea.heading) if w.heading is None else w.heading
    k = w.omega ** 2 / 9.81  # deep water
    phase = (np.outer(times, sea.encounter_frequency) - k * (x * np.cos(heading) + y * np.sin(heading)) + w.phase)
    return np.cos(phase) @ w.amplitude


def cable_table(cable_params: dict):
    """TowCable's wave table, depth, stretching and ramp, from its parameters as the FMU builds its scene."""
    from towcable_fmu.fmu import scene_overrides
    from towcable_fmu.hydro.waves import scene_waves
    from towcable_fmu.scene import load_scene

    return scene_waves(load_scene(cable_params["scene"], scene_overrides(cable_params)))


def cable_elevation(table: np.ndarray, ramp: float, x: float, y: float, times: np.ndarray) -> np.ndarray:
    """The elevation [m] the cable's kernels see, without the ramp (times after it)."""
    from towcable_fmu.hydro.waves import elevation

    assert times.min() >= ramp
    return np.array([elevation(table, ramp, x, y, float(t))[0] for t in times])


def same_sea(ship_params: dict, cable_params: dict, table: np.ndarray | None = None) -> bool:
    """The two sides' elevations agree at every point and time (to round-off)."""
    waves, _, _, ramp = cable_table(cable_params)
    table = waves if table is None else table
    for x, y in POINTS:
        ship = ship_elevation(ship_params, x, y, TIMES)
        cable = cable_elevation(table, ramp, x, y, TIMES)
        if not np.allclose(cable, ship, rtol=0.0, atol=1e-9 * np.abs(ship).max()):
            return False
    return True


@pytest.fixture(scope="module")
def cosim_parameters(fmu_paths):
    """The parameters the master gives the three FMUs for the waves scene with another seed
    (a scene override: it must reach ShipMotion too), after a two-step run."""
    from towcable_fmu.cosim import CosimConfig, run_cosim

    config = CosimConfig(scene=SCENE, overrides=[("motion.seed", 7)], duration=0.02, step=0.01)
    return run_cosim(config, echo=False, fmus=fmu_paths).parameters


def test_master_gives_both_fmus_one_sea(cosim_parameters):
    ship, cable = cosim_parameters["ShipMotion"], cosim_parameters["TowCable"]
    assert cable["overrides"].endswith("; " + ship["motion.config"])
    assert ship["motion.config"].startswith("motion = {") and "seed = 7" in ship["motion.config"]
    assert same_sea(ship, cable)
    # the override reached the sea: seed 7, not the scene's 22
    assert not same_sea({"motion.config": SCENE}, cable)


def test_ssp_file_gives_both_fmus_one_sea(cosim_parameters):
    from towcable_fmu.fmu_build.ssp import NS, system_structure

    root = ET.fromstring(system_structure(cosim_parameters))
    values = {}
    for comp in root.iter(f"{{{NS['ssd']}}}Component"):
        for par in comp.iter(f"{{{NS['ssv']}}}Parameter"):
            if par.get("name") in ("motion.config", "overrides"):
                values[comp.get("name")] = par.find(f"{{{NS['ssv']}}}String").get("value")
    assert values["ShipMotion"] == cosim_parameters["ShipMotion"]["motion.config"]
    assert values["TowCable"].endswith("; " + values["ShipMotion"])
    assert same_sea({"motion.config": values["ShipMotion"]}, {**cosim_parameters["TowCable"],
                                                             "overrides": values["TowCable"]})


@pytest.mark.parametrize("key, value, named", [("seed", 8, "seed 8"), ("heading", 140.0, "heading 140 deg")])
def test_a_different_seed_or_heading_is_another_sea(cosim_parameters, key, value, named):
    """The comparison fails, and the master refuses the run naming both seas."""
    import tomllib

    from towcable_fmu.cosim import CosimConfig, run_cosim
    from towcable_fmu.scene.sea import motion_config_text

    ship, cable = cosim_parameters["ShipMotion"], cosim_parameters["TowCable"]
    table = tomllib.loads(ship["motion.config"])["motion"]
    other = {**cable, "overrides": motion_config_text({**table, key: value})}
    assert not same_sea(ship, other)
    config = CosimConfig(scene=SCENE, overrides=[("motion.seed", 7)], duration=0.02, step=0.01,
                         cable_parameters={"overrides": other["overrides"]})
    with pytest.raises(SceneError) as info:
        run_cosim(config, echo=False, fmus={})
    message = str(info.value)
    assert "TowCable overrides" in message and "seed 7" in message and named in message


def test_components_in_another_order_are_another_sea(cosim_parameters):
    """The cable's components with their phases in another order: the comparison fails."""
    from towcable_fmu.hydro.waves import PHASE

    ship, cable = cosim_parameters["ShipMotion"], cosim_parameters["TowCable"]
    table = cable_table(cable)[0].copy()
    assert same_sea(ship, cable, table)
    table[:, PHASE] = np.roll(table[:, PHASE], 1)
    assert not same_sea(ship, cable, table)


def test_individual_ship_parameters_become_the_shared_sea(fmu_paths):
    """ShipMotion given by its motion.* parameters: both FMUs get the TOML text of that sea."""
    from towcable_fmu.cosim import CosimConfig, run_cosim

    config = CosimConfig(scene=SCENE, duration=0.01, step=0.01, motion="none",
                         ship_parameters={"motion.type": "irregular", "motion.seed": 3, "motion.hs": 2.0})
    params = run_cosim(config, echo=False, fmus=fmu_paths).parameters
    ship, cable = params["ShipMotion"], params["TowCable"]
    assert cable["overrides"] == ship["motion.config"] and "hs = 2.0" in ship["motion.config"]
    assert same_sea({k: v for k, v in ship.items() if k != "motion.config"}, cable)


def test_waves_without_a_sea_are_refused():
    from towcable_fmu.cosim import CosimConfig, run_cosim

    with pytest.raises(SceneError, match="water.waves"):
        run_cosim(CosimConfig(scene=SCENE, duration=0.01, step=0.01, motion="none"), echo=False, fmus={})


def test_towcable_fmu_takes_its_sea_from_its_overrides(fmu_paths):
    """The TowCable FMU builds its waves from the 'motion = {...}' item of its overrides (its
    log names the sea) and refuses one without a sea for its waves, naming the key."""
    from fmpy.fmi1 import FMICallException

    from fmu_util import open_fmu, set_inputs, ship_inputs

    for config, ok in (('motion = {type = "irregular", seed = 5}', True), ('motion = {type = "none"}', False)):
        fmu = open_fmu(fmu_paths, "TowCable", {"scene": SCENE, "overrides": config})
        set_inputs(fmu, ship_inputs(np.zeros((3, 6))))
        mark = len(fmu.messages)
        if ok:
            fmu.exit_initialization()
            assert "waves in the water" in fmu.log_text(mark, 0) and "seed 5)" in fmu.log_text(mark, 0)
        else:
            with pytest.raises(FMICallException):
                fmu.fmu.exitInitializationMode()
            assert "water.waves" in fmu.log_text(mark)
        fmu.free()


@pytest.mark.parametrize("ship_seed, warned", [(5, False), (6, True)])
def test_towcable_fmu_warns_when_the_ship_moves_by_another_sea(fmu_paths, ship_seed, warned):
    """A host that gives ShipMotion another sea than TowCable: TowCable sees it in the ship
    inputs after the ramp and warns once, naming the input, both values and its sea; the
    ship of TowCable's own sea gives no warning."""
    from ship_motion import motion_from_config

    from fmu_util import open_fmu, set_inputs, ship_inputs

    ship = motion_from_config({"type": "irregular", "seed": ship_seed})
    fmu = open_fmu(fmu_paths, "TowCable", {"scene": SCENE, "overrides": 'motion = {type = "irregular", seed = 5}'})
    set_inputs(fmu, ship_inputs(ship.evaluate(0.0)))
    fmu.exit_initialization()
    mark = len(fmu.messages)
    t, dt = 0.0, 0.5
    while t < 21.0:  # the ramp ends at 20 s
        set_inputs(fmu, ship_inputs(ship.evaluate(t)))
        fmu.fmu.doStep(t, dt)
        t += dt
    warnings = [text for status, text in fmu.messages[mark:] if status == 1]
    fmu.free()
    if not warned:
        assert warnings == []
        return
    assert len(warnings) == 1
    assert "t = 20 s" in warnings[0] and "seed 5" in warnings[0] and "overrides" in warnings[0]
    assert "ship input ship." in warnings[0]
