"""The kernels an ANCF simulation runs, as jobs for :mod:`towcable_fmu.jit.parallel_compile`.

The arguments are those :class:`~towcable_fmu.ancf.simulation.Simulation` passes (the same
calls: initial accelerations, statics, the recording loop). The model's numba types do
not depend on the scene (every array is float64 or intp, C-ordered, the force terms the
same tuples whether enabled or not), so one reference scene's arguments compile the
kernels of every ANCF scene; tests/test_parallel_compile.py checks that a run after
:func:`~towcable_fmu.jit.parallel_compile.compile_kernels` compiles nothing.
"""

from __future__ import annotations

import functools

import numpy as np

from .forces import rigid_link
from .forces.contact import elements
from .measures import element_tension, point_on_cable
from .prescribed import apply_prescribed
from .system import iteration_matrix, residual
from .forces import contact_quadrature as cable_contact
from ..runtime.drive import evaluate_drive
from .forces import hydro_quadrature as cable_hydro
from .forces import wave_quadrature as wave_hydro
from ..numerics.kinematics import rotation_derivatives, rotation_matrix, ship_point_kinematics
from . import genalpha
from ..numerics.banded import band_lu, band_positive_pivots, band_solve
from .output_kernel import Recording, advance_recording, output_values
from ..jit.parallel_compile import Job
from ..hydro.rigid_body import tow_point_state
from .simulation import _ALL_OUTPUTS, _NO_DRIVE, Simulation
from .stepper import new_stepper, save_state, step_to
from .buffer_step import step_on_values

#: The scene whose model supplies the argument types.
REFERENCE_SCENE = "full_scale"


@functools.cache
def _reference() -> Simulation:
    return Simulation.from_scene(REFERENCE_SCENE)


def _contact_state() -> tuple:
    """The arguments every contact kernel starts with: the contact data, the elements and the state."""
    s = _reference()
    m, st = s.model, s.state
    return m.terms.contact, elements(m), st.q, st.v


def _contact_residual() -> tuple:
    return *_contact_state(), _reference().workspace.ship, np.intp(0), np.intp(1), _reference().workspace.r


def _contact_jacobian() -> tuple:
    ne = _reference().model.el_len.shape[0]
    return (*_contact_state(), _reference().workspace.ship, 0.0, 1.0, np.empty((ne, 12, 12)),
            np.empty(ne, dtype=np.bool_))


def _surface_summary() -> tuple:
    return *_contact_state(), _reference().workspace.ship, cable_contact.new_summary(0)


def _hydro_residual() -> tuple:
    s = _reference()
    m, st = s.model, s.state
    return m.water, m.terms.hydrodynamics, m.el_len, st.q, st.v, st.a, 0.0, np.intp(0), np.intp(1), s.workspace.r


def _hydro_jacobians() -> tuple:
    s = _reference()
    m, st = s.model, s.state
    ne = m.el_len.shape[0]
    return (m.water, m.terms.hydrodynamics, m.el_len, st.q, st.v, 0.0, 1.0, 0.0, 0.0, np.zeros((ne, 12, 12)),
            np.zeros(ne, dtype=np.bool_))


def _link_rows() -> tuple:
    m = _reference().model
    return m.terms.rigid_link, m, *np.zeros((3, 9)), 0.0, np.zeros(9)


def _tow_point_state() -> tuple:
    return _reference().model.terms.rigid_link.body, *np.zeros((6, 6))


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
    return (s.model, s.options, s.state, s.workspace, np.zeros(1), *_NO_DRIVE,
            Recording(s.output_scene, _ALL_OUTPUTS, np.zeros((1, _ALL_OUTPUTS.size)), True, True, 1.0))


def _new_stepper() -> tuple:
    s = _reference()
    return (s.model, s.options, s.state, s.workspace, s.output_scene, _ALL_OUTPUTS,
            np.zeros((1, _ALL_OUTPUTS.size)), np.zeros(1), np.zeros((1, 3, 7)), genalpha.new_state(s.model))


def _step_to() -> tuple:
    return new_stepper(*_new_stepper()), 1.0, 0.0, np.zeros((3, 6)), 0.0, 0.0


def _step_on_values() -> tuple:
    return new_stepper(*_new_stepper()), np.zeros(20), np.zeros(22, dtype=np.intp), 1.0, np.inf


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
    """The ANCF simulation's kernels, callers after callees; costs measured with both cores
    of the 2-core machine class compiling [s]. The force terms' kernels are jobs of their
    own so that the residual and the iteration matrix (on the longest path) wait for less."""
    return [
        Job("kinematics.rotation_derivatives", rotation_derivatives, lambda: (np.zeros((3, 6)),), 2.0),
        Job("hydro.add_residual", cable_hydro.add_residual, _hydro_residual, 3.8),
        Job("hydro.add_residual_in_waves", wave_hydro.add_residual, _hydro_residual, 3.8),
        Job("rigid_body.tow_point_state", tow_point_state, _tow_point_state, 1.1),
        Job("contact.add_residual", cable_contact.add_residual, _contact_residual, 3.7,
            ("kinematics.rotation_derivatives",)),
        Job("ancf.rigid_link_rows", rigid_link.link_rows, _link_rows, 3.2, ("rigid_body.tow_point_state",)),
        Job("ancf.residual", residual, _residual, 8.1,
            ("contact.add_residual", "ancf.rigid_link_rows", "hydro.add_residual", "hydro.add_residual_in_waves")),
        Job("contact.add_jacobian", cable_contact.add_jacobian, _contact_jacobian, 3.1,
            ("kinematics.rotation_derivatives",)),
        Job("hydro.add_jacobians", cable_hydro.add_jacobians, _hydro_jacobians, 1.8),
        Job("hydro.add_jacobians_in_waves", wave_hydro.add_jacobians, _hydro_jacobians, 1.8),
        Job("ancf.iteration_matrix", iteration_matrix, _iteration_matrix, 8.0,
            ("contact.add_jacobian", "hydro.add_jacobians", "hydro.add_jacobians_in_waves", "ancf.rigid_link_rows")),
        Job("contact.surface_summary", cable_contact.surface_summary, _surface_summary, 2.8,
            ("kinematics.rotation_derivatives",)),
        Job("ancf.band_lu", band_lu, lambda: _band(False), 0.3),
        Job("ancf.band_solve", band_solve, lambda: _band(True), 0.2),
        Job("ancf.evaluate_drive", evaluate_drive, _evaluate_drive, 0.9),
        Job("ancf.apply_prescribed", apply_prescribed, _apply_prescribed, 1.6),
        Job("ancf.point_on_cable", point_on_cable, lambda: (_reference().model, _reference().state.q, 0, 0.0), 0.9),
        Job("ancf.element_tension", element_tension, lambda: (_reference().model, _reference().state.q, 0), 0.9),
        Job("ancf.output_values", output_values, _output_values, 9.0,
            ("ancf.residual", "contact.surface_summary", "rigid_body.tow_point_state", "ancf.point_on_cable",
             "ancf.element_tension")),
        Job("ancf.advance", genalpha.advance, _advance, 7.8,
            ("ancf.residual", "ancf.iteration_matrix", "ancf.band_lu", "ancf.band_solve", "ancf.evaluate_drive",
             "ancf.apply_prescribed")),
        Job("ancf.band_positive_pivots", band_positive_pivots, _positive_pivots, 0.2),
        Job("kinematics.rotation_matrix", rotation_matrix, lambda: (0.0, 0.0, 0.0), 0.2),
        Job("kinematics.ship_point_kinematics", ship_point_kinematics,  # a compensation's set-point
            lambda: (np.zeros((3, 6)), np.zeros(3)), 0.8),
        Job("ancf.advance_recording", advance_recording, _advance_recording, 6.8,
            ("ancf.advance", "ancf.output_values")),
        Job("stepper.new_stepper", new_stepper, _new_stepper, 1.5),
        Job("stepper.step_to", step_to, _step_to, 2.0, ("stepper.new_stepper", "ancf.advance_recording")),
        Job("stepper.save_state", save_state, lambda: (new_stepper(*_new_stepper()),), 1.0, ("stepper.new_stepper",)),
        Job("buffer_step.step_on_values", step_on_values, _step_on_values, 2.0,
            ("stepper.step_to", "stepper.save_state")),
    ]
