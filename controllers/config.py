"""Configuration of the heave-compensation set-point algorithms W(1)-(2).

A :class:`SetpointConfig` is validated when it is built: a bad value raises
:class:`towcable_fmu.errors.SceneError` naming the key (``compensation.winch_radius``
and so on), the value and what is allowed. :func:`setpoint_config_from_table` builds
one from a TOML table (stdlib ``tomllib``) and rejects unknown or missing keys.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import MISSING, InitVar, dataclass, fields
from numbers import Real

import numpy as np

from towcable_fmu.errors import SceneError

#: The set-point algorithms from the ship motion (:class:`controllers.SetpointAlgorithm`).
MOTION_ALGORITHMS: tuple[str, ...] = (
    "none",
    "simplified_sheave",
    "rigorous_sheave",
    "simplified_waterline",
    "rigorous_waterline",
)
#: Algorithm names, as used by the command line and the HeaveCompensation FMU: the motion
#: algorithms and the constant-tension winch (:class:`controllers.TensionControl`).
ALGORITHMS: tuple[str, ...] = MOTION_ALGORITHMS + ("constant_tension",)

#: What each configuration key allows (used in error messages).
ALLOWED: dict[str, str] = {
    "algorithm": "one of " + ", ".join(ALGORITHMS),
    "reference_point": "3 finite numbers [m]: body-frame X, Y, Z of the reference "
                       "point (normally the sheave centre)",
    "winch_radius": "a finite number > 0 [m]",
    "phi_nom": "a finite number [rad]",
    "theta_nom": "a number in [0, pi/2) [rad] (cable departure angle from vertical, "
                 "positive trailing aft)",
    "waterline_z": "a finite number [m] below the nominal reference-point height for "
                   "the waterline algorithms",
    "max_payout": "absent (no limit) or a finite number > 0 [m]",
    "max_winch_speed": "absent (no limit) or a finite number > 0 [rad/s]",
    "max_winch_acceleration": "absent (no limit) or a finite number > 0 [rad/s^2]",
    "tension_target": "a finite number > 0 [N] (required by constant_tension)",
    "tension_gain": "a finite number > 0 [m/(s N)]: payout rate per newton of tension above the target "
                    "(required by constant_tension)",
}


def _is_number(value: object) -> bool:
    """True for a finite real number that is not a Boolean."""
    return (isinstance(value, Real) and not isinstance(value, bool)
            and math.isfinite(value))


def _number(key: str, value: object, allowed: str) -> float:
    """Return ``value`` as a float, or raise SceneError if it is not a finite number."""
    if not _is_number(value):
        raise SceneError(key, value, allowed)
    return float(value)


def _point(key: str, value: object, allowed: str) -> tuple[float, float, float]:
    """Return ``value`` as a 3-tuple of floats, or raise SceneError."""
    items = value.tolist() if isinstance(value, np.ndarray) else value
    if (not isinstance(items, Sequence) or isinstance(items, str) or len(items) != 3
            or not all(_is_number(v) for v in items)):
        raise SceneError(key, value, allowed)
    return (float(items[0]), float(items[1]), float(items[2]))


@dataclass(frozen=True)
class SetpointConfig:
    """Parameters of one set-point algorithm.

    Parameters
    ----------
    algorithm
        One of :data:`ALGORITHMS`.
    reference_point
        Body-frame position ``s_ref`` [m] of the point whose displacement is
        compensated, normally the sheave centre. Its nominal inertial position is
        ``s_ref`` itself (ship at the origin with zero angles).
    winch_radius
        Winch drum radius ``r_w`` [m] (W(120)).
    phi_nom
        Nominal winch angle ``phi_nom`` [rad]; the set-point is
        ``phi_sp = phi_nom - payout / r_w``.
    theta_nom
        Nominal (steady-state) cable departure angle from the inertial vertical [rad],
        in [0, pi/2), positive when the cable trails aft.
    waterline_z
        Inertial height of the waterline [m] (0 when the origin is at the mean
        waterline). The waterline algorithms need the nominal reference point above it.
    max_payout
        Largest payout magnitude [m], or None for no limit. The payout is clipped to
        ``[-max_payout, max_payout]``; while it is clipped its rate is zero.
    max_winch_speed
        Largest winch set-point speed magnitude [rad/s], or None for no limit. For the
        motion algorithms only the rate ``phi_sp_rate`` is clipped (they are stateless:
        ``phi_sp`` still follows the payout); ``constant_tension`` integrates the clipped
        rate.
    max_winch_acceleration
        Largest change of the set-point speed [rad/s^2] (``constant_tension`` only), or
        None for no limit.
    tension_target
        Tension the ``constant_tension`` winch holds [N].
    tension_gain
        Payout rate per newton of measured tension above the target [m/(s N)]
        (``constant_tension``): with a cable of axial stiffness k [N/m] between the winch
        and a fixed point, the tension loop's bandwidth is ``k * tension_gain`` [rad/s].
    key
        Prefix of the keys named in error messages (default ``"compensation"``; empty:
        the field names alone); not stored.

    Raises
    ------
    SceneError
        If a value is out of range; the error names ``<key>.<field>``.
    """

    algorithm: str
    reference_point: tuple[float, float, float]
    winch_radius: float
    phi_nom: float
    theta_nom: float
    waterline_z: float = 0.0
    max_payout: float | None = None
    max_winch_speed: float | None = None
    max_winch_acceleration: float | None = None
    tension_target: float | None = None
    tension_gain: float | None = None
    key: InitVar[str] = "compensation"

    def __post_init__(self, key: str) -> None:
        def name(field: str) -> str:
            return f"{key}.{field}" if key else field

        if not isinstance(self.algorithm, str) or self.algorithm not in ALGORITHMS:
            raise SceneError(name("algorithm"), self.algorithm, ALLOWED["algorithm"])
        values: dict[str, object] = {
            "reference_point": _point(name("reference_point"), self.reference_point,
                                      ALLOWED["reference_point"]),
        }
        for field in ("winch_radius", "phi_nom", "theta_nom", "waterline_z"):
            values[field] = _number(name(field), getattr(self, field), ALLOWED[field])
        optional = ("max_payout", "max_winch_speed", "max_winch_acceleration", "tension_target", "tension_gain")
        for field in optional:
            value = getattr(self, field)
            values[field] = (None if value is None
                             else _number(name(field), value, ALLOWED[field]))

        if values["winch_radius"] <= 0.0:
            raise SceneError(name("winch_radius"), self.winch_radius,
                             ALLOWED["winch_radius"])
        if not 0.0 <= values["theta_nom"] < 0.5 * math.pi:
            raise SceneError(name("theta_nom"), self.theta_nom, ALLOWED["theta_nom"])
        for field in optional:
            if values[field] is not None and values[field] <= 0.0:
                raise SceneError(name(field), getattr(self, field), ALLOWED[field])
        if self.algorithm == "constant_tension":
            for field in ("tension_target", "tension_gain"):
                if values[field] is None:
                    raise SceneError(name(field), None, "required: " + ALLOWED[field])
        if (self.algorithm.endswith("_waterline")
                and values["reference_point"][2] <= values["waterline_z"]):
            raise SceneError(name("waterline_z"), self.waterline_z,
                             f"< {values['reference_point'][2]} m (the nominal height "
                             "of the reference point) for the waterline algorithms")
        for field, value in values.items():
            object.__setattr__(self, field, value)

    @property
    def rigorous(self) -> bool:
        """True when the algorithm uses the measured sheave angle."""
        return self.algorithm.startswith("rigorous_")

    @property
    def method(self) -> str:
        """``"none"``, ``"sheave"`` (W(2)), ``"waterline"`` (W(1)) or ``"tension"``."""
        return self.algorithm.rsplit("_", 1)[-1]


def setpoint_config_from_table(table: Mapping[str, object],
                               key: str = "compensation") -> SetpointConfig:
    """Build a :class:`SetpointConfig` from a TOML table.

    The table's keys are the field names of :class:`SetpointConfig`, in SI units
    (for example ``winch_radius = 0.3``, ``theta_nom = 0.6``,
    ``reference_point = [-36.8, 0.0, 3.7]``). ``waterline_z``, ``max_payout``,
    ``max_winch_speed``, ``max_winch_acceleration``, ``tension_target`` and
    ``tension_gain`` are optional (the last two required by ``constant_tension``).

    Parameters
    ----------
    table
        The parsed table, for example ``tomllib.loads(text)["compensation"]``.
    key
        Dotted path of the table, used in error messages.

    Returns
    -------
    SetpointConfig

    Raises
    ------
    SceneError
        On an unknown key, a missing required key, or an invalid value.
    """
    if not isinstance(table, Mapping):
        raise SceneError(key, table, "a table of " + ", ".join(ALLOWED))
    known = fields(SetpointConfig)
    names = [f.name for f in known]
    for entry, value in table.items():
        if entry not in names:
            raise SceneError(f"{key}.{entry}", value,
                             "one of the keys " + ", ".join(names))
    for f in known:
        if f.default is MISSING and f.name not in table:
            raise SceneError(f"{key}.{f.name}", None, "required: " + ALLOWED[f.name])
    return SetpointConfig(**table, key=key)
