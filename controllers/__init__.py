"""Active heave compensation (AHC) set-point algorithms W(1)-(2); see README.md."""

from controllers.config import ALGORITHMS, SetpointConfig, setpoint_config_from_table
from controllers.setpoint import Setpoint, SetpointAlgorithm, SetpointSeries

__all__ = [
    "ALGORITHMS",
    "Setpoint",
    "SetpointAlgorithm",
    "SetpointConfig",
    "SetpointSeries",
    "setpoint_config_from_table",
]
