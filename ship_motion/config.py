"""Building a motion source from a scene file's ``[motion]`` table.

The table of each ``type`` is declared once below, with the project's schema mechanism
(:mod:`towcable_fmu.common.schema`): the declaration gives the validation, the typed object and
the scene reference's ``[motion]`` section (``docs/reference/scene_keys.md``).
:func:`motion_from_config` validates a table (already parsed from TOML) against its
declaration and returns the source. Errors are :class:`towcable_fmu.common.errors.SceneError`
naming the full dotted key (``motion.heave.period``), the value and the allowed range
with units. Angles are given in degrees in the configuration and are radians inside.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from functools import partial
from pathlib import Path
from typing import ClassVar

import numpy as np

from towcable_fmu.common.errors import SceneError
from towcable_fmu.common.schema import parse_variant, spec

from .base import CONFIG_DOF_NAMES, IS_ANGLE, MotionSource, StillShip
from .irregular import DEFAULT_BAND, IrregularSea
from .manoeuvre import Manoeuvre, Turn
from .rao import FRIGATE, ClosedFormRao, Rao, RaoTable, ShipParticulars
from .rao_files import mirrored, read_capytaine, read_orcaflex, read_wamit_4
from .regular import Harmonic, RegularMotion
from .spectrum import SPACINGS, SPECTRA, Jonswap, OchiHubble, Spectrum, Torsethaugen
from .spectrum_file import read_wavespectra
from .spreading import Cos2s
from .superposition import SuperposedMotion
from .time_series import TimeSeriesMotion, read_motion_csv

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

#: Directions of a short-crested sea when ``directions`` is not given.
DEFAULT_DIRECTIONS = 15

#: :func:`~towcable_fmu.common.schema.spec` of a motion key: ranges written as intervals
#: (``a finite number in [0, 20] m``).
motion_spec = partial(spec, notation="interval")


# ------------------------------------------------------------------ declarations
@dataclass(frozen=True)
class StillShipTable:
    """The ship is still (no other keys)."""

    KIND: ClassVar[str] = "none"


@dataclass(frozen=True)
class Oscillation:
    """One degree of freedom of a regular motion, in metres:
    q(t) = mean + ramp(t) amplitude sin(2 pi t / period + phase)."""

    mean: float = motion_spec(0.0, unit="m", doc="mean value")
    amplitude: float = motion_spec(0.0, ge=0.0, unit="m", doc="amplitude")
    period: float | None = motion_spec(None, gt=0.0, unit="s", doc="period")
    phase: float = motion_spec(0.0, unit="deg", doc="phase")

    RULES: ClassVar[dict[str, str]] = {"period": "required when amplitude > 0"}

    def validate(self, path: str) -> None:
        """The period is required when the amplitude is not zero."""
        if self.amplitude > 0.0 and self.period is None:
            raise SceneError(f"{path}.period", None, "required: a finite number > 0 s")


@dataclass(frozen=True)
class Rotation(Oscillation):
    """One rotational degree of freedom of a regular motion, in degrees (as
    :class:`Oscillation`)."""

    mean: float = motion_spec(0.0, unit="deg", doc="mean angle")
    amplitude: float = motion_spec(0.0, ge=0.0, unit="deg", doc="amplitude")


@dataclass(frozen=True)
class Tilt(Rotation):
    """Roll or pitch of a regular motion, in degrees: the ship never reaches 90 deg."""

    RULES: ClassVar[dict[str, str]] = {**Oscillation.RULES, "amplitude": "|mean| + amplitude < 90 deg"}

    def validate(self, path: str) -> None:
        """|mean| + amplitude < 90 deg (and the period rule)."""
        if abs(self.mean) + self.amplitude >= 90.0:
            raise SceneError(f"{path}.amplitude", self.amplitude,
                             f"a finite number >= 0 deg with |mean| + amplitude < 90 deg (mean is {self.mean:g} deg)")
        super().validate(path)


@dataclass(frozen=True)
class Yaw(Rotation):
    """Yaw of a regular motion, in degrees: at most half a turn each way."""

    RULES: ClassVar[dict[str, str]] = {**Oscillation.RULES, "amplitude": "<= 180 deg"}

    def validate(self, path: str) -> None:
        """amplitude <= 180 deg (and the period rule)."""
        if self.amplitude > 180.0:
            raise SceneError(f"{path}.amplitude", self.amplitude, "a finite number in [0, 180] deg")
        super().validate(path)


def _dof(name: str, axis: str) -> object:
    return motion_spec(None, default_text="absent",
                       doc=f"{name} ({axis}): q(t) = mean + ramp(t) amplitude sin(2 pi t / period + phase); absent: 0")


@dataclass(frozen=True)
class RegularTable:
    """Regular oscillations, each degree of freedom its own sine (RegularMotion)."""

    KIND: ClassVar[str] = "regular"

    ramp: float = motion_spec(0.0, ge=0.0, unit="s",
                              doc="the oscillations grow from zero over this time (the means do not)")
    surge: Oscillation | None = _dof("surge", "x")
    sway: Oscillation | None = _dof("sway", "y")
    heave: Oscillation | None = _dof("heave", "z")
    roll: Tilt | None = _dof("roll", "about x")
    pitch: Tilt | None = _dof("pitch", "about y")
    yaw: Yaw | None = _dof("yaw", "about z")


@dataclass(frozen=True)
class TimeSeriesTable:
    """A recorded motion, interpolated by a quintic spline, no extrapolation (TimeSeriesMotion)."""

    KIND: ClassVar[str] = "time_series"

    file: str = motion_spec(
        doc="recorded motion: columns t, x, y, z, roll, pitch, yaw (position format) or t, vx, vy, vz, roll, pitch, "
            "yaw (velocity format); a CSV file relative to the scene file's folder")
    format: str | None = motion_spec(None, choices=("position", "velocity"),
                                     doc="column layout (absent: from the header)")
    angle_unit: str = motion_spec("deg", choices=("deg", "rad"), doc="unit of the angle columns")
    initial_position: tuple[float, float, float] | None = motion_spec(
        None, length=3, unit="m", default_text="[0.0, 0.0, 0.0]",
        doc="CG position at the first sample (velocity format only: the velocities are integrated from it)")
    time_offset: float = motion_spec(0.0, unit="s", doc="record time at simulation time 0")

    RULES: ClassVar[dict[str, str]] = {"initial_position": "only with the velocity format"}


#: Values of ``[motion.rao] source``: where the RAOs come from.
RAO_SOURCES: tuple[str, ...] = ("closed_form", "csv", "wamit", "orcaflex", "capytaine")
#: The keys each RAO source takes besides ``source`` (and ``file`` for the files).
RAO_SOURCE_KEYS: dict[str, tuple[str, ...]] = {
    "closed_form": ("length", "beam", "draught", "block_coefficient", "roll_period", "roll_damping"),
    "csv": ("file", "angle_unit", "symmetric"),
    "wamit": ("file", "ulen", "first_column", "centre_of_gravity", "symmetric"),
    "orcaflex": ("file", "vessel_type", "draught_name"),
    "capytaine": ("file", "symmetric"),
}


@dataclass(frozen=True)
class RaoConfig:
    """Response amplitude operators: the hull particulars (closed form) or a file of a hydrodynamic code."""

    source: str | None = motion_spec(
        None, choices=RAO_SOURCES, default_text='"csv" with file, else "closed_form"',
        doc="where the RAOs come from: the closed-form hull, our CSV table, WAMIT's .4 file, an OrcaFlex vessel "
            "type (text data file), a Capytaine dataset (netCDF; RAOs by capytaine.post_pro.rao); conventions in "
            "ship_motion/README.md")
    length: float | None = motion_spec(None, gt=0.0, le=500.0, unit="m", default_text=f"{FRIGATE.length:g}",
                                       doc="length between perpendiculars")
    beam: float | None = motion_spec(None, gt=0.0, le=100.0, unit="m", default_text=f"{FRIGATE.beam:g}", doc="beam")
    draught: float | None = motion_spec(None, gt=0.0, le=30.0, unit="m", default_text=f"{FRIGATE.draught:g}",
                                        doc="draught")
    block_coefficient: float | None = motion_spec(None, ge=0.3, le=1.0, unit="-",
                                                  default_text=f"{FRIGATE.block_coefficient:g}",
                                                  doc="block coefficient")
    roll_period: float | None = motion_spec(None, ge=1.0, le=60.0, unit="s",
                                            default_text=f"{FRIGATE.roll_period:g}", doc="natural roll period")
    roll_damping: float | None = motion_spec(None, gt=0.0, le=1.0, unit="-",
                                             default_text=f"{FRIGATE.roll_damping:g}",
                                             doc="roll damping (fraction of critical)")
    file: str | None = motion_spec(
        None, doc="the RAO file (csv: columns omega, heading, <dof>_amp, <dof>_phase); must cover the wave band and "
                  "the heading")
    angle_unit: str | None = motion_spec(None, choices=("deg", "rad"), default_text='"deg"',
                                         doc="csv: unit of the rotational amplitudes and of all phases")
    ulen: float | None = motion_spec(None, gt=0.0, le=1000.0, unit="m",
                                     doc="wamit (required): WAMIT's length scale ULEN (in its .out file)")
    first_column: str | None = motion_spec(None, choices=("period", "frequency"), default_text='"period"',
                                           doc="wamit: the .4 file's first column, period [s] (IPEROUT = 1) or "
                                               "frequency [rad/s] (IPEROUT = 2)")
    centre_of_gravity: tuple[float, float, float] | None = motion_spec(
        None, length=3, unit="m", doc="wamit (required): the CG in WAMIT's body coordinates (x forward, y port, z up)")
    symmetric: bool | None = motion_spec(
        None, default_text="false", doc="csv, wamit, capytaine: the hull is port-starboard symmetric, the headings "
                                        "given are mirrored (sway, roll, yaw change sign)")
    vessel_type: str | None = motion_spec(None, default_text="the only one",
                                          doc="orcaflex: the vessel type's name")
    draught_name: str | None = motion_spec(None, default_text="the only one", doc="orcaflex: the draught's name")

    PARTICULARS: ClassVar[tuple[str, ...]] = RAO_SOURCE_KEYS["closed_form"]
    RULES: ClassVar[dict[str, str]] = {"source": "each source takes its own keys (file required but for "
                                                 "closed_form)"}

    @property
    def kind(self) -> str:
        """The source: the key given, else csv with a file, else closed_form."""
        return self.source or ("csv" if self.file is not None else "closed_form")

    def validate(self, path: str) -> None:
        """Only the keys of the source, and those it requires."""
        allowed = RAO_SOURCE_KEYS[self.kind]
        for name in (f.name for f in fields(self)):
            if name != "source" and name not in allowed and getattr(self, name) is not None:
                raise SceneError(f"{path}.{name}", getattr(self, name), f"with source = {self.kind!r}, one of "
                                 "the keys " + ", ".join(allowed))
        required = ("file",) if self.kind != "closed_form" else ()
        required += ("ulen", "centre_of_gravity") if self.kind == "wamit" else ()
        for name in required:
            if getattr(self, name) is None:
                raise SceneError(f"{path}.{name}", None, f"required with source = {self.kind!r}")

    def particulars(self) -> ShipParticulars:
        """The hull particulars given, the frigate's for the others."""
        return ShipParticulars(**{name: getattr(FRIGATE, name) if getattr(self, name) is None
                                  else getattr(self, name) for name in self.PARTICULARS})


@dataclass(frozen=True)
class IrregularTable:
    """An irregular sea, long- or short-crested: a wave spectrum through the ship's RAOs (IrregularSea)."""

    KIND: ClassVar[str] = "irregular"

    hs: float = motion_spec(DEFAULT_SEA["hs"], ge=0.0, le=20.0, unit="m",
                            doc="significant wave height (ochi_hubble: of the wind sea; torsethaugen: of the whole "
                                "sea, > 0)")
    tp: float = motion_spec(DEFAULT_SEA["tp"], ge=2.0, le=30.0, unit="s",
                            doc="peak period (ochi_hubble: of the wind sea; torsethaugen: of the primary peak)")
    spectrum: str = motion_spec("jonswap", choices=SPECTRA,
                                doc="wave spectrum: JONSWAP (hs, tp, gamma), Ochi-Hubble's two peaks (hs, tp, "
                                    "shape: the wind sea; swell_hs, swell_tp, swell_shape: the swell), Torsethaugen's "
                                    "two peaks (hs, tp: wind sea and swell from the North Sea fit) or a directional "
                                    "spectrum file (spectrum_file, ship_heading; hs, tp, heading, components: the file's, an error if given)")
    gamma: float | None = motion_spec(None, ge=1.0, le=10.0, unit="-", default_text=f"{DEFAULT_SEA['gamma']:g}",
                                      doc="jonswap: peak enhancement factor (1: Pierson-Moskowitz)")
    shape: float | None = motion_spec(None, gt=0.0, le=20.0, unit="-", default_text="1",
                                      doc="ochi_hubble: shape lambda of the wind sea (1: Pierson-Moskowitz)")
    swell_hs: float | None = motion_spec(None, ge=0.0, le=20.0, unit="m",
                                         doc="ochi_hubble (required): significant height of the swell")
    swell_tp: float | None = motion_spec(None, ge=2.0, le=30.0, unit="s",
                                         doc="ochi_hubble (required): peak period of the swell")
    swell_shape: float | None = motion_spec(None, gt=0.0, le=20.0, unit="-", default_text="1",
                                            doc="ochi_hubble: shape lambda of the swell")
    spreading: float | None = motion_spec(
        None, gt=0.0, le=100.0, unit="-", default_text="absent: long-crested",
        doc="short-crested sea: exponent s of the cos-2s spreading about heading (wind sea 1-10, swell 15-75)")
    directions: int | None = motion_spec(None, ge=1, le=360, unit="-", default_text="15 with spreading",
                                         doc="number of directions of a short-crested sea (components each)")
    spectrum_file: str | None = motion_spec(
        None, doc="file (required): a directional spectrum E(f, theta) in wavespectra's netCDF format (efth "
                  "[m^2/Hz/deg], freq [Hz], dir [deg] coming from, nautical), relative to the scene file's folder")
    spectrum_record: int | None = motion_spec(None, ge=0, unit="-", default_text="the only one",
                                              doc="file: index of the spectrum along the file's time (and site)")
    ship_heading: float | None = motion_spec(
        None, unit="deg", doc="file (required): compass heading of the ship's X axis, clockwise from north (the "
                              "file's directions are nautical)")
    heading: float = motion_spec(
        DEFAULT_SEA["heading"], unit="deg",
        doc="direction the waves travel, from the ship's X axis counter-clockwise (180: head seas)")
    speed: float | None = motion_spec(
        None, ge=0.0, le=25.0, unit="m/s",
        default_text=f"{DEFAULT_SEA['speed']:g} (in motion.waves of a manoeuvre: its speed)",
        doc="ship speed for the encounter frequency")
    components: int = motion_spec(DEFAULT_SEA["components"], ge=1, le=5000, unit="-", doc="wave components")
    omega_min: float | None = motion_spec(
        None, gt=0.0, le=20.0, unit="rad/s", default_text=f"{DEFAULT_BAND[0]:g} x 2 pi / tp",
        doc="lower end of the wave band")
    omega_max: float | None = motion_spec(
        None, gt=0.0, le=20.0, unit="rad/s", default_text=f"{DEFAULT_BAND[1]:g} x 2 pi / tp",
        doc="upper end of the wave band")
    spacing: str = motion_spec(DEFAULT_SEA["spacing"], choices=SPACINGS,
                               doc="component frequencies: random within each bin, or the bin centres")
    seed: int = motion_spec(DEFAULT_SEA["seed"], ge=0, unit="-", doc="seed of the random phases (and frequencies)")
    ramp: float = motion_spec(DEFAULT_SEA["ramp"], ge=0.0, unit="s", doc="the sea grows from calm over this time")
    rao: RaoConfig = motion_spec(
        RaoConfig(), default_text="the closed-form frigate below",
        doc="response amplitude operators: the hull particulars below (closed form), or a file")

    RULES: ClassVar[dict[str, str]] = {"omega_max": "> omega_min", "spectrum": "takes its own keys",
                                       "tp": "torsethaugen: in [2 sqrt(hs), 25] s, hs > 0",
                                       "directions": "only with spreading"}

    @property
    def band(self) -> tuple[float, float]:
        """The wave band [rad/s]: the keys given, else the default band about the peak (two peaks: from the
        lower end about the swell's to the upper end about the wind sea's)."""
        periods = (self.tp, self.swell_tp) if self.spectrum == "ochi_hubble" and self.swell_tp else (self.tp,)
        if self.spectrum == "torsethaugen":
            periods = Torsethaugen(self.hs, self.tp).peak_periods
        return (DEFAULT_BAND[0] * 2.0 * math.pi / max(periods) if self.omega_min is None else self.omega_min,
                DEFAULT_BAND[1] * 2.0 * math.pi / min(periods) if self.omega_max is None else self.omega_max)

    def validate(self, path: str) -> None:
        """A given omega_max lies above the band's lower end."""
        if self.spectrum == "torsethaugen":
            if self.hs <= 0.0:
                raise SceneError(f"{path}.hs", self.hs, "> 0 m with spectrum = 'torsethaugen'")
            lower, upper = Torsethaugen.period_range(self.hs)
            if not lower <= self.tp <= upper:
                raise SceneError(f"{path}.tp", self.tp, f"a primary peak period in [{lower:.4g}, {upper:g}] s for hs "
                                 f"{self.hs:g} m (Torsethaugen's range: 2 sqrt(hs) to 25 s)")
        lo = self.band[0]
        if self.omega_max is not None and self.omega_max <= lo:
            raise SceneError(f"{path}.omega_max", self.omega_max, f"a finite number in ({lo:g}, 20] rad/s")
        own = {"jonswap": ("gamma",), "ochi_hubble": ("shape", "swell_hs", "swell_tp", "swell_shape"),
               "file": ("spectrum_file", "spectrum_record", "ship_heading")}
        if self.spectrum == "file":
            for name in ("hs", "tp", "heading", "components"):  # the file gives them: a value set here is an error
                if getattr(self, name) != DEFAULT_SEA[name]:
                    raise SceneError(f"{path}.{name}", getattr(self, name), "absent with spectrum = 'file' (the "
                                     "file's spectrum gives the sea's height, periods, directions and components)")
            for name in ("spreading", "directions", "omega_min", "omega_max"):
                if getattr(self, name) is not None:
                    raise SceneError(f"{path}.{name}", getattr(self, name), "absent with spectrum = 'file' (the "
                                     "file's frequencies and directions are the components)")
            for name in ("spectrum_file", "ship_heading"):
                if getattr(self, name) is None:
                    raise SceneError(f"{path}.{name}", None, "required with spectrum = 'file'")
        for kind, names in own.items():
            for name in names:
                if kind != self.spectrum and getattr(self, name) is not None:
                    raise SceneError(f"{path}.{name}", getattr(self, name),
                                     f"absent with spectrum = {self.spectrum!r} (a key of spectrum = {kind!r})")
        if self.spectrum == "ochi_hubble":
            for name in ("swell_hs", "swell_tp"):
                if getattr(self, name) is None:
                    raise SceneError(f"{path}.{name}", None, "required with spectrum = 'ochi_hubble'")
        if self.directions is not None and self.spreading is None:
            raise SceneError(f"{path}.directions", self.directions, "absent without spreading (a long-crested sea)")

    def wave_spectrum(self) -> Spectrum:
        """The spectrum the keys describe."""
        if self.spectrum == "torsethaugen":
            return Torsethaugen(self.hs, self.tp)
        if self.spectrum == "ochi_hubble":
            return OchiHubble(self.hs, self.tp, self.shape or 1.0, self.swell_hs, self.swell_tp,
                              self.swell_shape or 1.0)
        return Jonswap(self.hs, self.tp, DEFAULT_SEA["gamma"] if self.gamma is None else self.gamma)


@dataclass(frozen=True)
class ManoeuvreTable:
    """A ship under way: speed ramp and turn (Manoeuvre), with waves if given (SuperposedMotion)."""

    KIND: ClassVar[str] = "manoeuvre"

    speed: float = motion_spec(ge=0.0, le=30.0, unit="m/s", doc="cruise speed")
    speed_ramp: float = motion_spec(0.0, ge=0.0, unit="s", doc="time to ramp from initial_speed to speed, from t = 0")
    initial_speed: float | None = motion_spec(None, ge=0.0, le=30.0, unit="m/s",
                                              default_text="0 with a speed ramp, else speed", doc="speed at t = 0")
    heading: float = motion_spec(0.0, unit="deg", doc="initial heading (yaw)")
    position: tuple[float, float] = motion_spec([0.0, 0.0], length=2, unit="m", doc="initial CG (x, y)")
    turn_angle: float = motion_spec(0.0, ge=0.0, le=36000.0, unit="deg",
                                    doc="total heading change of the turn (0: no turn)")
    turn_rate: float | None = motion_spec(None, ge=-20.0, le=20.0, unit="deg/s",
                                          doc="yaw rate of the turn (> 0 turns to port)")
    turn_start: float = motion_spec(0.0, ge=0.0, unit="s", doc="time the yaw rate starts to ramp up")
    turn_ramp: float = motion_spec(10.0, gt=0.0, unit="s", doc="time for the yaw rate to ramp up (and down)")
    waves: RegularTable | IrregularTable | None = motion_spec(
        None, doc="waves superposed on the manoeuvre: the keys of that type, under motion.waves")

    RULES: ClassVar[dict[str, str]] = {
        "initial_speed": "differing from speed needs speed_ramp > 0",
        "turn_angle": ">= |turn_rate| x turn_ramp",
        "turn_rate": "non-zero; required when turn_angle > 0",
    }

    @property
    def start_speed(self) -> float:
        """The speed at t = 0 [m/s]: initial_speed, else 0 with a speed ramp, else speed."""
        if self.initial_speed is not None:
            return self.initial_speed
        return 0.0 if self.speed_ramp > 0.0 else self.speed

    def validate(self, path: str) -> None:
        """The rules across keys (:attr:`RULES`)."""
        if self.speed_ramp == 0.0 and self.start_speed != self.speed:
            raise SceneError(f"{path}.speed_ramp", self.speed_ramp,
                             "a finite number > 0 s when initial_speed differs from speed")
        if self.turn_rate is None and self.turn_angle != 0.0:
            raise SceneError(f"{path}.turn_rate", None, "required: a finite number in [-20, 20] deg/s "
                             "(non-zero; positive turns to port)")
        if self.turn_rate == 0.0:
            raise SceneError(f"{path}.turn_rate", self.turn_rate, "a finite non-zero number in [-20, 20] deg/s")
        if self.turn_angle > 0.0 and self.turn_angle < abs(self.turn_rate) * self.turn_ramp:
            raise SceneError(f"{path}.turn_angle", self.turn_angle,
                             f">= |turn_rate| * turn_ramp = {abs(self.turn_rate) * self.turn_ramp:g} deg "
                             "(the angle turned while the rate ramps up and down)")


#: The declaration of each ``type`` of a ``[motion]`` table.
MOTION_TABLES: dict[str, type] = {cls.KIND: cls for cls in (StillShipTable, RegularTable, TimeSeriesTable,
                                                             IrregularTable, ManoeuvreTable)}
#: Values of ``type``.
TYPES: tuple[str, ...] = tuple(MOTION_TABLES)


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
    config = parse_variant(MOTION_TABLES, table, key)
    if isinstance(config, RegularTable):
        return _regular(config)
    if isinstance(config, TimeSeriesTable):
        return _time_series(config, key, base_dir)
    if isinstance(config, IrregularTable):
        return _irregular(config, key, base_dir)
    if isinstance(config, ManoeuvreTable):
        return _manoeuvre(config, key, base_dir)
    return StillShip()


def _resolve(path_text: str, base_dir: Path | None) -> Path:
    path = Path(path_text).expanduser()
    return path if path.is_absolute() or base_dir is None else Path(base_dir) / path


def _regular(config: RegularTable) -> RegularMotion:
    harmonics = []
    mean = [0.0] * 6
    for dof, name in enumerate(CONFIG_DOF_NAMES):
        oscillation = getattr(config, name)
        if oscillation is None:
            continue
        scale = math.pi / 180.0 if IS_ANGLE[dof] else 1.0
        mean[dof] = oscillation.mean * scale
        if oscillation.amplitude > 0.0:
            harmonics.append(Harmonic(dof, oscillation.amplitude * scale, oscillation.period,
                                      math.radians(oscillation.phase)))
    return RegularMotion(harmonics, mean=mean, ramp=config.ramp)


def _time_series(config: TimeSeriesTable, key: str, base_dir: Path | None) -> TimeSeriesMotion:
    record = read_motion_csv(_resolve(config.file, base_dir), layout=config.format, angle_unit=config.angle_unit,
                             initial_position=config.initial_position or (0.0, 0.0, 0.0), key=f"{key}.file")
    if record.layout == "position" and config.initial_position is not None:
        raise SceneError(f"{key}.initial_position", list(config.initial_position),
                         "only with the velocity format (t, vx, vy, vz, roll, pitch, yaw)")
    return TimeSeriesMotion(record.t, record.positions, record.attitudes, time_offset=config.time_offset,
                            label=record.label)


def _rao(config: RaoConfig, key: str, base_dir: Path | None) -> Rao:
    kind = config.kind
    if kind == "closed_form":
        return ClosedFormRao(config.particulars())
    path, file_key = _resolve(config.file, base_dir), f"{key}.file"
    if kind == "wamit":
        return read_wamit_4(path, ulen=config.ulen, centre_of_gravity=config.centre_of_gravity,
                            first_column=config.first_column or "period", symmetric=bool(config.symmetric),
                            key=file_key)
    if kind == "capytaine":
        return read_capytaine(path, symmetric=bool(config.symmetric), key=file_key)
    if kind == "orcaflex":
        return read_orcaflex(path, vessel_type=config.vessel_type, draught=config.draught_name, key=file_key)
    table = RaoTable.from_csv(path, angle_unit=config.angle_unit or "deg", key=file_key)
    return mirrored(table) if config.symmetric else table


def _irregular(config: IrregularTable, key: str, base_dir: Path | None,
               default_speed: float | None = None) -> IrregularSea:
    omega_min, omega_max = config.band
    speed = config.speed if config.speed is not None else (
        DEFAULT_SEA["speed"] if default_speed is None else default_speed)
    rao = _rao(config.rao, f"{key}.rao", base_dir)
    if config.spectrum == "file":
        return _file_sea(config, rao, speed, key, base_dir)
    if isinstance(rao, RaoTable):
        lo, hi = rao.frequency_range
        rao_key = f"{key}.rao.file"
        if omega_min < lo or omega_max > hi:
            raise SceneError(rao_key, rao.label, f"an RAO table covering the wave band "
                             f"[{omega_min:.4g}, {omega_max:.4g}] rad/s (it covers "
                             f"[{lo:g}, {hi:g}] rad/s; set omega_min/omega_max)")
        headings = [0.0] if config.spreading is None else np.degrees(
            Cos2s(config.spreading).bin_weights(config.directions or DEFAULT_DIRECTIONS)[0])
        for offset in headings:
            if rao.heading_coordinate(math.radians(config.heading + offset)) is None:
                raise SceneError(rao_key, rao.label, f"an RAO table covering the heading {config.heading + offset:g}"
                                 " deg" + ("" if config.spreading is None else " (a direction of the spread sea; "
                                           "symmetric = true mirrors a half range)"))
    spreading = None if config.spreading is None else Cos2s(config.spreading)
    return IrregularSea(config.wave_spectrum(), rao, heading=math.radians(config.heading),
                        speed=speed, components=config.components, omega_min=omega_min, omega_max=omega_max,
                        spacing=config.spacing, seed=config.seed, ramp=config.ramp, spreading=spreading,
                        directions=config.directions or DEFAULT_DIRECTIONS)


def _file_sea(config: IrregularTable, rao: Rao, speed: float, key: str, base_dir: Path | None) -> IrregularSea:
    spectrum = read_wavespectra(_resolve(config.spectrum_file, base_dir), record=config.spectrum_record,
                                key=f"{key}.spectrum_file")
    waves = spectrum.components(ship_heading=config.ship_heading, spacing=config.spacing, seed=config.seed)
    if isinstance(rao, RaoTable):
        lo, hi = rao.frequency_range
        if waves.omega.min() < lo or waves.omega.max() > hi:
            raise SceneError(f"{key}.rao.file", rao.label, f"an RAO table covering the spectrum file's frequencies "
                             f"[{waves.omega.min():.4g}, {waves.omega.max():.4g}] rad/s (it covers [{lo:g}, {hi:g}])")
        for mu in np.unique(waves.heading):
            if rao.heading_coordinate(float(mu)) is None:
                raise SceneError(f"{key}.rao.file", rao.label, f"an RAO table covering the heading "
                                 f"{math.degrees(mu):g} deg (a direction of the spectrum file)")
    return IrregularSea(spectrum, rao, heading=math.radians(config.heading), speed=speed, seed=config.seed,
                        spacing=config.spacing, ramp=config.ramp, waves=waves)


def _manoeuvre(config: ManoeuvreTable, key: str, base_dir: Path | None) -> MotionSource:
    turn = None
    if config.turn_angle > 0.0:
        turn = Turn(config.turn_start, math.radians(config.turn_rate), math.radians(config.turn_angle),
                    config.turn_ramp)
    base = Manoeuvre(config.speed, heading=math.radians(config.heading), position=config.position,
                     initial_speed=config.start_speed, speed_ramp=config.speed_ramp, turn=turn)
    if config.waves is None:
        return base
    path = f"{key}.waves"
    waves = (_regular(config.waves) if isinstance(config.waves, RegularTable)
             else _irregular(config.waves, path, base_dir, default_speed=config.speed))
    return SuperposedMotion(base, waves)
