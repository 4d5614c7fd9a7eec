"""Scene ``sea_trial_turn`` (nodal-position paper, section 3.2): statics and the steady tow."""

from __future__ import annotations

import math

import numpy as np
import pytest

from towcable_fmu.ancf.simulation import Simulation


def _wet_weight_by_hand() -> float:
    """Wet weight [N] of the two cable segments and the body, from the scene file's numbers."""
    g, rho = 9.81, 1025.0
    bare = (5.20 - rho * math.pi * 0.0411**2 / 4.0) * 355.0
    faired = (8.32 - rho * math.pi * 0.080**2 / 4.0) * 125.0
    body = 9500.0 - rho * 6.25
    return (bare + faired + body) * g


def test_hanging_statics_carry_the_wet_weight():
    sim = Simulation.from_scene("sea_trial_turn")
    out = sim.initialize()
    # the ship is at rest at t = 0 (speed ramp from 0): the cable hangs vertically and the tow
    # point carries the wet weight of cable and body; stretch changes the buoyant volume by < 1e-3
    assert out["tension.top"] == pytest.approx(_wet_weight_by_hand(), rel=1e-3)
    assert out["towbody.z"] == pytest.approx(-480.0, rel=2e-3)


def test_steady_tow_follows_the_ship_and_the_turn():
    sim = Simulation.from_scene("sea_trial_turn")
    sim.initialize()
    res = sim.run(1400.0, interval=1.0)
    t = res["time"]
    ship = sim.motion.evaluate_many(t)
    steady = (t > 300.0) & (t < 400.0)
    # in the steady straight tow the body moves with the ship, at 12 kn along x
    assert np.mean(res["towbody.vx"][steady]) == pytest.approx(6.17, rel=2e-3)
    assert np.max(np.abs(res["towbody.vy"][steady])) < 1e-3
    # and it streams out: far shallower than the hanging 480 m, with the tension above the
    # wet weight (drag adds to it), never slack
    assert -300.0 < np.mean(res["towbody.z"][steady]) < -100.0
    assert np.mean(res["tension.top"][steady]) > _wet_weight_by_hand()
    assert np.all(res["tension.top"] > 0.0)
    # in the steady part of the turn (radius R = U / r) the body runs on the ship's circle a
    # chord d behind it (d: the horizontal distance in the straight tow), so its course lags
    # the ship's heading by 2 asin(d / 2R)
    d = float(np.mean(np.hypot(res["towbody.x"] - ship[:, 0, 0], res["towbody.y"] - ship[:, 0, 1])[steady]))
    radius = 6.17 / math.radians(0.4)
    lag_expected = math.degrees(2.0 * math.asin(d / (2.0 * radius)))
    turning = (t > 700.0) & (t < 1050.0)
    course = np.degrees(np.arctan2(res["towbody.vy"][turning], res["towbody.vx"][turning]))
    lag = np.mod(np.degrees(ship[turning, 0, 5]) - course, 360.0)
    assert np.mean(lag) == pytest.approx(lag_expected, abs=2.0)
    # after the turn (heading 270 deg) the body runs straight again along -y
    end = t > 1350.0
    assert math.degrees(math.atan2(np.mean(res["towbody.vy"][end]), np.mean(res["towbody.vx"][end]))) == \
        pytest.approx(-90.0, abs=0.5)
