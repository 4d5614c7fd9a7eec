"""Configuration of the heave-compensation set-point algorithms W(1)-(2).

:class:`SetpointConfig` is declared with the project's schema mechanism
(:mod:`towcable_fmu.common.schema`): the declaration gives the validation, the typed object and
the scene reference's ``[compensation]`` table (``docs/reference/scene_keys.md``). It is
validated when it is built: a bad value raises :class:`towcable_fmu.common.errors.SceneError`
naming the key (``compensation.winch_radius`` and so on), the value and what is allowed.
:func:`setpoint_config_from_table` builds one from a TOML table (stdlib ``tomllib``) and
rejects unknown or missing keys.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import InitVar, dataclass
from functools import partial
from typing import ClassVar

from towcable_fmu.common.errors import SceneError
from towcable_fmu.common.schema import check_fields, parse_fields, spec

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

#: :func:`~towcable_fmu.common.schema.spec` of a compensation key: ranges as intervals, the
#: algorithms as bare names (``one of none, simplified_sheave, ...``).
compensation_spec = partial(spec, notation="interval")


@dataclass(frozen=True)
class SetpointConfig:
    """Parameters of one set-point algorithm (a scene's ``[compensation]`` table).

    The fields' meanings, units and ranges are their declarations below. The defaults
    in words are what a scene supplies (:mod:`towcable_fmu.compensation_setup`); built
    directly, the first five fields are required. ``key`` is the prefix of the keys
    named in error messages (default ``"compensation"``; empty: the field names
    alone); it is not stored.

    Raises
    ------
    SceneError
        If a value is out of range; the error names ``<key>.<field>``.
    """

    algorithm: str = compensation_spec(
        choices=ALGORITHMS,
        doc="set-point algorithm: W(2) sheave or W(1) waterline reference, simplified (nominal departure angle) or "
            "rigorous (measured sheave angle); constant_tension: a constant-tension winch (payout from the measured "
            "tension); 'none' holds the winch")
    reference_point: tuple[float, float, float] = compensation_spec(
        unit="m", length=3, default_text="the sheave centre (without a sheave: the top of the winch drum)",
        doc="body-frame position s_ref of the point whose displacement is compensated, normally the sheave "
            "centre; its nominal inertial position is s_ref itself (ship at the origin with zero angles)")
    winch_radius: float = compensation_spec(
        unit="m", gt=0.0, default_text="the winch's (to the cable centreline)", doc="winch drum radius r_w (W(120))")
    phi_nom: float = compensation_spec(
        unit="rad", default_text="winch.phi_nom",
        doc="nominal winch angle phi_nom; the set-point is phi_sp = phi_nom - payout / r_w")
    theta_nom: float = compensation_spec(
        unit="rad", ge=0.0, lt=0.5 * math.pi, default_text="the model's own static departure angle",
        doc="nominal (steady-state) cable departure angle from the inertial vertical, positive when the cable "
            "trails aft")
    waterline_z: float = compensation_spec(
        0.0, unit="m", default_text="water.surface_z (0 without water)",
        doc="inertial height of the waterline (0 when the origin is at the mean waterline)")
    max_payout: float | None = compensation_spec(
        None, unit="m", gt=0.0,
        doc="largest payout magnitude (absent: no limit); the payout is clipped to [-max_payout, max_payout] and "
            "its rate is zero while clipped")
    max_winch_speed: float | None = compensation_spec(
        None, unit="rad/s", gt=0.0,
        doc="largest winch set-point speed magnitude (absent: no limit); the motion algorithms clip only the "
            "rate phi_sp_rate (phi_sp still follows the payout), constant_tension integrates the clipped rate")
    max_winch_acceleration: float | None = compensation_spec(
        None, unit="rad/s^2", gt=0.0,
        doc="largest change of the set-point speed (constant_tension only; absent: no limit)")
    tension_target: float | None = compensation_spec(
        None, unit="N", gt=0.0, doc="tension the constant_tension winch holds")
    tension_gain: float | None = compensation_spec(
        None, unit="m/(s N)", gt=0.0,
        doc="payout rate per newton of measured tension above the target (constant_tension): with a cable of "
            "axial stiffness k [N/m] between the winch and a fixed point, the tension loop's bandwidth is "
            "k tension_gain [rad/s]")
    key: InitVar[str] = "compensation"

    #: Rules across keys (checked by :meth:`validate`).
    RULES: ClassVar[dict[str, str]] = {
        "waterline_z": "below the nominal height of the reference point for the waterline algorithms",
        "tension_target": "required by constant_tension",
        "tension_gain": "required by constant_tension",
    }

    def __post_init__(self, key: str) -> None:
        check_fields(self, key)
        self.validate(key)

    def validate(self, key: str) -> None:
        """Check the rules across keys (:attr:`RULES`); raise SceneError naming the key."""
        def name(field: str) -> str:
            return f"{key}.{field}" if key else field

        if self.algorithm == "constant_tension":
            for field in ("tension_target", "tension_gain"):
                if getattr(self, field) is None:
                    allowed = type(self).__dataclass_fields__[field].metadata["spec"].allowed()
                    raise SceneError(name(field), None, f"required: {allowed} (required by constant_tension)")
        if self.algorithm.endswith("_waterline") and self.reference_point[2] <= self.waterline_z:
            raise SceneError(name("waterline_z"), self.waterline_z,
                             f"< {self.reference_point[2]} m (the nominal height "
                             "of the reference point) for the waterline algorithms")

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
    ``reference_point = [-36.8, 0.0, 3.7]``).

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
        raise SceneError(key, table, "a table of the keys of a [compensation] table")
    return SetpointConfig(**parse_fields(SetpointConfig, table, key), key=key)
