"""Self-tests of the independent reference solutions in ``tests/reference``.

These check the references against hand calculations, classical closed forms
and each other (catenary <-> steady-tow solver), so that the simulator tests
can trust them.  Nothing here imports ``towcable_fmu``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate, optimize

sys.path.insert(0, str(Path(__file__).resolve().parent))

from reference import catenary as cat  # noqa: E402
from reference import steady_tow as st  # noqa: E402

G0 = 9.81


# ---------------------------------------------------------------------------
# Elastic catenary
# ---------------------------------------------------------------------------
CATENARY_CASES = [
    # L0, EA, w, span, height
    (100.0, 1e5, 10.0, 80.0, 20.0),  # slack, inclined, noticeable stretch
    (100.0, 1e5, 10.0, 80.0, -30.0),  # B below A
    (100.0, 1e4, 10.0, 100.0, 10.0),  # taut: L0 < chord, held by stretch
    (450.0, 6.786e6, 3.03, 400.0, 100.0),  # steel cable, submerged weight
    (100.0, 1e6, 10.0, 10.0, 99.0),  # steep, B above the top of the arc
]


@pytest.mark.parametrize("L0,EA,w,span,height", CATENARY_CASES)
def test_catenary_shape_consistent_with_tension(L0, EA, w, span, height):
    """End conditions hold, and the stretch/direction of the returned shape
    (finite differences of x(s), z(s)) reproduce the returned tension."""
    c = cat.solve_elastic_catenary(L0, EA, w, span, height)
    assert c.x(L0) == pytest.approx(span, abs=1e-9 * L0)
    assert c.z(L0) == pytest.approx(height, abs=1e-9 * L0)
    assert c.x(0.0) == 0.0 and c.z(0.0) == 0.0
    s = np.linspace(0.02 * L0, 0.98 * L0, 25)
    h = 1e-4 * L0

    def deriv(f):  # fourth-order central difference
        return (-f(s + 2 * h) + 8 * f(s + h) - 8 * f(s - h) + f(s - 2 * h)) / (12 * h)

    dx, dz = deriv(c.x), deriv(c.z)
    stretch = np.hypot(dx, dz)
    T = c.tension(s)
    # |dr/ds| = 1 + T/EA  ->  T = EA (|dr/ds| - 1); compare the strains
    np.testing.assert_allclose(stretch - 1.0, T / EA, rtol=1e-5)
    # horizontal tension = T cos(angle) is the same everywhere and equals H
    np.testing.assert_allclose(T * dx / stretch, c.H, rtol=1e-6)
    # stretched length: integral of |dr/ds|
    ss = np.linspace(0.0, L0, 20001)
    tz = c.vertical_tension(ss)
    length = integrate.simpson(1.0 + np.hypot(c.H, tz) / EA, x=ss)
    assert c.stretched_length == pytest.approx(length, rel=1e-10)


@pytest.mark.parametrize("L0,EA,w,span,height", CATENARY_CASES)
def test_catenary_vertical_equilibrium_from_geometry(L0, EA, w, span, height):
    """Support forces computed from the tension magnitude and the tangent of
    the returned shape at each end add up to the total weight."""
    c = cat.solve_elastic_catenary(L0, EA, w, span, height)
    h = 1e-6 * L0

    def end_force(s0, s1):
        tx, tz = c.x(s1) - c.x(s0), c.z(s1) - c.z(s0)
        n = np.hypot(tx, tz)
        return c.tension(s0) * np.array([tx, tz]) / n

    # support A pulls the cable along -tangent at s=0, support B along +tangent at s=L0
    fa = -end_force(0.0, h)  # direction from A into the cable, reversed
    fb = end_force(L0, L0 - h) * -1.0
    # the forward difference is first order: allow O(h w / T) relative error
    assert fa[1] + fb[1] == pytest.approx(w * L0, rel=1e-5)
    assert fa[0] + fb[0] == pytest.approx(0.0, abs=1e-5 * w * L0)
    assert c.V_A + c.V_B == pytest.approx(w * L0, rel=1e-14)
    assert c.tension_A == pytest.approx(np.hypot(c.H, c.V_A))
    assert c.tension_B == pytest.approx(c.tension(L0))


@pytest.mark.parametrize("span,height", [(80.0, 20.0), (60.0, -40.0), (95.0, 0.0)])
def test_catenary_inextensible_limit(span, height):
    """For EA -> inf, H tends to the classical catenary H (independent
    transcendental equation), and the elastic correction is O(1/EA)."""
    L0, w = 100.0, 10.0
    H_inext = cat.inextensible_catenary_H(L0, w, span, height)
    c = cat.solve_elastic_catenary(L0, 1e13, w, span, height)
    assert c.H == pytest.approx(H_inext, rel=1e-7)
    d1 = cat.solve_elastic_catenary(L0, 1e6, w, span, height).H - H_inext
    d2 = cat.solve_elastic_catenary(L0, 1e7, w, span, height).H - H_inext
    # stretch makes the cable longer -> less tension; first-order in 1/EA
    assert d1 < 0 and d2 < 0
    assert d1 / d2 == pytest.approx(10.0, rel=0.02)


def test_catenary_level_supports_symmetry_and_sag():
    """Level supports: symmetric reactions, sag at mid-length equal to the
    brute-force maximum, close to the parabola w l^2/(8H) for a shallow cable,
    and the inextensible closed form z_mid = (H/w)(1 - cosh(w l/2H))."""
    L0, w, l = 101.0, 5.0, 100.0
    c = cat.solve_elastic_catenary(L0, 1e14, w, l, 0.0)
    assert c.V_A == pytest.approx(0.5 * w * L0, rel=1e-12)
    assert c.s_sag == pytest.approx(0.5 * L0, rel=1e-12)
    s = np.linspace(0.0, L0, 200001)
    assert c.sag == pytest.approx(np.max(-c.z(s)), rel=1e-9)
    assert c.sag == pytest.approx(c.H / w * (np.cosh(w * l / (2 * c.H)) - 1.0), rel=1e-9)
    assert c.sag == pytest.approx(w * l**2 / (8 * c.H), rel=0.01)


def test_catenary_inclined_sag_brute_force():
    c = cat.solve_elastic_catenary(120.0, 2e5, 8.0, 90.0, -35.0)
    s = np.linspace(0.0, 120.0, 400001)
    below = -35.0 * c.x(s) / 90.0 - c.z(s)
    assert c.sag == pytest.approx(below.max(), rel=1e-8)
    assert c.s_sag == pytest.approx(s[np.argmax(below)], abs=1e-3)


def test_hanging_cable_hand_calculation():
    """L0 = 100 m, EA = 1e6 N, w = 10 N/m, end weight 500 N:
    T_top = 500 + 1000 = 1500 N; stretch = (500*100 + 0.5*10*100^2)/1e6 = 0.1 m."""
    h = cat.hanging_cable(100.0, 1e6, 10.0, 500.0, top=2.0)
    assert h.top_tension == pytest.approx(1500.0, rel=1e-15)
    assert h.stretched_length == pytest.approx(100.1, rel=1e-14)
    assert h.bottom_z == pytest.approx(2.0 - 100.1, rel=1e-14)
    assert h.tension(0.0) == pytest.approx(1500.0)
    assert h.tension(100.0) == pytest.approx(500.0)
    assert h.tension(40.0) == pytest.approx(500.0 + 10.0 * 60.0)
    assert h.z(100.0) == pytest.approx(h.bottom_z, rel=1e-14)
    # midpoint by hand: the upper 50 m carry 1500 -> 1000 N, mean 1250 N
    assert h.z(50.0) == pytest.approx(2.0 - 50.0 - 1250.0 * 50.0 / 1e6, rel=1e-14)


# ---------------------------------------------------------------------------
# Loading functions and drag coefficient
# ---------------------------------------------------------------------------
def test_loading_functions_hand_values():
    e = np.pi / 2
    assert st.fn_bare(0.0) == pytest.approx(0.0, abs=1e-15)
    assert st.fn_bare(e) == pytest.approx(1.0, abs=1e-15)
    assert st.ft_bare(0.0) == pytest.approx(0.02009, rel=1e-14)
    # pi/4 by hand: 0.5 - 0.1/sqrt2 + 0.1/sqrt2 - 0.4*0 - 0.11*1 = 0.39
    assert st.fn_bare(np.pi / 4) == pytest.approx(0.39, abs=1e-14)
    x = 0.5
    assert st.ft_bare(x) == pytest.approx(
        0.01 * (2.009 - 0.1929 + 1.9159 / 4 - 4.1615 / 8 + 3.5064 / 16 - 1.1873 / 32), rel=1e-13)
    assert st.fn_faired(e) == pytest.approx(0.498609 + 0.2527 + 0.2487, rel=1e-14)
    assert st.fn_faired(0.0) == pytest.approx(0.498609 - 0.2499 - 0.2487, abs=1e-15)
    assert st.ft_faired(0.0) == pytest.approx(-0.2255 + 0.3417, rel=1e-13)
    assert st.ft_faired(e) == pytest.approx(-0.2255 + 0.255, rel=1e-12)
    assert st.ft_faired(np.pi / 4) == pytest.approx(
        -0.2255 + (0.3417 + 0.255) / np.sqrt(2) - 0.0811, rel=1e-13)


def test_drag_coefficient_hand_values():
    # Re = 1000: 1.1 + 4/sqrt(1000)
    assert st.drag_coefficient(1000.0) == pytest.approx(1.1 + 4 / 31.6227766016838, rel=1e-13)
    assert st.drag_coefficient(30.0) == pytest.approx(1.1 + 4 / np.sqrt(30.0), rel=1e-14)
    # Re = 10: 1.45 + 8.55 * 10^-0.9 = 1.45 + 8.55 * 0.125892541
    assert st.drag_coefficient(10.0) == pytest.approx(1.45 + 8.55 * 0.12589254117941673, rel=1e-13)
    # Re = 0.5: S = -0.077215665 + ln 16 = 2.695372112...
    S = -0.077215665 + 2.772588722239781
    assert st.drag_coefficient(0.5) == pytest.approx(8 * np.pi / (0.5 * S) * (1 - 0.87 / S**2), rel=1e-13)
    # branches meet reasonably at Re = 1 and Re = 30 (published fits, not exact)
    assert st.drag_coefficient(1.0) == pytest.approx(10.0, rel=0.02)
    assert st.drag_coefficient(29.999) == pytest.approx(st.drag_coefficient(30.0), rel=0.02)
    # finite at Re = 0 (floored)
    assert np.isfinite(st.drag_coefficient(0.0))
    assert st.reynolds_number(1026.0, 0.01, -2.2, 1.2e-3) == pytest.approx(18810.0, rel=1e-12)


def test_cable_drag_direction_magnitude_and_singular_cases():
    rho, mu, d = 1026.0, 1.2e-3, 0.01
    V = np.array([-2.2, 0.0, 0.0])
    # flow normal to the cable: pure normal drag along V with f_n = 1
    f = st.cable_drag_per_length(V, [0, 0, 1], d, rho, mu, G=3.0)
    cd = st.drag_coefficient(rho * d * 2.2 / mu)
    expected = 3.0 * 0.5 * rho * d * cd * 2.2**2 * (1.0 + 0.0)  # f_n(pi/2) = 1
    np.testing.assert_allclose(f, [-expected, 0, 0], rtol=1e-12, atol=1e-9)
    # 60 deg between flow and cable: both components along their V parts
    t = np.array([np.cos(np.pi / 3), 0.0, np.sin(np.pi / 3)])
    f1 = st.cable_drag_per_length(V, t, d, rho, mu)
    f2 = st.cable_drag_per_length(V, -t, d, rho, mu)
    np.testing.assert_allclose(f1, f2, rtol=1e-14)  # sense of the tangent is irrelevant
    vt = (V @ t) * t
    vn = V - vt
    eta = np.pi / 3
    assert st.flow_angle(V, t) == pytest.approx(eta, rel=1e-12)
    assert st.flow_angle(V, -t) == pytest.approx(eta, rel=1e-12)
    cd_n = st.drag_coefficient(rho * d * np.linalg.norm(vn) / mu)  # normal term: Re of the NORMAL velocity
    cd_t = st.drag_coefficient(rho * d * np.linalg.norm(V) / mu)  # tangential term: Re of the full speed
    q = 0.5 * rho * d * (V @ V)
    exp = q * (cd_n * st.fn_bare(eta) * vn / np.linalg.norm(vn) + cd_t * st.ft_bare(eta) * vt / np.linalg.norm(vt))
    np.testing.assert_allclose(f1, exp, rtol=1e-12)
    assert f1 @ V > 0 and (f1 @ vt) > 0  # along the flow, tangential part along V_t
    # no flow: exactly zero, no NaN
    assert np.all(st.cable_drag_per_length(np.zeros(3), t, d, rho, mu) == 0.0)
    # flow exactly along the cable: purely tangential skin friction along V, f_t(0) C_D(Re)
    fa = st.cable_drag_per_length(V, [1, 0, 0], d, rho, mu)
    skin = 0.5 * rho * d * st.drag_coefficient(rho * d * 2.2 / mu) * st.ft_bare(0.0) * 2.2**2
    np.testing.assert_allclose(fa, [-skin, 0, 0], rtol=1e-12)
    # faired loading functions are picked up
    ff = st.cable_drag_per_length(V, t, d, rho, mu, loading="faired", cd=1.2)
    q = 0.5 * rho * d * 1.2 * (V @ V)
    exp = q * (st.fn_faired(eta) * vn / np.linalg.norm(vn) + st.ft_faired(eta) * vt / np.linalg.norm(vt))
    np.testing.assert_allclose(ff, exp, rtol=1e-12)


def test_flume_current_profile():
    zwl = -0.46
    assert st.flume_current_speed(zwl, zwl) == pytest.approx(-0.3302)
    assert st.flume_current_speed(zwl - 0.5, zwl) == pytest.approx(0.5873 * 0.5 - 0.3302)
    np.testing.assert_allclose(st.flume_current(zwl)(zwl - 0.2), [0.5873 * 0.2 - 0.3302, 0, 0])


# ---------------------------------------------------------------------------
# Steady tow solver
# ---------------------------------------------------------------------------
def _steel(length=200.0, EA=2e6, loading="bare", G=1.0, cd=None):
    return st.CableSegment(length, 0.01, 0.389, EA, loading, G, cd)


def test_still_water_vertical_matches_hanging_cable():
    """No current, tow point at the waterline: vertical cable, top tension
    = body net weight + submerged cable weight; shape = hanging_cable."""
    seg = _steel(EA=2e6)
    water = st.Water(rho=1026.0, current=(0, 0, 0), z_waterline=0.0)
    body = st.TowedBody(mass=100.0, volume=0.02)
    Wb = (100.0 - 1026.0 * 0.02) * G0
    w_sub = (0.389 - 1026.0 * seg.area) * G0
    res = st.solve_steady_tow([seg], body, water, (5.0, -1.0, 0.0))
    assert res.tension_top == pytest.approx(Wb + w_sub * 200.0, rel=1e-10)
    assert res.top_angle == pytest.approx(0.0, abs=1e-9)
    ref = cat.hanging_cable(200.0, 2e6, w_sub, Wb, top=0.0)
    np.testing.assert_allclose(res.body_position, [5.0, -1.0, ref.bottom_z], atol=1e-8)
    # shape along s (s from the body = L0 - s_from_top)
    np.testing.assert_allclose(res.r[:, 2], ref.z(200.0 - res.s), atol=1e-8)
    np.testing.assert_allclose(res.tension, ref.tension(200.0 - res.s), rtol=1e-10)


def test_still_water_tow_point_above_waterline():
    """Vertical cable crossing the waterline: the dry part carries its full
    weight; the crossing is where a hand calculation puts it."""
    seg = _steel(EA=2e5)  # soft, so the stretch of the dry part matters
    water = st.Water(current=(0, 0, 0), z_waterline=0.0)
    body = st.TowedBody(mass=100.0, volume=0.02)
    Wb = (100.0 - 1026.0 * 0.02) * G0
    w_air = 0.389 * G0
    w_sub = w_air - 1026.0 * seg.area * G0
    ztop = 3.4
    res = st.solve_steady_tow([seg], body, water, (0.0, 0.0, ztop))

    # hand: dry unstretched length a with a + (T_wl a + w_air a^2/2)/EA = ztop
    def dry_height(a):
        T_wl = Wb + w_sub * (200.0 - a)
        return a + (T_wl * a + 0.5 * w_air * a * a) / seg.EA - ztop

    a = optimize.brentq(dry_height, 0.0, ztop, xtol=1e-14)
    assert len(res.waterline_s) == 1
    assert res.waterline_s[0] == pytest.approx(200.0 - a, abs=1e-7)
    assert res.tension_top == pytest.approx(Wb + w_sub * (200.0 - a) + w_air * a, rel=1e-10)
    wet = cat.hanging_cable(200.0 - a, seg.EA, w_sub, Wb, top=0.0)
    assert res.body_position[2] == pytest.approx(wet.bottom_z, abs=1e-7)


def test_no_cable_loads_gives_straight_cable_along_body_force():
    """Weightless, neutrally buoyant cable without drag: straight along -F_b,
    stretched by |F_b|/EA; the body force includes weight, drag and lift."""
    seg = st.CableSegment(150.0, 0.02, 1026.0 * np.pi * 0.02**2 / 4, 1e5,
                          loading=(lambda e: 0.0, lambda e: 0.0))
    water = st.Water(current=(-1.5, 0.4, 0.0), z_waterline=0.0)
    body = st.TowedBody(mass=60.0, volume=0.05, cd_area=(0.3, 0.5, 0.8), lift=(0.0, 30.0, -200.0))
    top = np.array([1.0, 2.0, -0.5])
    res = st.solve_steady_tow([seg], body, water, top)
    Fb = np.array([0.5 * 1026 * 0.3 * -1.5 * 1.5, 0.5 * 1026 * 0.5 * 0.4**2 + 30.0,
                   -(60.0 - 1026 * 0.05) * G0 - 200.0])
    np.testing.assert_allclose(res.body_force, Fb, rtol=1e-12)
    F = np.linalg.norm(Fb)
    expected = top + Fb / F * 150.0 * (1.0 + F / 1e5)
    np.testing.assert_allclose(res.body_position, expected, atol=1e-8)
    np.testing.assert_allclose(res.tension, F, rtol=1e-12)
    # every point on the straight line
    u = -Fb / F
    rel = res.r - res.body_position
    np.testing.assert_allclose(np.cross(rel, u), 0.0, atol=1e-8)


def test_cable_streams_along_flow_when_body_has_only_drag():
    """Neutral, weightless cable with bare f_n (f_n(0) = 0) and no tangential
    drag, neutral body with drag only: the cable lies along the flow."""
    seg = st.CableSegment(100.0, 0.01, 1026.0 * np.pi * 0.01**2 / 4, 1e6,
                          loading=(st.fn_bare, lambda e: 0.0))
    water = st.Water(current=(-2.0, 0.0, 0.0), z_waterline=10.0)
    body = st.TowedBody(mass=1026.0 * 0.1, volume=0.1, cd_area=(0.5, 0.5, 0.5))
    res = st.solve_steady_tow([seg], body, water, (0.0, 0.0, -5.0))
    D = 0.5 * 1026.0 * 0.5 * 4.0
    np.testing.assert_allclose(res.body_position, [-100.0 * (1 + D / 1e6), 0.0, -5.0], atol=1e-8)
    np.testing.assert_allclose(res.tension_top, D, rtol=1e-10)
    assert res.top_angle == pytest.approx(np.pi / 2, abs=1e-9)


@pytest.mark.parametrize("loading,G,U,eta_lo", [("bare", 1.0, 2.2, 0.15), ("faired", 3.54, 2.2, 1e-3),
                                                ("bare", 1.737, 0.3, 0.15)])
def test_critical_angle_straight_cable(loading, G, U, eta_lo):
    """If the body force points along the critical angle, the cable is straight
    at that angle: normal drag G*q*f_n(eta)*(C_D(Re_n)) balances the normal
    component of the submerged weight, w_sub cos(eta) (independent root solve)."""
    rho, mu = 1026.0, 1.2e-3
    seg = st.CableSegment(300.0, 0.01, 0.389, 6.786e6, loading, G)
    fn = st.LOADING_FUNCTIONS[loading][0]
    w_sub = (0.389 - rho * seg.area) * G0

    def normal_balance(eta):
        re_n = rho * 0.01 * U * np.sin(eta) / mu
        q = G * 0.5 * rho * 0.01 * st.drag_coefficient(re_n) * U**2
        return q * fn(eta) - w_sub * np.cos(eta)

    eta = optimize.brentq(normal_balance, eta_lo, np.pi / 2, xtol=1e-15)
    u = np.array([np.cos(eta), 0.0, np.sin(eta)])  # from the body up to the tow point
    F0 = 500.0
    body = st.TowedBody(mass=10.0, volume=10.0 / rho, lift=tuple(-F0 * u))
    water = st.Water(rho=rho, mu=mu, current=(-U, 0.0, 0.0), z_waterline=50.0)
    res = st.solve_steady_tow([seg], body, water, (0.0, 0.0, 0.0))
    assert res.top_angle == pytest.approx(np.pi / 2 - eta, abs=1e-8)
    rel = res.r - res.body_position
    np.testing.assert_allclose(np.cross(rel, u), 0.0, atol=1e-6)
    # tension grows upward by the tangential loads (weight + tangential drag)
    assert np.all(np.diff(res.tension) > 0)


def test_catenary_cross_check_no_current():
    """No current, horizontal pull on the body: the steady-tow cable is an
    elastic catenary with H = pull, V_A = -body weight (two independent codes)."""
    seg = st.CableSegment(120.0, 0.01, 0.389, 5e5)
    water = st.Water(rho=1026.0, current=(0, 0, 0), z_waterline=100.0)
    body = st.TowedBody(mass=50.0, volume=0.01, lift=(-300.0, 0.0, 0.0))
    res = st.solve_steady_tow([seg], body, water, (0.0, 0.0, 0.0))
    w_sub = (0.389 - 1026.0 * seg.area) * G0
    Wb = (50.0 - 10.26) * G0
    span, height = -res.body_position[0], -res.body_position[2]
    c = cat.solve_elastic_catenary(120.0, 5e5, w_sub, span, height)
    assert c.H == pytest.approx(300.0, rel=1e-8)
    assert c.V_A == pytest.approx(-Wb, rel=1e-8)
    assert c.tension_B == pytest.approx(res.tension_top, rel=1e-9)
    np.testing.assert_allclose(c.x(res.s, ) + res.body_position[0], res.r[:, 0], atol=1e-7)
    np.testing.assert_allclose(c.z(res.s) + res.body_position[2], res.r[:, 2], atol=1e-7)
    np.testing.assert_allclose(c.tension(res.s), res.tension, rtol=1e-9)


@pytest.fixture(scope="module")
def full_scale():
    return st.full_scale_case()


@pytest.fixture(scope="module")
def flume():
    return st.flume_case()


def _global_balance(res):
    """-(F_b + integral of f ds) by Simpson per integration piece."""
    total = res.body_force.copy()
    for s0, s1, dsol, idx, wet in res.pieces:
        ss = np.linspace(s0, s1, 4001)
        Y = dsol(ss)
        f = np.array([st.cable_load_per_length(Y[:3, k], Y[3:, k], res.segments[idx], res.water,
                                               submerged=wet, stretch_loads=res.stretch_loads)
                      for k in range(ss.size)])
        total += integrate.simpson(f, x=ss, axis=0)
    return -total


@pytest.mark.parametrize("case", ["full_scale", "flume"])
def test_global_force_balance(case, request):
    """Top tension vector = -(body force + all loads on the cable), the loads
    re-evaluated independently along the returned shape."""
    res = request.getfixturevalue(case)
    bal = _global_balance(res)
    np.testing.assert_allclose(res.tension_top_vector, bal, rtol=0, atol=1e-7 * res.tension_top)
    assert res.residual < 1e-7
    np.testing.assert_allclose(res.r[-1], res.tow_point, atol=1e-7)
    np.testing.assert_allclose(res.T[0], -res.body_force, rtol=1e-12)
    # the wet/dry switch sits on the waterline
    for s_wl in res.waterline_s:
        r, _ = res.state_at(s_wl)
        assert r[2] == pytest.approx(res.water.z_waterline, abs=1e-9)
    assert np.all(res.r[res.submerged][:, 2] <= res.water.z_waterline + 1e-9)
    assert np.all(res.r[~res.submerged][:, 2] >= res.water.z_waterline - 1e-9)


def test_full_scale_scene_inputs(full_scale):
    res = full_scale
    assert res.segments[0].EA == pytest.approx(6.786e6)
    assert [s.loading for s in res.segments] == ["bare", "faired"]
    assert res.body.lift[2] == pytest.approx(-0.5 * 1026 * 2.2**2 * 0.5 * 0.6, rel=1e-14)
    assert res.body.lift[2] == pytest.approx(-744.876, rel=1e-6)
    Fg = (res.body.mass - res.water.rho * res.body.volume) * G0
    assert Fg == pytest.approx(445.0, rel=1e-12)
    # body force by hand: drag x = -0.5*1026*(0.85*pi*0.15^2 + 0.008*0.5)*2.2^2
    dx = -0.5 * 1026 * (0.85 * np.pi * 0.0225 + 0.004) * 4.84
    np.testing.assert_allclose(res.body_force, [dx, 0.0, -445.0 - 744.876], rtol=1e-6)
    # the body trails downstream (flow along -x) and below the surface
    assert res.body_position[0] < -100 and res.body_position[2] < -10
    assert len(res.waterline_s) == 1


def test_full_scale_bare_vs_faired_differs(full_scale):
    """The faired segment really uses W(145): all-bare gives another answer."""
    segs, body, water, top = st.full_scale_scene()
    bare = [st.CableSegment(450.0, 0.01, 0.389, segs[0].EA, "bare", 3.54)]
    res = st.solve_steady_tow(bare, body, water, top)
    assert abs(res.body_position[2] - full_scale.body_position[2]) > 1.0


def test_flume_sphere_cd_matches_standard_curve(flume):
    res = flume
    v = res.water.velocity(res.body_position[2])
    re = 1026.0 * 0.010 * np.linalg.norm(v) / 1.2e-3
    assert st.sphere_drag_coefficient(re) == pytest.approx(st.SPHERE_CD, rel=0.03)
    assert st.sphere_drag_coefficient(1e3) == pytest.approx(0.47, rel=0.05)  # textbook value
    assert res.segments[0].EA == pytest.approx(1.4e9 * np.pi * 0.45e-3**2 / 4)
    assert res.body_position[2] < res.water.z_waterline


@pytest.mark.parametrize("case", ["full_scale", "flume"])
def test_converges_with_tolerance(case, request):
    """Body position and top tension settle as the ODE tolerance tightens."""
    fine = request.getfixturevalue(case)
    fun = st.full_scale_case if case == "full_scale" else st.flume_case
    mid = fun(rtol=1e-8)
    coarse = fun(rtol=1e-6)
    L = fine.length
    e_mid = np.linalg.norm(mid.body_position - fine.body_position)
    e_coarse = np.linalg.norm(coarse.body_position - fine.body_position)
    assert e_mid < 1e-6 * L
    assert e_mid <= e_coarse + 1e-12 * L
    assert mid.tension_top == pytest.approx(fine.tension_top, rel=1e-7)
    # dense shape agrees too
    for s in np.linspace(0.0, L, 7):
        np.testing.assert_allclose(mid.state_at(s)[0], fine.state_at(s)[0], atol=1e-6 * L)


def test_stretch_loads_option_is_small_and_in_the_right_direction(full_scale):
    """Loads per stretched length add ~eps = T/EA (< 1e-3) more buoyancy and drag."""
    res = st.full_scale_case(stretch_loads=True)
    d = res.body_position - full_scale.body_position
    assert 0 < np.linalg.norm(d) < 1e-3 * full_scale.length
    assert res.tension_top > full_scale.tension_top  # more drag


def test_amplification_G_means_total_drag():
    """G scales the whole steady drag: G = 2 on a cable equals G = 1 on a cable
    with twice the constant C_D (not 1 + G)."""
    water = st.Water(current=(-1.0, 0.0, 0.0), z_waterline=0.0)
    body = st.TowedBody(mass=80.0, volume=0.02, cd_area=(0.2, 0.2, 0.2))
    a = st.solve_steady_tow([_steel(cd=1.2, G=2.0)], body, water, (0, 0, 0))
    b = st.solve_steady_tow([_steel(cd=2.4, G=1.0)], body, water, (0, 0, 0))
    np.testing.assert_allclose(a.body_position, b.body_position, atol=1e-8)
