"""Ship rigid-body kinematics, W(24)-(25) (`towcable_fmu.numerics.kinematics`).

Checked independently of the code under test:

* the rotation matrix against a product of elementary rotations built here by hand,
  R = Rz(yaw) Ry(pitch) Rx(roll), and its orthonormality (R^T R = I, det R = +1);
* the velocity and acceleration of a ship-fixed point against central finite
  differences of its position along a smooth, large-amplitude 6-DOF trajectory written
  out analytically in this file;
* dR/dt = [omega]x R and the point velocity v_cg + omega x (R s), with the inertial
  angular velocity built from the Euler rates of the Z-Y-X sequence,
  omega = yaw_rate e_z + pitch_rate Rz e_y + roll_rate Rz Ry e_x;
* the point acceleration a_cg + alpha x r + omega x (omega x r), with alpha from a
  finite difference of that omega.
"""

import math

import numpy as np
import pytest

from towcable_fmu.numerics.kinematics import rotation_derivatives, rotation_matrix, ship_point_kinematics


def rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


# Analytic 6-DOF trajectory: q_j(t) = c_j + d_j t + a_j sin(w_j t + p_j), large
# angles (roll up to ~0.6 rad, pitch ~0.45 rad, yaw drifting through several radians)
# so that every coupling term of the Euler sequence matters.
_C = np.array([3.0, -2.0, 0.5, 0.1, -0.05, 0.3])
_D = np.array([5.0, 0.7, 0.0, 0.0, 0.0, 0.25])
_A = np.array([1.5, 2.0, 3.0, 0.5, 0.4, 0.6])
_W = np.array([0.6, 0.9, 0.8, 1.1, 0.7, 0.5])
_P = np.array([0.2, 1.0, -0.4, 0.7, 2.1, -1.3])

#: Body coordinates of ship-fixed points: a stern sheave, a point far off all axes.
POINTS = [np.array([-40.0, 3.0, 12.0]), np.array([25.0, -8.0, -6.0])]
TIMES = [0.0, 1.3, 4.7, 9.1]


def ship_state(t):
    """(3, 6) ship state of the analytic trajectory at time t (exact derivatives)."""
    ph = _W * t + _P
    q = _C + _D * t + _A * np.sin(ph)
    qd = _D + _A * _W * np.cos(ph)
    qdd = -_A * _W**2 * np.sin(ph)
    return np.array([q, qd, qdd])


def point_position(t, s):
    """Inertial position of the body point s, built here with the hand-made R."""
    q = ship_state(t)[0]
    return q[0:3] + rz(q[5]) @ ry(q[4]) @ rx(q[3]) @ s


def euler_rates_to_omega(state):
    """Inertial angular velocity of the Z-Y-X Euler sequence from the Euler rates."""
    roll, pitch, yaw = state[0, 3:6]
    droll, dpitch, dyaw = state[1, 3:6]
    ez = np.array([0.0, 0.0, 1.0])
    ey = np.array([0.0, 1.0, 0.0])
    ex = np.array([1.0, 0.0, 0.0])
    return dyaw * ez + dpitch * (rz(yaw) @ ey) + droll * (rz(yaw) @ ry(pitch) @ ex)


@pytest.mark.parametrize("roll, pitch, yaw", [
    (0.0, 0.0, 0.0), (0.3, 0.0, 0.0), (0.0, -0.4, 0.0), (0.0, 0.0, 2.5),
    (0.2, -0.35, 1.2), (-1.1, 0.9, -2.8), (3.0, 1.4, 6.0),
])
def test_rotation_matrix_is_zyx_product_and_orthonormal(roll, pitch, yaw):
    r = rotation_matrix(roll, pitch, yaw)
    expected = rz(yaw) @ ry(pitch) @ rx(roll)
    assert np.max(np.abs(r - expected)) < 1e-14
    assert np.max(np.abs(r.T @ r - np.eye(3))) < 1e-14
    assert abs(np.linalg.det(r) - 1.0) < 1e-14


def test_rotation_matrix_axis_conventions():
    """Elementary cases: which way the axes turn (z up, X forward, Y port)."""
    # yaw +90 deg turns the bow (body X) to inertial +y
    assert np.allclose(rotation_matrix(0.0, 0.0, math.pi / 2) @ [1.0, 0.0, 0.0],
                       [0.0, 1.0, 0.0], atol=1e-15)
    # pitch +90 deg about Y turns body X to inertial -z (bow down)
    assert np.allclose(rotation_matrix(0.0, math.pi / 2, 0.0) @ [1.0, 0.0, 0.0],
                       [0.0, 0.0, -1.0], atol=1e-15)
    # roll +90 deg about X turns body Y (port) to inertial +z
    assert np.allclose(rotation_matrix(math.pi / 2, 0.0, 0.0) @ [0.0, 1.0, 0.0],
                       [0.0, 0.0, 1.0], atol=1e-15)
    # the order matters: pitch then yaw differs from the reverse product
    r = rotation_matrix(0.0, 0.5, 0.8)
    assert np.max(np.abs(r - ry(0.5) @ rz(0.8))) > 0.1


@pytest.mark.parametrize("t", TIMES)
def test_rotation_derivatives_match_finite_differences(t):
    st = ship_state(t)
    r, r1, r2 = rotation_derivatives(st)
    h = 1e-4

    def rot(tt):
        q = ship_state(tt)[0]
        return rz(q[5]) @ ry(q[4]) @ rx(q[3])

    assert np.max(np.abs(r - rot(t))) < 1e-14
    fd1 = (rot(t + h) - rot(t - h)) / (2 * h)
    h2 = 1e-3
    fd2 = (rot(t + h2) - 2 * rot(t) + rot(t - h2)) / h2**2
    # truncation h^2/6 |R'''| ~ 2e-9 and h2^2/12 |R''''| ~ 1e-7; round-off 1e-16/h, 1e-16/h2^2
    assert np.max(np.abs(r1 - fd1)) < 1e-7
    assert np.max(np.abs(r2 - fd2)) < 1e-5
    # dR/dt = [omega]x R with omega from the Euler rates
    omega = euler_rates_to_omega(st)
    assert np.max(np.abs(r1 - skew(omega) @ r)) < 1e-13


@pytest.mark.parametrize("s", POINTS, ids=["stern_sheave", "off_axis"])
@pytest.mark.parametrize("t", TIMES)
def test_ship_point_velocity_and_acceleration_match_finite_differences(t, s):
    out = ship_point_kinematics(ship_state(t), s)
    assert np.max(np.abs(out[0] - point_position(t, s))) < 1e-12
    h = 1e-4
    vel_fd = (point_position(t + h, s) - point_position(t - h, s)) / (2 * h)
    h2 = 2e-3
    acc_fd = (point_position(t + h2, s) - 2 * point_position(t, s)
              + point_position(t - h2, s)) / h2**2
    scale_v = np.max(np.abs(vel_fd))
    scale_a = np.max(np.abs(acc_fd))
    assert scale_v > 5.0 and scale_a > 2.0  # the motion is not trivially small
    # central differences: truncation h^2/6 |r'''| (~1e-7 m/s for |r'''| ~ 50 m/s^3),
    # h2^2/12 |r''''| (~3e-5 m/s^2); round-off ~1e-14 m / h, 1e-14 m / h2^2
    assert np.max(np.abs(out[1] - vel_fd)) < 1e-6
    assert np.max(np.abs(out[2] - acc_fd)) < 1e-4


@pytest.mark.parametrize("s", POINTS, ids=["stern_sheave", "off_axis"])
@pytest.mark.parametrize("t", TIMES)
def test_ship_point_velocity_is_v_cg_plus_omega_cross_r(t, s):
    st = ship_state(t)
    out = ship_point_kinematics(st, s)
    r = rz(st[0, 5]) @ ry(st[0, 4]) @ rx(st[0, 3]) @ s
    omega = euler_rates_to_omega(st)
    v_expected = st[1, 0:3] + np.cross(omega, r)
    assert np.max(np.abs(out[1] - v_expected)) < 1e-12
    # rigid-body acceleration: a_cg + alpha x r + omega x (omega x r), alpha = d omega/dt
    h = 1e-5
    alpha = (euler_rates_to_omega(ship_state(t + h))
             - euler_rates_to_omega(ship_state(t - h))) / (2 * h)
    a_expected = st[2, 0:3] + np.cross(alpha, r) + np.cross(omega, np.cross(omega, r))
    # alpha has O(h^2) ~ 1e-10 1/s^2 truncation and ~1e-11 round-off; |r| <= 45 m
    assert np.max(np.abs(out[2] - a_expected)) < 1e-8


def test_pure_yaw_rate_gives_circular_motion():
    """A point at radius 40 m, yaw rate 0.1 rad/s: speed 4 m/s, centripetal 0.4 m/s^2."""
    st = np.zeros((3, 6))
    st[0, 5] = 0.7
    st[1, 5] = 0.1
    s = np.array([-40.0, 0.0, 0.0])
    out = ship_point_kinematics(st, s)
    r = out[0]
    assert abs(np.linalg.norm(out[1]) - 4.0) < 1e-13
    assert abs(np.dot(out[1], r)) < 1e-12
    # acceleration points to the axis (the CG), magnitude omega^2 |r|
    assert np.allclose(out[2], -0.01 * r, atol=1e-15)
