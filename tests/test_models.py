"""The registry of model kinds (towcable_fmu.models) and what every kind's simulation
declares about its outputs: the names it lists are the columns it records, each with a unit."""

from __future__ import annotations

import pytest

from towcable_fmu.common import contract
from towcable_fmu.models import model_kind, simulation_from
from towcable_fmu.scene import load_scene


@pytest.mark.parametrize("scene, kind, duration", [
    ("hanging_cable", "ancf", 0.1),
    ("pulley_static", "ancf", 0.05),  # with a rigid load: its three outputs
    ("snapping_cable_nodal", "nodal_position", 0.05),
    ("tug_tow", "rigid_link", 0.5),
])
def test_output_names_are_the_recorded_columns_each_with_a_unit(scene, kind, duration):
    assert model_kind(load_scene(scene)) == kind
    sim = simulation_from(scene)
    names = sim.output_names
    series = sim.run(duration, interval=duration / 2)
    assert tuple(series) == tuple(names)
    assert names[0] == "time" and len(set(names)) == len(names)
    for name in names:
        unit = sim.unit_of(name)
        assert isinstance(unit, str) and unit
        if name in contract.signals():
            assert unit == contract.unit_of(name)
    assert sim.unit_of("tension.top") == "N"


@pytest.mark.parametrize("scene", ["hanging_cable", "snapping_cable_nodal", "tug_tow"])
def test_every_model_kind_keeps_the_protocol_and_its_state_round_trips_bit_identical(scene):
    """Same methods, the shared solver counters under one set of names, and a state saved
    through JSON that continues exactly as the original (same outputs to the last bit)."""
    import json

    import numpy as np

    from towcable_fmu.runtime.protocol import SOLVER_STATISTICS, CableSimulation

    sim = simulation_from(scene)
    assert isinstance(sim, CableSimulation)
    sim.initialize()
    ship = np.zeros((3, 6))
    sim.step(0.02, ship)
    stats = sim.statistics()
    assert set(SOLVER_STATISTICS) <= set(stats) and all(k.startswith("solver.") for k in stats)
    assert stats["solver.steps"] >= 1 and stats["solver.residual_evaluations"] >= stats["solver.steps"]
    saved = json.loads(json.dumps(sim.get_state()))
    twin = simulation_from(scene)
    twin.set_state(saved)
    assert twin.outputs() == sim.outputs()
    for _ in range(3):
        assert twin.step(0.02, ship) == sim.step(0.02, ship)
    def counters(s):  # the statics' figures describe how the state was found, not the state
        return {k: v for k, v in s.statistics().items() if not k.startswith("solver.statics")}

    assert counters(twin) == counters(sim)


@pytest.mark.parametrize("scene", ["pulley_static", "full_scale", "snapping_cable_nodal", "tug_tow"])
def test_a_caller_that_reads_fewer_outputs_gets_the_same_values_for_those(scene):
    """only_outputs (the TowCable FMU reads no energy): the names keep every output asked
    for and the outputs computed in Python, and each value kept is the full run's to the last
    bit; the ANCF model drops the energies it was told nobody reads."""
    import numpy as np

    full, lean = simulation_from(scene), simulation_from(scene)
    wanted = [name for name in full.names if not name.startswith("energy.")]
    lean.only_outputs(wanted)
    assert set(wanted) <= set(lean.names) <= set(full.names)
    if model_kind(full.scene) == "ancf":
        assert not {"energy.kinetic", "energy.strain", "energy.gravity"} & set(lean.names)
    full.initialize()
    lean.initialize()
    ship = np.zeros((3, 6))
    for _ in range(3):
        a, b = full.step_row(0.01, ship), lean.step_row(0.01, ship)
        assert dict(zip(lean.names, b.tolist())) == {n: x for n, x in zip(full.names, a.tolist()) if n in lean.names}
    assert {n: x for n, x in full.outputs().items() if n in lean.output_names} == lean.outputs()


class _SceneRead(AssertionError):
    pass


class _Untouchable:
    """Stands in for a simulation's scene after construction: any read fails the test."""

    def __getattr__(self, name):
        raise _SceneRead(f"the scene's '{name}' was read after the simulation was built")


@pytest.mark.parametrize("scene", ["hanging_cable", "flume", "full_scale", "pulley_static", "viv_sheave",
                                   "snapping_cable_nodal", "sea_trial_turn_rigid", "tug_tow"])
def test_the_scene_is_read_once_where_the_model_is_built(scene):
    """After construction every part has its own data: initialising (initial shape,
    statics, compensation, turbulence, wake oscillators), stepping and reading outputs
    never go back to the scene."""
    import numpy as np

    sim = simulation_from(scene)
    sim.scene = _Untouchable()
    out = sim.initialize()
    assert np.isfinite(out["tension.top"])
    series = sim.run(0.02, interval=0.01)
    assert np.all(np.isfinite(series["tension.top"]))
