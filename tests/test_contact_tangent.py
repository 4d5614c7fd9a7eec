"""The contact's exact tangent: a face's force derivatives against central differences of
the force, and the contact part of the assembled iteration matrix against central
differences of the residual in running scenes."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import TermPart

from towcable_fmu.ancf.forces.contact import build_contact
from towcable_fmu.contact.surfaces import CYLINDER, RIM, face_force, face_tangent
from towcable_fmu.scene import load_scene
from towcable_fmu.ancf.simulation import Simulation

#: states closer than this to a kink of the force or of the indicator are not compared [m]
#: (delta = 0, the clipped damping bracket, the switch between the terms of a minimum,
#: y = 0 for the rim): there the difference quotient straddles the kink
KINK = 1e-5


def _faces(damping: float, exponent: float):
    """full_scale's drum and grooved sheave (walls and rims), with a contact law of the given
    damping [s/m] and exponent."""
    scene = load_scene("full_scale")
    c = build_contact(scene)
    nf = c.face_kind.size
    c = c._replace(face_damping=np.full(nf, damping), face_n=np.full(nf, exponent))
    return c, 0.5 * scene.cable.segments[0].diameter


def _kinks(c, f, half_d, x, y, z, vx, vy, vz) -> list[float]:
    """Distances of a state to the force's and the indicator's kinks [m] (rates scaled by D)."""
    inv = 1.0 / np.hypot(x, z)
    h = np.hypot(x, z) - (c.face_radius[f] + half_d)
    rho_dot = (x * vx + z * vz) * inv
    kind = c.face_kind[f]
    if kind == CYLINDER or kind == RIM:
        delta = (c.face_depth[f] if kind == RIM else 0.0) - h
        rate = -rho_dot
    else:
        sign = 1.0 if kind == 1 else -1.0
        delta = sign * y * c.face_cos[f] - h * c.face_sin[f]
        rate = sign * vy * c.face_cos[f] - rho_dot * c.face_sin[f]
    out = [abs(delta), abs(1.0 + c.face_damping[f] * rate) * 1e-2]
    if kind == RIM:
        ca, sa = c.face_cos[f], c.face_sin[f]
        terms = sorted([delta, h * ca * ca + abs(y) * ca * sa - c.face_depth[f],
                        c.face_open[f] + c.face_rim[f] - abs(y)])
        out += [terms[1] - terms[0], abs(y)]
    elif kind != CYLINDER:
        top = c.face_depth[f] - (h + delta * c.face_sin[f])
        out.append(abs(top - delta))
    return out


@pytest.mark.parametrize("damping, exponent", [(0.0, 1.5), (2.0, 1.5), (5.0, 1.0)])
def test_face_tangent_matches_central_differences_of_the_face_force(damping, exponent):
    """Every face of a drum and a grooved sheave (walls, rims), random points around the
    seat (heights -80 to +20 mm, across the groove and the rims) and random velocities
    (some clipping the damping bracket): the force and indicator equal face_force's, and
    their derivatives agree with central differences to 1e-6 of the largest entry."""
    c, half_d = _faces(damping, exponent)
    rng = np.random.default_rng(3)
    checked = 0
    for f in range(c.face_kind.size):
        rc = c.face_radius[f] + half_d
        reach = c.face_open[f] + c.face_rim[f]
        for _ in range(400):
            psi = rng.uniform(-np.pi, np.pi)
            rho = rc + rng.uniform(-0.08, 0.02)
            s = np.array([rho * np.sin(psi), rng.uniform(-1.3 * reach, 1.3 * reach) if reach else 0.0,
                          rho * np.cos(psi)])
            w = rng.normal(0.0, 0.3, 3)
            if min(_kinks(c, f, half_d, *s, *w)) < KINK:
                continue
            force, g, dfx, dfv, dg = face_tangent(c, f, half_d, *s, *w)
            ref = face_force(c, f, half_d, *s, *w)
            np.testing.assert_allclose(force, ref[:3], rtol=1e-14, atol=1e-12)
            assert g == ref[3]
            fd_x, fd_v, fd_g = np.empty((3, 3)), np.empty((3, 3)), np.empty(3)
            for k in range(3):
                e = np.eye(3)[k] * 1e-7
                plus, minus = face_force(c, f, half_d, *(s + e), *w), face_force(c, f, half_d, *(s - e), *w)
                fd_x[:, k] = (np.array(plus[:3]) - minus[:3]) / 2e-7
                fd_g[k] = (plus[3] - minus[3]) / 2e-7
                plus, minus = face_force(c, f, half_d, *s, *(w + e)), face_force(c, f, half_d, *s, *(w - e))
                fd_v[:, k] = (np.array(plus[:3]) - minus[:3]) / 2e-7
            scale = max(np.abs(fd_x).max(), 1.0)
            np.testing.assert_allclose(np.reshape(dfx, (3, 3)), fd_x, rtol=0, atol=1e-6 * scale)
            np.testing.assert_allclose(np.reshape(dfv, (3, 3)), fd_v, rtol=0, atol=1e-6 * max(np.abs(fd_v).max(), 1.0))
            np.testing.assert_allclose(dg, fd_g, rtol=0, atol=1e-6)
            checked += ref[0] != 0.0 or ref[1] != 0.0 or ref[2] != 0.0
    assert checked > 200  # pushing states compared, not only the zero force of a face apart


@pytest.mark.parametrize("scene, t_run, overrides", [
    ("full_scale", 2.0, {}),
    ("full_scale", 2.0, {"sheave.contact.damping": 2.0, "winch.contact.damping": 2.0}),
    ("pulley_moving", 0.5, {})])
def test_iteration_matrix_contact_part_matches_central_differences_of_the_residual(scene, t_run, overrides):
    """In a running scene (the ship rolling and heaving: the faces move; a damped law, whose
    force depends on the velocity relative to the rotating ship), the part of the
    iteration matrix that the contact adds (the matrix minus that with the contact
    disabled), its damping C and stiffness K parts separately, against central differences
    of the residual's contact part, to 1e-5 of each part's largest entry. Left out: the
    entries coupling two coordinates of an element whose active length ends inside it (the
    moving boundary's stiffness, crossing_stiffness, differentiates the active length but
    not the load at the moving end point)."""
    sim = Simulation.from_scene(scene, overrides)
    sim.initialize()
    sim.run(t_run)
    m = sim.model
    contact = TermPart(sim, m._replace(terms=m.terms._replace(contact=m.terms.contact._replace(enabled=False))))
    free = m.free_dofs
    n = free.size

    where = np.ones((n, n), dtype=bool)
    for e in _elements_with_a_contact_end(sim):
        rows = (free >= 6 * e) & (free < 6 * e + 12)
        where &= ~(rows[:, None] & rows[None, :])
    stiffness = contact.differences(1e-7, 0.0, 0.0) / 1e-7
    assert np.abs(stiffness[where]).max() > 0.0
    checks = [((0.0, 0.0, 1.0), stiffness)]
    if m.terms.contact.face_damping.any():
        checks.append(((0.0, 1.0, 0.0), contact.differences(0.0, 1e-7, 0.0) / 1e-7))
    else:  # an undamped law: no damping part (the differences are round-off)
        assert not contact.matrix((0.0, 1.0, 0.0)).any()
    for weights, fd in checks:
        scale = np.abs(fd[where]).max()
        error = np.abs(contact.matrix(weights) - fd)[where].max()
        assert error < 1e-5 * scale, (weights, error / scale)


def _elements_with_a_contact_end(sim) -> list[int]:
    """Elements in which a face's active length starts or ends (its indicator changes sign
    between the element's grid points)."""
    from towcable_fmu.ancf.forces.contact_quadrature import _face_quadrature, _element_points, _touching_faces
    from towcable_fmu.numerics.kinematics import rotation_derivatives

    m = sim.model
    c = m.terms.contact
    rot, rot1, _ = rotation_derivatives(sim.workspace.ship)
    q, v = sim.state.q, sim.state.v
    out = []
    for e in range(m.el_len.size):
        npts = int(m.el_npts[e])
        pts = np.empty((2 * npts, 6))
        xi, wt, g = np.empty(2 * npts), np.empty(2 * npts), np.empty(2 * npts)
        cross = np.empty(2 * npts, dtype=np.int64)
        fpt = np.zeros((2 * npts, 7))
        faces = np.empty(c.face_kind.size, dtype=np.int64)
        half_d = 0.5 * m.el_d[e]
        nfaces = _touching_faces(c, half_d, q, 6 * e, m.el_len[e], rot, sim.workspace.ship, faces)
        _element_points(q, v, 6 * e, m.el_len[e], npts, pts)
        for k in range(nfaces):
            _face_quadrature(c, faces[k], half_d, rot, rot1, sim.workspace.ship, q, v, 6 * e, m.el_len[e], npts,
                             pts, xi, wt, g, cross, fpt)
            if np.any(g[:npts] > 0.0) and np.any(g[:npts] <= 0.0):
                out.append(e)
                break
    return out
