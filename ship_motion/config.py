"""Building a motion source from a scene file's ``[motion]`` table.

:func:`motion_from_config` reads the table (already parsed from TOML), checks every
key and range, and returns the source. Errors are
:class:`towcable_fmu.errors.SceneError` naming the full dotted key
(``motion.heave.period``), the value and the allowed range with units. The keys, units,
defaults and ranges of every ``type`` are listed in ``ship_motion/README.md``.
Angles are given in degrees in the configuration and are radians inside.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

from towcable_fmu.errors import SceneError

from . import validation as v
from .base import CONFIG_DOF_NAMES, IS_ANGLE, MotionSource, StillShip
from .irregular import DEFAULT_BAND, IrregularSea
from .manoeuvre import Manoeuvre, Turn
from .rao import FRIGATE, ClosedFormRao, Rao, RaoTable, ShipParticulars
from .regular import Harmonic, RegularMotion
from .spectrum import SPACINGS, Jonswap
from .superposition import SuperposedMotion
from .time_series import TimeSeriesMotion, read_motion_csv

#: Values of ``type``.
TYPES: tuple[str, ...] = ("none", "regular", "time_series", "irregular", "manoeuvre")

#: The built-in sea: the FFG-7-sized frigate (:data:`ship_motion.rao.FRIGATE`) at
#: 2.2 m/s in NATO sea state 5 (North Atlantic: Hs 3.25 m, modal period 9.7 s), waves
#: 50 deg off the starboard bow. Its keys are also the defaults of ``type =
#: "irregular"``. Resulting motion (README.md): heave std 0.43 m, roll 1.9 deg, pitch
#: 0.97 deg. Treat it as read-only: copy it (``{**DEFAULT_SEA, "hs": 2.0}``) to vary it.
DEFAULT_SEA: dict[str, object] = {
    "type": "irregular",
    "hs": 3.25,
    "tp": 9.7,
    "gamma": 3.3,
    "heading": 130.0,
    "speed": 2.2,
    "components": 200,
    "spacing": "random",
    "seed": 22,
    "ramp": 20.0,
    "rao": {
        "length": FRIGATE.length,
        "beam": FRIGATE.beam,
        "draught": FRIGATE.draught,
        "block_coefficient": FRIGATE.block_coefficient,
        "roll_period": FRIGATE.roll_period,
        "roll_damping": FRIGATE.roll_damping,
    },
}

_REGULAR_DOF_KEYS = ("mean", "amplitude", "period", "phase")
_IRREGULAR_KEYS = ("type", "hs", "tp", "gamma", "heading", "speed", "components", "omega_min",
                   "omega_max", "spacing", "seed", "ramp", "rao")
_PARTICULAR_RANGES = {  # name: (lo, lo_open, hi, unit)
    "length": (0.0, True, 500.0, "m"),
    "beam": (0.0, True, 100.0, "m"),
    "draught": (0.0, True, 30.0, "m"),
    "block_coefficient": (0.3, False, 1.0, "-"),
    "roll_period": (1.0, False, 60.0, "s"),
    "roll_damping": (0.0, True, 1.0, "-"),
}
_MANOEUVRE_KEYS = ("type", "speed", "initial_speed", "speed_ramp", "heading", "position",
                   "turn_start", "turn_rate", "turn_angle", "turn_ramp", "waves")


def motion_from_config(table: Mapping[str, object], *, key: str = "motion",
                       base_dir: Path | None = None) -> MotionSource:
    """Build a ship motion source from a ``[motion]`` table.

    Parameters
    ----------
    table
        The parsed TOML table, e.g. ``tomllib.load(f)["motion"]``; ``type`` is one of
        :data:`TYPES`.
    key
        Dotted path of the table, used in error messages.
    base_dir
        Folder against which relative file paths (CSV time series, RAO tables) are
        resolved, normally the scene file's folder; None: the working directory.

    Returns
    -------
    MotionSource

    Raises
    ------
    SceneError
        On an unknown key, a missing required key, or a value out of range.
    """
    table = v.check_table(table, key, "a table with type = " + " | ".join(TYPES))
    kind = v.choice(table, "type", key, TYPES)
    if kind == "none":
        v.check_keys(table, ("type",), key)
        return StillShip()
    if kind == "regular":
        return _regular(table, key)
    if kind == "time_series":
        return _time_series(table, key, base_dir)
    if kind == "irregular":
        return _irregular(table, key, base_dir)
    return _manoeuvre(table, key, base_dir)


def _resolve(path_text: str, base_dir: Path | None) -> Path:
    path = Path(path_text).expanduser()
    return path if path.is_absolute() or base_dir is None else Path(base_dir) / path


def _regular(table: Mapping[str, object], key: str) -> RegularMotion:
    v.check_keys(table, ("type", "ramp", *CONFIG_DOF_NAMES), key)
    ramp = v.number(table, "ramp", key, default=0.0, lo=0.0, unit="s")
    harmonics = []
    mean = [0.0] * 6
    for dof, name in enumerate(CONFIG_DOF_NAMES):
        if name not in table:
            continue
        path = v.join(key, name)
        sub = v.check_table(table[name], path, "a table with keys " + ", ".join(_REGULAR_DOF_KEYS))
        v.check_keys(sub, _REGULAR_DOF_KEYS, path)
        unit = "deg" if IS_ANGLE[dof] else "m"
        m = v.number(sub, "mean", path, default=0.0, unit=unit)
        amplitude = v.number(sub, "amplitude", path, default=0.0, lo=0.0, unit=unit)
        if name in ("roll", "pitch") and abs(m) + amplitude >= 90.0:
            raise SceneError(v.join(path, "amplitude"), sub.get("amplitude"),
                             f"a finite number >= 0 deg with |mean| + amplitude < 90 deg "
                             f"(mean is {m:g} deg)")
        if name == "yaw" and amplitude > 180.0:
            raise SceneError(v.join(path, "amplitude"), sub["amplitude"],
                             "a finite number in [0, 180] deg")
        period = v.number(sub, "period", path, default=None if amplitude == 0.0 else v.REQUIRED,
                          lo=0.0, lo_open=True, unit="s")
        phase = v.number(sub, "phase", path, default=0.0, unit="deg")
        scale = math.pi / 180.0 if IS_ANGLE[dof] else 1.0
        mean[dof] = m * scale
        if amplitude > 0.0:
            harmonics.append(Harmonic(dof, amplitude * scale, period, math.radians(phase)))
    return RegularMotion(harmonics, mean=mean, ramp=ramp)


def _time_series(table: Mapping[str, object], key: str, base_dir: Path | None) -> TimeSeriesMotion:
    v.check_keys(table, ("type", "file", "format", "angle_unit", "initial_position",
                         "time_offset"), key)
    file = _resolve(v.string(table, "file", key, "a path to a CSV file (relative to the scene "
                             "file's folder)"), base_dir)
    layout = v.choice(table, "format", key, ("position", "velocity"), default=None)
    angle_unit = v.choice(table, "angle_unit", key, ("deg", "rad"), default="deg")
    initial = v.vector(table, "initial_position", key, 3, default=(0.0, 0.0, 0.0), unit="m")
    offset = v.number(table, "time_offset", key, default=0.0, unit="s")
    record = read_motion_csv(file, layout=layout, angle_unit=angle_unit, initial_position=initial,
                             key=v.join(key, "file"))
    if record.layout == "position" and "initial_position" in table:
        raise SceneError(v.join(key, "initial_position"), table["initial_position"],
                         "only with the velocity format (t, vx, vy, vz, roll, pitch, yaw)")
    return TimeSeriesMotion(record.t, record.positions, record.attitudes, time_offset=offset,
                            label=record.label)


def _rao(table: Mapping[str, object], key: str, base_dir: Path | None) -> Rao:
    sub = v.check_table(table, key, "a table with either file (and angle_unit) or the hull "
                        "particulars " + ", ".join(_PARTICULAR_RANGES))
    if "file" in sub:
        v.check_keys(sub, ("file", "angle_unit"), key)
        file = _resolve(v.string(sub, "file", key, "a path to an RAO CSV file"), base_dir)
        angle_unit = v.choice(sub, "angle_unit", key, ("deg", "rad"), default="deg")
        return RaoTable.from_csv(file, angle_unit=angle_unit, key=v.join(key, "file"))
    v.check_keys(sub, tuple(_PARTICULAR_RANGES), key)
    values = {}
    for name, (lo, lo_open, hi, unit) in _PARTICULAR_RANGES.items():
        values[name] = v.number(sub, name, key, default=getattr(FRIGATE, name), lo=lo,
                                lo_open=lo_open, hi=hi, unit=unit)
    return ClosedFormRao(ShipParticulars(**values))


def _irregular(table: Mapping[str, object], key: str, base_dir: Path | None,
               default_speed: float | None = None) -> IrregularSea:
    v.check_keys(table, _IRREGULAR_KEYS, key)
    d = DEFAULT_SEA
    hs = v.number(table, "hs", key, default=d["hs"], lo=0.0, hi=20.0, unit="m")
    tp = v.number(table, "tp", key, default=d["tp"], lo=2.0, hi=30.0, unit="s")
    gamma = v.number(table, "gamma", key, default=d["gamma"], lo=1.0, hi=10.0, unit="-")
    heading = v.number(table, "heading", key, default=d["heading"], unit="deg")
    speed = v.number(table, "speed", key, default=d["speed"] if default_speed is None
                     else default_speed, lo=0.0, hi=25.0, unit="m/s")
    components = v.integer(table, "components", key, default=d["components"], lo=1, hi=5000)
    peak = 2.0 * math.pi / tp
    omega_min = v.number(table, "omega_min", key, default=DEFAULT_BAND[0] * peak, lo=0.0,
                         lo_open=True, hi=20.0, unit="rad/s")
    omega_max = v.number(table, "omega_max", key, default=DEFAULT_BAND[1] * peak,
                         lo=omega_min, lo_open=True, hi=20.0, unit="rad/s")
    spacing = v.choice(table, "spacing", key, SPACINGS, default=d["spacing"])
    seed = v.integer(table, "seed", key, default=d["seed"], lo=0)
    ramp = v.number(table, "ramp", key, default=d["ramp"], lo=0.0, unit="s")
    rao = _rao(table.get("rao", d["rao"]), v.join(key, "rao"), base_dir)
    if isinstance(rao, RaoTable):
        lo, hi = rao.frequency_range
        rao_key = v.join(key, "rao.file")
        if omega_min < lo or omega_max > hi:
            raise SceneError(rao_key, rao.label, f"an RAO table covering the wave band "
                             f"[{omega_min:.4g}, {omega_max:.4g}] rad/s (it covers "
                             f"[{lo:g}, {hi:g}] rad/s; set omega_min/omega_max)")
        if rao.heading_coordinate(math.radians(heading)) is None:
            raise SceneError(rao_key, rao.label, f"an RAO table covering the heading {heading:g} deg")
    return IrregularSea(Jonswap(hs, tp, gamma), rao, heading=math.radians(heading), speed=speed,
                        components=components, omega_min=omega_min, omega_max=omega_max,
                        spacing=spacing, seed=seed, ramp=ramp)


def _manoeuvre(table: Mapping[str, object], key: str, base_dir: Path | None) -> MotionSource:
    v.check_keys(table, _MANOEUVRE_KEYS, key)
    speed = v.number(table, "speed", key, lo=0.0, hi=30.0, unit="m/s")
    speed_ramp = v.number(table, "speed_ramp", key, default=0.0, lo=0.0, unit="s")
    initial_speed = v.number(table, "initial_speed", key,
                             default=0.0 if speed_ramp > 0.0 else speed, lo=0.0, hi=30.0,
                             unit="m/s")
    if speed_ramp == 0.0 and initial_speed != speed:
        raise SceneError(v.join(key, "speed_ramp"), table.get("speed_ramp", 0.0),
                         "a finite number > 0 s when initial_speed differs from speed")
    heading = v.number(table, "heading", key, default=0.0, unit="deg")
    position = v.vector(table, "position", key, 2, default=(0.0, 0.0), unit="m")
    turn_angle = v.number(table, "turn_angle", key, default=0.0, lo=0.0, hi=36000.0, unit="deg")
    turn_start = v.number(table, "turn_start", key, default=0.0, lo=0.0, unit="s")
    turn_ramp = v.number(table, "turn_ramp", key, default=10.0, lo=0.0, lo_open=True, unit="s")
    rate = v.number(table, "turn_rate", key, default=None if turn_angle == 0.0 else v.REQUIRED,
                    lo=-20.0, hi=20.0, unit="deg/s (non-zero; positive turns to port)")
    if rate == 0.0:
        raise SceneError(v.join(key, "turn_rate"), table["turn_rate"],
                         "a finite non-zero number in [-20, 20] deg/s")
    turn = None
    if turn_angle > 0.0:
        if turn_angle < abs(rate) * turn_ramp:
            raise SceneError(v.join(key, "turn_angle"), table["turn_angle"],
                             f">= |turn_rate| * turn_ramp = {abs(rate) * turn_ramp:g} deg "
                             "(the angle turned while the rate ramps up and down)")
        turn = Turn(turn_start, math.radians(rate), math.radians(turn_angle), turn_ramp)
    base = Manoeuvre(speed, heading=math.radians(heading), position=position,
                     initial_speed=initial_speed, speed_ramp=speed_ramp, turn=turn)
    if "waves" not in table:
        return base
    path = v.join(key, "waves")
    waves_table = v.check_table(table["waves"], path, 'a table with type = "regular" or "irregular"')
    kind = v.choice(waves_table, "type", path, ("regular", "irregular"))
    waves = (_regular(waves_table, path) if kind == "regular"
             else _irregular(waves_table, path, base_dir, default_speed=speed))
    return SuperposedMotion(base, waves)
