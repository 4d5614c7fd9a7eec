"""Tests of the AHC set-point algorithms W(1)-(2) (controllers package).

Expected values are closed forms written out by hand from the thesis formulas and
the rotation W(24)-(25), or finite differences of the code's own payout.
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

from controllers import (
    MOTION_ALGORITHMS,
    SetpointAlgorithm,
    SetpointConfig,
    setpoint_config_from_table,
)
from towcable_fmu.common.errors import SceneError

# full-scale case, W Table 8 / section 5.4
SHEAVE = (-36.8, 0.0, 3.7)  # m, body frame
R_W = 0.30  # m
PHI_NOM = 3.8  # rad
THETA_NOM = 0.6  # rad


def algorithm(name: str, **overrides) -> SetpointAlgorithm:
    """Algorithm with the full-scale parameters, optionally overridden."""
    params = dict(algorithm=name, reference_point=SHEAVE, winch_radius=R_W,
                  phi_nom=PHI_NOM, theta_nom=THETA_NOM)
    params.update(overrides)
    return SetpointAlgorithm(SetpointConfig(**params))


def ship_state(value=(), rate=()) -> np.ndarray:
    """Ship state (3, 6) from {column index: value} pairs of position and rate."""
    ship = np.zeros((3, 6))
    for col, v in dict(value).items():
        ship[0, col] = v
    for col, v in dict(rate).items():
        ship[1, col] = v
    return ship


def smooth_ship(t: float) -> np.ndarray:
    """Analytic 6-DOF ship motion: every DOF a sinusoid, with exact derivatives."""
    amp = np.array([0.8, 0.5, 1.5, 0.06, 0.04, 0.03])
    omega = np.array([0.4, 0.55, 0.7, 0.5, 0.65, 0.3])
    phase = np.array([0.1, 0.7, 1.3, 0.4, 2.0, 1.1])
    arg = omega * t + phase
    return np.array([amp * np.sin(arg),
                     amp * omega * np.cos(arg),
                     -amp * omega**2 * np.sin(arg)])


# ---------------------------------------------------------------- closed forms

@pytest.mark.parametrize("name", ["simplified_sheave", "rigorous_sheave"])
def test_heave_sheave_pays_out_dz_cos_theta(name):
    dz, vz = 0.7, -0.3
    sp = algorithm(name).compute(ship_state({2: dz}, {2: vz}), THETA_NOM)
    c = math.cos(THETA_NOM)
    assert sp.payout == pytest.approx(dz * c, rel=1e-12)
    assert sp.phi_sp == pytest.approx(PHI_NOM - dz * c / R_W, rel=1e-12)
    assert sp.payout_rate == pytest.approx(vz * c, rel=1e-12)
    assert sp.phi_sp_rate == pytest.approx(-vz * c / R_W, rel=1e-12)
    assert sp.theta_used == THETA_NOM and not sp.theta_fallback


@pytest.mark.parametrize("name", ["simplified_waterline", "rigorous_waterline"])
def test_heave_waterline_pays_out_dz_over_cos_theta(name):
    dz, vz = 0.7, -0.3
    sp = algorithm(name, waterline_z=-0.4).compute(ship_state({2: dz}, {2: vz}),
                                                    THETA_NOM)
    c = math.cos(THETA_NOM)
    assert sp.payout == pytest.approx(dz / c, rel=1e-12)
    assert sp.phi_sp == pytest.approx(PHI_NOM - dz / c / R_W, rel=1e-12)
    assert sp.payout_rate == pytest.approx(vz / c, rel=1e-12)
    assert sp.phi_sp_rate == pytest.approx(-vz / c / R_W, rel=1e-12)


def test_surge_sheave_pays_out_dx_sin_theta_and_waterline_nothing():
    dx, vx = 1.2, 0.25
    ship = ship_state({0: dx}, {0: vx})
    sheave = algorithm("simplified_sheave").compute(ship)
    assert sheave.payout == pytest.approx(dx * math.sin(THETA_NOM), rel=1e-12)
    assert sheave.payout_rate == pytest.approx(vx * math.sin(THETA_NOM), rel=1e-12)
    waterline = algorithm("simplified_waterline").compute(ship)
    assert waterline.payout == pytest.approx(0.0, abs=1e-12)
    assert waterline.payout_rate == pytest.approx(0.0, abs=1e-12)


def test_pitch_moves_aft_sheave_vertically():
    beta, beta_rate = 0.04, 0.1  # rad, rad/s (positive pitch: bow down)
    X, _, Z = SHEAVE
    # R_y(beta) s - s, and d/dt of R_y(beta) s, by hand from W(25b)
    dx = X * (math.cos(beta) - 1.0) + Z * math.sin(beta)
    dz = -X * math.sin(beta) + Z * (math.cos(beta) - 1.0)
    vx = (-X * math.sin(beta) + Z * math.cos(beta)) * beta_rate
    vz = (-X * math.cos(beta) - Z * math.sin(beta)) * beta_rate
    assert dz > 1.4  # the aft sheave rises by about 36.8 * 0.04 m
    ship = ship_state({4: beta}, {4: beta_rate})
    s, c = math.sin(THETA_NOM), math.cos(THETA_NOM)

    sheave = algorithm("simplified_sheave").compute(ship)
    assert sheave.payout == pytest.approx(dx * s + dz * c, rel=1e-12)
    assert sheave.payout_rate == pytest.approx(vx * s + vz * c, rel=1e-12)
    waterline = algorithm("simplified_waterline").compute(ship)
    assert waterline.payout == pytest.approx(dz / c, rel=1e-12)
    assert waterline.payout_rate == pytest.approx(vz / c, rel=1e-12)


def test_none_gives_nominal_winch_angle():
    sp = algorithm("none").compute(smooth_ship(3.0), 0.2)
    assert (sp.payout, sp.payout_rate, sp.phi_sp_rate) == (0.0, 0.0, 0.0)
    assert sp.phi_sp == PHI_NOM


@pytest.mark.parametrize("name", ["simplified_sheave", "simplified_waterline"])
def test_rates_are_time_derivatives_of_the_setpoint(name):
    alg = algorithm(name)
    h = 1e-5
    for t in np.linspace(0.0, 20.0, 7):
        sp = alg.compute(smooth_ship(t))
        ahead, behind = alg.compute(smooth_ship(t + h)), alg.compute(smooth_ship(t - h))
        fd_payout = (ahead.payout - behind.payout) / (2 * h)
        fd_phi = (ahead.phi_sp - behind.phi_sp) / (2 * h)
        assert sp.payout_rate == pytest.approx(fd_payout, rel=1e-6, abs=1e-8)
        assert sp.phi_sp_rate == pytest.approx(fd_phi, rel=1e-6, abs=1e-8)


# ------------------------------------------------------- rigorous measured angle

@pytest.mark.parametrize("method", ["sheave", "waterline"])
def test_rigorous_equals_simplified_at_nominal_angle(method):
    ship = smooth_ship(4.2)
    simplified = algorithm(f"simplified_{method}").compute(ship, 0.9)  # angle ignored
    rigorous = algorithm(f"rigorous_{method}").compute(ship, THETA_NOM)
    assert rigorous == simplified


def test_rigorous_uses_the_measured_angle():
    theta = 0.35
    dx, dz = 0.5, 0.9
    ship = ship_state({0: dx, 2: dz})
    sheave = algorithm("rigorous_sheave").compute(ship, theta)
    assert sheave.payout == pytest.approx(dx * math.sin(theta) + dz * math.cos(theta),
                                          rel=1e-12)
    assert sheave.theta_used == theta and not sheave.theta_fallback

    # ship at rest: W(1) with H = H_nom but theta != theta_nom
    z_wl = -0.4
    h_nom = SHEAVE[2] - z_wl
    waterline = algorithm("rigorous_waterline", waterline_z=z_wl).compute(
        np.zeros((3, 6)), theta)
    assert waterline.payout == pytest.approx(
        h_nom / math.cos(theta) - h_nom / math.cos(THETA_NOM), rel=1e-12)


@pytest.mark.parametrize("method", ["sheave", "waterline"])
@pytest.mark.parametrize("angle", [None, math.nan, math.inf, 0.5 * math.pi, -2.0])
def test_unusable_angle_falls_back_to_nominal(method, angle):
    ship = smooth_ship(7.5)
    sp = algorithm(f"rigorous_{method}").compute(ship, angle)
    reference = algorithm(f"simplified_{method}").compute(ship)
    assert sp.theta_fallback
    assert sp.theta_used == THETA_NOM
    assert np.isfinite([sp.phi_sp, sp.phi_sp_rate, sp.payout, sp.payout_rate]).all()
    assert (sp.phi_sp, sp.phi_sp_rate) == (reference.phi_sp, reference.phi_sp_rate)


# --------------------------------------------------------------------- limits

def test_payout_limit_clips_and_holds():
    alg = algorithm("simplified_sheave", max_payout=0.5)
    sp = alg.compute(ship_state({2: 2.0}, {2: 1.0}))
    assert sp.payout_clipped and sp.payout == 0.5
    assert sp.payout_rate == 0.0 and sp.phi_sp_rate == 0.0
    assert sp.phi_sp == pytest.approx(PHI_NOM - 0.5 / R_W)
    below = alg.compute(ship_state({2: -0.2}, {2: 1.0}))
    assert not below.payout_clipped
    assert below.payout == pytest.approx(-0.2 * math.cos(THETA_NOM))


def test_winch_speed_limit_clips_rate_only():
    alg = algorithm("simplified_sheave", max_winch_speed=1.0)
    sp = alg.compute(ship_state({2: 0.3}, {2: -2.0}))
    c = math.cos(THETA_NOM)
    assert sp.rate_clipped
    assert sp.phi_sp_rate == pytest.approx(1.0)  # unclipped: 2 c / 0.3 = 5.5 rad/s
    assert sp.payout_rate == pytest.approx(-R_W)
    assert sp.phi_sp == pytest.approx(PHI_NOM - 0.3 * c / R_W)  # position unlimited


# --------------------------------------------------------------------- series

@pytest.mark.parametrize("name", MOTION_ALGORITHMS)
def test_series_matches_single_evaluations(name):
    times = np.linspace(0.0, 10.0, 6)
    ships = np.array([smooth_ship(t) for t in times])
    angles = np.array([0.5, math.nan, 0.7, 0.55, math.inf, 0.62])
    alg = algorithm(name, max_payout=1.0, waterline_z=-1.0)
    series = alg.compute_series(ships, angles)
    for i, (ship, angle) in enumerate(zip(ships, angles)):
        single = alg.compute(ship, angle)
        for field in ("phi_sp", "phi_sp_rate", "payout", "payout_rate", "theta_used",
                      "theta_fallback", "payout_clipped", "rate_clipped"):
            assert getattr(series, field)[i] == getattr(single, field), field
    unmeasured = alg.compute_series(ships)
    assert unmeasured.theta_fallback.all() == name.startswith("rigorous")


def test_wrong_ship_shape_is_rejected():
    with pytest.raises(ValueError):
        algorithm("simplified_sheave").compute(np.zeros(18))
    with pytest.raises(ValueError):
        algorithm("simplified_sheave").compute_series(np.zeros((4, 3, 6)), np.zeros(3))


# --------------------------------------------------------------------- config

@pytest.mark.parametrize(("field", "value"), [
    ("winch_radius", -0.3),
    ("winch_radius", 0.0),
    ("algorithm", "sheave"),
    ("theta_nom", 0.5 * math.pi),
    ("theta_nom", -0.1),
    ("phi_nom", math.nan),
    ("reference_point", (1.0, 2.0)),
    ("reference_point", "sheave"),
    ("max_payout", 0.0),
    ("max_winch_speed", True),
])
def test_bad_config_names_the_key(field, value):
    with pytest.raises(SceneError) as err:
        algorithm("simplified_sheave", **{field: value})
    assert err.value.key == f"compensation.{field}"
    assert err.value.value is value


def test_waterline_needs_reference_point_above_waterline():
    algorithm("simplified_sheave", waterline_z=5.0)  # irrelevant for the sheave
    with pytest.raises(SceneError) as err:
        algorithm("rigorous_waterline", waterline_z=5.0)
    assert err.value.key == "compensation.waterline_z"


TABLE = """
[hc]
algorithm = "rigorous_sheave"
reference_point = [-36.8, 0, 3.7]
winch_radius = 0.3
phi_nom = 4
theta_nom = 0.6
max_payout = 2.5
"""


def test_config_from_toml_table():
    config = setpoint_config_from_table(tomllib.loads(TABLE)["hc"], key="hc")
    assert config == SetpointConfig("rigorous_sheave", SHEAVE, 0.3, 4.0, 0.6,
                                    max_payout=2.5)
    assert isinstance(config.phi_nom, float) and config.reference_point == SHEAVE
    assert config.rigorous and config.method == "sheave"


@pytest.mark.parametrize(("edit", "key"), [
    (lambda t: t.update(winch_radus=0.3), "hc.winch_radus"),
    (lambda t: t.pop("theta_nom"), "hc.theta_nom"),
    (lambda t: t.update(winch_radius=-1), "hc.winch_radius"),
    (lambda t: t.update(algorithm="rigorous"), "hc.algorithm"),
])
def test_bad_toml_table_names_the_key(edit, key):
    table = tomllib.loads(TABLE)["hc"]
    edit(table)
    with pytest.raises(SceneError) as err:
        setpoint_config_from_table(table, key="hc")
    assert err.value.key == key
