"""Drive tables: the ship motion within one solver call."""

from __future__ import annotations

import numpy as np

from towcable_fmu.runtime.drive import knot_drive, taylor_drive
from towcable_fmu.runtime.drive import evaluate_drive

W = np.array([0.7, 0.3, 1.1, 0.5, 0.9, 0.2])
AMP = np.array([1.0, 0.5, 2.0, 0.1, 0.05, 0.3])


def _ship(t):
    s = np.zeros((3, 6))
    s[0] = AMP * np.sin(W * t)
    s[1] = AMP * W * np.cos(W * t)
    s[2] = -AMP * W**2 * np.sin(W * t)
    return s


def test_knot_drive_matches_knots_and_interpolates_to_sixth_order():
    times = np.linspace(2.0, 3.0, 6)
    ships = np.array([_ship(t) for t in times])
    sp = np.column_stack([1.0 + 0.2 * times**2, 0.4 * times])  # phi_sp and its exact rate
    dt, tab = knot_drive(times, ships, sp)
    out = np.zeros((3, 6))
    for t in times:
        phi, rate = evaluate_drive(dt, tab, t, out)
        np.testing.assert_allclose(out, _ship(t), atol=1e-12)
        assert abs(phi - (1.0 + 0.2 * t**2)) < 1e-12 and abs(rate - 0.4 * t) < 1e-12
    # between knots: O(h^6) in value, O(h^4) in acceleration; the quadratic set-point is exact
    errors = []
    for n in (4, 8):
        times = np.linspace(2.0, 3.0, n + 1)
        dt, tab = knot_drive(times, np.array([_ship(t) for t in times]),
                             np.column_stack([1.0 + 0.2 * times**2, 0.4 * times]))
        mids = 0.5 * (times[1:] + times[:-1])
        err = 0.0
        for t in mids:
            phi, rate = evaluate_drive(dt, tab, t, out)
            err = max(err, np.abs(out[0] - _ship(t)[0]).max())
            assert abs(phi - (1.0 + 0.2 * t**2)) < 1e-12 and abs(rate - 0.4 * t) < 1e-12
        errors.append(err)
    assert errors[1] < errors[0] / 40  # 2^6 = 64 for a sixth-order error
    assert errors[0] < 1e-7


def test_taylor_drive_is_constant_acceleration():
    ship = _ship(1.0)
    dt, tab = taylor_drive(1.0, ship, (0.5, -0.1))
    out = np.zeros((3, 6))
    sp, rate = evaluate_drive(dt, tab, 1.2, out)
    np.testing.assert_allclose(out[2], ship[2], atol=1e-14)
    np.testing.assert_allclose(out[1], ship[1] + 0.2 * ship[2], atol=1e-14)
    np.testing.assert_allclose(out[0], ship[0] + 0.2 * ship[1] + 0.02 * ship[2], atol=1e-14)
    assert abs(sp - 0.48) < 1e-14 and rate == -0.1
