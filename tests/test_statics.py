"""Statics against closed forms: elastic catenary, hanging cable, cantilever."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import cable_scene, segment

from reference.catenary import solve_elastic_catenary

G = 9.81


EA_CATENARY = 1e6  # strain ~0.1 %: the reference's engineering strain and our Green strain differ by O(1e-6)


def _catenary_sim(make_sim, elements: int):
    # 100 m cable, 1 kg/m, between (0,0,0) and (80,0,10)
    table = cable_scene([segment(100.0, elements, mu=1.0, EA=EA_CATENARY, EI=1e-4)],
                        top={"type": "pinned", "position": [0.0, 0.0, 0.0]},
                        bottom={"type": "pinned", "position": [80.0, 0.0, 10.0]})
    sim = make_sim(table)
    sim.initialize()
    return sim


def test_elastic_catenary_between_two_supports_converges_to_closed_form(make_sim):
    """Support tensions, sag and shape against Irvine's elastic catenary (computed
    independently in tests/reference), with the error falling as the mesh is refined."""
    ref = solve_elastic_catenary(L0=100.0, EA=EA_CATENARY, w=1.0 * G, span=80.0, height=10.0)
    errors = []
    for n in (2, 4, 8, 16):
        sim = _catenary_sim(make_sim, n)
        out = sim.outputs()
        pos = sim.node_positions()
        s = sim.mesh.node_arc
        x_ref = np.array([ref.x(si) for si in s])
        z_ref = np.array([ref.z(si) for si in s])
        shape_err = np.max(np.hypot(pos[:, 0] - x_ref, pos[:, 2] - z_ref))
        errors.append((abs(out["tension.top"] / ref.tension_A - 1), abs(out["tension.bottom"] / ref.tension_B - 1),
                       shape_err))
    errors = np.array(errors)
    # 16 cubic elements: tensions within 1e-5 (measured 4.6e-6), shape within 1 mm (0.7 mm)
    assert errors[-1, 0] < 1e-5 and errors[-1, 1] < 1e-5
    assert errors[-1, 2] < 1e-3
    # refinement reduces every error (monotone over the first refinements)
    assert np.all(errors[1:, 2] < errors[:-1, 2])
    assert errors[-1, 0] < errors[0, 0] and errors[-1, 1] < errors[0, 1]


def test_catenary_sag_at_nodes_matches_closed_form(make_sim):
    ref = solve_elastic_catenary(L0=100.0, EA=EA_CATENARY, w=1.0 * G, span=80.0, height=10.0)
    sim = _catenary_sim(make_sim, 16)
    # node at the arc length of maximum sag: interpolate the deflection below the chord
    s, pos = sim.shape(points_per_element=16)
    below = 10.0 / 80.0 * pos[:, 0] - pos[:, 2]  # vertical distance below the chord
    below_ref = 10.0 / 80.0 * ref.x(s) - ref.z(s)
    np.testing.assert_allclose(below, below_ref, atol=2e-3)  # 16 elements: 0.7 mm at nodes, 1.5 mm between
    assert below.max() == pytest.approx(ref.sag, abs=2e-3)


def test_hanging_cable_tension_is_total_weight(make_sim):
    table = cable_scene([segment(50.0, 10, mu=0.5, EA=1e6)],
                        top={"type": "pinned", "position": [0.0, 0.0, 0.0]},
                        towbody={"mass": 20.0})
    sim = make_sim(table)
    out = sim.initialize()
    # exact up to the statics tolerance (1e-8 of the load scale)
    assert out["tension.top"] == pytest.approx((50 * 0.5 + 20) * G, rel=1e-7)
    assert out["tension.towbody"] == pytest.approx(20 * G, rel=1e-7)
    # stretched length: integral of (1 + T/EA) with the Green-strain law T = EA (lambda^2-1)/2
    s = np.linspace(0, 50, 20001)
    tension = (20 + 0.5 * (50 - s)) * G
    stretch = np.sqrt(1 + 2 * tension / 1e6)
    length = np.sum(0.5 * (stretch[1:] + stretch[:-1]) * np.diff(s))
    assert -out["towbody.z"] == pytest.approx(length, rel=1e-6)  # 10 cubic elements


def test_cantilever_tip_deflection_small_load(make_sim):
    """Clamped horizontal cable with a tip mass: PL^3/(3EI) + wL^4/(8EI) for small loads."""
    L, ei, mu, m = 1.0, 10.0, 0.01, 0.1
    table = cable_scene([segment(L, 10, mu=mu, EA=1e7, EI=ei)],
                        top={"type": "clamped", "position": [0.0, 0.0, 0.0], "slope": [1.0, 0.0, 0.0]},
                        towbody={"mass": m})
    sim = make_sim(table)
    out = sim.initialize()
    expected = m * G * L**3 / (3 * ei) + mu * G * L**4 / (8 * ei)
    # deflection/L = 3.4 %: geometric non-linearity is O((d/L)^2) ~ 0.1 %
    assert -out["towbody.z"] == pytest.approx(expected, rel=3e-3)


def test_statics_from_straight_slack_start_converges(make_sim):
    """A cable laid straight between supports far closer than its length (compressed by a
    third) must find the catenary: PTC handles the buckled start."""
    table = cable_scene([segment(30.0, 12, mu=2.0, EA=1e6, EI=1e-2)],
                        top={"type": "pinned", "position": [0.0, 0.0, 0.0]},
                        bottom={"type": "pinned", "position": [20.0, 0.0, 0.0]})
    table["cable"]["initial"] = {"shape": "straight", "direction": [1.0, 0.0, 0.0]}
    sim = make_sim(table)
    out = sim.initialize()
    ref = solve_elastic_catenary(L0=30.0, EA=1e6, w=2.0 * G, span=20.0, height=0.0)
    assert out["tension.top"] == pytest.approx(ref.tension_A, rel=1e-4)
