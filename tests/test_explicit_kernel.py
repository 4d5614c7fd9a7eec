"""The explicit path's lean force kernel (towcable_fmu/nodal/explicit_kernel.py) against the
implicit path's residual (towcable_fmu/nodal/assembly.cable_residual), an independent
computation of the same loads: on random configurations with water crossing the cable,
slack and taut elements, a partly submerged body with lift, a current, and every kind of
drag the kernel evaluates (the closed-form normal_tangential drag and the general one)."""

from __future__ import annotations

import numpy as np
import pytest

from towcable_fmu.nodal.assembly import cable_residual
from towcable_fmu.nodal.explicit import lumped_accelerations, node_masses
from towcable_fmu.nodal.explicit_kernel import lumped_forces, lumped_outputs
from towcable_fmu.nodal.integrators import output_values
from towcable_fmu.nodal.simulation import NodalSimulation

#: the snapping scene's cable (its law and drag: closed form), with a current, lift and a body of height
SNAPPING = {"cable.segments[0].elements": 12, "towbody.height": 0.3,
            "towbody.lift": {"area": 0.05, "coefficient": 0.4, "direction": [0.0, 0.6, -0.8], "axis": [1.0, 0.0, 0.0]},
            "water.current": {"type": "linear", "velocity": [0.3, -0.1, 0.0], "gradient": [0.05, 0.0, 0.0]}}
#: the formulation's law (the L/L0 factor) and the general drag: bare loading, C_D(Re), amplified, with compression
GENERAL = {**SNAPPING, "cable.segments[0].axial_law": "formulation", "cable.segments[0].loading": "bare",
           "cable.segments[0].drag_coefficient": None, "cable.segments[0].tangential_drag_coefficient": None,
           "cable.segments[0].drag_amplification": 1.4, "cable.segments[0].compression": True}


def _model(overrides: dict):
    return NodalSimulation.from_scene("snapping_cable_nodal", overrides).model


def _configuration(m, rng: np.random.Generator, top_z: float) -> tuple[np.ndarray, np.ndarray]:
    """Nodes hanging from (0, 0, top_z) with element strains from -2 % (slack) to +1 %, random
    lateral offsets, random velocities [m/s]."""
    ne = m.n_nodes - 1
    steps = m.L0 * (1.0 + rng.uniform(-0.02, 0.01, ne))
    dirs = np.column_stack([rng.normal(0.0, 0.15, ne), rng.normal(0.0, 0.15, ne), -np.ones(ne)])
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    nodes = np.vstack([[0.0, 0.0, top_z], [0.0, 0.0, top_z] + np.cumsum(steps[:, None] * dirs, axis=0)])
    return nodes.ravel(), rng.normal(0.0, 0.5, nodes.size)


@pytest.mark.parametrize("overrides", [SNAPPING, GENERAL], ids=["closed-form drag", "general drag"])
@pytest.mark.parametrize("place", ["submerged", "crossing", "body at surface"])
def test_forces_equal_minus_the_residual_at_zero_acceleration(overrides, place):
    m = _model(overrides)
    q, v = _configuration(m, np.random.default_rng(7), 3.0 if place == "crossing" else -1.0)
    if place == "body at surface":  # the cable dry, the body's centre 6 cm above the surface: 30 % submerged
        q[2::3] += 0.06 - q[-1]
    strain = np.linalg.norm(np.diff(q.reshape(-1, 3), axis=0), axis=1) / m.L0 - 1.0
    assert strain.min() < 0.0 < strain.max()  # slack and taut elements
    wet = q[2::3] < 0.0
    assert {"submerged": wet.all(), "crossing": wet.any() and not wet.all(), "body at surface": not wet.any()}[place]
    mass = node_masses(m)
    f = np.empty(q.size)
    added = np.zeros((m.n_nodes, 6))
    lumped_forces(m, mass, q, v, f, added, np.zeros(q.size))
    r = np.empty(q.size)
    cable_residual(m, q, v, np.zeros(q.size), 0.0, r)
    assert np.max(np.abs(f + r)) <= 1e-11 * np.max(np.abs(r))
    if place == "body at surface":
        assert added[-1, 0] == pytest.approx(0.3 * m.body.added_mass[0], rel=1e-12)


@pytest.mark.parametrize("overrides", [SNAPPING, GENERAL], ids=["closed-form drag", "general drag"])
def test_lumped_masses_are_the_row_sums_of_the_residuals_mass_matrices(overrides):
    """The residual's change when every node accelerates alike, e_j, is the row sums of its
    consistent and added mass matrices: the lumped 3x3 masses the explicit path inverts."""
    m = _model(overrides)
    q, v = _configuration(m, np.random.default_rng(3), 3.0)
    mass = node_masses(m)
    f, added, a = np.empty(q.size), np.zeros((m.n_nodes, 6)), np.zeros(q.size)
    lumped_accelerations(m, mass, q, v, f, added, a)
    r0, r1 = np.empty(q.size), np.empty(q.size)
    cable_residual(m, q, v, np.zeros(q.size), 0.0, r0)
    for j in range(3):
        unit = np.tile(np.eye(3)[j], m.n_nodes)
        cable_residual(m, q, v, unit, 0.0, r1)
        column = (r1 - r0).reshape(-1, 3)[1:]
        p = added[1:]
        matrix = np.stack([[p[:, 0], p[:, 3], p[:, 4]], [p[:, 3], p[:, 1], p[:, 5]],
                           [p[:, 4], p[:, 5], p[:, 2]]]).transpose(2, 0, 1) + mass[1:, None, None] * np.eye(3)
        assert np.allclose(matrix[:, :, j], column, rtol=1e-12, atol=1e-12 * np.max(np.abs(column)))
    # and the accelerations solve (M + M_a) a = F node by node
    for node in range(1, m.n_nodes):
        p = added[node]
        matrix = np.array([[p[0], p[3], p[4]], [p[3], p[1], p[5]], [p[4], p[5], p[2]]]) + mass[node] * np.eye(3)
        assert np.allclose(matrix @ a[3 * node:3 * node + 3], f[3 * node:3 * node + 3], rtol=1e-12,
                           atol=1e-12 * np.max(np.abs(f)))


@pytest.mark.parametrize("overrides", [SNAPPING, GENERAL], ids=["closed-form drag", "general drag"])
def test_outputs_equal_the_implicit_paths(overrides):
    m = _model(overrides)
    rng = np.random.default_rng(11)
    q, v = _configuration(m, rng, 3.0)
    x = rng.normal(0.0, 20.0, q.size)
    out, ref = np.zeros(10), np.zeros(14)
    lumped_outputs(m, node_masses(m), q, v, x, out)
    output_values(m, q, v, x, 0.0, ref)
    assert np.allclose(out, ref[:10], rtol=1e-11, atol=1e-11 * np.max(np.abs(ref[:4])))
