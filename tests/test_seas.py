"""Seas: Ochi-Hubble and Torsethaugen spectra, cos-2s spreading, short-crested seas against their definitions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad, trapezoid
from scipy.signal import csd, welch

from ship_motion import ClosedFormRao, IrregularSea, Jonswap, motion_from_config
from ship_motion.rao import GRAVITY
from ship_motion.spectrum import OchiHubble, Torsethaugen
from ship_motion.spreading import Cos2s
from towcable_fmu.common.errors import SceneError


@pytest.mark.parametrize("shape, swell_shape", [(1.0, 1.0), (2.5, 0.7), (0.6, 4.0)])
def test_ochi_hubble_moments_and_peaks(shape, swell_shape):
    """Zeroth moment (H1^2 + H2^2) / 16; each part peaks at its own 2 pi / Tp; lambda = 1 is PM."""
    s = OchiHubble(2.0, 7.0, shape, 1.5, 14.0, swell_shape)
    m0 = quad(lambda w: float(s.density(w)), 0.0, np.inf, limit=500)[0]
    assert m0 == pytest.approx((2.0 ** 2 + 1.5 ** 2) / 16.0, rel=1e-8)
    assert s.significant_height == pytest.approx(2.5)
    for hs, tp, lam in ((2.0, 7.0, shape), (1.5, 14.0, swell_shape)):
        part = OchiHubble(hs, tp, lam, 0.0, 10.0, 1.0)
        wp = 2.0 * math.pi / tp
        left, peak, right = part.density([wp * (1 - 1e-4), wp, wp * (1 + 1e-4)])
        assert peak > left and peak > right
    pm = OchiHubble(3.0, 9.0, 1.0, 0.0, 9.0, 1.0)
    w = np.linspace(0.3, 3.0, 50)
    np.testing.assert_allclose(pm.density(w), Jonswap(3.0, 9.0, 1.0).density(w), rtol=1e-10)


@pytest.mark.parametrize("s", [1.0, 4.0, 30.0])
def test_cos2s_normalised_first_moment_and_bins(s):
    d = Cos2s(s)
    assert quad(lambda x: float(d.density(x)), -math.pi, math.pi)[0] == pytest.approx(1.0, rel=1e-10)
    r1 = quad(lambda x: float(d.density(x)) * math.cos(x), -math.pi, math.pi)[0]
    assert r1 == pytest.approx(s / (s + 1.0), rel=1e-10)
    assert d.circular_spread == pytest.approx(math.sqrt(2.0 * (1.0 - r1)))
    centres, weights = d.bin_weights(36)
    assert weights.sum() == pytest.approx(1.0)
    assert np.sum(weights * np.cos(centres)) == pytest.approx(r1, rel=2e-3)


def test_short_crested_realisation_recovers_hs_tp_and_spread():
    """A 4 h record of the elevation and the slopes at a point: Hs = 4 std, the Welch peak at Tp,
    and the directional moment a1 + i b1 (cross spectra of elevation and slopes, as a pitch-roll
    buoy measures it) of modulus s / (s + 1) in the mean direction."""
    hs, tp, s, heading = 2.5, 9.0, 5.0, math.radians(130.0)
    sea = IrregularSea(Jonswap(hs, tp), ClosedFormRao(), heading=heading, components=150, directions=24,
                       spreading=Cos2s(s), omega_min=0.25, omega_max=3.0, seed=11, ramp=0.0)
    w, a, eps, mu = sea.waves.omega, sea.waves.amplitude, sea.waves.phase, sea.waves.heading
    k = w * w / GRAVITY
    dt = 0.5
    t = np.arange(0.0, 4 * 3600.0, dt)
    eta = sea.wave_elevation(t)
    slope = np.empty((2, t.size))
    for start in range(0, t.size, 2000):
        part = slice(start, start + 2000)
        sine = np.sin(np.outer(t[part], w) + eps)           # eta_x = a k cos(mu) sin(omega t + eps) at x = 0
        slope[0, part] = sine @ (a * k * np.cos(mu))
        slope[1, part] = sine @ (a * k * np.sin(mu))
    assert 4.0 * eta.std() == pytest.approx(hs, rel=0.03)
    f, pzz = welch(eta, fs=1.0 / dt, nperseg=2048)
    assert 1.0 / f[np.argmax(pzz)] == pytest.approx(tp, rel=0.05)
    _, pxx = welch(slope[0], fs=1.0 / dt, nperseg=2048)
    _, pyy = welch(slope[1], fs=1.0 / dt, nperseg=2048)
    _, cx = csd(eta, slope[0], fs=1.0 / dt, nperseg=2048)
    _, cy = csd(eta, slope[1], fs=1.0 / dt, nperseg=2048)
    band = pzz > 0.05 * pzz.max()
    norm = np.sqrt(pzz * (pxx + pyy))[band]
    weight = pzz[band] / pzz[band].sum()
    a1 = np.sum(weight * -cx.imag[band] / norm)
    b1 = np.sum(weight * -cy.imag[band] / norm)
    assert math.hypot(a1, b1) == pytest.approx(s / (s + 1.0), abs=0.02)
    assert math.degrees(math.atan2(b1, a1)) % 360.0 == pytest.approx(130.0, abs=2.0)


def test_heave_variance_in_a_spread_sea_is_the_integral_of_rao_squared_times_spectrum():
    """sum |a H|^2 / 2 of the components and the variance of a 3 h record against
    int int |H(omega, theta)|^2 S(omega) D(theta - theta_0) domega dtheta (fine grid)."""
    spectrum, rao, spread = Jonswap(3.0, 8.0), ClosedFormRao(), Cos2s(3.0)
    heading, band = math.radians(130.0), (0.3, 3.0)
    sea = IrregularSea(spectrum, rao, heading=heading, components=100, directions=24, spreading=spread,
                       omega_min=band[0], omega_max=band[1], seed=4, ramp=0.0)
    omega = np.linspace(*band, 1500)
    theta = np.linspace(-math.pi, math.pi, 721)
    h2 = np.stack([np.abs(rao(omega, heading + x, 0.0)) ** 2 for x in theta], axis=1)   # (nw, nt, 6)
    density = spectrum.density(omega)[:, None, None] * spread.density(theta)[None, :, None]
    integral = trapezoid(trapezoid(h2 * density, theta, axis=1), omega, axis=0)
    for dof in (2, 3, 4):   # heave, roll, pitch
        assert sea.response_std()[dof] ** 2 == pytest.approx(integral[dof], rel=0.03)
    record = sea.evaluate_many(np.arange(0.0, 3 * 3600.0, 1.0))[:, 0, :]
    assert record[:, 2].var() == pytest.approx(integral[2], rel=0.06)


def test_short_crested_and_two_peak_keys(tmp_path):
    sea = motion_from_config({"type": "irregular", "spectrum": "ochi_hubble", "hs": 2.0, "tp": 7.0,
                              "swell_hs": 1.5, "swell_tp": 14.0, "spreading": 4.0, "directions": 9,
                              "components": 50})
    assert sea.waves.omega.size == 450
    assert "Ochi-Hubble" in sea.description and "short-crested" in sea.description
    assert sea.band[0] == pytest.approx(0.5 * 2.0 * math.pi / 14.0)
    assert sea.band[1] == pytest.approx(4.0 * 2.0 * math.pi / 7.0)
    for table, key in (({"spectrum": "ochi_hubble", "swell_tp": 12.0}, "motion.swell_hs"),
                       ({"spectrum": "ochi_hubble", "swell_hs": 1.0, "swell_tp": 12.0, "gamma": 2.0}, "motion.gamma"),
                       ({"swell_hs": 1.0}, "motion.swell_hs"),
                       ({"directions": 5}, "motion.directions"),
                       ({"spreading": 0.0}, "motion.spreading"),
                       ({"spectrum": "pm"}, "motion.spectrum")):
        with pytest.raises(SceneError) as err:
            motion_from_config({"type": "irregular", **table})
        assert err.value.key == key


# Torsethaugen & Haver (2004) / DNV-RP-C205 3.5.6, written out here from the source's formulas as an independent
# computation: the two partitions, and each peak with the source's G_0 = 3.26 and fitted A_gamma.
def _source_partitions(hs, tp):
    tpf, tl, tu = 6.6 * hs ** (1 / 3), 2.0 * math.sqrt(hs), 25.0
    if tp <= tpf:
        r = 0.7 + 0.3 * math.exp(-(((tpf - tp) / (tpf - tl)) / 0.5) ** 2)
        gamma = 35.0 * (2 * math.pi * r * hs / (9.81 * tp ** 2)) ** 0.857
        return [(r * hs, tp, gamma), (math.sqrt(1 - r * r) * hs, tpf + 2.0, 1.0)]
    eps = (tp - tpf) / (tu - tpf)
    r = 0.6 + 0.4 * math.exp(-(eps / 0.3) ** 2)
    gamma = 35.0 * (2 * math.pi * hs / (9.81 * tpf ** 2)) ** 0.857 * (1 + 6 * eps)
    h2 = math.sqrt(1 - r * r) * hs
    return [(r * hs, tp, gamma), (h2, 6.6 * h2 ** (1 / 3), 1.0)]


def _source_density(hs, tp, omega):
    total = np.zeros_like(omega)
    for h, t, gamma in _source_partitions(hs, tp):
        x = omega * t / (2 * math.pi)
        sigma = np.where(x <= 1.0, 0.07, 0.09)
        a_gamma = (1 + 1.1 * math.log(gamma) ** 1.19) / gamma
        total += h * h * t / 16 / (2 * math.pi) * 3.26 * a_gamma * x ** -4 * np.exp(-x ** -4) * gamma ** np.exp(
            -(x - 1) ** 2 / (2 * sigma ** 2))
    return total


# wind-dominated (Tp < Tpf) and swell-dominated (Tp > Tpf) seas, gamma >= 1 in each; Hs 10 m, Tp 10 s has its
# swell as a shoulder on the wind sea's flank (no local maximum there, in the source's formula as well)
TORSETHAUGEN_SEAS = [(4.0, 7.0, True), (10.0, 10.0, False), (4.0, 4.0, True), (2.0, 5.0, True), (3.0, 16.0, True),
                     (1.0, 20.0, True), (10.0, 25.0, True)]


@pytest.mark.parametrize("hs, tp, two_peaks", TORSETHAUGEN_SEAS)
def test_torsethaugen_hs_peaks_and_the_source_formula(hs, tp, two_peaks):
    """4 sqrt(m0) = Hs; the spectrum matches the source's formula within its A_gamma fit (3.5 %); the primary
    peak at Tp and the secondary where the source puts it (Tpf + 2 s, or 6.6 H_2^(1/3) for a swell-dominated sea;
    within 5 %: the other part's flank shifts the sum's maximum)."""
    s = Torsethaugen(hs, tp)
    assert s.wind_dominated == (tp <= 6.6 * hs ** (1 / 3))
    (h1, tp1, _), (h2, tp2, _) = _source_partitions(hs, tp)
    m0 = quad(lambda w: float(s.density(w)), 0.0, np.inf, limit=500, points=None)[0]
    assert 4.0 * math.sqrt(m0) == pytest.approx(hs, rel=1e-6)
    w = np.linspace(0.05, 6.0, 6000)
    np.testing.assert_allclose(s.density(w), _source_density(hs, tp, w), rtol=0.035, atol=1e-6 * s.density(w).max())
    for period, tolerance in ((tp1, 0.005), (tp2, 0.05) if two_peaks else (tp1, 0.005)):
        wp = 2.0 * math.pi / period
        near = (w > 0.85 * wp) & (w < 1.15 * wp)
        assert w[near][np.argmax(s.density(w[near]))] == pytest.approx(wp, rel=tolerance)
    for (height, period, gamma), (h, t, g) in zip(s.parts, _source_partitions(hs, tp)):
        assert (height, period, gamma) == pytest.approx((h, t, g), rel=1e-12)


@pytest.mark.parametrize("hs", [4.0, 12.0])
def test_torsethaugen_fully_developed_sea_is_one_peak(hs):
    """At Tp = Tpf = 6.6 Hs^(1/3) both branches give R = 1: one peak of Hs at Tpf with gamma =
    35 (2 pi Hs / (g Tpf^2))^0.857, the swell-dominated form with epsilon_u = 0; the spectrum is continuous there."""
    tpf = 6.6 * hs ** (1 / 3)
    s = Torsethaugen(hs, tpf)
    assert s.fully_developed_period == pytest.approx(tpf)
    (h1, t1, gamma), (h2, _, _) = s.parts
    assert (h1, t1, h2) == pytest.approx((hs, tpf, 0.0), abs=1e-12)
    assert s.peak_periods == (tpf,) and s.peak_frequency == pytest.approx(2.0 * math.pi / tpf)
    assert gamma == pytest.approx(35.0 * (2 * math.pi * hs / (9.81 * tpf ** 2)) ** 0.857, rel=1e-12)
    w = np.linspace(0.1, 4.0, 400)
    np.testing.assert_allclose(s.density(w), _source_density(hs, tpf * (1 - 1e-12), w), rtol=0.035, atol=1e-9)
    for side in (1 - 1e-7, 1 + 1e-7):
        np.testing.assert_allclose(Torsethaugen(hs, tpf * side).density(w), s.density(w), rtol=1e-4, atol=1e-9)


def test_torsethaugen_bad_input_names_key_value_and_range():
    for hs, tp, message in ((0.0, 7.0, "hs must be finite and > 0 m, got 0.0"),
                            (-1.0, 7.0, "hs must be finite and > 0 m, got -1.0"),
                            (4.0, 3.9, "tp must lie in [4, 25] s (2 sqrt(hs) to 25 s), got 3.9"),
                            (4.0, 25.5, "tp must lie in [4, 25] s (2 sqrt(hs) to 25 s), got 25.5"),
                            (4.0, float("nan"), "tp must lie in [4, 25] s (2 sqrt(hs) to 25 s), got nan")):
        with pytest.raises(ValueError) as err:
            Torsethaugen(hs, tp)
        assert str(err.value) == message
    for table, key, value, allowed in (({"hs": 0.0}, "motion.hs", 0.0, "> 0 m"),
                                       ({"hs": 4.0, "tp": 3.0}, "motion.tp", 3.0, "[4, 25] s"),
                                       ({"hs": 1.0, "tp": 26.0}, "motion.tp", 26.0, "[2, 25] s"),
                                       ({"gamma": 2.0}, "motion.gamma", 2.0, "absent")):
        with pytest.raises(SceneError) as err:
            motion_from_config({"type": "irregular", "spectrum": "torsethaugen", **table})
        assert (err.value.key, err.value.value) == (key, value)
        assert allowed in err.value.allowed


def test_torsethaugen_sea_from_keys_spans_both_peaks():
    sea = motion_from_config({"type": "irregular", "spectrum": "torsethaugen", "hs": 4.0, "tp": 7.0,
                              "components": 100})
    tp2 = 6.6 * 4.0 ** (1 / 3) + 2.0  # the swell of a wind-dominated sea
    assert sea.band == pytest.approx((0.5 * 2.0 * math.pi / tp2, 4.0 * 2.0 * math.pi / 7.0))
    assert "Torsethaugen" in sea.description and "wind-dominated" in sea.description
    assert 4.0 * math.sqrt(sea.waves.variance) == pytest.approx(4.0, rel=0.01)
