"""The kernels a nodal-position simulation runs, as jobs for :mod:`towcable_fmu.jit.parallel_compile`.

The arguments have the types :class:`~towcable_fmu.nodal.simulation.NodalSimulation`
passes (sizes do not matter: the jobs compile, they do not run). The nodal model's numba
types do not depend on the scene (the rigid body and the water are the same tuples
whether enabled or not), so one reference scene compiles the kernels of every nodal
scene; tests/test_parallel_compile.py checks both.
"""

from __future__ import annotations

import functools
from typing import Callable

import numpy as np

from ..jit.parallel_compile import Job
from ..scene import load_scene
from .assembly import cable_residual, expand, iteration_matrix, residual
from .explicit import leapfrog_recording, lumped_accelerations, node_masses
from .integrators import accelerations, advance_recording, genalpha_step, output_values, prescribe_top, rk4_step
from .simulation import NodalSimulation
from .statics import solve_statics

#: The scene whose model supplies the argument types (its rigid body makes every branch typed).
REFERENCE_SCENE = "sea_trial_turn_rigid"
#: A drive table (times, (knots, 3, 7) coefficients), as drive.knot_drive returns.
_DRIVE = (np.zeros(1), np.zeros((1, 3, 7)))


@functools.cache
def _reference() -> NodalSimulation:
    return NodalSimulation(load_scene(REFERENCE_SCENE))


def _state_call(*tail) -> Callable[[], tuple]:
    """Arguments ``(model, q, v, a, t, *tail)`` (``tail`` may name ``"q"`` for a vector)."""
    def arguments() -> tuple:
        s = _reference()
        st = s.state
        return (s.model, st.q, st.v, st.x, 0.0) + tuple(st.q if isinstance(x, str) else x for x in tail)
    return arguments


def _iteration_matrix() -> tuple:
    return _state_call(1.0, 0.0, 0.0, 1.0, "q", np.zeros((1, 1)), np.zeros((4, 1)))()


def _prescribe_top() -> tuple:
    s = _reference()
    return s.model, *_DRIVE, 0.0, s.state.q, s.state.v, s.state.x


def _expand() -> tuple:
    st = _reference().state
    return _reference().model, st.q, st.v, st.x, st.q, st.v, st.x


def _genalpha_step() -> tuple:
    s = _reference()
    return s.model, s.options, 0.1, 0.0, *_DRIVE, s.state, np.zeros((4, 1))


def _rk4_step() -> tuple:
    s = _reference()
    return s.model, 0.1, 0.0, *_DRIVE, s.state.q, s.state.v, np.zeros((4, 1)), s.state.stats


def _solve_statics() -> tuple:
    s = _reference()
    return s.model, s.state.q, 0.0, 1e-8, 100


def _advance_recording() -> tuple:
    s = _reference()
    return s.model, s.options, s.state, np.zeros(1), *_DRIVE, np.zeros((1, 1)), s._interpolant, True, 1.0


def _lumped_accelerations() -> tuple:
    s = _reference()
    st = s.state
    return s.model, node_masses(s.model), st.q, st.v, st.q, np.zeros((1, 6)), st.x


def _leapfrog_recording() -> tuple:
    s = _reference()
    return (s.model, node_masses(s.model), s.options, s.state, np.zeros(1), *_DRIVE, np.zeros((1, 1)),
            s._interpolant, True, 1.0)


def kernel_jobs() -> list[Job]:
    """The nodal simulation's kernels, callers after callees; costs measured on the 2-core
    machine class with both cores compiling [s]."""
    core = ("nodal.residual", "nodal.iteration_matrix")
    return [
        Job("nodal.residual", residual, _state_call("q"), 20.0),
        Job("nodal.iteration_matrix", iteration_matrix, _iteration_matrix, 18.5),
        Job("nodal.output_values", output_values, _state_call(np.zeros(1)), 4.5),
        Job("nodal.prescribe_top", prescribe_top, _prescribe_top, 5.5),
        Job("nodal.cable_residual", cable_residual, _state_call("q"), 3.0),
        Job("nodal.expand", expand, _expand, 1.0),
        Job("nodal.genalpha_step", genalpha_step, _genalpha_step, 5.5, core + ("nodal.prescribe_top",)),
        Job("nodal.accelerations", accelerations, lambda: _state_call(_reference().state.stats)(), 2.0, core),
        Job("nodal.rk4_step", rk4_step, _rk4_step, 3.5, ("nodal.accelerations", "nodal.prescribe_top")),
        Job("nodal.solve_statics", solve_statics, _solve_statics, 2.5, core),
        Job("nodal.advance_recording", advance_recording, _advance_recording, 4.5,
            ("nodal.genalpha_step", "nodal.rk4_step", "nodal.output_values")),
        Job("nodal.lumped_accelerations", lumped_accelerations, _lumped_accelerations, 3.0),
        Job("nodal.leapfrog_recording", leapfrog_recording, _leapfrog_recording, 4.0,
            ("nodal.lumped_accelerations", "nodal.prescribe_top", "nodal.output_values")),
    ]
