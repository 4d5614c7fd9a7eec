"""The FMU's step on its buffer of values in one compiled call (towcable_fmu.ancf.buffer_step),
and as the C function the FMU's loader calls (towcable_fmu.ancf.native_step): the same
states and outputs as Simulation.step_row, and what step_row refuses left to it with
nothing changed."""

from __future__ import annotations

import ctypes

import numpy as np

from ship_motion import DEFAULT_SEA, motion_from_config
from towcable_fmu.ancf.simulation import Simulation


def _pair() -> tuple[Simulation, Simulation]:
    """Two full_scale simulations initialised alike."""
    first, second = Simulation.from_scene("full_scale"), Simulation.from_scene("full_scale")
    first.initialize()
    second.initialize()
    return first, second


def _buffer(sim: Simulation) -> tuple[np.ndarray, np.ndarray]:
    """A buffer laid out in reverse (outputs first, then the inputs) and its plan."""
    n = len(sim.names)
    values = np.zeros(n + 20)
    plan = sim.buffer_plan(np.arange(n, n + 20)[::-1], np.arange(n)[::-1], np.arange(n), np.zeros(n, dtype=bool))
    return values, plan


def _put_inputs(values: np.ndarray, ship: np.ndarray, setpoint: tuple[float, float]) -> None:
    n = values.size - 20
    values[n:][::-1] = np.concatenate([ship.ravel(), setpoint])


def _same_state(a: Simulation, b: Simulation) -> None:
    """The same integrator state and the same state beyond it (the statics' wall time aside)."""
    for x, y in zip(a.state, b.state):
        np.testing.assert_array_equal(x, y)
    saved = [s.get_state() for s in (a, b)]
    for state in saved:
        del state["statics"]["solver.statics_wall_time"]
    assert saved[0] == saved[1]


def _compare_with_step_row(rows: Simulation, other: Simulation, values: np.ndarray, step, taken_over=None) -> None:
    """30 steps in the default sea: ``rows`` with step_row, ``other`` with ``step(t, h)`` (True
    if made) on ``values``; bit-identical integrator states (without ``taken_over``, the whole
    states) and step_row's outputs in the buffer at every step; then (after ``taken_over()``) the same whole state, set-point and
    outputs."""
    sea = motion_from_config(dict(DEFAULT_SEA))
    setpoint = (rows._setpoint[0], 0.05)
    for k in range(30):
        t = rows.time
        ship = sea.evaluate(t + 20.0)
        row = rows.step_row((t + 0.01) - t, ship, setpoint)
        _put_inputs(values, ship, setpoint)
        assert step(t, 0.01)
        np.testing.assert_array_equal(values[:row.size][::-1], row)
        if taken_over is None:
            _same_state(rows, other)
        for x, y in zip(rows.state, other.state):
            np.testing.assert_array_equal(x, y)
    if taken_over is not None:
        taken_over()
    _same_state(rows, other)
    assert other._setpoint == setpoint
    assert other.outputs() == rows.outputs()


def test_step_on_values_equals_step_row():
    """The compiled step on the buffer and step_row reach bit-identical states, and the
    buffer holds step_row's outputs."""
    rows, buffered = _pair()
    values, plan = _buffer(buffered)
    _compare_with_step_row(rows, buffered, values, lambda t, h: buffered.step_on_values(t + h, values, plan))


def _refusal_setup() -> tuple[Simulation, Simulation, np.ndarray, np.ndarray]:
    """Two simulations alike, and a buffer (with its plan) of the first holding the default
    sea's ship state at t = 0, the set-point and outputs 7.0."""
    sim, reference = _pair()
    values, plan = _buffer(sim)
    _put_inputs(values, motion_from_config(dict(DEFAULT_SEA)).evaluate(0.0), sim._setpoint)
    values[:len(sim.names)] = 7.0
    return sim, reference, values, plan


def test_refused_steps_change_nothing():
    """A NaN input, a step that does not move forward and a step whose payout exceeds the
    drum are not made: False, the state and the buffer's outputs as before."""
    sim, reference, values, plan = _refusal_setup()
    before = values.copy()
    bad = values.copy()
    bad[-5] = np.nan
    assert not sim.step_on_values(0.01, bad, plan)
    assert not sim.step_on_values(sim.time, values, plan)
    sim._payout_limit = reference._payout_limit = sim._payout() - 1.0  # every step goes beyond
    assert not sim.step_on_values(0.01, values, plan)
    np.testing.assert_array_equal(values, before)
    _same_state(sim, reference)


_C_STEP = ctypes.CFUNCTYPE(ctypes.c_int32, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_double, ctypes.c_double)


def _native(sim: Simulation, values: np.ndarray, plan: np.ndarray):
    """The C step of ``sim`` on ``values`` called as the loader calls it: (step(t, h) -> 0 if
    made, its data)."""
    address, data = sim.native_step(values.size, plan)
    function = _C_STEP(address)
    return (lambda t, h: function(values.ctypes.data, data.ctypes.data, t, h)), data


def test_the_c_step_equals_step_row():
    """The C function of the loader layer: bit-identical states and step_row's outputs in
    the buffer; the set-point and the outputs of its last step are the Simulation's once
    taken over."""
    rows, native = _pair()
    values, plan = _buffer(native)
    step, data = _native(native, values, plan)
    _compare_with_step_row(rows, native, values, lambda t, h: step(t, h) == 0,
                           lambda: native.native_steps_made(data))


def test_the_c_step_refuses_what_step_row_must_report():
    """A NaN input and a step that does not move forward: not made, nothing changed; a step
    whose payout exceeds the drum: not made, and the state as before once taken over."""
    sim, reference, values, plan = _refusal_setup()
    before = values.copy()
    values[-5] = np.nan
    step, data = _native(sim, values, plan)
    assert step(0.0, 0.01) != 0
    values[-5] = before[-5]
    assert step(0.0, 0.0) != 0
    np.testing.assert_array_equal(values, before)
    _same_state(sim, reference)
    sim._payout_limit = reference._payout_limit = sim._payout() - 1.0  # every step goes beyond
    step, data = _native(sim, values, plan)
    assert step(0.0, 0.01) != 0
    sim.native_steps_made(data)
    np.testing.assert_array_equal(values, before)
    _same_state(sim, reference)


def test_a_spool_scene_steps_in_python_and_remeshes_at_every_communication_step():
    """A spool scene (its fed element's mesh is state the FMU saves) has no compiled step on
    the buffer: the FMU steps with step_row, whose steps, half the scene's time step here
    (each one solver step that reaches the caller's time), split the fed element when it
    leaves its band. Paid out 3 m by the winch set-point: the fed element is within its band
    after every step, and the mesh is split once."""
    from pathlib import Path

    from towcable_fmu.ancf.feed import MERGE_FACTOR, SPLIT_FACTOR

    scene = str(Path(__file__).parent / "data" / "spool_hanging.toml")
    sim = Simulation.from_scene(scene)
    sim.initialize(0.0, np.zeros((3, 6)))
    n = len(sim.names)
    assert sim.buffer_plan(np.arange(n, n + 20), np.arange(n), np.arange(n), np.zeros(n, dtype=bool)) is None
    feed, radius, phi0 = sim.model.terms.feed, 0.3 + 0.005, sim._setpoint[0]
    h = 0.5 * sim.options.h_max
    for k in range(int(round(7.0 / h))):
        t = (k + 1) * h
        s = min(max((t - 0.5) / 6.0, 0.0), 1.0)   # 3 m paid out from 0.5 s to 6.5 s
        sim.step_row(t - sim.time, np.zeros((3, 6)), (phi0 - 3.0 * s / radius, -(0.5 / radius if 0.0 < s < 1.0 else 0.0)))
        assert MERGE_FACTOR * feed.length_nom < sim.model.el_len[feed.element] < SPLIT_FACTOR * feed.length_nom
    assert sim.mesh.n_elements == 5
