"""The kernels of a simulation's inputs, as jobs for :mod:`towcable_fmu.jit.parallel_compile`:
the ship motion's harmonic sum (:func:`ship_motion.irregular.harmonic_state`, a scene's
irregular sea and the ShipMotion FMU) and a compensation's set-point law
(:func:`controllers.setpoint.setpoint_law`, a compensating scene and the
HeaveCompensation FMU). Every model kind that runs them lists this module
(:data:`towcable_fmu.models.KERNEL_SOURCES`), and ``towcable cosim`` compiles it too.
"""

from __future__ import annotations

import numpy as np

from controllers.setpoint import setpoint_law
from ship_motion.irregular import harmonic_state

from ..jit.parallel_compile import Job


def kernel_jobs() -> list[Job]:
    """The inputs' kernels with arguments of the types their callers pass (costs: estimated
    compile time [s] on one core)."""
    return [
        Job("ship_motion.harmonic_state", harmonic_state,
            lambda: (0.0, np.zeros((8, 2)), np.zeros(1, dtype=np.intp), 0.0), 1.5),
        Job("controllers.setpoint_law", setpoint_law, lambda: (np.zeros((3, 6)), np.zeros(11), 0.0), 1.5,
            ("kinematics.ship_point_kinematics",)),
    ]
