"""The ANCF element: shape functions, constant matrices, decoupled axial force."""

from __future__ import annotations

import numpy as np
import pytest

from towcable_fmu.ancf import element
from towcable_fmu.ancf.axial import at_length, axial_force, axial_strains, axial_tangent, axial_work


def test_shape_functions_interpolate_nodes_and_slopes():
    L = 2.5
    n = element.shape_functions(np.array([0.0, 1.0]), L)
    dn = element.shape_derivatives(np.array([0.0, 1.0]), L)
    np.testing.assert_allclose(n, [[1, 0, 0, 0], [0, 0, 1, 0]], atol=1e-15)
    # slope functions carry the factor L: d r/dp at the nodes equals the nodal slopes
    np.testing.assert_allclose(dn, [[0, 1, 0, 0], [0, 0, 0, 1]], atol=1e-15)


def test_mass_matrix_equals_closed_form_w12():
    L, mu = 3.0, 0.7
    expected = mu * L / 420 * np.array([[156, 22 * L, 54, -13 * L],
                                        [22 * L, 4 * L**2, 13 * L, -3 * L**2],
                                        [54, 13 * L, 156, -22 * L],
                                        [-13 * L, -3 * L**2, -22 * L, 4 * L**2]])
    np.testing.assert_allclose(element.mass_matrix(L, mu), expected, rtol=1e-13)


def test_bending_and_damping_matrices_closed_form():
    L, ei, c = 1.7, 2.0, 0.3
    kb = ei / L**3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L**2, -6 * L, 2 * L**2],
                               [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L**2, -6 * L, 4 * L**2]])
    cd = c / (30 * L) * np.array([[36, 3 * L, -36, 3 * L], [3 * L, 4 * L**2, -3 * L, -L**2],
                                  [-36, -3 * L, 36, -3 * L], [3 * L, -L**2, -3 * L, 4 * L**2]])
    np.testing.assert_allclose(element.bending_matrix(L, ei), kb, rtol=1e-12)
    np.testing.assert_allclose(element.damping_matrix(L, c), cd, rtol=1e-12, atol=1e-15)


def test_load_vector_is_consistent_nodal_load():
    L = 4.0
    np.testing.assert_allclose(element.load_vector(L), [L / 2, L**2 / 12, L / 2, -L**2 / 12], rtol=1e-14)


def test_trapezoid_weights_integrate_length():
    xi, w = element.trapezoid_points(10)
    assert w.sum() == pytest.approx(1.0)
    assert xi[0] == 0.0 and xi[-1] == 1.0


class AxialElement:
    """One element's axial force with the package's Gauss quadrature."""

    def __init__(self, L: float, ea: float, tension_only: bool = False, engineering: bool = False):
        gx, gw = element.gauss_legendre(5)
        self.work = axial_work(element.shape_derivatives(gx, 1.0), gw)
        at_length(self.work, L)
        self.L, self.ea, self.tension_only, self.engineering = L, ea, tension_only, engineering

    def force(self, x):
        f = np.zeros(12)
        energy, _ = axial_force(x, 0, self.L, self.ea, self.tension_only, self.engineering, self.work, f)
        return f, energy

    def tangent(self, x):
        k = np.zeros((12, 12))
        axial_tangent(x, 0, self.L, self.ea, self.tension_only, self.engineering, self.work, 1.0, k)
        return k

    def taut(self, x):
        """The taut Gauss points' bit masks the force and the tangent report."""
        f, k = np.zeros(12), np.zeros((12, 12))
        return (axial_force(x, 0, self.L, self.ea, self.tension_only, self.engineering, self.work, f)[1],
                axial_tangent(x, 0, self.L, self.ea, self.tension_only, self.engineering, self.work, 1.0, k))

    def strain(self, x, xi):
        dn = element.shape_derivatives(np.array([xi]), 1.0)
        out = np.zeros(1)
        axial_strains(x, 0, self.L, self.work, dn, out)
        return out[0]


def _random_element(rng, L):
    return np.array([0, 0, 0, 1, 0, 0, L, 0, 0, 1, 0, 0.0]) + 0.1 * rng.normal(size=12)


@pytest.mark.parametrize("engineering", [False, True])
@pytest.mark.parametrize("tension_only", [False, True])
def test_axial_force_is_gradient_of_energy_and_tangent_is_its_jacobian(tension_only, engineering):
    rng = np.random.default_rng(3)
    el = AxialElement(2.0, 1e5, tension_only, engineering)
    x = _random_element(rng, 2.0)
    f, _ = el.force(x)
    h = 1e-6
    grad = np.array([(el.force(x + h * e)[1] - el.force(x - h * e)[1]) / (2 * h) for e in np.eye(12)])
    np.testing.assert_allclose(f, grad, rtol=1e-6, atol=1e-6 * np.abs(f).max())
    k = el.tangent(x)
    kfd = np.array([(el.force(x + h * e)[0] - el.force(x - h * e)[0]) / (2 * h) for e in np.eye(12)]).T
    np.testing.assert_allclose(k, kfd, rtol=1e-5, atol=1e-6 * np.abs(k).max())
    np.testing.assert_allclose(k, k.T, atol=1e-9 * np.abs(k).max())


def test_taut_points_are_those_in_tension():
    """The bit masks of the taut Gauss points (what Newton compares between the residual
    and the matrix) mark exactly the points of positive strain; an element that takes
    compression reports none."""
    rng = np.random.default_rng(5)
    gx, _ = element.gauss_legendre(5)
    slack = AxialElement(2.0, 1e5, tension_only=True)
    elastic = AxialElement(2.0, 1e5, tension_only=False)
    seen = set()
    for _ in range(40):
        x = _random_element(rng, 2.0) * rng.uniform(0.97, 1.03)
        expected = sum(1 << g for g, xi in enumerate(gx) if slack.strain(x, xi) >= 0.0)
        assert slack.taut(x) == (expected, expected)
        assert elastic.taut(x) == (0, 0)
        seen.add(expected)
    assert len(seen) > 2  # slack, taut and partly taut elements were drawn


def test_uniform_stretch_gives_green_strain_and_end_forces():
    L, ea, lam = 2.0, 1e5, 1.01
    el = AxialElement(L, ea)
    x = np.array([0, 0, 0, lam, 0, 0, lam * L, 0, 0, lam, 0, 0])
    f, energy = el.force(x)
    eps = 0.5 * (lam**2 - 1)
    assert el.strain(x, 0.3) == pytest.approx(eps, rel=1e-12)
    # end forces: the work-conjugate force EA eps lambda, pulling the ends together
    assert f[0] == pytest.approx(-ea * eps * lam, rel=1e-12)
    assert f[6] == pytest.approx(ea * eps * lam, rel=1e-12)
    assert energy == pytest.approx(0.5 * ea * eps**2 * L, rel=1e-12)


def test_kelvin_voigt_law_on_a_stretching_straight_element():
    """The snapping case's law N = EA (lambda - 1) + BA d(eps)/dt on a uniformly stretched
    straight element moving at a uniform strain rate: the elastic end forces are
    EA (lambda - 1) (engineering strain; the Green law gives EA eps_G lambda, larger by
    3 (lambda - 1) / 2 to first order) and the Rayleigh damping W(55), C v, gives the end
    forces BA d(eps)/dt, the slope rows nothing."""
    L, ea, lam, ba, rate = 2.0, 1e5, 1.004, 10.0, 0.37
    el = AxialElement(L, ea, engineering=True)
    x = np.array([0, 0, 0, lam, 0, 0, lam * L, 0, 0, lam, 0, 0])
    f, energy = el.force(x)
    assert f[6] == pytest.approx(ea * (lam - 1.0), rel=1e-12)
    assert f[0] == pytest.approx(-ea * (lam - 1.0), rel=1e-12)
    assert energy == pytest.approx(0.5 * ea * (lam - 1.0) ** 2 * L, rel=1e-12)
    green, _ = AxialElement(L, ea).force(x)
    assert green[6] / f[6] - 1.0 == pytest.approx(1.5 * (lam - 1.0), rel=2e-3)
    # the element stretches at d(lambda)/dt = rate: the far end moves at rate L, slopes at rate
    v = np.array([0, 0, 0, rate, 0, 0, rate * L, 0, 0, rate, 0, 0])
    damping = np.kron(element.damping_matrix(L, ba), np.eye(3)) @ v
    np.testing.assert_allclose(damping[[0, 6]], [-ba * rate, ba * rate], rtol=1e-12)
    np.testing.assert_allclose(np.delete(damping, [0, 6]), 0.0, atol=1e-12 * ba * rate)


def _arc_element(radius: float, angle: float) -> np.ndarray:
    """Cubic element through the ends of a circular arc with unit end tangents."""
    r1 = radius * np.array([np.sin(angle), 0.0, 1 - np.cos(angle)])
    return np.concatenate([[0, 0, 0], [1, 0, 0], r1, [np.cos(angle), 0, np.sin(angle)]])


def test_decoupling_bent_unstretched_element_has_no_axial_force():
    """An element bent into an arc whose arc length equals its unstretched length, with
    unit end slopes, carries no axial force with the decoupled strain W(42)-(47); the
    coupled Green strain W(41) of the same shape is not zero."""
    from scipy.optimize import brentq

    L, angle = 1.0, 1.2
    el = AxialElement(L, 1e6)

    def arc_length(radius):
        el.force(_arc_element(radius, angle))
        return float(np.sum(el.work.gw * el.work.lam)) * L - L

    x = _arc_element(brentq(arc_length, 0.5, 1.5, xtol=1e-14), angle)
    f, energy = el.force(x)
    for xi in (0.0, 0.3, 0.5, 1.0):
        assert abs(el.strain(x, xi)) < 1e-12
    assert np.abs(f).max() < 1e-6 and energy < 1e-12
    dn = element.shape_derivatives(np.array(0.5), L)
    rp = dn[0] * x[0:3] + dn[1] * x[3:6] + dn[2] * x[6:9] + dn[3] * x[9:12]
    assert abs(0.5 * (rp @ rp - 1.0)) > 1e-3  # the Green strain of W(41) would be non-zero


def test_gauss_arc_length_of_circular_element_converges():
    """s = int |r_p| dp by 5 Gauss points equals the arc length of the cubic (fine trapezoid)."""
    el = AxialElement(1.0, 1.0)
    angle = 0.9
    r1 = np.array([np.sin(angle), 0.0, 1 - np.cos(angle)]) / angle
    x = np.concatenate([[0, 0, 0], [1, 0, 0], r1, [np.cos(angle), 0, np.sin(angle)]])
    xi = np.linspace(0, 1, 20001)
    dn = element.shape_derivatives(xi, 1.0)
    rp = dn[:, [0]] * x[0:3] + dn[:, [1]] * x[3:6] + dn[:, [2]] * x[6:9] + dn[:, [3]] * x[9:12]
    speed = np.linalg.norm(rp, axis=1)
    exact = np.sum(0.5 * (speed[1:] + speed[:-1]) * np.diff(xi))
    el.force(x)
    s_gauss = float(np.sum(el.work.gw * el.work.lam))
    assert s_gauss == pytest.approx(exact, rel=1e-7)
