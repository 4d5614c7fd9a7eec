"""An element split during a run (towcable_fmu/ancf/remesh.py, Simulation.split_element):
the split cubic is the old one, and a running cable does not notice the split."""

from __future__ import annotations

import numpy as np
import pytest

from towcable_fmu.ancf import element
from towcable_fmu.ancf.mesh import build_mesh
from towcable_fmu.ancf.model import Mesh
from towcable_fmu.ancf.remesh import (
    merge_coordinates,
    merge_defect,
    merge_mesh,
    split_coordinates,
    split_mesh,
)
from towcable_fmu.common.errors import SceneError
from towcable_fmu.ancf.simulation import Simulation


def _field(x: np.ndarray, mesh: Mesh, arc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position and slope of the cable ``x`` at unstretched arc lengths ``arc`` [m]."""
    e = np.clip(np.searchsorted(mesh.node_arc, arc, side="right") - 1, 0, mesh.n_elements - 1)
    r, rp = np.empty((arc.size, 3)), np.empty((arc.size, 3))
    for k, (el, p) in enumerate(zip(e, arc)):
        length = mesh.lengths[el]
        xi = (p - mesh.node_arc[el]) / length
        nodal = x[6 * el: 6 * el + 12].reshape(4, 3)
        r[k] = element.shape_functions(xi, length) @ nodal
        rp[k] = element.shape_derivatives(xi, length) @ nodal
    return r, rp


@pytest.mark.parametrize("e, xi", [(0, 0.5), (2, 0.137), (3, 0.9)])
def test_split_reproduces_the_cubic_everywhere(e, xi):
    rng = np.random.default_rng(7)
    mesh = Mesh(np.array([0.7, 1.3, 2.0, 0.4]), np.array([0, 0, 1, 1]), np.array([0.0, 0.7, 2.0, 4.0, 4.4]))
    x = np.concatenate([rng.normal(size=6 * mesh.n_nodes), [1.5, -2.0, 0.25]])  # a load's 3 coordinates follow
    fine = split_mesh(mesh, e, xi)
    y = split_coordinates(x, mesh, e, xi)
    assert fine.n_elements == mesh.n_elements + 1 and y.size == x.size + 6
    np.testing.assert_allclose(fine.lengths[e:e + 2], [xi * mesh.lengths[e], (1 - xi) * mesh.lengths[e]])
    np.testing.assert_allclose(fine.node_arc, np.concatenate([[0.0], np.cumsum(fine.lengths)]))
    assert fine.segment_of_element[e] == fine.segment_of_element[e + 1] == mesh.segment_of_element[e]
    arc = np.linspace(0.0, mesh.node_arc[-1], 101)
    for old, new in zip(_field(x, mesh, arc), _field(y, fine, arc)):
        np.testing.assert_allclose(new, old, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(y[-3:], x[-3:])


@pytest.mark.parametrize("e, xi", [(-1, 0.5), (4, 0.5), (1, 0.0), (1, 1.0), (1, float("nan"))])
def test_split_outside_the_mesh_is_refused(e, xi):
    mesh = build_mesh([type("S", (), {"length": 4.0, "elements": 4})()])
    with pytest.raises(ValueError, match="element|xi"):
        split_mesh(mesh, e, xi)


def _twins_in_heave() -> tuple[Simulation, Simulation]:
    """Two full_scale runs at 5 s of a regular 1 m heave, uncompensated."""
    overrides = {"motion.type": "regular", "motion.heave.amplitude": 1.0, "motion.heave.period": 6.0,
                 "compensation.algorithm": "none"}
    twins = Simulation.from_scene("full_scale", overrides), Simulation.from_scene("full_scale", overrides)
    for sim in twins:
        sim.run(5.0)
    return twins


def test_a_running_cable_does_not_notice_a_split():
    """full_scale at 5 s (sheave contact, drag, towed body): split an element of the
    free span and one in contact with the sheave. What depends on the cubic alone
    (kinetic, gravity energy, the body's state) is unchanged to round-off; the strain
    energy changes by the decoupled strain's interpolation error of the split elements
    (measured 8e-6 of it); the next 5 s agree with the unsplit run within the
    discretisation (strain, contact and drag now on the finer elements): sheave tension
    within 0.1 % of its range RMS (measured 0.02 N in 430 N)."""
    ref, sim = _twins_in_heave()
    before = sim.outputs()
    first, last = sim.contact_state()["ends"][1, [0, 2]].astype(int)  # elements meeting and leaving the sheave
    assert 0 <= first < last
    on_sheave = (first + last) // 2
    sim.split_element(60, 0.3)  # bare span, in the water
    after = sim.split_element(on_sheave, 0.5)
    assert sim.n_elements == ref.n_elements + 2
    for name in ("energy.kinetic", "energy.gravity", "towbody.x", "towbody.z", "towbody.vz", "winch.phi"):
        assert after[name] == pytest.approx(before[name], rel=1e-9, abs=1e-9), name
    assert after["energy.strain"] == pytest.approx(before["energy.strain"], rel=1e-4)
    a = ref.run(5.0)
    b = sim.run(5.0)
    rms = np.sqrt(np.mean((a["tension.sheave"] - b["tension.sheave"]) ** 2))
    assert rms < 1e-3 * np.ptp(a["tension.sheave"])
    assert np.ptp(a["tension.sheave"]) > 100.0  # the heave loads the cable


def test_split_with_a_bad_element_changes_nothing():
    sim = Simulation.from_scene("hanging_cable")
    sim.initialize()
    before = sim.get_state()
    with pytest.raises(SceneError, match="split_element"):
        sim.split_element(sim.n_elements, 0.5)
    assert sim.get_state() == before


# ------------------------------------------------------------------------- merging
def test_merge_undoes_a_split_exactly():
    rng = np.random.default_rng(3)
    mesh = Mesh(np.array([0.7, 1.3, 2.0]), np.array([0, 0, 0]), np.array([0.0, 0.7, 2.0, 4.0]))
    x = rng.normal(size=6 * mesh.n_nodes)
    fine = split_mesh(mesh, 1, 0.4)
    y = split_coordinates(x, mesh, 1, 0.4)
    assert merge_defect(y, fine, 1) == pytest.approx((0.0, 0.0), abs=1e-12)
    back = merge_mesh(fine, 1)
    np.testing.assert_allclose(back.lengths, mesh.lengths, rtol=1e-15)
    np.testing.assert_array_equal(back.node_arc, mesh.node_arc)
    np.testing.assert_array_equal(merge_coordinates(y, fine, 1), x)


def test_merge_defect_of_an_arc_falls_with_the_fourth_power_of_the_length():
    """Two elements lying exactly on a circle of radius 1 (nodes and unit slopes on it),
    merged: the cubic through the outer nodes misses the middle one by O(L^4) (cubic
    Hermite interpolation of a smooth curve)."""
    def arc_defect(length: float) -> float:
        angles = np.array([0.0, length, 2.0 * length])
        x = np.concatenate([[np.cos(a), np.sin(a), 0.0, -np.sin(a), np.cos(a), 0.0] for a in angles])
        mesh = Mesh(np.array([length, length]), np.array([0, 0]), np.array([0.0, length, 2.0 * length]))
        return merge_defect(x, mesh, 0)[0]

    coarse, fine = arc_defect(0.4), arc_defect(0.2)
    assert 0.0 < fine < coarse
    assert coarse / fine == pytest.approx(16.0, rel=0.05)


def test_elements_of_different_segments_are_not_merged():
    mesh = Mesh(np.array([1.0, 1.0, 1.0]), np.array([0, 0, 1]), np.array([0.0, 1.0, 2.0, 3.0]))
    with pytest.raises(ValueError, match="different segments"):
        merge_mesh(mesh, 1)
    with pytest.raises(ValueError, match="no next element"):
        merge_mesh(mesh, 2)


def test_split_and_merge_in_a_run_restore_the_cable():
    sim = Simulation.from_scene("full_scale")
    sim.run(3.0)
    q, v, before = sim.state.q.copy(), sim.state.v.copy(), sim.outputs()
    sim.split_element(62, 0.5)
    out = sim.merge_elements(62)
    np.testing.assert_array_equal(sim.state.q, q)
    np.testing.assert_array_equal(sim.state.v, v)
    assert out["remesh.position_defect"] == pytest.approx(0.0, abs=1e-12)
    for name, value in before.items():
        assert out[name] == pytest.approx(value, rel=1e-12, abs=1e-9), name
    with pytest.raises(SceneError, match="merge_elements"):
        sim.merge_elements(sim.n_elements - 1)


def test_a_merge_in_the_free_span_leaves_the_run_within_its_discretisation():
    """full_scale in heave: two 37.5 m elements of the bare span merged into one. The
    merged cubic misses the dropped node by the Hermite interpolation error of the
    catenary's shape (measured 0.5 mm); the next 10 s agree with the unmerged run within
    0.1 % of the sheave tension's range RMS (measured 0.05 N of 441 N)."""
    ref, sim = _twins_in_heave()
    assert sim.mesh.lengths[57] == sim.mesh.lengths[58] == 37.5
    out = sim.merge_elements(57)
    assert 0.0 < out["remesh.position_defect"] < 1e-3
    a, b = ref.run(10.0), sim.run(10.0)
    rms = np.sqrt(np.mean((a["tension.sheave"] - b["tension.sheave"]) ** 2))
    assert rms < 1e-3 * np.ptp(a["tension.sheave"])


def test_a_split_mesh_initialises_again():
    """The split mesh is the simulation's mesh from then on: initialising again solves
    the statics on it (the same hanging cable: top tension within the solver's tolerance)."""
    sim = Simulation.from_scene("hanging_cable")
    top = sim.initialize()["tension.top"]
    sim.split_element(0, 0.5)
    again = sim.initialize()
    assert sim.n_elements == Simulation.from_scene("hanging_cable").n_elements + 1
    assert again["tension.top"] == pytest.approx(top, rel=1e-6)
