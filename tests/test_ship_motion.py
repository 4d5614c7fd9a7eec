"""Tests of the ship motion sources (ship_motion/).

Reference values are closed forms or independent computations (scipy quadrature,
analytic integrals, finite differences), never numbers the code printed before.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from ship_motion import (
    DEFAULT_SEA,
    EXAMPLE_CSV,
    ClosedFormRao,
    Harmonic,
    IrregularSea,
    Jonswap,
    Manoeuvre,
    RaoTable,
    RegularMotion,
    StillShip,
    SuperposedMotion,
    TimeRangeError,
    TimeSeriesMotion,
    Turn,
    motion_from_config,
)
from ship_motion.ramp import smoothstep_integral
from ship_motion.rao import GRAVITY
from towcable_fmu.common.errors import SceneError

DEG = math.pi / 180.0


# ----------------------------------------------------------------------------- helpers

def assert_derivatives_consistent(source, times, h=1e-3, rtol=1e-5):
    """Rows 1 and 2 against central differences of row 0.

    Truncation error of the central differences: h^2 |f'''| / 6 and h^2 |f''''| / 12.
    Every source here has its content below omega = 3 rad/s, where these are
    h^2 omega^2 / 6 = 1.5e-6 and 7.5e-7 of the derivative's own size; rtol = 1e-5 leaves
    a margin of about 10, while a missing product-rule term (an error of order
    amplitude / ramp time) is orders of magnitude larger. Rounding adds a few ulps of
    |f| / h and |f| / h^2 (2e-15 allows 9 ulps). The ramps are C2 only (the third
    derivative jumps at their ends), so the times must stay more than h away from the
    ramp ends, where the second difference has an extra error of order h |f^(3)|.
    """
    s = source.evaluate_many(times)
    sp = source.evaluate_many(times + h)
    sm = source.evaluate_many(times - h)
    fd1 = (sp[:, 0] - sm[:, 0]) / (2.0 * h)
    fd2 = (sp[:, 0] - 2.0 * s[:, 0] + sm[:, 0]) / h ** 2
    size0 = np.abs(s[:, 0]).max(axis=0)
    scale1 = np.abs(s[:, 1]).max(axis=0)
    scale2 = np.abs(s[:, 2]).max(axis=0)
    err1 = np.abs(fd1 - s[:, 1]).max(axis=0)
    err2 = np.abs(fd2 - s[:, 2]).max(axis=0)
    tol1 = rtol * scale1 + 2e-15 * size0 / h + 1e-12
    tol2 = rtol * scale2 + 2e-15 * size0 / h ** 2 + 1e-12
    assert np.all(err1 <= tol1), f"rate errors {err1} exceed {tol1}"
    assert np.all(err2 <= tol2), f"acceleration errors {err2} exceed {tol2}"


def write_csv(path: Path, header: str, rows: np.ndarray) -> None:
    np.savetxt(path, rows, delimiter=",", header=header, comments="", fmt="%.12f")


def fit_circle(x: np.ndarray, y: np.ndarray) -> tuple[float, float, float]:
    """Algebraic least-squares circle: centre (a, b) and radius."""
    a = np.column_stack([2 * x, 2 * y, np.ones_like(x)])
    sol, *_ = np.linalg.lstsq(a, x ** 2 + y ** 2, rcond=None)
    cx, cy, c = sol
    return cx, cy, math.sqrt(c + cx ** 2 + cy ** 2)


# ----------------------------------------------------------------------------- interface

SOURCE_NAMES = ("still", "regular", "time_series", "irregular", "manoeuvre", "manoeuvre+waves")


def all_sources():
    """One of each source (same order as SOURCE_NAMES)."""
    t = np.linspace(0.0, 30.0, 301)
    attitudes = np.column_stack([0.05 * np.sin(t), 0.02 * np.cos(0.8 * t), 0.1 * t])
    positions = np.column_stack([np.sin(0.3 * t), t, 0.5 * np.cos(0.9 * t)])
    return [
        StillShip(),
        RegularMotion([Harmonic(2, 1.0, 8.0), Harmonic(3, 3 * DEG, 10.0, 0.4)], ramp=5.0),
        TimeSeriesMotion(t, positions, attitudes),
        motion_from_config(DEFAULT_SEA),
        Manoeuvre(4.0, initial_speed=1.0, speed_ramp=8.0, turn=Turn(2.0, 2 * DEG, 90 * DEG, 5.0)),
        motion_from_config({"type": "manoeuvre", "speed": 3.0, "turn_rate": 3.0, "turn_angle": 90.0,
                            "turn_start": 2.0, "turn_ramp": 4.0,
                            "waves": {"type": "regular", "surge": {"amplitude": 0.5, "period": 7.0},
                                      "heave": {"amplitude": 1.0, "period": 9.0}}}),
    ]


def test_interface_shapes_and_descriptions():
    for source in all_sources():
        many = source.evaluate_many(np.array([1.0, 2.5, 7.0, 29.3]))
        assert many.shape == (4, 3, 6)
        # single-time evaluation (the FMUs' path) agrees with the batched one, in and after ramps
        np.testing.assert_allclose(source.evaluate(2.5), many[1], rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(source.evaluate(29.3), many[3], rtol=1e-12, atol=1e-14)
        assert source.evaluate(2.5).shape == (3, 6)
        text = source.description
        assert isinstance(text, str) and text and "\n" not in text


@pytest.mark.parametrize("index", range(len(SOURCE_NAMES)), ids=SOURCE_NAMES)
def test_derivatives_consistent_for_every_source(index):
    source = all_sources()[index]
    # inside and after the ramps and turns, offset from their ends (whole seconds)
    times = np.linspace(0.5, 29.5, 233) + 0.0123
    assert_derivatives_consistent(source, times)


def test_still_ship_is_zero():
    np.testing.assert_array_equal(StillShip().evaluate_many([0.0, 5.0]), np.zeros((2, 3, 6)))
    assert isinstance(motion_from_config({"type": "none"}), StillShip)


# ----------------------------------------------------------------------------- regular

def test_regular_matches_closed_form():
    source = motion_from_config({
        "type": "regular",
        "heave": {"mean": 0.2, "amplitude": 1.5, "period": 8.0, "phase": 30.0},
        "pitch": {"mean": 1.0, "amplitude": 2.0, "period": 10.0, "phase": -45.0},
    })
    t = np.array([0.0, 1.3, 7.7, 100.0])
    out = source.evaluate_many(t)
    w3, p3 = 2 * math.pi / 8.0, 30 * DEG
    w5, p5, a5 = 2 * math.pi / 10.0, -45 * DEG, 2 * DEG
    np.testing.assert_allclose(out[:, 0, 2], 0.2 + 1.5 * np.sin(w3 * t + p3), atol=1e-12)
    np.testing.assert_allclose(out[:, 1, 2], 1.5 * w3 * np.cos(w3 * t + p3), atol=1e-12)
    np.testing.assert_allclose(out[:, 2, 2], -1.5 * w3 ** 2 * np.sin(w3 * t + p3), atol=1e-12)
    np.testing.assert_allclose(out[:, 0, 4], DEG + a5 * np.sin(w5 * t + p5), atol=1e-12)
    np.testing.assert_allclose(out[:, 2, 4], -a5 * w5 ** 2 * np.sin(w5 * t + p5), atol=1e-12)
    untouched = [0, 1, 3, 5]
    np.testing.assert_array_equal(out[:, :, untouched], 0.0)


def test_regular_ramp():
    ramped = RegularMotion([Harmonic(2, 1.0, 6.0, 0.7)], mean=[0, 0, -0.5, 0, 0, 0], ramp=12.0)
    full = RegularMotion([Harmonic(2, 1.0, 6.0, 0.7)], mean=[0, 0, -0.5, 0, 0, 0])
    start = ramped.evaluate(0.0)
    np.testing.assert_allclose(start[:, 2], [-0.5, 0.0, 0.0], atol=1e-14)
    # the quintic step is 1/2 at mid-ramp: the oscillation has half its amplitude
    mid = ramped.evaluate(6.0)[0, 2] + 0.5
    assert mid == pytest.approx(0.5 * (full.evaluate(6.0)[0, 2] + 0.5), abs=1e-12)
    t = np.array([12.0, 13.1, 40.0])
    np.testing.assert_allclose(ramped.evaluate_many(t), full.evaluate_many(t), atol=1e-12)


# ----------------------------------------------------------------------------- time series

def analytic_motion(t):
    """Positions [m], attitudes [rad] and their first two derivatives, shape (3, n, 6)."""
    out = np.zeros((3, t.size, 6))
    terms = [  # dof, amplitude, omega, phase
        (0, 3.0, 0.7, 0.0), (1, 1.0, 0.4, 0.5 * math.pi), (2, 0.8, 1.1, 0.3),
        (3, 5 * DEG, 0.6, 0.0), (4, 2 * DEG, 0.9, 0.5 * math.pi), (5, 20 * DEG, 0.05, 0.0),
    ]
    for dof, a, w, p in terms:
        out[0, :, dof] += a * np.sin(w * t + p)
        out[1, :, dof] += a * w * np.cos(w * t + p)
        out[2, :, dof] -= a * w * w * np.sin(w * t + p)
    out[0, :, 0] += 0.5 * t          # steady surge drift
    out[1, :, 0] += 0.5
    out[0, :, 5] += 170 * DEG         # the yaw crosses 180 deg
    return out


def test_time_series_positions_reproduce_motion(tmp_path):
    t = np.linspace(0.0, 60.0, 601)  # 10 Hz
    exact = analytic_motion(t)
    yaw_wrapped = (exact[0, :, 5] + math.pi) % (2 * math.pi) - math.pi
    rows = np.column_stack([t, exact[0, :, 0:3], np.degrees(exact[0, :, 3:5]), np.degrees(yaw_wrapped)])
    write_csv(tmp_path / "pos.csv", "t [s],x [m],y [m],z [m],roll [deg],pitch [deg],yaw [deg]", rows)
    source = motion_from_config({"type": "time_series", "file": "pos.csv"}, base_dir=tmp_path)
    # interior points (not-a-knot ends are less accurate), between the samples
    tq = np.linspace(2.0, 58.0, 1117) + 0.037
    got = source.evaluate_many(tq)
    want = analytic_motion(tq)
    # quintic interpolation at h = 0.1 s of content below 1.1 rad/s: the error is about
    # (h omega)^6 |f| for values, (h omega)^4 omega^2 |f| for accelerations (1e-8, 1e-4 * |f''|)
    for k, tol in enumerate([1e-7, 1e-6, 1e-5]):
        np.testing.assert_allclose(got[:, k, :], want[k].reshape(-1, 6), atol=tol)


def test_time_series_velocity_format_integrates_back(tmp_path):
    # linear velocities: the trapezoidal rule is exact, positions are quadratic in t
    t = np.linspace(5.0, 25.0, 201)
    v = np.column_stack([1.0 + 0.1 * t, np.full_like(t, -0.5), 0.2 - 0.01 * t])
    start = np.array([10.0, -3.0, 0.4])
    angles = np.column_stack([np.sin(0.5 * t), 0.5 * np.cos(0.3 * t), 0.2 * t])
    write_csv(tmp_path / "vel.csv", "t,vx,vy,vz,roll,pitch,yaw", np.column_stack([t, v, angles]))
    source = motion_from_config({"type": "time_series", "file": str(tmp_path / "vel.csv"),
                                 "format": "velocity", "angle_unit": "rad",
                                 "initial_position": list(start), "time_offset": 5.0})
    assert source.time_range == pytest.approx((0.0, 20.0))
    ts = np.array([0.0, 3.33, 12.0, 20.0])          # simulation time = record time - 5 s
    tr = ts + 5.0
    dt = tr - 5.0
    x = start + np.column_stack([dt + 0.05 * (tr ** 2 - 25.0), -0.5 * dt,
                                 0.2 * dt - 0.005 * (tr ** 2 - 25.0)])
    got = source.evaluate_many(ts)
    np.testing.assert_allclose(got[:, 0, 0:3], x, atol=1e-9)
    np.testing.assert_allclose(got[:, 1, 0:3], np.column_stack([1.0 + 0.1 * tr, -0.5 + 0 * tr,
                                                                0.2 - 0.01 * tr]), atol=1e-9)
    np.testing.assert_allclose(got[:, 2, 0:3], np.tile([0.1, 0.0, -0.01], (4, 1)), atol=1e-7)


def test_time_series_velocity_format_sinusoid_within_trapezoid_error(tmp_path):
    h = 0.1
    t = np.arange(0.0, 60.0 + h / 2, h)
    exact = analytic_motion(t)
    rows = np.column_stack([t, exact[1, :, 0:3], np.degrees(exact[0, :, 3:6])])
    write_csv(tmp_path / "vel.csv", "t,vx,vy,vz,roll,pitch,yaw", rows)
    source = motion_from_config({"type": "time_series", "file": "vel.csv",
                                 "initial_position": list(exact[0, 0, 0:3])}, base_dir=tmp_path)
    got = source.evaluate_many(t)[:, 0, 0:3]
    # composite trapezoidal rule: |error| <= (t - t0) h^2 / 12 max |x'''|, x''' <= a omega^3
    bound = 60.0 * h ** 2 / 12.0 * np.array([3.0 * 0.7 ** 3, 0.4 ** 3, 0.8 * 1.1 ** 3])
    assert np.all(np.abs(got - exact[0, :, 0:3]).max(axis=0) <= bound)
    assert np.abs(got - exact[0, :, 0:3]).max() < 0.05


def test_time_series_outside_range_is_an_error(tmp_path):
    t = np.linspace(0.0, 10.0, 11)
    source = TimeSeriesMotion(t, np.zeros((11, 3)), np.zeros((11, 3)), time_offset=2.0)
    source.evaluate(8.0)
    with pytest.raises(TimeRangeError, match=r"t = 8.5 s .*\[-2, 8\] s"):
        source.evaluate(8.5)
    with pytest.raises(TimeRangeError):
        source.evaluate_many([0.0, -2.1])


def test_time_series_bad_header_names_the_key(tmp_path):
    write_csv(tmp_path / "bad.csv", "t,x,y,z,roll,pitch", np.zeros((8, 6)))
    with pytest.raises(SceneError) as err:
        motion_from_config({"type": "time_series", "file": "bad.csv"}, base_dir=tmp_path)
    assert err.value.key == "motion.file"


def test_example_csv_reproduces_default_sea():
    source = motion_from_config({"type": "time_series", "file": str(EXAMPLE_CSV)})
    assert source.time_range == pytest.approx((0.0, 120.0))
    sea = motion_from_config({**DEFAULT_SEA, "ramp": 0.0})
    t = np.linspace(1.0, 119.0, 500)
    got, want = source.evaluate_many(t), sea.evaluate_many(t)
    z0 = sea.evaluate(0.0)[0, 2]
    # trapezoidal rule at 10 Hz over 120 s: 120 h^2/12 max|z'''| ~ 0.1 * 0.01 * 2 m
    np.testing.assert_allclose(got[:, 0, 2] + z0, want[:, 0, 2], atol=3e-3)
    np.testing.assert_allclose(got[:, 0, 3:6], want[:, 0, 3:6], atol=1e-6)  # 7 decimals of deg


# ----------------------------------------------------------------------------- spectrum

@pytest.mark.parametrize("gamma", [1.0, 3.3, 7.0])
def test_jonswap_integrates_to_hs2_over_16(gamma):
    spec = Jonswap(hs=2.7, tp=8.3, gamma=gamma)
    wp = spec.peak_frequency
    m0 = sum(quad(lambda w: float(spec.density(w)), a * wp, b * wp, limit=400)[0]
             for a, b in ((0.2, 1.0), (1.0, 2.0), (2.0, 50.0)))
    tail = 2.7 ** 2 * 5.0 / 16.0 / 4.0 / 50.0 ** 4  # the PM tail beyond 50 omega_p
    assert m0 + tail == pytest.approx(2.7 ** 2 / 16.0, rel=1e-6)
    # at the peak S = C(gamma) gamma S_PM; the usual closed-form normalisation
    # C = 1 - 0.287 ln(gamma) (DNV-RP-C205) agrees within 2 %
    ratio = spec.density(wp) / Jonswap(2.7, 8.3, 1.0).density(wp) / gamma
    assert ratio == pytest.approx(1.0 - 0.287 * math.log(gamma), rel=0.02)


def test_jonswap_gamma_one_is_pierson_moskowitz_and_peaks_at_tp():
    hs, tp = 3.0, 9.0
    wp = 2 * math.pi / tp
    w = np.linspace(0.2, 3.0, 5001)
    pm = 5.0 / 16.0 * hs ** 2 * wp ** 4 * w ** -5 * np.exp(-1.25 * (wp / w) ** 4)
    np.testing.assert_allclose(Jonswap(hs, tp, 1.0).density(w), pm, rtol=1e-10, atol=1e-14)
    for gamma in (1.0, 3.3):
        s = Jonswap(hs, tp, gamma).density(w)
        assert w[np.argmax(s)] == pytest.approx(wp, abs=w[1] - w[0])


# ----------------------------------------------------------------------------- irregular

def unit_heave_rao(path: Path) -> None:
    rows = [[w, h, 1.0, 0.0] for w in (0.05, 1.0, 6.0) for h in (0.0, 90.0, 180.0, 270.0)]
    write_csv(path, "omega [rad/s],heading [deg],heave_amp [m/m],heave_phase [deg]",
              np.array(rows))


def test_irregular_unit_rao_heave_variance_is_hs2_over_16(tmp_path):
    unit_heave_rao(tmp_path / "rao.csv")
    hs, tp = 3.0, 9.0
    wp = 2 * math.pi / tp
    sea = motion_from_config({"type": "irregular", "hs": hs, "tp": tp, "gamma": 3.3,
                              "heading": 200.0, "speed": 3.0, "components": 300,
                              "omega_min": 0.3 * wp, "omega_max": 6.0 * wp, "ramp": 0.0,
                              "rao": {"file": "rao.csv"}}, base_dir=tmp_path)
    t = np.arange(0.0, 3 * 3600.0, 0.5)
    heave = sea.evaluate_many(t)[:, 0, 2]
    eta = sea.wave_elevation(t)
    np.testing.assert_allclose(heave, eta, atol=1e-9)      # unit RAO, zero phase
    # the band [0.3, 6] omega_p holds all but 0.1 % of the energy; a 3 h record of 300
    # components reproduces the variance to about 1 %
    assert np.var(heave) == pytest.approx(hs ** 2 / 16.0, rel=0.03)
    assert sea.waves.variance == pytest.approx(hs ** 2 / 16.0, rel=2e-3)
    other = [v for k, v in enumerate(sea.evaluate(100.0).T) if k != 2]
    np.testing.assert_array_equal(other, 0.0)


def test_irregular_seed_reproducible_and_distinct():
    t = np.linspace(0.0, 300.0, 601)
    a = motion_from_config({**DEFAULT_SEA, "seed": 7}).evaluate_many(t)
    b = motion_from_config({**DEFAULT_SEA, "seed": 7}).evaluate_many(t)
    c = motion_from_config({**DEFAULT_SEA, "seed": 8}).evaluate_many(t)
    np.testing.assert_array_equal(a, b)
    assert np.abs(a[:, 0, 2] - c[:, 0, 2]).max() > 0.3
    equal = motion_from_config({**DEFAULT_SEA, "seed": 7, "spacing": "equal"})
    assert np.all(np.diff(equal.waves.omega) == pytest.approx(equal.waves.omega[1] - equal.waves.omega[0]))


def test_irregular_ramp_starts_at_rest():
    sea = motion_from_config(DEFAULT_SEA)
    np.testing.assert_allclose(sea.evaluate(0.0), 0.0, atol=1e-15)
    assert np.abs(sea.evaluate_many(np.linspace(30, 60, 50))[:, 0, 2]).max() > 0.1


def test_default_sea_statistics():
    sea = motion_from_config(DEFAULT_SEA)
    t = np.arange(DEFAULT_SEA["ramp"], DEFAULT_SEA["ramp"] + 3600.0, 0.5)
    std = sea.evaluate_many(t)[:, 0, :].std(axis=0)
    # moderate sea on a frigate: heave about +-1 m, pitch about +-2 deg, roll a few deg
    assert 0.35 <= std[2] <= 0.55
    assert 0.7 * DEG <= std[4] <= 1.2 * DEG
    assert 1.2 * DEG <= std[3] <= 2.6 * DEG
    # independent check: frequency-domain variance int S |H|^2 domega over the band
    rao = ClosedFormRao()
    spec = Jonswap(DEFAULT_SEA["hs"], DEFAULT_SEA["tp"], DEFAULT_SEA["gamma"])
    heading, speed = DEFAULT_SEA["heading"] * DEG, DEFAULT_SEA["speed"]
    lo, hi = sea.band
    for dof in (2, 3, 4):
        var = quad(lambda w: float(spec.density(w) * abs(rao(np.array([w]), heading, speed)[0, dof]) ** 2),
                   lo, hi, limit=400, points=[spec.peak_frequency, 2 * math.pi / 10.0])[0]
        assert std[dof] == pytest.approx(math.sqrt(var), rel=0.06)
        assert sea.response_std()[dof] == pytest.approx(math.sqrt(var), rel=0.03)


def test_closed_form_rao_limits():
    rao = ClosedFormRao()
    w = np.array([0.005])
    k = w[0] ** 2 / GRAVITY
    for mu in (0.0, 40.0, 90.0, 130.0, 180.0, 300.0):
        h = rao(w, mu * DEG, 0.0)[0]
        # long waves: heave follows the surface, pitch = -d eta/dX (bow down positive),
        # roll = d eta/dY (port up positive), phases included; the roll oscillator at
        # omega / omega_4 = 0.008 deviates by 2 zeta 0.008 = 1.6e-3 from the static slope
        assert h[2] == pytest.approx(1.0, abs=1e-3)
        assert h[4] == pytest.approx(1j * k * math.cos(mu * DEG), abs=1e-3 * k)
        assert h[3] == pytest.approx(-1j * k * math.sin(mu * DEG), abs=3e-3 * k)
        assert h[0] == h[1] == h[5] == 0
    # roll resonance at omega_e = omega_4: amplification 1 / (2 zeta) of the effective slope
    w4 = 2 * math.pi / rao.particulars.roll_period
    k4 = w4 ** 2 / GRAVITY
    # beam seas: omega_e = omega whatever the speed, no averaging along the hull
    h4 = rao(np.array([w4]), 90 * DEG, 5.0)[0, 3]
    slope = k4 * math.exp(-0.5 * k4 * rao.particulars.draught)
    assert abs(h4) == pytest.approx(slope / (2 * rao.particulars.roll_damping), rel=1e-9)


def test_encounter_frequency():
    sea = motion_from_config({**DEFAULT_SEA, "heading": 180.0, "speed": 5.0})
    w = sea.waves.omega
    np.testing.assert_allclose(sea.encounter_frequency, w + w ** 2 * 5.0 / GRAVITY)


def test_rao_table_bilinear_and_periodic(tmp_path):
    rows = []
    for w in (0.5, 1.0, 1.5):
        for h in (0.0, 120.0, 240.0):
            rows.append([w, h, w + h / 100.0, 10.0 * w, 2.0, 0.0])
    write_csv(tmp_path / "rao.csv", "frequency,heading,heave_amp,heave_phase,pitch_amp,pitch_phase",
              np.array(rows))
    table = RaoTable.from_csv(tmp_path / "rao.csv")
    assert table.periodic
    got = table(np.array([0.75]), 60.0 * DEG, 0.0)[0]
    # heave: real/imag bilinear between (0.5, 0), (1, 0), (0.5, 120), (1, 120)
    corners = [(a + h / 100.0) * np.exp(1j * 10.0 * a * DEG) for a in (0.5, 1.0) for h in (0.0, 120.0)]
    assert got[2] == pytest.approx(np.mean(corners))
    assert got[4] == pytest.approx(2.0 * DEG)
    # 300 deg lies between 240 and 360 (= 0): periodic wrap
    got = table(np.array([1.0]), 300.0 * DEG, 0.0)[0]
    assert got[2].real == pytest.approx(0.5 * ((1.0 + 2.4) + 1.0) * math.cos(10 * DEG))


# ----------------------------------------------------------------------------- manoeuvre

def test_manoeuvre_turn_angle_and_radius():
    speed, rate, angle = 6.0, 1.5 * DEG, 270.0 * DEG
    turn = Turn(start=40.0, rate=rate, angle=angle, ramp=8.0)
    ship = Manoeuvre(speed, heading=20 * DEG, position=(100.0, -50.0), initial_speed=0.0,
                     speed_ramp=30.0, turn=turn)
    end = ship.evaluate(turn.end + 50.0)
    assert end[0, 5] - 20 * DEG == pytest.approx(angle, abs=1e-12)
    assert end[1, 5] == 0.0 and end[2, 5] == 0.0
    steady = np.linspace(turn.start + turn.ramp, turn.start + turn.ramp + turn.hold, 400)
    state = ship.evaluate_many(steady)
    np.testing.assert_allclose(state[:, 1, 5], rate, rtol=1e-12)
    cx, cy, radius = fit_circle(state[:, 0, 0], state[:, 0, 1])
    assert radius == pytest.approx(speed / rate, rel=1e-7)
    # port turn: the centre is on the left of the track
    psi = state[0, 0, 5]
    left = np.array([-math.sin(psi), math.cos(psi)])
    np.testing.assert_allclose([cx, cy], state[0, 0, 0:2] + radius * left, atol=1e-5 * radius)
    # the track is the integral of the speed along the heading (scipy quadrature)
    def speed(t):
        return 6.0 * (t / 30.0) ** 3 * (10 - 15 * t / 30.0 + 6 * (t / 30.0) ** 2) if t < 30.0 else 6.0
    corners = [30.0, turn.start, turn.start + turn.ramp, turn.start + turn.ramp + turn.hold, turn.end]
    for t_end in (25.0, 61.3, turn.end - 3.7, turn.end + 20.0):
        points = [p for p in corners if p < t_end]
        for axis, trig in ((0, math.cos), (1, math.sin)):
            exact = quad(lambda t: speed(t) * trig(ship.evaluate(t)[0, 5]), 0.0, t_end,
                         points=points, limit=400, epsabs=1e-11, epsrel=1e-12)[0]
            start = (100.0, -50.0)[axis]
            assert ship.evaluate(t_end)[0, axis] == pytest.approx(start + exact, abs=1e-7)


def test_manoeuvre_straight_run_with_speed_ramp_is_exact():
    ship = Manoeuvre(5.0, heading=30 * DEG, position=(1.0, 2.0), initial_speed=1.0, speed_ramp=20.0)
    t = np.array([-3.0, 0.0, 4.2, 10.0, 19.9, 20.0, 55.0])
    # distance = u0 t + (U - u0) T int_0^{t/T} s(tau) dtau
    dist = 1.0 * t + 4.0 * 20.0 * smoothstep_integral(t / 20.0)
    got = ship.evaluate_many(t)
    np.testing.assert_allclose(got[:, 0, 0], 1.0 + dist * math.cos(30 * DEG), atol=1e-9)
    np.testing.assert_allclose(got[:, 0, 1], 2.0 + dist * math.sin(30 * DEG), atol=1e-9)
    np.testing.assert_array_equal(got[:, :, 2:5], 0.0)


def test_manoeuvre_starboard_turn_and_derivatives():
    config = {"type": "manoeuvre", "speed": 4.0, "heading": 90.0, "turn_start": 5.0,
              "turn_rate": -3.0, "turn_angle": 45.0, "turn_ramp": 5.0}
    ship = motion_from_config(config)
    assert math.degrees(ship.evaluate(100.0)[0, 5]) == pytest.approx(45.0, abs=1e-12)
    assert_derivatives_consistent(ship, np.linspace(0.0, 30.0, 301) + 0.0123)


def test_superposition_rotates_wave_surge_with_heading():
    waves = RegularMotion([Harmonic(0, 0.5, 7.0), Harmonic(2, 1.0, 9.0)])
    base = Manoeuvre(0.0, heading=90 * DEG, position=(3.0, 4.0))
    both = SuperposedMotion(base, waves).evaluate_many(np.array([1.0, 2.0]))
    alone = waves.evaluate_many(np.array([1.0, 2.0]))
    np.testing.assert_allclose(both[:, :, 0], np.tile([3.0, 0.0, 0.0], (2, 1)), atol=1e-12)
    np.testing.assert_allclose(both[:, :, 1] - [4.0, 0, 0], alone[:, :, 0], atol=1e-12)
    np.testing.assert_allclose(both[:, :, 2], alone[:, :, 2], atol=1e-12)
    # a constant-speed run without turn is one straight line, t = 0 included
    run = Manoeuvre(2.0, heading=90 * DEG, position=(3.0, 4.0)).evaluate_many([-1.0, 0.0, 5.0])
    np.testing.assert_allclose(run[:, 0, 0:2], [[3.0, 2.0], [3.0, 4.0], [3.0, 14.0]], atol=1e-12)
    np.testing.assert_allclose(run[:, 1, 0:2], [[0.0, 2.0]] * 3, atol=1e-12)


def test_manoeuvre_with_irregular_waves_uses_manoeuvre_speed():
    motion = motion_from_config({"type": "manoeuvre", "speed": 6.0,
                                 "waves": {"type": "irregular", "heading": 180.0}})
    assert isinstance(motion, SuperposedMotion)
    assert isinstance(motion.waves, IrregularSea) and motion.waves.speed == 6.0
    state = motion.evaluate(100.0)
    assert state[1, 0] == pytest.approx(6.0)   # forward speed (surge RAO is zero)


# ----------------------------------------------------------------------------- config errors

@pytest.mark.parametrize("table, key", [
    ({"type": "regular", "heave": {"amplitude": 1.0, "periode": 8.0}}, "motion.heave.periode"),
    ({"type": "regular", "heave": {"amplitude": 1.0, "period": -8.0}}, "motion.heave.period"),
    ({"type": "regular", "heave": {"amplitude": float("nan"), "period": 8.0}}, "motion.heave.amplitude"),
    ({"type": "regular", "heave": {"amplitude": 1.0}}, "motion.heave.period"),
    ({"type": "regular", "pitch": {"amplitude": 60.0, "mean": 40.0, "period": 8.0}},
     "motion.pitch.amplitude"),
    ({"type": "regular", "surf": {}}, "motion.surf"),
    ({"type": "wobble"}, "motion.type"),
    ({"type": "none", "hs": 1.0}, "motion.hs"),
    ({"type": "irregular", "hs": 25.0}, "motion.hs"),
    ({"type": "irregular", "tp": float("inf")}, "motion.tp"),
    ({"type": "irregular", "seed": 1.5}, "motion.seed"),
    ({"type": "irregular", "spacing": "log"}, "motion.spacing"),
    ({"type": "irregular", "omega_min": 1.0, "omega_max": 0.5}, "motion.omega_max"),
    ({"type": "irregular", "rao": {"roll_damping": 0.0}}, "motion.rao.roll_damping"),
    ({"type": "irregular", "rao": {"lenght": 100.0}}, "motion.rao.lenght"),
    ({"type": "time_series"}, "motion.file"),
    ({"type": "time_series", "file": "missing.csv"}, "motion.file"),
    ({"type": "manoeuvre"}, "motion.speed"),
    ({"type": "manoeuvre", "speed": 5.0, "initial_speed": 1.0}, "motion.speed_ramp"),
    ({"type": "manoeuvre", "speed": 5.0, "turn_angle": 90.0}, "motion.turn_rate"),
    ({"type": "manoeuvre", "speed": 5.0, "turn_angle": 5.0, "turn_rate": 1.0}, "motion.turn_angle"),
    ({"type": "manoeuvre", "speed": 5.0, "turn_angle": 90.0, "turn_rate": 0.0}, "motion.turn_rate"),
    ({"type": "manoeuvre", "speed": 5.0, "position": [1.0]}, "motion.position"),
    ({"type": "manoeuvre", "speed": 5.0, "waves": {"type": "irregular", "hs": -1.0}}, "motion.waves.hs"),
    ({"type": "manoeuvre", "speed": 5.0, "waves": {"type": "time_series"}}, "motion.waves.type"),
])
def test_config_errors_name_the_key(table, key, tmp_path):
    with pytest.raises(SceneError) as err:
        motion_from_config(table, base_dir=tmp_path)
    assert err.value.key == key
    assert err.value.allowed


def test_config_error_message_states_range_with_units():
    with pytest.raises(SceneError, match=r"motion.heave.period = -8.0 is invalid: allowed .*> 0 s"):
        motion_from_config({"type": "regular", "heave": {"amplitude": 1.0, "period": -8.0}})
    with pytest.raises(SceneError, match=r"scene.motion.hs .*\[0, 20\] m"):
        motion_from_config({"type": "irregular", "hs": 30.0}, key="scene.motion")


def test_rao_table_must_cover_band(tmp_path):
    unit_heave_rao(tmp_path / "rao.csv")
    with pytest.raises(SceneError) as err:
        motion_from_config({"type": "irregular", "omega_max": 7.0, "rao": {"file": "rao.csv"}},
                           base_dir=tmp_path)
    assert err.value.key == "motion.rao.file"


def test_quintic_hermite_is_scipys_bpoly_from_derivatives():
    """The manoeuvre's track in one array operation is the polynomial scipy builds
    interval by interval from the same values and two derivatives at each knot."""
    from scipy.interpolate import BPoly

    from ship_motion.manoeuvre import quintic_hermite

    rng = np.random.default_rng(7)
    x = np.cumsum(rng.uniform(0.1, 2.0, 40))
    p, v, a = (rng.normal(size=(40, 2)) for _ in range(3))
    ours = quintic_hermite(x, p, v, a)
    scipys = BPoly.from_derivatives(x, np.stack([p, v, a], axis=1))
    t = np.linspace(x[0], x[-1], 2001)
    for nu in range(3):
        np.testing.assert_allclose(ours(t, nu), scipys(t, nu), rtol=1e-12, atol=1e-11)
    for k, values in enumerate((p, v, a)):
        np.testing.assert_allclose(ours(x, k), values, rtol=1e-12, atol=1e-11)
