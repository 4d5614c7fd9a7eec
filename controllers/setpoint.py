"""Active heave compensation set-point algorithms, W(1)-(2).

The algorithms turn the ship motion into a cable payout set-point ``L`` [m]
(positive = cable paid out) and the winch set-point of the W(136) PD loop:

    phi_sp = phi_nom - L / r_w,        phi_sp_rate = -L_rate / r_w,

because increasing the winch angle reels cable in (W(120); docs/design.md, "Conventions").

With ``Delta = r_ref(t) - s_ref`` the displacement of the reference point (normally
the sheave centre) from its nominal position (its body coordinates: the frame moves
with the mean tow speed, so the ship oscillates about the origin), and ``theta`` the
cable departure angle from the inertial vertical (positive trailing aft):

* sheave, W(2):     L = Delta_x sin(theta) + Delta_z cos(theta)
* waterline, W(1):  L = H / cos(theta) - H_nom / cos(theta_nom),
  H = z_ref - z_waterline, H_nom its nominal value.

The *simplified* variants use ``theta = theta_nom``; the *rigorous* ones use the
measured sheave angle and fall back to ``theta_nom`` (flag ``theta_fallback``) when
it is missing, not finite or outside (-pi/2, pi/2). The rates hold ``theta`` constant
over a step (the sheave angle rate is not an input), so for the rigorous variants
they omit the ``d theta/dt`` term; for the simplified ones they are exact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from controllers.config import SetpointConfig
from towcable_fmu.jit.kernel_cache import njit
from towcable_fmu.numerics.kinematics import ship_point_kinematics

#: :func:`setpoint_law`'s codes of the methods (:attr:`SetpointConfig.method`).
METHOD_CODES = {"none": 0, "sheave": 1, "waterline": 2}


class Setpoint(NamedTuple):
    """Output of one set-point evaluation (a named tuple: made in a fraction of a
    microsecond from :func:`setpoint_law`'s values).

    Attributes
    ----------
    phi_sp
        Winch angle set-point [rad].
    phi_sp_rate
        Winch angle set-point rate [rad/s].
    payout
        Cable payout set-point ``L`` [m], positive when cable is paid out.
    payout_rate
        ``dL/dt`` [m/s], equal to ``-r_w * phi_sp_rate``.
    theta_used
        Sheave angle used in the formula [rad].
    theta_fallback
        True when a rigorous algorithm had no usable measured angle and used
        ``theta_nom`` instead.
    payout_clipped
        True when the payout was clipped to ``max_payout`` (its rate is then 0).
    rate_clipped
        True when ``phi_sp_rate`` was clipped to ``max_winch_speed``.
    """

    phi_sp: float
    phi_sp_rate: float
    payout: float
    payout_rate: float
    theta_used: float
    theta_fallback: bool = False
    payout_clipped: bool = False
    rate_clipped: bool = False


@dataclass(frozen=True)
class SetpointSeries:
    """Set-points along a time series; fields as in :class:`Setpoint`, each an
    array of shape (n,)."""

    phi_sp: np.ndarray
    phi_sp_rate: np.ndarray
    payout: np.ndarray
    payout_rate: np.ndarray
    theta_used: np.ndarray
    theta_fallback: np.ndarray
    payout_clipped: np.ndarray
    rate_clipped: np.ndarray


@njit(cache=True)
def setpoint_law(ship: np.ndarray, law: np.ndarray, angle: float) -> tuple:
    """One set-point of the module docstring's laws, compiled (the arithmetic of
    :meth:`SetpointAlgorithm.compute_series` for one ship state, in the same order).

    Parameters
    ----------
    ship
        Ship state, shape (3, 6).
    law
        The algorithm (:meth:`SetpointAlgorithm.law`): the reference point in the ship
        frame [m] (3), the :data:`METHOD_CODES` code, 1 for a rigorous algorithm (0 for a
        simplified one), theta_nom [rad], the waterline height [m], the payout limit [m]
        and the payout rate limit [m/s] (``max_winch_speed * winch_radius``; negative:
        none), r_w [m] and phi_nom [rad].
    angle
        The measured sheave angle [rad] (NaN: not measured), used by a rigorous
        algorithm if it is usable.

    Returns
    -------
    tuple
        phi_sp, phi_sp_rate, payout, payout_rate, theta_used, theta_fallback,
        payout_clipped, rate_clipped (as :class:`Setpoint`).
    """
    s_ref = law[0:3]
    method, rigorous, theta_nom, waterline_z = int(law[3]), law[4] != 0.0, law[5], law[6]
    max_payout, max_rate, winch_radius, phi_nom = law[7], law[8], law[9], law[10]
    theta, fallback = theta_nom, False
    if rigorous:
        if math.isfinite(angle) and abs(angle) < 0.5 * math.pi:
            theta = angle
        else:
            fallback = True
    payout, rate = 0.0, 0.0
    if method != 0:
        point = ship_point_kinematics(ship, s_ref)
        if method == 1:
            sin_t, cos_t = math.sin(theta), math.cos(theta)
            payout = (point[0, 0] - s_ref[0]) * sin_t + (point[0, 2] - s_ref[2]) * cos_t
            rate = point[1, 0] * sin_t + point[1, 2] * cos_t
        else:
            payout = (point[0, 2] - waterline_z) / math.cos(theta) - (s_ref[2] - waterline_z) / math.cos(theta_nom)
            rate = point[1, 2] / math.cos(theta)
    payout_clipped = False
    if max_payout >= 0.0:
        payout_clipped = abs(payout) > max_payout
        payout = min(max(payout, -max_payout), max_payout)
        if payout_clipped:
            rate = 0.0
    rate_clipped = False
    if max_rate >= 0.0:
        rate_clipped = abs(rate) > max_rate
        rate = min(max(rate, -max_rate), max_rate)
    return (phi_nom - payout / winch_radius, (0.0 - rate) / winch_radius,  # 0.0 - : no -0.0 output
            payout, rate, theta, fallback, payout_clipped, rate_clipped)


class SetpointAlgorithm:
    """Evaluate one set-point algorithm (stateless).

    Parameters
    ----------
    config
        The validated configuration.
    """

    def __init__(self, config: SetpointConfig) -> None:
        if config.method == "tension":
            raise ValueError("constant_tension depends on the measured tension and has a state: use "
                             "controllers.TensionControl")
        self.config = config
        self._s_ref = np.array(config.reference_point, dtype=np.float64)
        max_rate = -1.0 if config.max_winch_speed is None else config.max_winch_speed * config.winch_radius
        #: the algorithm as :func:`setpoint_law` takes it
        self.law = np.array([*config.reference_point, METHOD_CODES[config.method], float(config.rigorous),
                             config.theta_nom, config.waterline_z,
                             -1.0 if config.max_payout is None else config.max_payout, max_rate,
                             config.winch_radius, config.phi_nom], dtype=np.float64)

    def compute(self, ship: np.ndarray, sheave_angle: float | None = None) -> Setpoint:
        """Set-point for one ship state.

        Parameters
        ----------
        ship
            Ship state, shape (3, 6): rows value/rate/acceleration, columns
            x, y, z [m] and roll, pitch, yaw [rad] of the CG (inertial frame).
        sheave_angle
            Measured cable departure angle from the inertial vertical [rad]; used only by the
            rigorous algorithms. None or NaN means "not measured".

        Returns
        -------
        Setpoint
        """
        ship = np.ascontiguousarray(ship, dtype=np.float64)
        if ship.shape != (3, 6):
            raise ValueError(f"ship state must have shape (3, 6), got {ship.shape}")
        angle = math.nan if sheave_angle is None else float(sheave_angle)
        return Setpoint(*setpoint_law(ship, self.law, angle))

    def compute_series(self, ships: np.ndarray,
                       angles: np.ndarray | None = None) -> SetpointSeries:
        """Set-points along a time series (for post-processing).

        Parameters
        ----------
        ships
            Ship states, shape (n, 3, 6).
        angles
            Measured sheave angles [rad], shape (n,), or None (not measured).

        Returns
        -------
        SetpointSeries
        """
        ships = np.ascontiguousarray(ships, dtype=np.float64)
        if ships.ndim != 3 or ships.shape[1:] != (3, 6):
            raise ValueError(f"ships must have shape (n, 3, 6), got {ships.shape}")
        n = ships.shape[0]
        if angles is None:
            angles = np.full(n, math.nan)
        angles = np.asarray(angles, dtype=np.float64)
        if angles.shape != (n,):
            raise ValueError(f"angles must have shape ({n},), got {angles.shape}")
        return SetpointSeries(**self._evaluate(ships, angles))

    def _theta(self, angles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Sheave angle to use [rad] and the fallback flag, shape (n,) each."""
        theta_nom = self.config.theta_nom
        if not self.config.rigorous:
            return np.full(angles.shape, theta_nom), np.zeros(angles.shape, dtype=bool)
        with np.errstate(invalid="ignore"):
            usable = np.isfinite(angles) & (np.abs(angles) < 0.5 * math.pi)
        return np.where(usable, angles, theta_nom), ~usable

    def _evaluate(self, ships: np.ndarray, angles: np.ndarray) -> dict[str, np.ndarray]:
        """Core of :meth:`compute` and :meth:`compute_series` for n ship states."""
        cfg = self.config
        n = ships.shape[0]
        theta, fallback = self._theta(angles)
        if cfg.method == "none":
            payout = np.zeros(n)
            rate = np.zeros(n)
        else:
            point = np.array([ship_point_kinematics(ship, self._s_ref)
                              for ship in ships]).reshape(n, 3, 3)
            position, velocity = point[:, 0], point[:, 1]
            if cfg.method == "sheave":
                sin_t, cos_t = np.sin(theta), np.cos(theta)
                delta = position - self._s_ref
                payout = delta[:, 0] * sin_t + delta[:, 2] * cos_t
                rate = velocity[:, 0] * sin_t + velocity[:, 2] * cos_t
            else:
                height = position[:, 2] - cfg.waterline_z
                height_nom = self._s_ref[2] - cfg.waterline_z
                payout = height / np.cos(theta) - height_nom / math.cos(cfg.theta_nom)
                rate = velocity[:, 2] / np.cos(theta)

        payout_clipped = np.zeros(n, dtype=bool)
        if cfg.max_payout is not None:
            payout_clipped = np.abs(payout) > cfg.max_payout
            payout = np.clip(payout, -cfg.max_payout, cfg.max_payout)
            rate = np.where(payout_clipped, 0.0, rate)

        rate_clipped = np.zeros(n, dtype=bool)
        if cfg.max_winch_speed is not None:
            max_rate = cfg.max_winch_speed * cfg.winch_radius  # [m/s]
            rate_clipped = np.abs(rate) > max_rate
            rate = np.clip(rate, -max_rate, max_rate)

        return {
            "phi_sp": cfg.phi_nom - payout / cfg.winch_radius,
            "phi_sp_rate": (0.0 - rate) / cfg.winch_radius,  # 0.0 - : no -0.0 output
            "payout": payout,
            "payout_rate": rate,
            "theta_used": theta,
            "theta_fallback": fallback,
            "payout_clipped": payout_clipped,
            "rate_clipped": rate_clipped,
        }
