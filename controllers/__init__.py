"""Active heave compensation (AHC) set-point algorithms W(1)-(2) and the constant-tension
winch; see README.md."""

from controllers.config import ALGORITHMS, MOTION_ALGORITHMS, SetpointConfig, setpoint_config_from_table
from controllers.setpoint import Setpoint, SetpointAlgorithm, SetpointSeries
from controllers.tension import TensionControl

__all__ = [
    "ALGORITHMS",
    "MOTION_ALGORITHMS",
    "Setpoint",
    "SetpointAlgorithm",
    "SetpointConfig",
    "SetpointSeries",
    "setpoint_config_from_table",
    "TensionControl",
]
