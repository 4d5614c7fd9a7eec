"""Outputs between step ends come from the integrator's interpolant (issue: sampling never
drives the integrator): the output interval changes neither the steps nor the accuracy."""

from __future__ import annotations

import numpy as np
import pytest

from towcable_fmu.models import simulation_from

H = 0.01  #: fixed step [s] of the runs compared
DURATION = 4.0


def run(time_step: float, interval: float) -> tuple[dict[str, np.ndarray], dict[str, float], float]:
    sim = simulation_from("hanging_cable", {"solver.time_step": time_step})
    series = sim.run(DURATION, interval=interval)
    return series, sim.statistics(), sim.time


@pytest.fixture(scope="module")
def reference():
    """A run with an eight times smaller step, sampled at every one of its steps."""
    return run(H / 8.0, H / 8.0)[0]


def _errors(series: dict[str, np.ndarray], reference: dict[str, np.ndarray], key: str) -> np.ndarray:
    index = np.searchsorted(np.round(reference["time"], 9), np.round(series["time"], 9))
    assert np.allclose(reference["time"][index], series["time"], rtol=0.0, atol=1e-9)
    return series[key] - reference[key][index]


def test_the_output_interval_does_not_change_the_steps():
    runs = {interval: run(H, interval) for interval in (H, 0.75 * H, 0.25 * H, 3.7 * H)}
    for interval, (series, stats, t_end) in runs.items():
        # one step of H after another, whatever the samples; the run still ends on its last sample
        assert stats["solver.steps"] == round(DURATION / H), interval
        assert stats["solver.jacobian_factorisations"] == runs[H][1]["solver.jacobian_factorisations"]
        assert t_end == pytest.approx(DURATION, abs=1e-12) and series["time"][-1] == pytest.approx(DURATION)


@pytest.mark.parametrize("key", ["tension.top", "towbody.z"])
def test_samples_inside_a_step_are_as_accurate_as_the_step_ends(reference, key):
    """Against the converged run: the samples at 0.75 h (mostly inside steps) err no more
    than those at the step ends (the cubic Hermite interpolant's O(h^4) is below the
    scheme's O(h^2))."""
    at_ends = _errors(run(H, H)[0], reference, key)
    inside = _errors(run(H, 0.75 * H)[0], reference, key)
    rms = lambda e: float(np.sqrt(np.mean(e ** 2)))  # noqa: E731
    assert rms(at_ends) > 0.0
    assert rms(inside) <= 1.1 * rms(at_ends)
    assert np.max(np.abs(inside)) <= 1.25 * np.max(np.abs(at_ends))
