"""Write the example ship motion record ``ship_motion/data/default_sea_velocities.csv``.

Run ``python -m ship_motion.make_example_data``. The record is 120 s of the default
sea (:data:`ship_motion.DEFAULT_SEA`) sampled at 10 Hz, without the ramp-in (so it
starts mid-motion, like a measured record), in the velocity layout of the FFG-7
trial data used by Westin (2018, section 5): t [s], inertial velocities vx, vy, vz
[m/s], roll, pitch, yaw [deg].
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ship_motion.config import DEFAULT_SEA, motion_from_config

#: Length of the record [s].
DURATION = 120.0
#: Sampling rate [Hz].
RATE = 10.0
#: Output file.
TARGET = Path(__file__).parent / "data" / "default_sea_velocities.csv"


def write_example(path: Path = TARGET) -> None:
    """Sample the default sea (no ramp) and write the CSV file.

    Parameters
    ----------
    path
        Output file.
    """
    sea = motion_from_config({**DEFAULT_SEA, "ramp": 0.0})
    t = np.linspace(0.0, DURATION, int(round(DURATION * RATE)) + 1)
    states = sea.evaluate_many(t)
    velocity = states[:, 1, 0:3]
    attitude = np.degrees(states[:, 0, 3:6])
    z0 = states[0, 0, 2]
    header = [
        "# Example ship motion record: the default sea of ship_motion (DEFAULT_SEA) without",
        "# ramp-in, 120 s at 10 Hz; written by python -m ship_motion.make_example_data.",
        f"# {sea.description}",
        "# Frame moving with the ship at the towing speed (vx = vy = 0: the closed-form RAO",
        "# has no surge or sway). Velocities are inertial, m/s; angles in deg.",
        f"# The CG height at t = 0 is {z0:.6f} m: use initial_position = [0.0, 0.0, {z0:.6f}]",
        "# to reproduce the sea's z(t) exactly (default [0, 0, 0] starts it at zero).",
        "t [s],vx [m/s],vy [m/s],vz [m/s],roll [deg],pitch [deg],yaw [deg]",
    ]
    rows = np.column_stack([t, velocity, attitude])
    with path.open("w", encoding="utf-8") as handle:
        handle.write("\n".join(header) + "\n")
        np.savetxt(handle, rows, fmt=["%.1f"] + ["%.7f"] * 6, delimiter=",")


if __name__ == "__main__":
    write_example()
    print(f"wrote {TARGET}")
