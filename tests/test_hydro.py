"""Hydrodynamics: loading functions, steady towing, buoyancy, added mass, terminal velocity,
turbulence, and what a scene skips."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import TermPart, cable_scene, segment
from scipy.optimize import brentq

from reference import steady_tow as ref_tow
from towcable_fmu.ancf.system import iteration_matrix, residual
from towcable_fmu.hydro.loading import (
    BARE,
    FAIRED,
    NORMAL_TANGENTIAL,
    SUN_BARE,
    SUN_FAIRED,
    drag_coefficient,
    drag_coefficient_slope,
    loading_functions,
    loading_slopes,
)
from towcable_fmu.hydro.turbulence import TurbulenceSeries
from towcable_fmu.scene import scene_from_table
from towcable_fmu.scene.model import Turbulence
from towcable_fmu.ancf.simulation import Simulation

G = 9.81
RHO = 1025.0


# ----------------------------------------------------------------- loading functions
def _fn_ft(kind, eta):
    return loading_functions(kind, math.cos(eta), math.sin(eta))


def test_bare_loading_functions_hand_values():
    # W(60) at eta = 90 deg: f_n = 0.5 + 0.1 + 0.4 = 1; f_t = 0.01 * polynomial
    fn, ft = _fn_ft(BARE, math.pi / 2)
    e = math.pi / 2
    assert fn == pytest.approx(1.0, abs=1e-12)
    assert ft == pytest.approx(0.01 * (2.009 - 0.3858 * e + 1.9159 * e**2 - 4.1615 * e**3 + 3.5064 * e**4
                                       - 1.1873 * e**5), abs=1e-12)
    # eta = 30 deg by hand: 0.5 - 0.1*0.8660 + 0.1*0.5 - 0.4*0.5 - 0.11*0.8660 = 0.068147
    fn, ft = _fn_ft(BARE, math.radians(30))
    assert fn == pytest.approx(0.5 - 0.0866025 + 0.05 - 0.2 - 0.0952628, abs=1e-6)
    e = math.radians(30)
    assert ft == pytest.approx(0.01 * (2.009 - 0.3858 * e + 1.9159 * e**2 - 4.1615 * e**3 + 3.5064 * e**4
                                       - 1.1873 * e**5), rel=1e-12)


def test_faired_loading_functions_hand_values():
    # W(145) at eta = 0: f_n = 0.498609 - 0.2499 - 0.2487; f_t (W(145b)) = -0.2255 + 0.3417
    fn, ft = _fn_ft(FAIRED, 0.0)
    assert fn == pytest.approx(0.498609 - 0.2499 - 0.2487, abs=1e-12)
    assert ft == pytest.approx(-0.2255 + 0.3417, abs=1e-12)
    fn, ft = _fn_ft(FAIRED, math.pi / 2)
    assert fn == pytest.approx(0.498609 + 0.2527 + 0.2487, abs=1e-12)
    assert ft == pytest.approx(-0.2255 + 0.255, abs=1e-12)


def test_sun2011_bare_loading_functions_hand_values():
    # eq. 28: f_n = sin^2 a; f_t = -0.019 + 0.0239 cos a + 0.02 sin a + 0.001 cos 2a
    fn, ft = _fn_ft(SUN_BARE, 0.0)
    assert fn == pytest.approx(0.0, abs=1e-15)
    assert ft == pytest.approx(-0.019 + 0.0239 + 0.001, abs=1e-12)  # 0.0059 along the flow
    fn, ft = _fn_ft(SUN_BARE, math.pi / 2)
    assert fn == pytest.approx(1.0, abs=1e-12)
    assert ft == pytest.approx(0.0, abs=1e-12)  # -0.019 + 0.02 - 0.001 = 0: no drag along a normal flow
    fn, ft = _fn_ft(SUN_BARE, math.radians(45))
    assert fn == pytest.approx(0.5, abs=1e-12)
    assert ft == pytest.approx(-0.019 + 0.0439 / math.sqrt(2.0), abs=1e-12)


def test_sun2011_faired_loading_functions_hand_values_and_continuity():
    # eq. 29: g = 0.273 + 0.827 a^2 below 30 deg, sin a above; f_n = g sin a, f_t = g cos a
    fn, ft = _fn_ft(SUN_FAIRED, 0.0)
    assert (fn, ft) == pytest.approx((0.0, 0.273), abs=1e-12)
    a = math.radians(20)
    g = 0.273 + 0.827 * a * a
    assert _fn_ft(SUN_FAIRED, a) == pytest.approx((g * math.sin(a), g * math.cos(a)), abs=1e-12)
    assert _fn_ft(SUN_FAIRED, math.pi / 2) == pytest.approx((1.0, 0.0), abs=1e-12)
    below = _fn_ft(SUN_FAIRED, math.pi / 6 - 1e-9)
    above = _fn_ft(SUN_FAIRED, math.pi / 6 + 1e-9)
    # the branches meet to within 3e-4 at 30 deg (0.4997 against 0.5)
    assert below == pytest.approx(above, abs=3e-4)


def test_drag_coefficient_hand_values_and_continuity():
    assert drag_coefficient(100.0) == pytest.approx(1.1 + 4.0 / 10.0, rel=1e-12)
    assert drag_coefficient(1e4) == pytest.approx(1.1 + 4.0 / 100.0, rel=1e-12)
    assert drag_coefficient(10.0) == pytest.approx(1.45 + 8.55 * 10.0**-0.9, rel=1e-12)
    s = -0.077215665 + math.log(8.0 / 0.5)
    assert drag_coefficient(0.5) == pytest.approx(8 * math.pi / (0.5 * s) * (1 - 0.87 / s**2), rel=1e-12)
    # the printed branches jump at Re = 1 and 30; the blend makes C_D continuous
    re = np.exp(np.linspace(np.log(0.2), np.log(200.0), 20001))
    cd = np.array([drag_coefficient(r) for r in re])
    assert np.max(np.abs(np.diff(cd)) / cd[:-1]) < 2e-3


def test_drag_coefficient_slope_matches_central_differences_in_log_re():
    """Re dC_D/dRe against central differences of C_D in log Re over all three branches and
    both blends (Re 2e-3 to 1e5; the blends' edges, where the slope jumps, left out)."""
    edges = np.log([1.0 / 1.1, 1.1, 30.0 / 1.1, 30.0 * 1.1])
    x = np.linspace(np.log(2e-3), np.log(1e5), 2001)
    x = x[np.min(np.abs(x[:, None] - edges[None, :]), axis=1) > 1e-3]
    hx = 1e-6
    for xi in x:
        fd = (drag_coefficient(math.exp(xi + hx)) - drag_coefficient(math.exp(xi - hx))) / (2 * hx)
        assert drag_coefficient_slope(math.exp(xi)) == pytest.approx(fd, rel=1e-6, abs=1e-9)
    assert drag_coefficient_slope(1e-4) == 0.0  # C_D is held constant below RE_MIN


@pytest.mark.parametrize("kind", [BARE, FAIRED, SUN_BARE, SUN_FAIRED])
def test_loading_slopes_match_central_differences_in_the_flow_angle(kind):
    """(df_n/deta, df_t/deta) against central differences of the loading functions over
    0 < eta < 90 deg (the faired nodal-position functions' break at 30 deg left out)."""
    h = 1e-6
    for eta in np.linspace(0.01, math.pi / 2 - 0.01, 300):
        if kind == SUN_FAIRED and abs(eta - math.pi / 6) < 0.01:
            continue
        plus = loading_functions(kind, math.cos(eta + h), math.sin(eta + h))
        minus = loading_functions(kind, math.cos(eta - h), math.sin(eta - h))
        slopes = loading_slopes(kind, math.cos(eta), math.sin(eta))
        for s, p, m in zip(slopes, plus, minus):
            assert s == pytest.approx((p - m) / (2 * h), rel=1e-6, abs=1e-8)


# ----------------------------------------------------------------- steady towing
def _full_scale(elements_bare: int, elements_faired: int):
    sim = Simulation.from_scene("full_scale_pinned", {"cable.segments[0].elements": elements_bare,
                                               "cable.segments[1].elements": elements_faired})
    return sim.initialize()


def test_full_scale_steady_tow_matches_independent_solution_and_converges():
    ref = ref_tow.full_scale_case()  # tow point (0, 0, 3.4); ours is (-28.8, 0, 3.4)
    errors = []
    for n in (7, 14, 28):
        out = _full_scale(2 * n, n)
        errors.append((abs(out["tension.top"] / ref.tension_top - 1),
                       abs(out["towbody.z"] / ref.body_position[2] - 1),
                       abs((out["towbody.x"] + 28.8) / ref.body_position[0] - 1),
                       abs(out["tension.towbody"] / ref.tension_body - 1)))
    errors = np.array(errors)
    assert np.all(errors[-1] < 0.01)  # within 1 % on a fine mesh (measured: 0.2 %, 0.1 %)
    assert errors[-1, 0] < errors[0, 0] and errors[-1, 1] < errors[0, 1]


def test_flume_steady_tow_matches_independent_solution():
    ref = ref_tow.flume_case()
    errors = []
    for n in (6, 12, 24):
        sim = Simulation.from_scene("flume_pinned", {"cable.segments[0].elements": n})
        out = sim.initialize()
        errors.append((abs(out["tension.top"] / ref.tension_top - 1),
                       abs(out["towbody.z"] / ref.body_position[2] - 1),
                       abs(out["towbody.x"] / ref.body_position[0] - 1)))
    errors = np.array(errors)
    assert np.all(errors[-1] < 0.01)
    assert errors[-1].max() < errors[0].max()


def test_vertical_cable_tension_kinks_at_the_waterline_by_the_buoyancy():
    """Tension of a cable hanging through the surface: slope mu g above, (mu - rho A) g below."""
    mu, d, m, length = 1.0, 0.02, 10.0, 20.0
    area = math.pi * d**2 / 4
    table = cable_scene([segment(length, 10, mu=mu, EA=1e9, EI=1e-3, diameter=d)],
                        top={"type": "pinned", "position": [0.0, 0.0, 5.0]}, towbody={"mass": m},
                        water={"density": RHO})
    sim = Simulation(scene_from_table(table))
    sim.initialize()
    arc, tension = sim.tension_profile()
    s_wl = 5.0  # the waterline, 5 m below the top (stretch ~1e-7)
    expected = m * G + mu * G * (length - arc) - RHO * area * G * (length - np.maximum(arc, s_wl))
    # the strain of cubic elements approximates the kink: within 0.2 % in the element that
    # crosses the surface, 0.1 % elsewhere (the support reaction and the force on the
    # body, below, are exact)
    crossing = (arc >= 4.0) & (arc <= 6.0)
    np.testing.assert_allclose(tension[~crossing], expected[~crossing], rtol=1e-3)
    np.testing.assert_allclose(tension[crossing], expected[crossing], rtol=2e-3)
    assert sim.outputs()["tension.top"] == pytest.approx(expected[0], rel=1e-7)
    assert sim.outputs()["tension.towbody"] == pytest.approx(m * G, rel=1e-7)
    above = (arc < 4.0)
    below = (arc > 6.0)
    slope_above = np.polyfit(arc[above], tension[above], 1)[0]
    slope_below = np.polyfit(arc[below], tension[below], 1)[0]
    assert slope_below - slope_above == pytest.approx(RHO * area * G, rel=1e-2)


# ----------------------------------------------------------------- dynamics in water
def _submerged(body: dict, seg: dict, solver: dict) -> Simulation:
    """A cable hanging from (0, 0, -1), below the surface z = 0."""
    table = cable_scene([seg], top={"type": "pinned", "position": [0.0, 0.0, -1.0]}, towbody=body,
                        water={"density": RHO}, solver=solver)
    return Simulation(scene_from_table(table))


def _period(t, y):
    y = y - y.mean()
    idx = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    times = t[idx] - y[idx] * (t[idx + 1] - t[idx]) / (y[idx + 1] - y[idx])
    return float(np.mean(np.diff(times)))


def test_axial_oscillation_under_water_uses_body_added_mass_but_no_axial_cable_added_mass():
    """Added mass acts normal to the cable only (W(66)-(74)): in an axial oscillation the
    cable contributes its structural mass, the body its mass plus rho V C_m,b."""
    length, mu, d, ea = 10.0, 1.0, 0.05, 1e6
    m_b, volume, cmb = 20.0, 0.004, 0.5
    sim = _submerged({"mass": m_b, "volume": volume, "added_mass_coefficient": [cmb, cmb, cmb]},
                     segment(length, 10, mu=mu, EA=ea, EI=1e-3, diameter=d, drag_coefficient=1e-9),
                     {"time_step": 2e-4, "rho_inf": 1.0})
    sim.initialize()
    z_eq = sim.outputs()["towbody.z"]
    v = np.zeros_like(sim.state.q).reshape(-1, 2, 3)
    v[:, 0, 2] = -0.02 * sim.mesh.node_arc / length
    sim.set_coordinates(sim.state.q, v.ravel())
    res = sim.run(0.6, interval=4e-4)
    omega = 2 * np.pi / _period(res["time"], res["towbody.z"] - z_eq)
    big_m = m_b + RHO * volume * cmb
    beta = brentq(lambda b: b * np.tan(b) - mu * length / big_m, 1e-6, np.pi / 2 - 1e-9)
    assert omega == pytest.approx(beta * np.sqrt(ea / mu) / length, rel=3e-3)
    # had the cable's added mass acted along it, the frequency would be 12 % lower
    mu_wrong = mu + RHO * math.pi * d**2 / 4
    beta_w = brentq(lambda b: b * np.tan(b) - mu_wrong * length / big_m, 1e-6, np.pi / 2 - 1e-9)
    assert beta_w * np.sqrt(ea / mu_wrong) / length < 0.9 * omega


def test_pendulum_under_water_period_with_added_mass():
    """Small swing of a submerged body on a cable (a rigid pendulum: the cable stays straight):
    omega^2 = restoring moment / inertia with the net weights and the normal added masses."""
    length, mu, d = 5.0, 0.5, 0.03
    m_b, volume, cmb = 50.0, 0.01, 0.5
    area = math.pi * d**2 / 4
    sim = _submerged({"mass": m_b, "volume": volume, "added_mass_coefficient": [cmb, cmb, cmb]},
                     segment(length, 8, mu=mu, EA=1e7, EI=1e-2, diameter=d, drag_coefficient=1e-9),
                     {"time_step": 5e-3})
    sim.initialize()
    # rotate the hanging equilibrium about the top by a small angle
    angle = 0.03
    rot = np.array([[np.cos(angle), 0.0, np.sin(angle)], [0.0, 1.0, 0.0], [-np.sin(angle), 0.0, np.cos(angle)]])
    q = sim.state.q.copy().reshape(-1, 2, 3)
    top = np.array([0.0, 0.0, -1.0])
    q[:, 0, :] = (q[:, 0, :] - top) @ rot.T + top
    q[:, 1, :] = q[:, 1, :] @ rot.T
    sim.set_coordinates(q.ravel())
    res = sim.run(30.0, interval=0.01)
    moment = (m_b - RHO * volume) * G * length + (mu - RHO * area) * G * length**2 / 2
    inertia = (m_b + RHO * volume * cmb) * length**2 + (mu + RHO * area * 1.0) * length**3 / 3
    period = 2 * np.pi / math.sqrt(moment / inertia)
    assert _period(res["time"], res["towbody.x"]) == pytest.approx(period, rel=5e-3)


def test_body_released_in_still_water_reaches_terminal_velocity():
    """A free body with a short line falls at the speed where net weight = drag."""
    m_b, volume, dia = 5.0, 1e-3, 0.2
    cda = 0.5 * math.pi * dia**2 / 4
    mu, d, length = 0.05, 0.005, 1.0
    table = cable_scene([segment(length, 2, mu=mu, EA=1e6, EI=1e-3, diameter=d)],
                        top={"type": "free", "position": [0.0, 0.0, -10.0]}, bottom={"type": "free"},
                        towbody={"mass": m_b, "volume": volume, "added_mass_coefficient": [0.5, 0.5, 0.5],
                                 "parts": [{"area": [math.pi * dia**2 / 4] * 3, "drag_coefficient": [0.5] * 3}]},
                        water={"density": RHO, "viscosity": 1.2e-3}, statics={"enabled": False},
                        solver={"time_step": 0.01})
    sim = Simulation(scene_from_table(table))
    sim.initialize()
    res = sim.run(15.0, interval=0.1)
    net = (m_b - RHO * volume) * G + (mu - RHO * math.pi * d**2 / 4) * G * length

    def balance(v):
        skin = 0.5 * RHO * d * ref_tow.drag_coefficient(RHO * d * v / 1.2e-3) * ref_tow.ft_bare(0.0) * v**2
        return 0.5 * RHO * cda * v**2 + skin * length - net

    v_term = brentq(balance, 0.01, 20.0)
    assert -res["towbody.vz"][-1] == pytest.approx(v_term, rel=2e-3)
    assert abs(res["towbody.vx"][-1]) < 1e-6  # straight down


# ----------------------------------------------------------------- turbulence
def test_turbulence_standard_deviation_reproducibility_and_blocks():
    cfg = Turbulence(std=(0.03, 0.0262, 0.0152), cutoff=2.0, seed=7)
    a = TurbulenceSeries(cfg)
    a.extend_to(7200.0)
    np.testing.assert_allclose(a.samples.std(axis=0), cfg.std, rtol=0.03)
    b = TurbulenceSeries(cfg)
    b.extend_to(100.0)
    b.extend_to(7200.0)
    np.testing.assert_array_equal(a.samples, b.samples)  # built in blocks: the same series
    c = TurbulenceSeries(Turbulence(std=cfg.std, cutoff=2.0, seed=8))
    c.extend_to(10.0)
    assert not np.allclose(c.samples[:100], a.samples[:100])
    # low-pass: almost no power above the stop-band edge
    spec = np.abs(np.fft.rfft(a.samples[:, 0])) ** 2
    freq = np.fft.rfftfreq(a.samples.shape[0], a.dt)
    assert spec[freq > 3.0].sum() < 1e-4 * spec.sum()


def test_flume_run_with_turbulence_moves_the_sphere_and_is_reproducible():
    outs = []
    for _ in range(2):
        sim = Simulation.from_scene("flume_pinned")
        sim.initialize()
        outs.append(sim.run(5.0, interval=0.05))
    np.testing.assert_array_equal(outs[0]["towbody.z"], outs[1]["towbody.z"])
    assert np.std(outs[0]["towbody.y"]) > 1e-5  # the cross-flow turbulence moves it sideways


def test_flume_sphere_in_turbulence_only_moves_as_the_reference_model():
    """Westin 2018, Table 4 (the flume, no winch motion, turbulence only): the reference's
    own model of this system gives the sphere a 95 % ellipsoid of 7.76 cm^3 with standard
    deviations 1.56 / 1.23 cm along X_E / Y_E. The flume scene is that model with our
    turbulence filter; in each 40 s window after 10 s of settling it must agree to within
    the window-to-window spread found in docs/studies/flume_turbulence (15 windows: the
    standard deviations within 35 %, the volume within a factor 3)."""
    from towcable_fmu.analysis import enclosing_ellipsoid

    sim = Simulation.from_scene("flume")
    sim.initialize()
    res = sim.run(90.0, interval=0.02)
    track = np.column_stack([res["towbody.x"], res["towbody.y"], res["towbody.z"]])
    for start in (10.0, 50.0):
        inside = (res["time"] >= start - 1e-9) & (res["time"] < start + 40.0 - 1e-9)
        ell = enclosing_ellipsoid(track[inside])
        std = ((track[inside] - ell.centre) @ ell.axes.T).std(axis=0)
        assert std[0] == pytest.approx(1.56e-2, rel=0.35)
        assert std[1] == pytest.approx(1.23e-2, rel=0.35)
        assert 7.76e-6 / 3.0 < ell.volume < 3.0 * 7.76e-6


# ----------------------------------------------------------------- what a scene skips
def test_dry_scene_never_calls_the_hydrodynamic_kernels():
    sim = Simulation.from_scene("hanging_cable")
    sim.initialize()
    sim.run(1.0)
    assert not sim.model.water.enabled
    assert sim.model.terms.hydrodynamics.calls[0] == 0 and sim.model.terms.towbody.calls[0] == 0


def test_elements_above_the_water_cost_no_hydrodynamics():
    sim = Simulation.from_scene("full_scale_pinned", {"water.surface_z": -1000.0})
    sim.initialize()
    sim.run(0.5)
    assert sim.model.terms.hydrodynamics.calls[0] == 0 and sim.model.terms.towbody.calls[0] == 0
    wet = Simulation.from_scene("full_scale_pinned")
    wet.initialize()
    assert wet.model.terms.hydrodynamics.calls[0] > 0 and wet.model.terms.towbody.calls[0] > 0


def test_wet_scene_without_a_towed_body_never_calls_the_body_kernel():
    from towcable_fmu.scene import scene_from_table

    table = cable_scene([segment(20.0, 8, mu=0.5, EA=1e6, EI=0.1, diameter=0.02)],
                        top={"type": "pinned", "position": [0.0, 0.0, 0.0]},
                        water={"density": 1025.0, "current": {"type": "uniform", "velocity": [-1.0, 0.0, 0.0]}})
    sim = Simulation(scene_from_table(table))
    sim.initialize()
    sim.run(0.5)
    assert sim.model.terms.hydrodynamics.calls[0] > 0
    assert not sim.model.terms.towbody.enabled and sim.model.terms.towbody.calls[0] == 0


def test_no_impulse_when_an_element_enters_the_water():
    """The hydrodynamic generalised force changes continuously as an element is lowered
    through the surface (partial-element quadrature W(78)-(80))."""
    from towcable_fmu.scene import scene_from_table

    table = cable_scene([segment(2.0, 1, mu=0.1, EA=1e6, diameter=0.05, integration_points=5)],
                        top={"type": "pinned", "position": [0.0, 0.0, 0.0]},
                        water={"density": RHO, "surface_z": 0.0})
    sim = Simulation(scene_from_table(table))
    m = sim.model
    zero = np.zeros(12)
    forces = []
    shifts = np.linspace(-0.1, 2.1, 2201)  # element from fully dry to fully wet, 1 mm steps
    for dz in shifts:
        q = np.array([0, 0, 1 - dz, 0, 0, -1, 0, 0, -1 - dz, 0, 0, -1.0])
        r = np.zeros(12)
        residual(m, q, zero, zero, 0.0, np.zeros((3, 6)), r)
        forces.append(r - residual_dry(m, q))
    forces = np.array(forces)
    step = np.abs(np.diff(forces, axis=0)).max()
    buoyancy_per_m = RHO * math.pi * 0.05**2 / 4 * G
    assert step < 2e-3 * buoyancy_per_m * 2.0  # Lipschitz: 1 mm of wet length at a time
    assert np.abs(forces[-1]).max() > 0.5 * buoyancy_per_m  # and fully wet it does carry the load


def residual_dry(model, q):
    """The same element's residual without water."""
    dry = model._replace(water=model.water._replace(enabled=False))
    r = np.zeros(12)
    zero = np.zeros(12)
    residual(dry, q, zero, zero, 0.0, np.zeros((3, 6)), r)
    return r


@pytest.mark.parametrize("scene", ["flume_pinned", "full_scale_pinned"])
def test_newton_with_the_assembled_jacobian_converges(scene):
    """From a slightly perturbed equilibrium, Newton steps with the compiled iteration matrix
    (stiffness part) reduce the residual a thousandfold in four steps: the tangents of
    drag, current profile and waterline crossing are consistent with the residual (with the
    crossing tangent missing, Newton stalls at a few per cent of the start)."""
    from towcable_fmu.numerics.banded import band_lu, band_solve, band_storage

    sim = Simulation.from_scene(scene)
    sim.initialize()
    m = sim.model
    q = sim.state.q.copy()
    free = m.free_dofs
    rng = np.random.default_rng(1)
    q[free] += 1e-6 * m.el_len.min() * rng.standard_normal(free.size)
    v = np.zeros_like(q)
    r = np.zeros_like(q)
    ship = np.zeros((3, 6))
    n = free.size
    norms = []
    for _ in range(5):
        residual(m, q, v, v, 0.0, ship, r)
        norms.append(np.abs(r[free]).max())
        ab = band_storage(n, m.kl, m.ku)
        iteration_matrix(m, q, v, 0.0, ship, 0.0, 0.0, 1.0, ab)
        ipiv = np.zeros(n, dtype=np.int64)
        band_lu(ab, n, m.kl, m.ku, ipiv)
        dx = -r[free]
        band_solve(ab, n, m.kl, m.ku, ipiv, dx)
        q[free] += dx
    assert norms[4] < 1e-3 * norms[0]


#: snapping_cable with the bare-cable loading functions and a constant C_D (its kink along the
#: flow is a cone, whose central differences converge to the tangent's mean); its own
#: normal/tangential drag, rho d C_D |V_n| V_n / 2 along the flow, has central differences
#: off by O(step) there, checked point by point in the drag tests instead
SNAP_BARE = {"cable.segments[0].loading": "bare", "cable.segments[0].tangential_drag_coefficient": None}


@pytest.mark.parametrize("scene, t_run, h, overrides", [("full_scale", 0.5, 0.05, {}),
                                                        ("snapping_cable", 0.05, 5e-4, SNAP_BARE),
                                                        ("flume", 0.1, 2e-3, {}),
                                                        ("full_scale", 1.5, 0.05, {"water.waves": "motion",
                                                                                    "motion.ramp": 1.0})])
def test_iteration_matrix_water_part_matches_central_differences_of_the_residual(scene, t_run, h, overrides):
    """In a running scene, the part of the iteration matrix ``M + cv C + cq K`` that the water
    adds (the matrix minus that of the same state with the water disabled: cable and body
    hydrodynamics) against central differences of the residual's water part.
    full_scale: bare and faired cable, C_D(Re), G = 3.54, a cable crossing the surface;
    snapping_cable (with SNAP_BARE): constant C_D; flume: a current varying with depth, turbulence;
    full_scale in the motion's waves (Wheeler, the wave kinematics moving with the point).

    * As Newton uses it: a + da, v + cv da, q + cq da with the integrator's weights at
      step h (cv = h/2, cq = h^2/4) and a position change of 1e-8 m (smaller and round-off
      dominates), at the state's own accelerations: to 1e-6 of the largest entry.
    * Part by part, which the sum cannot resolve (in snapping_cable cq K is 1e-8 of M):
      M (a + da), C (v + 1e-7 m/s), K (q + 1e-7), to 1e-6 of each part's largest entry,
      K to 1e-5: snapping_cable's K is small (a unit in the last place of the body's 120 N
      weight over the step is 3e-6 of it) and its flow runs exactly along the cable, the
      drag's kink, where the differences converge only linearly (3e-6 of K at 1e-7).
      K at a = 0: the tangent leaves out how the added-mass force -rho A C_m (a - (a.u) u)
      turns with the cable (its added-mass matrix is exact); at the running accelerations
      that changes K by up to 70 % in snapping_cable but the matrix by < 1e-8 (the first
      check).

    Left out: the K entries of an element crossing the surface (crossing_stiffness
    differentiates the wet length but not the load at the moving crossing point: up to
    4 % of K's largest entry; in waves, every element that reaches between the deepest
    trough and the highest crest) and, in the depth-varying current or in waves, the
    body's rows (its tangent, hydro/towbody.py, leaves out how the flow changes with the
    body's position).
    """
    sim = Simulation.from_scene(scene, overrides)
    sim.initialize()
    sim.run(t_run)
    m = sim.model
    # in waves the residual expands the kinematics about references taken by the first residual
    # at a time (wave_quadrature): forgotten here, they are taken at (within 1e-7 m of) this
    # state, and the residual's differences are the exact derivatives the tangent has
    m.terms.hydrodynamics.wave_clock[0] = np.nan
    water = TermPart(sim, m._replace(water=m.water._replace(enabled=False)))
    cv, cq = 0.5 * h, 0.25 * h * h
    free = m.free_dofs
    n = free.size

    z = water.q[2:6 * m.el_len.size + 3:6] - m.water.surface_z
    crossing = np.zeros(n, dtype=bool)
    band = m.water.wave_crest
    for e in np.flatnonzero((z[:-1] * z[1:] < 0.0) | (np.minimum(z[:-1], z[1:]) < band)
                            & (np.maximum(z[:-1], z[1:]) > -band)):
        crossing |= (free >= 6 * e) & (free < 6 * e + 12)
    rows = np.ones(n, dtype=bool)
    if m.water.current_kind == CURRENT_LINEAR or band > 0.0:
        rows &= (free < m.terms.towbody.index) | (free >= m.terms.towbody.index + 3)
    everywhere = rows[:, None] & np.ones(n, dtype=bool)
    away_from_crossing = everywhere & ~crossing[:, None] & ~crossing[None, :]

    da = 1e-8 / cq
    # in waves the cable's accelerations are larger and the added-mass turning left out of the
    # tangent reaches 1.5e-6 of the matrix at them (measured): the waves' own tangent is checked at a = 0
    at = np.zeros_like(water.a) if band > 0.0 else None
    checks = [((1.0, cv, cq), water.differences(cq * da, cv * da, da, at) / da, away_from_crossing),
              ((1.0, 0.0, 0.0), water.differences(0.0, 0.0, 1.0), everywhere),
              ((0.0, 1.0, 0.0), water.differences(0.0, 1e-7, 0.0) / 1e-7, everywhere),
              ((0.0, 0.0, 1.0), water.differences(1e-7, 0.0, 0.0, np.zeros_like(water.a)) / 1e-7, away_from_crossing)]
    for (weights, fd, where), rtol in zip(checks, (1e-6, 1e-6, 1e-6, 1e-5)):
        scale = np.abs(fd[where]).max()
        assert scale > 0.0
        error = np.abs(water.matrix(weights) - fd)[where].max()
        assert error < rtol * scale, (weights, error / scale)


# ----------------------------------------------------------------- point kernel: G and flow acceleration
# These tests call the per-point kernel `towcable_fmu.hydro.cable.point_load` with a
# WaterModel built here, and compare with W(58) evaluated independently below from the
# loading functions and C_D(Re) (themselves checked against hand values above).
from towcable_fmu.hydro.cable import Section, point_load  # noqa: E402
from towcable_fmu.hydro.water import CURRENT_LINEAR, CURRENT_NONE, CURRENT_UNIFORM, WaterModel, flow

MU_W = 1.2e-3
D_CAB = 0.03
AREA = math.pi * D_CAB**2 / 4
# an oblique cable direction (slope not of unit length: the kernel must normalise it)
SLOPE = np.array([0.6, -0.4, -2.0]) * 1.7
U_CAB = SLOPE / np.linalg.norm(SLOPE)
DEPTH_Z = -12.0  # height of the evaluation point [m]


def _water(kind=CURRENT_NONE, v0=(0.0, 0.0, 0.0), grad=(0.0, 0.0, 0.0), turb=None, turb_dt=0.5):
    table = np.zeros((0, 3)) if turb is None else np.ascontiguousarray(turb, dtype=float)
    return WaterModel(True, RHO, MU_W, 0.0, G, kind, np.array(v0, dtype=float), np.array(grad, dtype=float),
                      0.0, turb_dt, table, np.zeros((0, 9)), math.inf, 0, 0.0, 0.0, 0.0)


def _load(w, kind, g_amp, cm=1.0, v=(0.0, 0.0, 0.0), a=(0.0, 0.0, 0.0), t=0.0, cd=0.0):
    """Kernel load per unit length minus the buoyancy rho A g e_z (checked separately)."""
    section = Section(int(kind), D_CAB, AREA, float(cd), float(g_amp), float(cm), 0.0)
    v, a = (tuple(float(x) for x in vec) for vec in (v, a))
    f = np.array(point_load(w, section, float(t), DEPTH_Z, tuple(float(x) for x in SLOPE), v, a))
    f[2] -= RHO * AREA * G
    return f


def _drag_w58(kind, rel, u, cd_fixed=0.0):
    """W(58) with the sign and Reynolds-number conventions of docs/design.md / hydro/cable.py:
    f = 1/2 rho d |V|^2 (C_D(Re_n) f_n V_n/|V_n| + C_D(Re) f_t sign(V.u) u)."""
    rel = np.asarray(rel, dtype=float)
    speed = np.linalg.norm(rel)
    if speed == 0.0:
        return np.zeros(3)
    vt = rel @ u
    vn_vec = rel - vt * u
    vn = np.linalg.norm(vn_vec)
    fn, ft = loading_functions(kind, abs(vt) / speed, vn / speed)
    cdn = cd_fixed or drag_coefficient(RHO * D_CAB * vn / MU_W)
    cdt = cd_fixed or drag_coefficient(RHO * D_CAB * speed / MU_W)
    q = 0.5 * RHO * D_CAB * speed**2
    return q * (cdn * fn * vn_vec / vn + cdt * ft * math.copysign(1.0, vt) * u)


CURRENTS = {
    "uniform": (CURRENT_UNIFORM, (0.9, 0.25, -0.05), (0.0, 0.0, 0.0)),
    # linear profile: the steady drag is that of the local current at DEPTH_Z
    "linear": (CURRENT_LINEAR, (1.2, -0.1, 0.0), (0.02, 0.01, 0.0)),
}


def _local_current(name):
    _, v0, grad = CURRENTS[name]
    return np.array(v0) + np.array(grad) * (DEPTH_Z - 0.0)


@pytest.mark.parametrize("kind", [BARE, FAIRED])
@pytest.mark.parametrize("g_amp", [0.5, 1.8, 3.0])
@pytest.mark.parametrize("current", ["uniform", "linear"])
def test_drag_amplification_applies_to_the_steady_current_drag_only(kind, g_amp, current):
    """W(64)-(65) as corrected in docs/design.md: mean drag = G x steady drag; the drag from the
    cable's own motion (and from turbulence) is not amplified."""
    v_cab = np.array([-0.7, 0.45, 0.3])
    still = _water()
    code, v0, grad = CURRENTS[current]
    steady = _water(code, v0, grad)
    uc = _local_current(current)

    # (a) a cable moving in still water: the same drag with and without amplification
    f1 = _load(still, kind, 1.0, v=v_cab)
    fg = _load(still, kind, g_amp, v=v_cab)
    expected = _drag_w58(kind, -v_cab, U_CAB)
    assert np.linalg.norm(expected) > 5.0  # N/m: a real load, not a vanishing one
    np.testing.assert_allclose(f1, expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fg, f1, rtol=1e-12, atol=1e-12)

    # (b) a cable at rest in a steady current: the drag scales by exactly G
    f1 = _load(steady, kind, 1.0)
    fg = _load(steady, kind, g_amp)
    steady_drag = _drag_w58(kind, uc, U_CAB)
    assert np.linalg.norm(steady_drag) > 5.0
    np.testing.assert_allclose(f1, steady_drag, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fg, g_amp * steady_drag, rtol=1e-12, atol=1e-12)

    # (c) both: total drag at V = V_f - rdot plus (G - 1) x the steady-current-only drag
    f1 = _load(steady, kind, 1.0, v=v_cab)
    fg = _load(steady, kind, g_amp, v=v_cab)
    np.testing.assert_allclose(f1, _drag_w58(kind, uc - v_cab, U_CAB), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fg - f1, (g_amp - 1.0) * steady_drag, rtol=1e-12, atol=1e-11)
    # the test discriminates: amplifying the relative-flow drag instead would differ by
    wrong = (g_amp - 1.0) * _drag_w58(kind, uc - v_cab, U_CAB)
    assert np.linalg.norm(wrong - (g_amp - 1.0) * steady_drag) > 0.1 * np.linalg.norm(wrong)


@pytest.mark.parametrize("g_amp", [0.5, 2.5])
def test_drag_amplification_leaves_the_turbulent_fluctuation_unamplified(g_amp):
    """The amplified part uses the mean current only, W(64): a (here constant) turbulent
    fluctuation adds to the relative flow but not to the amplified steady drag."""
    code, v0, grad = CURRENTS["uniform"]
    fluct = np.array([0.35, -0.2, 0.1])
    w = _water(code, v0, grad, turb=np.tile(fluct, (12, 1)))
    v_cab = np.array([0.2, 0.1, -0.15])
    f1 = _load(w, BARE, 1.0, v=v_cab, t=2.0)
    fg = _load(w, BARE, g_amp, v=v_cab, t=2.0)
    uc = np.array(v0)
    np.testing.assert_allclose(f1, _drag_w58(BARE, uc + fluct - v_cab, U_CAB), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fg - f1, (g_amp - 1.0) * _drag_w58(BARE, uc, U_CAB), rtol=1e-12, atol=1e-11)


def _accelerating_water(acc, dt=0.5, n=13, i0=6):
    """Water whose flow accelerates uniformly at ``acc``: the turbulence table (the one
    place a WaterModel carries a time-varying flow) sampled from V_f(t) = acc (t - t_i0).
    The cubic Hermite through linear samples is exact, and at t = t_i0 the flow speed is
    exactly zero, so no drag acts on a cable at rest."""
    times = np.arange(n) * dt
    table = np.outer(times - times[i0], acc)
    return _water(turb=table, turb_dt=dt), times[i0]


ACC_F = np.array([0.8, -0.5, 1.1])  # flow acceleration [m/s^2]


@pytest.mark.parametrize("cm", [0.0, 1.0, 2.5])
def test_flow_acceleration_normal_inertia_force_on_a_cable_at_rest(cm):
    """W(66)-(69) with the Froude-Krylov term once (docs/design.md): on a cable at rest in a
    uniformly accelerating flow the normal force per length is (1 + C_m) rho A a_n."""
    w, t0 = _accelerating_water(ACC_F)
    vel, acc = np.empty(3), np.empty(3)
    flow(w, DEPTH_Z, t0, vel, acc)  # the water model does accelerate the flow
    np.testing.assert_allclose(vel, 0.0, atol=1e-15)
    np.testing.assert_allclose(acc, ACC_F, rtol=1e-13)
    flow(w, DEPTH_Z, t0 + 0.37, vel, acc)  # also between the samples
    np.testing.assert_allclose(vel, 0.37 * ACC_F, rtol=1e-12)
    np.testing.assert_allclose(acc, ACC_F, rtol=1e-12)

    a_t = (ACC_F @ U_CAB) * U_CAB
    a_n = ACC_F - a_t
    assert np.linalg.norm(a_t) > 0.5 and np.linalg.norm(a_n) > 0.5
    f = _load(w, BARE, 1.0, cm=cm, t=t0)
    f_n = f - (f @ U_CAB) * U_CAB
    np.testing.assert_allclose(f_n, (1.0 + cm) * RHO * AREA * a_n, rtol=1e-12, atol=1e-12)

    # the cable accelerating along itself meets no added mass (W(67): normal part only)
    still = _water()
    along = 2.0 * U_CAB
    np.testing.assert_allclose(_load(still, BARE, 1.0, cm=cm, a=along), 0.0, atol=1e-12)
    # ... and across itself it meets rho A C_m a_n
    across = np.cross(U_CAB, [0.0, 1.0, 0.0])
    np.testing.assert_allclose(_load(still, BARE, 1.0, cm=cm, a=across), -cm * RHO * AREA * across,
                               rtol=1e-12, atol=1e-12)
    # a cable accelerating with the flow: no relative normal acceleration, only the
    # Froude-Krylov part rho A a_n remains normal to the cable
    f = _load(w, BARE, 1.0, cm=cm, a=ACC_F, t=t0)
    f_n = f - (f @ U_CAB) * U_CAB
    np.testing.assert_allclose(f_n, RHO * AREA * a_n, rtol=1e-12, atol=1e-12)


def test_flow_acceleration_along_a_cable_at_rest_gives_no_inertia_force():
    """Tangential part: docs/design.md's reading of W(66)/(69b), f_I = rho A (C_m + 1) dV_f,n/dt,
    puts neither added mass nor Froude-Krylov force along the cable (a deviation from the
    pressure-gradient force rho A a_t that e.g. MoorDyn applies; kept as designed)."""
    w, t0 = _accelerating_water(ACC_F)
    f = _load(w, BARE, 1.0, cm=1.0, t=t0)
    assert abs(ACC_F @ U_CAB) > 0.1 * np.linalg.norm(ACC_F)  # the flow does accelerate along it
    assert f @ U_CAB == pytest.approx(0.0, abs=1e-12 * RHO * AREA * np.linalg.norm(ACC_F))


def test_flow_acceleration_generalised_force_of_an_element():
    """The same inertia load through the assembled residual: a straight, fully submerged
    element at rest in a uniformly accelerating flow carries a uniform load f per length;
    its generalised force is f L/2 on each node position and +-f L^2 (1 - h^2)/12 on the
    slopes (trapezoidal rule with N_I points, step h = 1/(N_I - 1), on the cubic slope
    shape functions: exact by Euler-Maclaurin)."""
    length, npts, cm = 2.0, 5, 1.5
    table = cable_scene([segment(length, 1, mu=0.1, EA=1e6, diameter=D_CAB, integration_points=npts,
                                 added_mass_coefficient=cm)],
                        top={"type": "pinned", "position": [0.0, 0.0, -5.0]}, water={"density": RHO})
    m = Simulation(scene_from_table(table)).model
    w_acc, t0 = _accelerating_water(ACC_F)
    top = np.array([0.0, 0.0, -5.0])
    q = np.concatenate([top, U_CAB, top + length * U_CAB, U_CAB])
    zero = np.zeros(12)
    ship = np.zeros((3, 6))
    r_acc = np.zeros(12)
    r_still = np.zeros(12)
    residual(m._replace(water=w_acc), q, zero, zero, t0, ship, r_acc)
    residual(m._replace(water=_water()), q, zero, zero, t0, ship, r_still)
    gen = r_still - r_acc  # the residual holds minus the generalised hydrodynamic force
    a_n = ACC_F - (ACC_F @ U_CAB) * U_CAB
    f = (1.0 + cm) * RHO * AREA * a_n  # normal only (docs/design.md on W(69b))
    h = 1.0 / (npts - 1)
    slope_w = length**2 * (1.0 - h * h) / 12.0
    gen_n = gen.reshape(4, 3) - np.outer(gen.reshape(4, 3) @ U_CAB, U_CAB)
    expected = np.array([f * length / 2, f * slope_w, f * length / 2, -f * slope_w])
    np.testing.assert_allclose(gen_n, expected, rtol=1e-10, atol=1e-12)


# ----------------------------------------------------------------- exact tangent of the drag and the point load
# `drag_jacobian` and `point_tangent` (the iteration matrix's derivatives of the point load)
# against central differences of `drag` and `point_load`.
from towcable_fmu.hydro.cable import drag, drag_jacobian, point_tangent  # noqa: E402

#: Flow angles closer than this to a kink of the drag are left out of the comparisons with
#: central differences [rad]: at eta = 0 (flow along the cable: the drag is a cone in V_n)
#: and 90 deg (flow across: f_n has a kink in V_t, the tangential drag jumps), and at the
#: 30 deg break of the faired nodal-position functions; near them the difference quotient's
#: truncation error (the curvature grows as 1/margin) is no test of the derivative.
KINK_MARGIN = 0.01


def _sphere_directions(rng, n):
    x = rng.standard_normal((n, 3))
    return x / np.linalg.norm(x, axis=1)[:, None]


def _flow_angle(rel, u):
    vt = rel @ u
    return math.atan2(np.linalg.norm(rel - vt * u), abs(vt))


def _near_kink(kind, eta):
    return (eta < KINK_MARGIN or eta > math.pi / 2 - KINK_MARGIN
            or (kind == SUN_FAIRED and abs(eta - math.pi / 6) < KINK_MARGIN))


#: tangential C_Dt of the normal/tangential drag in the drag tests (the other kinds ignore it)
CDT = 0.05


def _drag_at(kind, cd, rel, u, cdt=CDT):
    return np.array(drag(RHO, MU_W, kind, D_CAB, cd, cdt, *map(float, rel), *map(float, u)))


def _drag_jac_at(kind, cd, rel, u, cdt=CDT):
    f, dv, du = drag_jacobian(RHO, MU_W, kind, D_CAB, cd, cdt, *map(float, rel), *map(float, u))
    return np.array(f), np.array(dv).reshape(3, 3), np.array(du).reshape(3, 3)


def _drag_central_differences(kind, cd, rel, u):
    """df/dV and df/du (I - u u^T) by central differences (u moved on the unit sphere)."""
    hv = 1e-6 * np.linalg.norm(rel)
    hu = 1e-6
    dv = np.empty((3, 3))
    du = np.empty((3, 3))
    for k in range(3):
        e = np.eye(3)[k]
        dv[:, k] = (_drag_at(kind, cd, rel + hv * e, u) - _drag_at(kind, cd, rel - hv * e, u)) / (2 * hv)
        up = (u + hu * e) / np.linalg.norm(u + hu * e)
        um = (u - hu * e) / np.linalg.norm(u - hu * e)
        du[:, k] = (_drag_at(kind, cd, rel, up) - _drag_at(kind, cd, rel, um)) / (2 * hu)
    return dv, du @ (np.eye(3) - np.outer(u, u))


def test_normal_tangential_drag_is_the_peers_definition():
    """loading = 'normal_tangential': rho d C_D |V_n| V_n / 2 + rho pi d C_Dt |V_t| V_t / 2
    (MoorDyn's normal and tangential drag), for flows along, across and oblique to the
    cable; C_D(Re) plays no part."""
    cd, cdt = 1.2, 0.01
    u = np.array([0.0, 0.6, -0.8])
    rng = np.random.default_rng(4)
    for rel in (0.7 * u, -0.3 * u, np.array([0.0, 0.8, 0.6]), *rng.normal(size=(5, 3))):
        vt = rel @ u
        vn = rel - vt * u
        expected = (0.5 * RHO * D_CAB * cd * np.linalg.norm(vn) * vn
                    + 0.5 * RHO * math.pi * D_CAB * cdt * abs(vt) * vt * u)
        np.testing.assert_allclose(_drag_at(NORMAL_TANGENTIAL, cd, rel, u, cdt), expected,
                                   rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("kind, cd", [(k, c) for k in (BARE, FAIRED, SUN_BARE, SUN_FAIRED) for c in (0.0, 1.2)]
                         + [(NORMAL_TANGENTIAL, 1.2)])  # constant coefficients only (scene validation)
def test_drag_jacobian_matches_central_differences(kind, cd):
    """Over random relative flows (random direction, 1e-3 to 5 m/s: Re from 25, across all
    branches of C_D(Re)) and cable directions, the exact derivatives agree with central
    differences of the drag to 1e-5 (the truncation error of the differences; states
    within KINK_MARGIN of a kink left out)."""
    rng = np.random.default_rng(11 + kind)
    speeds = 10.0 ** rng.uniform(-3.0, math.log10(5.0), 300)
    rels = _sphere_directions(rng, 300) * speeds[:, None]
    dirs = _sphere_directions(rng, 300)
    checked = 0
    for rel, u in zip(rels, dirs):
        if _near_kink(kind, _flow_angle(rel, u)):
            continue
        f, dv, du = _drag_jac_at(kind, cd, rel, u)
        np.testing.assert_allclose(f, _drag_at(kind, cd, rel, u), rtol=0.0, atol=1e-13 * np.linalg.norm(f))
        dv_fd, du_fd = _drag_central_differences(kind, cd, rel, u)
        scale = np.linalg.norm(f)
        assert np.abs(dv - dv_fd).max() < 1e-5 * max(np.abs(dv_fd).max(), scale / np.linalg.norm(rel))
        assert np.abs(du - du_fd).max() < 1e-5 * max(np.abs(du_fd).max(), scale)
        checked += 1
    assert checked > 250


@pytest.mark.parametrize("kind, cd", [(k, c) for k in (BARE, FAIRED) for c in (0.0, 1.2)]
                         + [(NORMAL_TANGENTIAL, 1.2)])
def test_drag_jacobian_at_the_kinks_is_finite_and_the_mean_of_the_derivatives_around(kind, cd):
    """No flow: zero (the drag is quadratic there). Flow exactly across the cable: the mean of
    the derivatives on either side of the kink. Flow exactly along it: finite; with a
    constant C_D and f_n(0) = 0 (bare) the mean of the derivatives around the cable."""
    u = U_CAB
    e1 = np.cross(u, [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    f, dv, du = _drag_jac_at(kind, cd, np.zeros(3), u)
    assert not f.any() and not dv.any() and not du.any()

    across = 0.8 * e1 + 0.3 * e2
    delta = 1e-7
    f, dv, du = _drag_jac_at(kind, cd, across, u)
    sides = [_drag_jac_at(kind, cd, across + s * delta * u, u) for s in (1.0, -1.0)]
    np.testing.assert_allclose(dv, 0.5 * (sides[0][1] + sides[1][1]), rtol=0, atol=1e-5 * np.abs(dv).max())
    np.testing.assert_allclose(du, 0.5 * (sides[0][2] + sides[1][2]), rtol=0, atol=1e-5 * np.abs(du).max())

    along = -1.3 * u
    f, dv, du = _drag_jac_at(kind, cd, along, u)
    assert np.all(np.isfinite(dv)) and np.all(np.isfinite(du))
    assert np.abs(dv).max() > 0.0
    if kind in (BARE, NORMAL_TANGENTIAL) and cd > 0.0:
        around = [_drag_jac_at(kind, cd, along + delta * e, u) for e in (e1, -e1, e2, -e2)]
        np.testing.assert_allclose(dv, np.mean([j[1] for j in around], axis=0), rtol=0,
                                   atol=1e-5 * np.abs(dv).max())
        np.testing.assert_allclose(du, np.mean([j[2] for j in around], axis=0), rtol=0,
                                   atol=1e-5 * np.abs(du).max())


@pytest.mark.parametrize("kind", [BARE, FAIRED])
@pytest.mark.parametrize("cd", [0.0, 1.2])
def test_point_tangent_matches_central_differences_of_the_point_load(kind, cd):
    """The load and its derivatives with respect to the point velocity, the slope (any
    length) and the height, in a linearly depth-dependent current with turbulence (the
    Froude-Krylov term depends on the direction) and amplified mean drag, against central
    differences of point_load without added mass (states near a kink of either the
    relative or the mean flow left out)."""
    rng = np.random.default_rng(5 + kind)
    code, v0, grad = CURRENTS["linear"]
    w = _water(code, v0, grad, turb=rng.normal(0.0, 0.3, (12, 3)), turb_dt=0.5)
    section = Section(int(kind), D_CAB, AREA, float(cd), 2.2, 1.0, 0.0)
    t = 2.3
    zero = (0.0, 0.0, 0.0)

    def load(rz, p, v):
        return np.array(point_load(w, section, t, float(rz), tuple(map(float, p)), tuple(map(float, v)), zero))

    vel, acc = np.empty(3), np.empty(3)
    checked = 0
    for _ in range(100):
        rz = -rng.uniform(1.0, 30.0)
        p = _sphere_directions(rng, 1)[0] * rng.uniform(0.5, 2.0)
        u = p / np.linalg.norm(p)
        flow(w, rz, t, vel, acc)
        rel = _sphere_directions(rng, 1)[0] * 10.0 ** rng.uniform(-3.0, math.log10(5.0))
        v = vel - rel
        mean = np.array(v0) + np.array(grad) * rz
        if _near_kink(kind, _flow_angle(rel, u)) or _near_kink(kind, _flow_angle(mean, u)):
            continue
        f, dv, dp, dz = (np.array(x) for x in point_tangent(w, section, t, rz, tuple(p), tuple(v)))
        np.testing.assert_allclose(f, load(rz, p, v), rtol=0.0, atol=1e-13 * np.linalg.norm(f))
        dv = dv.reshape(3, 3)
        dp = dp.reshape(3, 3)
        hv = 1e-6 * np.linalg.norm(rel)
        hp = 1e-6 * np.linalg.norm(p)
        hz = 1e-6 * min(np.linalg.norm(rel), np.linalg.norm(mean)) / np.linalg.norm(grad)
        dv_fd = np.column_stack([(load(rz, p, v + hv * e) - load(rz, p, v - hv * e)) / (2 * hv) for e in np.eye(3)])
        dp_fd = np.column_stack([(load(rz, p + hp * e, v) - load(rz, p - hp * e, v)) / (2 * hp) for e in np.eye(3)])
        dz_fd = (load(rz + hz, p, v) - load(rz - hz, p, v)) / (2 * hz)
        drag_scale = np.linalg.norm(_drag_at(kind, cd, rel, u)) + np.linalg.norm(_drag_at(kind, cd, mean, u))
        assert np.abs(dv - dv_fd).max() < 1e-5 * max(np.abs(dv_fd).max(), drag_scale / np.linalg.norm(rel))
        assert np.abs(dp - dp_fd).max() < 1e-5 * max(np.abs(dp_fd).max(), np.linalg.norm(f) / np.linalg.norm(p))
        assert np.abs(dz - dz_fd).max() < 1e-5 * max(np.abs(dz_fd).max(), 1e-12)
        checked += 1
    assert checked > 80


# ------------------------------------------------------------------ a body through the surface
@pytest.mark.parametrize("height", [0.0, 0.6])
def test_a_body_passes_through_the_surface_over_its_height(height):
    """towbody.height = h: buoyancy rho V g, drag and added mass scale with the submerged
    fraction clip(1/2 - z/h, 0, 1) of the centre's height z above the surface; h = 0: all
    or nothing at the surface."""
    from towcable_fmu.hydro.towbody import body_force

    sim = Simulation.from_scene("full_scale_recovery", {"towbody.height": height})
    water, body = sim.model.water, sim.model.terms.towbody
    buoyancy = water.density * body.volume * water.gravity
    assert buoyancy == pytest.approx(250.0 * 9.81 - 445.0, rel=1e-12)   # mass g - net weight
    still, rising = np.zeros(3), np.array([0.0, 0.0, 0.5])
    for z in (-1.0, -0.3, -0.15, -1e-9, 0.0, 0.1, 0.3, 1.0):
        wet = min(max(0.5 - z / height, 0.0), 1.0) if height else float(z < 0.0)
        force = np.empty(3)
        body_force(water, body, np.array([0.0, 0.0, z]), still, still, 0.0, force)
        assert force[2] == pytest.approx(wet * buoyancy, rel=1e-12, abs=1e-12), z
        moving = np.empty(3)   # rising at 0.5 m/s: drag (and the lift of its foil) on the wet part
        body_force(water, body, np.array([0.0, 0.0, z]), rising, still, 0.0, moving)
        full = np.empty(3)
        body_force(water, body, np.array([0.0, 0.0, -5.0]), rising, still, 0.0, full)
        np.testing.assert_allclose(moving - force, wet * (full - buoyancy * np.array([0.0, 0.0, 1.0])),
                                   rtol=1e-12, atol=1e-12)
