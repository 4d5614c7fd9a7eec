"""The FMU's step through a Stepper (towcable_fmu.ancf.stepper): the same numbers as the
integrator's own recording loop with the one-knot drive table, and a rollback point that
holds every field of the integrator state."""

from __future__ import annotations

import numpy as np

from ship_motion import DEFAULT_SEA, motion_from_config
from towcable_fmu.runtime import drive as drive_poly
from towcable_fmu.ancf import genalpha
from towcable_fmu.ancf.simulation import Simulation


def _pair():
    sims = []
    for _ in range(2):
        sim = Simulation.from_scene("full_scale")
        sim.initialize()
        sims.append(sim)
    return sims


def test_step_through_the_stepper_equals_the_recording_loop_with_a_drive_table():
    """Steps with the ship state of the default sea: Simulation.step (the Stepper, its drive
    filled in compiled code) and the recording loop given taylor_drive's table reach
    bit-identical states and outputs."""
    sea = motion_from_config(dict(DEFAULT_SEA))
    fast, table = _pair()
    setpoint = fast._setpoint
    for k in range(30):
        t = fast.time
        ship = sea.evaluate(t + 20.0)
        row = fast.step_row(0.01, ship, setpoint)
        table._integrate_to(t + 0.01, drive_poly.taylor_drive(t, ship, setpoint))
        np.testing.assert_array_equal(row, table._output_row())
        for a, b in zip(fast.state, table.state):
            np.testing.assert_array_equal(a, b)
    assert fast.outputs() == table.outputs()


def test_the_rollback_point_holds_every_field_of_the_state():
    """_snapshot copies each field of the IntegratorState (compiled, save_state); _restore
    puts back exactly those values after every field was changed."""
    sim, _ = _pair()
    sim.step(0.01, np.zeros((3, 6)))
    before = [x.copy() for x in sim.state]
    saved = sim._snapshot()
    assert len(saved[0]) == len(genalpha.IntegratorState._fields)
    for x in sim.state:
        x[...] = 7
    sim._restore(saved)
    for name, a, b in zip(genalpha.IntegratorState._fields, sim.state, before):
        np.testing.assert_array_equal(a, b, err_msg=name)


def test_the_predictor_extrapolates_only_in_steps_shorter_than_the_nominal_one():
    """Fixed steps: a step that ends at the caller's time before the nominal step does
    (a co-simulation's communication step), after two steps of its size; not at the run's
    own step, not after steps of another size, not in an adaptive run."""
    sim = Simulation.from_scene("full_scale")  # fixed steps of 0.05 s
    opt, st = sim.options, sim.state
    st.clock[genalpha.CLOCK_STEP] = 0.05
    st.h_hist[:] = 0.01
    assert genalpha._predicting(opt, st, 0.01)
    assert not genalpha._predicting(opt._replace(adaptive=True), st, 0.01)
    st.h_hist[:] = (0.01, 0.02)
    assert not genalpha._predicting(opt, st, 0.01)
    st.h_hist[:] = 0.05
    assert not genalpha._predicting(opt, st, 0.05)

