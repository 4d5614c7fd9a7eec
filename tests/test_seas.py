"""Seas: the Ochi-Hubble spectrum, cos-2s spreading, short-crested realisations against their definitions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad, trapezoid
from scipy.signal import csd, welch

from ship_motion import ClosedFormRao, IrregularSea, Jonswap, motion_from_config
from ship_motion.rao import GRAVITY
from ship_motion.spectrum import OchiHubble
from ship_motion.spreading import Cos2s
from towcable_fmu.errors import SceneError


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
