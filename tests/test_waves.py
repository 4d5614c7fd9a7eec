"""Wave kinematics (towcable_fmu/hydro/waves.py) against linear (Airy) wave theory written
out here independently: one component, superposition, Wheeler stretching at a crest and a
trough, the derivatives against finite differences, the cut-off's bound, and the field's
elevation at the ship's reference point against the ship's own sea."""

from __future__ import annotations

import math

import numpy as np
import pytest

from towcable_fmu.hydro import waves as W

G = 9.81


def airy(a, omega, k, h, mu, eps, omega_e, x, y, z, t):
    """Linear wave kinematics of one component from the textbook formulas (z <= 0 from the
    mean level; h None: deep water): elevation, velocity (3), acceleration (3)."""
    th = omega_e * t - k * (x * math.cos(mu) + y * math.sin(mu)) + eps
    if h is None:
        ch = sh = math.exp(k * z)
    else:
        ch = math.cosh(k * (z + h)) / math.sinh(k * h)
        sh = math.sinh(k * (z + h)) / math.sinh(k * h)
    u = a * omega * ch * math.cos(th)
    w = -a * omega * sh * math.sin(th)
    du = -a * omega ** 2 * ch * math.sin(th)
    dw = -a * omega ** 2 * sh * math.cos(th)
    return (a * math.cos(th), np.array([u * math.cos(mu), u * math.sin(mu), w]),
            np.array([du * math.cos(mu), du * math.sin(mu), dw]))


def evaluate(table, depth, stretch, ramp, x, y, z, t, gradients=False):
    out = np.empty(W.OUT_SIZE)
    used = W.wave_at(table, math.inf if depth is None else depth, stretch, ramp, W.crest_bound(table), x, y, z, t,
                     gradients,
                     np.empty(W.scratch_size(table)), out)
    return out, used


def one(a=1.2, period=7.0, depth=25.0, mu=0.7, eps=0.4, speed=0.0):
    omega = 2 * math.pi / period
    table = W.component_table(np.array([omega]), np.array([a]), np.array([eps]), np.array([mu]), None, speed,
                              depth, G)
    return table, omega


def test_finite_depth_dispersion():
    omega = np.array([0.3, 0.8, 2.0])
    for h in (5.0, 40.0, 500.0):
        k = W.dispersion(omega, h, G)
        assert np.allclose(G * k * np.tanh(k * h), omega ** 2, rtol=1e-13)
    assert np.allclose(W.dispersion(omega, None, G), omega ** 2 / G, rtol=0)
    # shallow water: k -> omega / sqrt(g h)
    k = W.dispersion(np.array([0.01]), 10.0, G)
    assert k[0] == pytest.approx(0.01 / math.sqrt(G * 10.0), rel=1e-4)


@pytest.mark.parametrize("depth", [25.0, None])
def test_one_component_against_airy(depth):
    table, omega = one(depth=depth, speed=1.5)
    k = table[0, W.K]
    omega_e = omega - k * 1.5 * math.cos(0.7)
    assert table[0, W.OMEGA_E] == pytest.approx(omega_e, rel=1e-14)
    for x, y, z, t in ((3.0, -2.0, -4.0, 1.3), (-20.0, 7.0, -0.5, 8.9), (0.0, 0.0, -12.0, 30.0)):
        out, used = evaluate(table, depth, W.STRETCH_EXTRAPOLATION, 0.0, x, y, z, t)
        eta, vel, acc = airy(1.2, omega, k, depth, 0.7, 0.4, omega_e, x, y, z, t)
        assert used == 1
        assert out[W.ETA] == pytest.approx(eta, abs=1e-12)
        assert np.allclose(out[W.VEL:W.VEL + 3], vel, rtol=1e-12, atol=1e-13)
        assert np.allclose(out[W.ACC:W.ACC + 3], acc, rtol=1e-12, atol=1e-13)


def test_superposition_is_the_sum():
    omega = np.array([0.5, 0.9, 1.4])
    amp = np.array([1.0, 0.6, 0.2])
    eps = np.array([0.3, 2.0, -1.0])
    mu = np.array([3.0, 2.2, 0.4])
    whole = W.component_table(omega, amp, eps, mu, None, 2.0, 60.0, G)
    for x, y, z, t in ((5.0, 1.0, -3.0, 4.0), (-40.0, 9.0, -20.0, 17.0), (1.0, 1.0, 0.7, 2.0)):
        total, _ = evaluate(whole, 60.0, W.STRETCH_EXTRAPOLATION, 0.0, x, y, z, t, gradients=True)
        parts = sum(evaluate(W.component_table(omega[i:i + 1], amp[i:i + 1], eps[i:i + 1], mu[i:i + 1], None, 2.0,
                                               60.0, G), 60.0, W.STRETCH_EXTRAPOLATION, 0.0, x, y, z, t,
                             gradients=True)[0] for i in range(3))
        assert np.allclose(total, parts, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("depth", [30.0, None])
def test_wheeler_at_crest_and_trough(depth):
    """Wheeler: the kinematics at z are linear theory's at z_s = h (z - eta) / (h + eta): at
    the crest and the trough the surface values are the mean level's, and a point below maps
    to its stretched height."""
    a, mu, eps = 1.5, 0.0, 0.0
    table, omega = one(a=a, depth=depth, mu=mu, eps=eps)
    k = table[0, W.K]
    h = math.inf if depth is None else depth
    period = 2 * math.pi / omega
    for t, eta in ((0.0, a), (period / 2, -a)):  # crest and trough at x = 0
        for z_s in (0.0, -4.0):
            z = eta + z_s * (1.0 if depth is None else (h + eta) / h)
            out, _ = evaluate(table, depth, W.STRETCH_WHEELER, 0.0, 0.0, 0.0, z, t)
            ref_eta, vel, acc = airy(a, omega, k, depth, mu, eps, omega, 0.0, 0.0, z_s, t)
            assert out[W.ETA] == pytest.approx(eta, abs=1e-12)
            assert np.allclose(out[W.VEL:W.VEL + 3], vel, rtol=1e-12, atol=1e-12)
            assert np.allclose(out[W.ACC:W.ACC + 3], acc, rtol=1e-12, atol=1e-12)
    # extrapolation above the mean level at the crest: value plus slope at z = 0
    out, _ = evaluate(table, depth, W.STRETCH_EXTRAPOLATION, 0.0, 0.0, 0.0, a, 0.0)
    _, v0, _ = airy(a, omega, k, depth, mu, eps, omega, 0.0, 0.0, 0.0, 0.0)
    dz = 1e-6
    _, v1, _ = airy(a, omega, k, depth, mu, eps, omega, 0.0, 0.0, -dz, 0.0)
    assert np.allclose(out[W.VEL:W.VEL + 3], v0 + a * (v0 - v1) / dz, rtol=1e-6)


@pytest.mark.parametrize("stretch,z", [(W.STRETCH_WHEELER, -2.0), (W.STRETCH_WHEELER, 0.3),
                                       (W.STRETCH_EXTRAPOLATION, -2.0), (W.STRETCH_EXTRAPOLATION, 0.4)])
@pytest.mark.parametrize("depth", [20.0, None])
def test_derivatives_against_finite_differences(stretch, z, depth):
    omega = np.array([0.55, 0.8, 1.3])
    table = W.component_table(omega, np.array([0.8, 0.5, 0.2]), np.array([0.1, 1.0, 2.5]),
                              np.array([2.4, 2.0, 0.3]), None, 2.2, depth, G)
    ramp, t = 20.0, 7.0  # inside the ramp: the acceleration's product rule
    p = np.array([3.0, -1.0, z])
    out, _ = evaluate(table, depth, stretch, ramp, *p, t, gradients=True)
    h = 1e-6
    for m in range(3):
        dp = np.zeros(3)
        dp[m] = h
        hi, _ = evaluate(table, depth, stretch, ramp, *(p + dp), t)
        lo, _ = evaluate(table, depth, stretch, ramp, *(p - dp), t)
        fd = (hi - lo) / (2 * h)
        for c in range(3):
            assert out[W.DVEL + 3 * c + m] == pytest.approx(fd[W.VEL + c], rel=1e-6, abs=1e-9)
            assert out[W.DACC + 3 * c + m] == pytest.approx(fd[W.ACC + c], rel=1e-6, abs=1e-9)
        if m < 2:
            assert out[W.ETA_X + m] == pytest.approx(fd[W.ETA], rel=1e-6, abs=1e-9)
    # the acceleration is the time derivative of the (ramped) velocity below the surface
    if stretch == W.STRETCH_EXTRAPOLATION and z < 0:
        hi, _ = evaluate(table, depth, stretch, ramp, *p, t + h)
        lo, _ = evaluate(table, depth, stretch, ramp, *p, t - h)
        fd = (hi - lo) / (2 * h)
        omega_e = table[:, W.OMEGA_E]
        assert np.allclose(omega_e, table[:, W.OMEGA] - table[:, W.K] * 2.2 * table[:, W.CX])
        # in the moving frame d/dt = the earth frame's d/dt + U d/dx
        assert np.allclose(out[W.ACC:W.ACC + 3] + 2.2 * out[W.DVEL:W.DVEL + 9:3], fd[W.VEL:W.VEL + 3], rtol=1e-6,
                           atol=1e-9)


def test_cutoff_bound():
    """Deep points drop the short components: what is dropped adds at most THRESHOLD of the
    sea's surface velocity and acceleration bounds, and a point below every component's
    reach sums nothing."""
    omega = np.linspace(0.4, 2.5, 60)
    amp = np.full(60, 0.1)
    rng = np.random.default_rng(1)
    table = W.component_table(omega, amp, rng.uniform(0, 2 * math.pi, 60), np.full(60, 2.3), None, 0.0, None, G)
    z = -40.0
    out, used = evaluate(table, None, W.STRETCH_EXTRAPOLATION, 0.0, 1.0, 2.0, z, 3.0)
    assert 0 < used < 60
    fields = [airy(table[i, W.A], table[i, W.OMEGA], table[i, W.K], None, math.atan2(table[i, W.CY], table[i, W.CX]),
                   table[i, W.PHASE], table[i, W.OMEGA_E], 1.0, 2.0, z, 3.0) for i in range(60)]
    for field, scale in ((1, np.sum(amp * omega)), (2, np.sum(amp * omega ** 2))):
        ref = sum(f[field] for f in fields)
        got = out[W.VEL:W.VEL + 3] if field == 1 else out[W.ACC:W.ACC + 3]
        assert np.all(np.abs(got - ref) <= W.THRESHOLD * scale)
        assert np.any(np.abs(got - ref) > 1e-3 * W.THRESHOLD * scale)  # something was dropped
        left_out = sum(np.abs(f[field]) for f in fields[used:])
        assert np.all(left_out <= W.THRESHOLD * scale / 60 * (60 - used))  # each within its share
    deepest = table[0, W.REACH]
    _, used = evaluate(table, None, W.STRETCH_WHEELER, 0.0, 1.0, 2.0, deepest - W.crest_bound(table) - 1.0, 3.0)
    assert used == 0
    _, used = evaluate(table, None, W.STRETCH_EXTRAPOLATION, 0.0, 1.0, 2.0, deepest + 0.5, 3.0)
    assert used > 0


def test_reach_in_finite_depth():
    """In finite depth a component's depth factor at its reach is its share of the
    threshold, and one that stays above its share down to the bottom is never left out."""
    omega = np.array([0.3, 0.8, 1.5, 2.4])
    amp = np.array([0.5, 1.0, 0.3, 0.05])
    h = 40.0
    table = W.component_table(omega, amp, np.zeros(4), np.zeros(4), None, 0.0, h, G)
    speed, acceleration = np.sum(amp * omega), np.sum(amp * omega ** 2)
    for row in table:
        a, w, k, z = row[W.A], row[W.OMEGA], row[W.K], row[W.REACH]
        share = W.THRESHOLD / 4 * min(speed / (a * w), acceleration / (a * w * w))
        factor = lambda zz: math.cosh(k * (zz + h)) / math.sinh(k * h)  # noqa: E731
        if math.isinf(z):
            assert factor(-h) > share
        else:
            assert -h < z < 0 and factor(z) == pytest.approx(share, rel=1e-9)
    assert np.all(table[1:, W.REACH] >= table[:-1, W.REACH])


def test_elevation_at_the_ship_is_the_ships_sea():
    """The field's elevation at the reference point (the ship's CG, the origin) is the
    elevation the ship's motion is computed from, the same realisation."""
    from ship_motion import DEFAULT_SEA, motion_from_config

    sea = motion_from_config(DEFAULT_SEA)
    table = W.component_table(sea.waves.omega, sea.waves.amplitude, sea.waves.phase,
                              np.full(sea.waves.omega.size, sea.heading), sea.encounter_frequency, sea.speed, None, G)
    times = np.array([0.0, 13.7, 250.0])
    mine = [W.elevation(table, 0.0, 0.0, 0.0, t)[0] for t in times]
    assert np.allclose(mine, sea.wave_elevation(times), rtol=1e-12, atol=1e-12)


def test_no_components_no_waves():
    out, used = evaluate(np.zeros((0, W.COLUMNS)), None, W.STRETCH_WHEELER, 0.0, 1.0, 2.0, -1.0, 3.0, True)
    assert used == 0 and not out.any()


def test_scene_keys_bad_input():
    """waves asked for with no sea, on a formulation without waves, and bad values: errors
    naming the key."""
    from towcable_fmu.common.errors import SceneError
    from towcable_fmu.scene import load_scene

    with pytest.raises(SceneError, match="water.waves.*irregular"):
        load_scene("full_scale_pinned", {"water.waves": "motion", "motion": {"type": "none"}})
    with pytest.raises(SceneError, match="water.stretching"):
        load_scene("full_scale", {"water.waves": "motion", "water.stretching": "vertical"})
    with pytest.raises(SceneError, match="water.depth"):
        load_scene("full_scale", {"water.waves": "motion", "water.depth": -3.0})
    with pytest.raises(SceneError, match="water.waves.*ancf"):
        load_scene("snapping_cable_nodal", {"water.waves": "motion", "motion": {"type": "irregular"}})
    scene = load_scene("full_scale", {"water.waves": "motion", "water.depth": 800.0})
    assert scene.water.waves == "motion" and scene.water.depth == 800.0
