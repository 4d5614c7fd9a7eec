"""Constant-tension winch: the winch set-point from the measured tension (``constant_tension``).

The usual alternative to motion-based heave compensation: the winch pays out when the
tension rises above a target and hauls in when it falls below, so the cable's tension
stays near the target whatever moves the ship. In continuous time, with ``T`` the
measured tension [N] and ``L`` the payout [m] (positive paid out, as in
:mod:`controllers.setpoint`):

    u = g (T - T_target),   v -> u at |dv/dt| <= a_max,  |v| <= v_max,   dL/dt = v,

and the winch set-point ``phi_sp = phi_nom - L / r_w``, ``phi_sp_rate = -v / r_w``
(``g`` = ``tension_gain`` [m/(s N)], ``v_max`` = r_w ``max_winch_speed``, ``a_max`` =
r_w ``max_winch_acceleration``; ``max_payout`` bounds L).

The law is integral action on the tension error: in steady state the mean tension is
the target. Linearised (no limit active), a cable of axial stiffness k [N/m] from the
winch to a body of mass m hanging from it, the winch carried up and down by ``X(s)``:

    T(s) / X(s) = k m s^2 / (m s^2 + g W(s) k m s + k),

where ``W(s) = (k2 s + k1) / (s^2 + k2 s + k1)`` is the winch's PD drive W(136) following
its set-point (gains ``winch.kp`` = k1, ``winch.kd`` = k2; W = 1 for an ideal drive),

and with the body held fixed (m -> infinity) a high-pass ``k s / (s + g W(s) k)``: the
loop's bandwidth is ``g k`` [rad/s] for an ideal drive; heave well below it is absorbed, heave above it
passes to the tension as through a fixed winch.

The controller is sampled: at each control instant t_n (a communication point of the
HeaveCompensation FMU, an output sample of a standalone run) it reads the tension T_n;
over [t_n, t_n+1] the winch set-point moves at the rate v_n decided at the previous
instant, and v_n+1 is decided from T_n (within the acceleration limit). The set-point is
thus continuous and piecewise linear, and its outputs at t_n depend on the controller's
state only: no direct feedthrough from the measured tension, so a co-simulation's
tension feedback is no algebraic loop. The price is one interval of delay: for a control
interval h, the linearised loop above holds with ``g`` replaced by ``g exp(-1.5 s h)``
(the sample-and-hold's half interval and the one of delay; exact as ``omega h -> 0``).

The payout limit: the rate decided at t_n is cut so that the payout reaches
``max_payout`` at t_n+1 if the next interval is as long as this one; a longer interval
would carry it past the limit, and the payout is then set back to the limit (a step of
the set-point no larger than the difference of the intervals times the rate).
"""

from __future__ import annotations

import math
from typing import Any, Mapping

from controllers.config import SetpointConfig
from controllers.setpoint import Setpoint


class TensionControl:
    """The sampled constant-tension law of the module docstring, with its state.

    Parameters
    ----------
    config
        A validated configuration with ``algorithm = "constant_tension"``. The controller
        starts at payout 0 (the winch at ``phi_nom``) and rest (:meth:`set_state` to start
        elsewhere).
    """

    def __init__(self, config: SetpointConfig) -> None:
        if config.algorithm != "constant_tension":
            raise ValueError(f"TensionControl needs algorithm 'constant_tension', got {config.algorithm!r}")
        self.config = config
        #: payout L [m] at the last control instant
        self.payout = 0.0
        #: commanded payout rate v [m/s] held since the last control instant
        self.rate = 0.0

    def setpoint(self) -> Setpoint:
        """The set-point at the current control instant: payout and the rate held until the
        next (decided at the previous instant; the state is not changed)."""
        cfg = self.config
        return Setpoint(phi_sp=cfg.phi_nom - self.payout / cfg.winch_radius,
                        phi_sp_rate=(0.0 - self.rate) / cfg.winch_radius, payout=self.payout,
                        payout_rate=self.rate, theta_used=cfg.theta_nom,
                        payout_clipped=cfg.max_payout is not None and abs(self.payout) >= cfg.max_payout)

    def advance(self, tension: float, dt: float) -> Setpoint:
        """Move to the next control instant ``dt`` [s] later: the payout by the rate held, the
        rate towards the law's from the ``tension`` [N] measured now. Returns the new
        :meth:`setpoint` (``rate_clipped``: a speed, acceleration or payout limit cut the law's
        rate).

        Raises
        ------
        ValueError
            If ``tension`` is not finite or ``dt`` not a finite number > 0; the state is not
            changed.
        """
        if not math.isfinite(tension):
            raise ValueError(f"measured tension = {tension!r} N is not a finite number")
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError(f"control interval dt = {dt!r} s must be a finite number > 0")
        cfg = self.config
        payout = self.payout + self.rate * dt
        wanted = cfg.tension_gain * (tension - cfg.tension_target)
        rate = wanted
        if cfg.max_winch_speed is not None:
            v_max = cfg.max_winch_speed * cfg.winch_radius
            rate = min(max(rate, -v_max), v_max)
        if cfg.max_winch_acceleration is not None:
            dv = cfg.max_winch_acceleration * cfg.winch_radius * dt
            rate = min(max(rate, self.rate - dv), self.rate + dv)
        if cfg.max_payout is not None:
            payout = min(max(payout, -cfg.max_payout), cfg.max_payout)
            rate = min(max(rate, (-cfg.max_payout - payout) / dt), (cfg.max_payout - payout) / dt)
        self.payout, self.rate = payout, rate
        return self.setpoint()._replace(rate_clipped=rate != wanted)

    def get_state(self) -> dict[str, float]:
        """The controller's state (JSON-able)."""
        return {"payout": self.payout, "rate": self.rate}

    def set_state(self, data: Mapping[str, Any]) -> None:
        """Restore :meth:`get_state`."""
        self.payout = float(data["payout"])
        self.rate = float(data["rate"])
