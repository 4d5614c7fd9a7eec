"""The registry of model kinds (towcable_fmu.models) and what every kind's simulation
declares about its outputs: the names it lists are the columns it records, each with a unit."""

from __future__ import annotations

import pytest

from towcable_fmu import contract
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
