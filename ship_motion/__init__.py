"""6-DOF ship motion sources with consistent first and second derivatives; see README.md.

Every source has ``evaluate(t) -> (3, 6)`` and ``evaluate_many(t) -> (n, 3, 6)``
(rows: value, rate, acceleration; columns: x, y, z [m], roll, pitch, yaw [rad]) and a
one-line ``description``. :func:`motion_from_config` builds one from a scene file's
``[motion]`` table.
"""

from pathlib import Path

from ship_motion.base import DOF_NAMES, MotionSource, StillShip
from ship_motion.config import DEFAULT_SEA, TYPES, motion_from_config
from ship_motion.irregular import IrregularSea
from ship_motion.manoeuvre import Manoeuvre, Turn
from ship_motion.rao import FRIGATE, ClosedFormRao, Rao, RaoTable, ShipParticulars
from ship_motion.regular import Harmonic, RegularMotion
from ship_motion.spectrum import Jonswap, WaveComponents, discretise
from ship_motion.superposition import SuperposedMotion
from ship_motion.time_series import (
    TimeRangeError,
    TimeSeriesMotion,
    integrate_velocities,
    read_motion_csv,
)

#: The example record shipped with the package: 120 s of the default sea at 10 Hz,
#: velocity layout (t, vx, vy, vz, roll, pitch, yaw; angles in deg).
EXAMPLE_CSV = Path(__file__).parent / "data" / "default_sea_velocities.csv"

__all__ = [
    "DEFAULT_SEA",
    "DOF_NAMES",
    "EXAMPLE_CSV",
    "FRIGATE",
    "TYPES",
    "ClosedFormRao",
    "Harmonic",
    "IrregularSea",
    "Jonswap",
    "Manoeuvre",
    "MotionSource",
    "Rao",
    "RaoTable",
    "RegularMotion",
    "ShipParticulars",
    "StillShip",
    "SuperposedMotion",
    "TimeRangeError",
    "TimeSeriesMotion",
    "Turn",
    "WaveComponents",
    "discretise",
    "integrate_velocities",
    "motion_from_config",
    "read_motion_csv",
]
