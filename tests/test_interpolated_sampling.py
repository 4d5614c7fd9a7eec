"""Outputs between step ends come from the integrator's interpolant (issue: sampling never
drives the integrator): the output interval changes neither the steps nor the accuracy."""

from __future__ import annotations

import numpy as np
import pytest

from towcable_fmu.models import simulation_from

H = 0.01  #: fixed step [s] of the runs compared
DURATION = 4.0


#: The hanging cable on both cable formulations.
FORMULATIONS = ("ancf", "nodal_position")


def run(formulation: str, time_step: float, interval: float) -> tuple[dict[str, np.ndarray], dict[str, float], float]:
    sim = simulation_from("hanging_cable", {"solver.time_step": time_step, "cable.formulation": formulation})
    series = sim.run(DURATION, interval=interval)
    return series, sim.statistics(), sim.time


@pytest.fixture(scope="module", params=FORMULATIONS)
def reference(request):
    """The formulation, and its run with an eight times smaller step, sampled at every one
    of its steps."""
    return request.param, run(request.param, H / 8.0, H / 8.0)[0]


def _errors(series: dict[str, np.ndarray], reference: dict[str, np.ndarray], key: str) -> np.ndarray:
    index = np.searchsorted(np.round(reference["time"], 9), np.round(series["time"], 9))
    assert np.allclose(reference["time"][index], series["time"], rtol=0.0, atol=1e-9)
    return series[key] - reference[key][index]


@pytest.mark.parametrize("formulation", FORMULATIONS)
def test_the_output_interval_does_not_change_the_steps(formulation):
    runs = {interval: run(formulation, H, interval) for interval in (H, 0.75 * H, 0.25 * H, 3.7 * H)}
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
    formulation, converged = reference
    at_ends = _errors(run(formulation, H, H)[0], converged, key)
    inside = _errors(run(formulation, H, 0.75 * H)[0], converged, key)
    rms = lambda e: float(np.sqrt(np.mean(e ** 2)))  # noqa: E731
    assert rms(at_ends) > 0.0
    assert rms(inside) <= 1.1 * rms(at_ends)
    assert np.max(np.abs(inside)) <= 1.25 * np.max(np.abs(at_ends))


def test_the_nodal_interpolant_reproduces_a_cubic_motion_exactly():
    """Coordinates moving as cubics in time and accelerations linearly: the state the
    nodal model's interpolant gives inside a step is exact (to round-off), away from the
    top node (which follows the ship)."""
    from towcable_fmu.nodal.integrators import _interpolate, new_interpolant

    sim = simulation_from("hanging_cable", {"cable.formulation": "nodal_position"})
    n = sim.state.q.size
    c = np.random.default_rng(7).normal(size=(6, n))
    q = lambda t: c[0] + c[1] * t + c[2] * t ** 2 + c[3] * t ** 3  # noqa: E731
    v = lambda t: c[1] + 2.0 * c[2] * t + 3.0 * c[3] * t ** 2  # noqa: E731
    x = lambda t: c[4] + c[5] * t  # noqa: E731
    t0, t1 = 0.3, 0.7
    ip = new_interpolant(n)
    ip.start[:] = q(t0), v(t0), x(t0)
    ip.t0[0] = t0
    for t in (t0, 0.35, 0.5, 0.69, t1):
        _interpolate(sim.model, ip, q(t1), v(t1), x(t1), t1, t, np.zeros(1), np.zeros((1, 3, 7)))
        for row, exact in zip(ip.state, (q(t), v(t), x(t))):
            assert np.allclose(row[3:], exact[3:], rtol=0.0, atol=1e-12 * np.abs(c).max()), t
