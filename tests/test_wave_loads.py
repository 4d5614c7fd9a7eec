"""Wave loads on the ANCF cable and the towed body, against Morison's equation evaluated
here independently: linear wave kinematics written out in this file, Wheeler stretching
by its definition, the wet length up to the instantaneous surface, and scipy's adaptive
quadrature (not the code's trapezoidal rule)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from towcable_fmu.ancf.forces import wave_quadrature as cable_hydro
from towcable_fmu.ancf.forces.hydro_quadrature import CableHydro
from towcable_fmu.hydro import waves as W
from towcable_fmu.hydro.loading import NORMAL_TANGENTIAL
from towcable_fmu.hydro.water import CURRENT_NONE, WaterModel

RHO, MU, G = 1025.0, 1.2e-3, 9.81
D, CD, CM = 0.05, 1.2, 1.0
AMP, PERIOD, DEPTH, PHASE = 1.0, 6.0, 30.0, 0.3
BOTTOM, TOP, ELEMENTS = -8.0, 4.0, 12


def _water(stretch: int) -> WaterModel:
    """Still water at z = 0 with one regular wave travelling along x (no current)."""
    table = W.component_table(np.array([2 * math.pi / PERIOD]), np.array([AMP]), np.array([PHASE]), np.zeros(1),
                              None, 0.0, DEPTH, G)
    return WaterModel(True, RHO, MU, 0.0, G, CURRENT_NONE, np.zeros(3), np.zeros(3), 0.0, 1.0, np.zeros((0, 3)),
                      table, DEPTH, stretch, 0.0, W.crest_bound(table),
                      float(np.sum(table[:, W.A] * table[:, W.K])))


def _cable() -> tuple[CableHydro, np.ndarray, np.ndarray]:
    """A straight vertical cable from BOTTOM to TOP at x = 0 (at rest: held by its stiffness),
    normal/tangential loading with constant C_D: the normal drag is rho d C_D |V_n| V_n / 2."""
    ne = ELEMENTS
    hy = CableHydro(True, np.ones(ne, dtype=bool), np.full(ne, NORMAL_TANGENTIAL, dtype=np.int64), np.full(ne, D),
                    np.full(ne, math.pi * D * D / 4), np.full(ne, CD), np.zeros(ne), np.ones(ne), np.full(ne, CM),
                    np.full(ne, 10, dtype=np.int64), np.zeros(1, dtype=np.int64), *cable_hydro.wave_cache(ne, 10, True))
    length = (TOP - BOTTOM) / ne
    q = np.zeros(6 * (ne + 1))
    q[2::6] = BOTTOM + length * np.arange(ne + 1)
    q[5::6] = 1.0
    return hy, np.full(ne, length), q


def _airy_x(z_s: float, t: float, k: float, omega: float) -> tuple[float, float]:
    """Horizontal particle velocity and acceleration of the wave at x = 0, height z_s <= 0."""
    th = omega * t + PHASE
    c = math.cosh(k * (z_s + DEPTH)) / math.sinh(k * DEPTH)
    return AMP * omega * c * math.cos(th), -AMP * omega ** 2 * c * math.sin(th)


def _morison_x(t: float, stretch: int) -> float:
    """Horizontal Morison force [N] on the cable at rest, integrated from its bottom to the
    instantaneous surface: drag rho d C_D |u| u / 2 and inertia (1 + C_m) rho A du/dt."""
    omega = 2 * math.pi / PERIOD
    k = W.dispersion(np.array([omega]), DEPTH, G)[0]
    eta = AMP * math.cos(omega * t + PHASE)

    def load(z):
        if stretch == W.STRETCH_WHEELER:
            u, a = _airy_x(DEPTH * (z - eta) / (DEPTH + eta), t, k, omega)
        elif z <= 0.0:
            u, a = _airy_x(z, t, k, omega)
        else:  # linear extrapolation from the mean level
            u0, a0 = _airy_x(0.0, t, k, omega)
            h = 1e-6
            u1, a1 = _airy_x(-h, t, k, omega)
            u, a = u0 + z * (u0 - u1) / h, a0 + z * (a0 - a1) / h
        return 0.5 * RHO * D * CD * abs(u) * u + (1.0 + CM) * RHO * math.pi * D * D / 4 * a

    return quad(load, BOTTOM, eta, epsabs=1e-10, epsrel=1e-10, limit=200)[0]


@pytest.mark.parametrize("stretch", [W.STRETCH_WHEELER, W.STRETCH_EXTRAPOLATION])
def test_surface_piercing_vertical_cable_horizontal_force_over_a_period(stretch):
    """The cable's generalised hydrodynamic force summed over the x coordinates of its
    nodes (the shape functions of position sum to one: the integral of the load) at 24
    times over a period, against the Morison integral of the undisturbed kinematics up to
    the instantaneous surface (a flat surface at z = 0 or kinematics without the waves
    would be tens of percent off)."""
    w = _water(stretch)
    hy, el_len, q = _cable()
    zero = np.zeros_like(q)
    forces, expected = [], []
    for t in np.linspace(0.0, PERIOD, 24, endpoint=False):
        out = np.zeros_like(q)
        cable_hydro.add_residual(w, hy, el_len, q, zero, zero, t, 0, ELEMENTS, out)
        forces.append(-out[0::6].sum())
        expected.append(_morison_x(t, stretch))
    forces, expected = np.array(forces), np.array(expected)
    scale = np.abs(expected).max()
    assert scale > 100.0
    assert np.abs(forces - expected).max() < 2e-3 * scale
    # the vertical load is the buoyancy of the wet length rho A g (eta - BOTTOM) plus the
    # waves' tangential drag (normal/tangential loading: C_Dt = 0 here) and no inertia along
    # the cable: its sum at the crest and the trough
    for t, eta in ((-PHASE * PERIOD / (2 * math.pi), AMP), ((math.pi - PHASE) * PERIOD / (2 * math.pi), -AMP)):
        out = np.zeros_like(q)
        cable_hydro.add_residual(w, hy, el_len, q, zero, zero, t, 0, ELEMENTS, out)
        assert -out[2::6].sum() == pytest.approx(RHO * math.pi * D * D / 4 * G * (eta - BOTTOM), rel=1e-9)


@pytest.mark.parametrize("crest", [True, False])
def test_body_held_at_the_surface_at_crest_and_trough(crest):
    """A lumped body of height 3 m held with its centre on the mean level: at the crest
    (eta = +1 m) and the trough (-1 m) the submerged fraction 1/2 + eta/3, buoyancy
    rho V g and drag 1/2 rho C_D A |u| u by that fraction, u and the vertical acceleration
    Airy's at Wheeler's height z_s = h (0 - eta) / (h + eta) (hand formulas here)."""
    from towcable_fmu.hydro.towbody import BodyHydro, body_force

    w = _water(W.STRETCH_WHEELER)
    volume, height = 0.4, 3.0
    cda = np.array([0.5, 0.6, 0.9])
    body = BodyHydro(True, 0, volume, height, RHO * volume * np.array([0.1, 1.0, 1.0]),
                     RHO * volume * np.array([1.1, 2.0, 2.0]), cda, 0.0, np.zeros(3), np.array([1.0, 0.0, 0.0]),
                     np.zeros(1, dtype=np.int64))
    omega = 2 * math.pi / PERIOD
    k = W.dispersion(np.array([omega]), DEPTH, G)[0]
    theta = 0.0 if crest else math.pi
    t = (theta - PHASE) / omega
    eta = AMP * math.cos(theta)
    fraction = 0.5 + eta / height
    z_s = DEPTH * (0.0 - eta) / (DEPTH + eta)
    u = AMP * omega * math.cosh(k * (z_s + DEPTH)) / math.sinh(k * DEPTH) * math.cos(theta)
    a_z = -AMP * omega ** 2 * math.sinh(k * (z_s + DEPTH)) / math.sinh(k * DEPTH) * math.cos(theta)
    force = np.empty(3)
    assert body_force(w, body, np.zeros(3), np.zeros(3), np.zeros(3), t, force)
    assert force[0] == pytest.approx(fraction * 0.5 * RHO * cda[0] * abs(u) * u, rel=1e-9)
    assert force[1] == pytest.approx(0.0, abs=1e-9)
    assert force[2] == pytest.approx(fraction * (RHO * volume * G + RHO * volume * 2.0 * a_z), rel=1e-9)


def test_kinematics_expanded_about_the_step_references_against_the_full_evaluation():
    """Within a time step the residual expands the waves' kinematics about references taken
    at the first residual of that time (wave_quadrature): at the iterates its load differs
    from the full evaluation by the second-order remainder only. A submerged inclined cable
    (Wheeler: the stretched height follows the elevation at the point) displaced by a smooth
    field d of amplitude delta: the difference falls 4-fold as delta halves (a wrong
    gradient leaves a first-order error, 2-fold), and stays below the remainder's bound.

    The bound, per node: the kinematics' second derivative along d is at most
    2 a omega k^2 coth(k h) |d|^2 (each of xx, xz, zz; (1 + a k)^2 for Wheeler's dependence
    on the elevation), so the velocity's remainder at most a omega k^2 coth(kh) (1 + ak)^2
    |d|^2 and the acceleration's omega times that; the drag changes with the velocity by at
    most rho d C_D |V| (|V| <= a omega coth(kh) here: no current, cable at rest), the
    inertia by (1 + C_m) rho A per unit acceleration; a node's shape functions weigh at
    most one element length."""
    w = _water(W.STRETCH_WHEELER)
    hy, el_len, q0 = _cable()
    q0[2::6] -= TOP + 2.0 * AMP  # below the deepest trough: no waterline
    q0[0::6] = 0.3 * (q0[2::6] - q0[2])  # inclined in x (nodes: the slopes follow)
    q0[3::6] = 0.3
    norm = math.hypot(0.3, 1.0)
    q0[3::6] /= norm
    q0[5::6] /= norm
    zero = np.zeros_like(q0)
    s = np.zeros_like(q0)
    s[0::6] = np.cos(0.7 * q0[2::6])  # a smooth displacement field of amplitude up to 1.37
    s[1::6] = 0.5 * np.sin(0.4 * q0[2::6])
    s[2::6] = 0.8 * np.cos(0.3 * q0[2::6] + 1.0)
    t = 1.3

    def residual(q, fresh):
        if fresh:
            hy.wave_clock[0] = math.nan  # references at q: the full evaluation
        out = np.zeros_like(q)
        cable_hydro.add_residual(w, hy, el_len, q, zero, zero, t, 0, ELEMENTS, out)
        return out

    omega = 2 * math.pi / PERIOD
    k = W.dispersion(np.array([omega]), DEPTH, G)[0]
    coth = 1.0 / math.tanh(k * DEPTH)
    velocity = AMP * omega * coth
    per_d2 = AMP * omega * k * k * coth * (1.0 + AMP * k) ** 2  # velocity remainder per |d|^2 [1/(m s)]
    sensitivity = RHO * D * CD * velocity + (1.0 + CM) * RHO * math.pi * D * D / 4 * omega  # [N s/m^2]
    errors = []
    for delta in (0.05, 0.025):
        residual(q0, True)  # the references at q0 (the predicted state)
        expanded = residual(q0 + delta * s, False)
        errors.append(np.abs(expanded - residual(q0 + delta * s, True)).max())
        d2 = delta ** 2 * (s[0::6] ** 2 + s[1::6] ** 2 + s[2::6] ** 2).max()
        assert 0.0 < errors[-1] < el_len[0] * sensitivity * per_d2 * d2
    assert 3.5 < errors[0] / errors[1] < 4.5
