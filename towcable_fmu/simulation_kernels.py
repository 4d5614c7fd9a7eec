"""The kernels an ANCF simulation runs, as jobs for :mod:`towcable_fmu.parallel_compile`.

The arguments are those :class:`~towcable_fmu.simulation.Simulation` passes (the same
calls: initial accelerations, statics, the recording loop). The model's numba types do
not depend on the scene (every array is float64 or intp, C-ordered, the force terms the
same tuples whether enabled or not), so one reference scene's arguments compile the
kernels of every ANCF scene; tests/test_parallel_compile.py checks that a run after
:func:`~towcable_fmu.parallel_compile.compile_kernels` compiles nothing.
"""

from __future__ import annotations

import functools

import numpy as np

from .ancf.prescribed import apply_prescribed
from .ancf.system import iteration_matrix, residual
from .drive import evaluate_drive
from .kinematics import rotation_matrix, ship_point_kinematics
from .numerics import genalpha
from .numerics.banded import band_lu, band_positive_pivots, band_solve
from .output_kernel import advance_recording, output_values
from .parallel_compile import Job
from .simulation import _ALL_OUTPUTS, _NO_DRIVE, Simulation

#: The scene whose model supplies the argument types.
REFERENCE_SCENE = "full_scale"


@functools.cache
def _reference() -> Simulation:
    return Simulation.from_scene(REFERENCE_SCENE)


def _residual() -> tuple:
    s = _reference()
    return s.model, s.state.q, s.state.v, s.state.a, 0.0, s.workspace.ship, s.workspace.r


def _iteration_matrix() -> tuple:
    s = _reference()
    return s.model, s.state.q, s.state.v, 0.0, s.workspace.ship, 1.0, 0.0, 0.0, s.workspace.ab


def _output_values() -> tuple:
    s = _reference()
    st = s.state
    return (s.model, st.q, st.v, st.a, st.phi, 0.0, s.workspace.ship, s.output_scene, s.workspace.r)


def _advance() -> tuple:
    s = _reference()
    return s.model, s.options, s.state, s.workspace, 1.0, *_NO_DRIVE, True


def _advance_recording() -> tuple:
    s = _reference()
    return (s.model, s.options, s.state, s.workspace, np.zeros(1), *_NO_DRIVE, s.output_scene,
            _ALL_OUTPUTS, np.zeros((1, _ALL_OUTPUTS.size)), True, True, 1.0)


def _band(with_rhs: bool) -> tuple:
    s = _reference()
    ws, m = s.workspace, s.model
    return (ws.ab, m.free_dofs.size, m.kl, m.ku, ws.ipiv) + ((ws.dx,) if with_rhs else ())


def _positive_pivots() -> tuple:
    s = _reference()
    ws, m = s.workspace, s.model
    return ws.ab, m.free_dofs.size, m.kl, m.ku, np.zeros_like(ws.ab)


def _apply_prescribed() -> tuple:
    s = _reference()
    m, st, ws = s.model, s.state, s.workspace
    return m.att_index, m.att_kind, m.att_vec, m.att_radius, ws.ship, st.phi, st.q, st.v, st.a


def _evaluate_drive() -> tuple:
    return *_NO_DRIVE, 0.0, _reference().workspace.ship


def kernel_jobs() -> list[Job]:
    """The ANCF simulation's kernels, callers after callees; costs measured on one core
    of the 2-core machine class [s]."""
    return [
        Job("ancf.residual", residual, _residual, 27.0),
        Job("ancf.iteration_matrix", iteration_matrix, _iteration_matrix, 19.0),
        Job("ancf.output_values", output_values, _output_values, 25.0),
        Job("ancf.advance", genalpha.advance, _advance, 11.0, ("ancf.residual", "ancf.iteration_matrix")),
        Job("ancf.band_lu", band_lu, lambda: _band(False), 0.3, ("ancf.advance",)),
        Job("ancf.band_solve", band_solve, lambda: _band(True), 0.2, ("ancf.advance",)),
        Job("ancf.evaluate_drive", evaluate_drive, _evaluate_drive, 0.9, ("ancf.advance",)),
        Job("ancf.apply_prescribed", apply_prescribed, _apply_prescribed, 1.5, ("ancf.advance",)),
        Job("ancf.band_positive_pivots", band_positive_pivots, _positive_pivots, 1.7),
        Job("kinematics.rotation_matrix", rotation_matrix, lambda: (0.0, 0.0, 0.0), 0.2),
        Job("kinematics.ship_point_kinematics", ship_point_kinematics,  # a compensation's set-point
            lambda: (np.zeros((3, 6)), np.zeros(3)), 6.0),
        Job("ancf.advance_recording", advance_recording, _advance_recording, 9.0,
            ("ancf.advance", "ancf.output_values")),
    ]
