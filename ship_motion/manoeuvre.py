"""A ship manoeuvre: straight run at constant speed, with a speed ramp and a turn.

Speed (C2 quintic step ``s`` of :mod:`ship_motion.ramp`, ramp from t = 0)::

    u(t) = u0 + (U - u0) s(t / T_u)

Yaw rate: ramps from 0 to the turning rate r over T_r, holds it, ramps back to 0::

    psi'(t) = r [s((t - t_s) / T_r) - s((t - t_s - T_r - T_h) / T_r)]

so the heading changes by r (T_r + T_h); the hold time T_h is chosen to make this the
requested turn angle. The heading is integrated analytically (integral of the quintic
step). The CG track is ``x' = u cos(psi)``, ``y' = u sin(psi)``: on [0, t_end] (until
the last ramp ends) it is a piecewise quintic Hermite spline whose knots carry the
exact position (cumulative 8-point Gauss-Legendre quadrature between knots that
include every ramp breakpoint), velocity and acceleration, so position, velocity and
acceleration are continuous and are derivatives of one another; before t = 0 and
after t_end the track is an exact straight line. Roll, pitch and z are zero.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import BPoly

from .base import MotionSource, as_times
from .ramp import smoothstep, smoothstep_integral

#: Largest spacing of the track spline's knots [s] (also at most 1/8 of any ramp).
KNOT_SPACING = 0.5

_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(8)


@dataclass(frozen=True)
class Turn:
    """A turn of the ship (module docstring).

    Parameters
    ----------
    start
        Time t_s at which the yaw rate starts to ramp up [s], >= 0.
    rate
        Steady turning rate r [rad/s], non-zero; positive turns to port
        (counter-clockwise seen from above, yaw increasing).
    angle
        Total heading change [rad], > 0 (its sign is that of ``rate``).
    ramp
        Duration T_r [s] of each yaw-rate ramp (up and down), > 0, with
        ``angle >= |rate| * ramp``.
    """

    start: float
    rate: float
    angle: float
    ramp: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.start) and self.start >= 0.0):
            raise ValueError(f"turn start must be finite and >= 0 s, got {self.start}")
        if not (math.isfinite(self.rate) and self.rate != 0.0):
            raise ValueError(f"turn rate must be finite and non-zero, got {self.rate}")
        if not (math.isfinite(self.ramp) and self.ramp > 0.0):
            raise ValueError(f"turn ramp must be finite and > 0 s, got {self.ramp}")
        if not (math.isfinite(self.angle) and self.angle >= abs(self.rate) * self.ramp):
            raise ValueError(f"turn angle must be >= |rate| * ramp = {abs(self.rate) * self.ramp:g} rad, "
                             f"got {self.angle}")

    @property
    def hold(self) -> float:
        """Time T_h at the steady turning rate [s]."""
        return self.angle / abs(self.rate) - self.ramp

    @property
    def end(self) -> float:
        """Time at which the yaw rate is back to zero [s]."""
        return self.start + 2.0 * self.ramp + self.hold


def quintic_hermite(x: np.ndarray, p: np.ndarray, v: np.ndarray, a: np.ndarray) -> BPoly:
    """The piecewise quintic through values ``p``, first derivatives ``v`` and second
    derivatives ``a`` (shape (n, d)) at the knots ``x`` (n, increasing), in Bernstein form.

    The same polynomial as ``BPoly.from_derivatives`` with three derivatives a side, built
    in one array operation (that one loops over the intervals in Python: minutes for the
    hundreds of thousands of knots of a long turn). On [x0, x1] with h = x1 - x0 the six
    Bernstein coefficients are p0, p0 + h v0 / 5, p0 + 2 h v0 / 5 + h^2 a0 / 20 and,
    mirrored, p1 - 2 h v1 / 5 + h^2 a1 / 20, p1 - h v1 / 5, p1.
    """
    h = np.diff(x)[:, None]
    p0, v0, a0, p1, v1, a1 = p[:-1], v[:-1], a[:-1], p[1:], v[1:], a[1:]
    c = np.stack([p0, p0 + h * v0 / 5.0, p0 + 2.0 * h * v0 / 5.0 + h * h * a0 / 20.0,
                  p1 - 2.0 * h * v1 / 5.0 + h * h * a1 / 20.0, p1 - h * v1 / 5.0, p1])
    return BPoly(c, x)


class Manoeuvre(MotionSource):
    """Straight run with an optional speed ramp and an optional turn (module docstring).

    Parameters
    ----------
    speed
        Cruise speed U [m/s], >= 0.
    heading
        Initial heading (yaw) psi0 [rad]; the ship moves along its heading.
    position
        CG position (x, y) [m] at t = 0.
    initial_speed
        Speed u0 [m/s] at and before t = 0; None means ``speed`` (no ramp).
    speed_ramp
        Duration T_u [s] of the speed ramp from u0 to U, starting at t = 0; must be
        > 0 when u0 differs from U.
    turn
        The turn, or None for a straight run.
    """

    def __init__(self, speed: float, *, heading: float = 0.0,
                 position: tuple[float, float] = (0.0, 0.0), initial_speed: float | None = None,
                 speed_ramp: float = 0.0, turn: Turn | None = None) -> None:
        u0 = speed if initial_speed is None else initial_speed
        for name, value in (("speed", speed), ("initial_speed", u0), ("speed_ramp", speed_ramp)):
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"{name} must be finite and >= 0, got {value}")
        if u0 != speed and speed_ramp <= 0.0:
            raise ValueError("a speed change needs speed_ramp > 0 s")
        if not (math.isfinite(heading) and all(math.isfinite(p) for p in position)):
            raise ValueError("heading and position must be finite")
        self.speed = float(speed)
        self.initial_speed = float(u0)
        self.speed_ramp = float(speed_ramp) if u0 != speed else 0.0
        self.heading = float(heading)
        self.position = (float(position[0]), float(position[1]))
        self.turn = turn
        self.t_end = max(self.speed_ramp, turn.end if turn is not None else 0.0)
        final_heading = self.heading + (math.copysign(turn.angle, turn.rate) if turn else 0.0)
        self._initial_velocity = self.initial_speed * np.array([math.cos(self.heading),
                                                                math.sin(self.heading)])
        self._final_velocity = self.speed * np.array([math.cos(final_heading),
                                                      math.sin(final_heading)])
        self._track = self._build_track() if self.t_end > 0.0 else None
        self._end_position = (self._track(self.t_end) if self._track is not None
                              else np.array(self.position))

    def _speed(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Speed [m/s] and its time derivative [m/s^2]."""
        if self.speed_ramp == 0.0:
            return np.full_like(t, self.speed), np.zeros_like(t)
        s, ds, _ = smoothstep(t / self.speed_ramp)
        du = self.speed - self.initial_speed
        return self.initial_speed + du * s, du * ds / self.speed_ramp

    def _yaw(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Heading [rad] and its first two derivatives."""
        if self.turn is None:
            return np.full_like(t, self.heading), np.zeros_like(t), np.zeros_like(t)
        turn = self.turn
        tau1 = (t - turn.start) / turn.ramp
        tau2 = (t - turn.start - turn.ramp - turn.hold) / turn.ramp
        s1, ds1, _ = smoothstep(tau1)
        s2, ds2, _ = smoothstep(tau2)
        psi = self.heading + turn.rate * turn.ramp * (smoothstep_integral(tau1)
                                                      - smoothstep_integral(tau2))
        return psi, turn.rate * (s1 - s2), turn.rate * (ds1 - ds2) / turn.ramp

    def _velocity(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Horizontal velocity [m/s] and acceleration [m/s^2], shape (n, 2) each."""
        u, du = self._speed(t)
        psi, dpsi, _ = self._yaw(t)
        c, s = np.cos(psi), np.sin(psi)
        velocity = np.column_stack([u * c, u * s])
        acceleration = np.column_stack([du * c - u * dpsi * s, du * s + u * dpsi * c])
        return velocity, acceleration

    def _breakpoints(self) -> list[float]:
        points = [0.0, self.speed_ramp, self.t_end]
        if self.turn is not None:
            t = self.turn
            points += [t.start, t.start + t.ramp, t.start + t.ramp + t.hold, t.end]
        return points

    def _build_track(self) -> BPoly:
        ramps = [r for r in (self.speed_ramp, self.turn.ramp if self.turn else 0.0) if r > 0.0]
        spacing = min([KNOT_SPACING] + [r / 8.0 for r in ramps])
        grid = np.linspace(0.0, self.t_end, int(math.ceil(self.t_end / spacing)) + 1)
        knots = np.unique(np.concatenate([grid, self._breakpoints()]))
        knots = knots[(knots >= 0.0) & (knots <= self.t_end)]
        knots = knots[np.concatenate([[True], np.diff(knots) > 1e-9 * self.t_end])]
        mid, half = 0.5 * (knots[1:] + knots[:-1]), 0.5 * np.diff(knots)
        nodes = (mid[:, None] + half[:, None] * _GAUSS_NODES).ravel()
        velocity, _ = self._velocity(nodes)
        steps = half[:, None] * (velocity.reshape(mid.size, _GAUSS_NODES.size, 2)
                                 * _GAUSS_WEIGHTS[None, :, None]).sum(axis=1)
        position = np.vstack([np.zeros(2), np.cumsum(steps, axis=0)]) + self.position
        velocity, acceleration = self._velocity(knots)
        return quintic_hermite(knots, position, velocity, acceleration)

    def evaluate_many(self, t: ArrayLike) -> np.ndarray:
        times = as_times(t)
        out = np.zeros((times.size, 3, 6))
        psi = self._yaw(times)
        for k in range(3):
            out[:, k, 5] = psi[k]
        before = times < 0.0
        after = times > self.t_end if self._track is not None else ~before
        inside = ~(before | after)
        if np.any(inside):
            ti = times[inside]
            for k in range(3):
                out[inside, k, 0:2] = self._track(ti, nu=k)
        # straight lines at constant speed and heading (zero acceleration)
        for mask, origin, t0, velocity in ((before, self.position, 0.0, self._initial_velocity),
                                           (after, self._end_position, self.t_end, self._final_velocity)):
            out[mask, 0, 0:2] = np.asarray(origin) + np.outer(times[mask] - t0, velocity)
            out[mask, 1, 0:2] = velocity
        return out

    @property
    def description(self) -> str:
        text = f"manoeuvre: speed {self.speed:g} m/s"
        if self.speed_ramp > 0.0:
            text += f" (from {self.initial_speed:g} m/s over {self.speed_ramp:g} s)"
        text += (f", initial heading {math.degrees(self.heading):g} deg, start "
                 f"({self.position[0]:g}, {self.position[1]:g}) m")
        if self.turn is not None:
            t = self.turn
            side = "port" if t.rate > 0 else "starboard"
            text += (f"; turn to {side} at {t.start:g} s: {math.degrees(abs(t.rate)):g} deg/s "
                     f"through {math.degrees(t.angle):g} deg (rate ramps {t.ramp:g} s)")
        return text
