"""Co-simulation master: ShipMotion -> HeaveCompensation -> TowCable on fmpy's low-level API.

The three FMUs (built by ``build_fmu.py`` / :func:`towcable_fmu.fmu_build.build.ensure_fmus`)
are driven with ``fmpy.fmi2.FMU2Slave`` at a fixed communication step ``h``. Which
output feeds which input comes from the contract (``[system]`` in
``towcable_fmu/common/contract.toml``); nothing here names a signal except for plotting.

Order at each communication point t_k (documented contract, tested):

1. ``HeaveCompensation`` gets the ship state at t_k and the sheave angle the cable
   reported at t_k (the end of its previous step: the measured angle reaches the
   controller with one step of delay, which the rigorous algorithms need because the
   cable has not computed its angle for the new step yet); its outputs follow at once
   (direct feedthrough) and are read: the set-point u(t_k).
2. The row at t_k is recorded (ship, set-point, cable outputs: one consistent time).
3. ``TowCable`` gets the ship state at t_k and u(t_k). (Its Simulation extrapolates
   the ship with constant acceleration over the step: it needs the state at the start.)
4. All three step from t_k to t_{k+1} (ShipMotion, HeaveCompensation, TowCable).
5. ShipMotion's and TowCable's outputs at t_{k+1} are read.

Values move in blocks: per step one setReal per FMU with inputs, one getReal per FMU
with all its Real outputs (and one getBoolean for TowCable's Boolean output). The
stepping loop is compiled (:mod:`towcable_fmu.cosim.loop`): it makes these calls
through the FMI functions' addresses, without ctypes' per-call conversions, and returns
to Python about every 0.2 s of wall time for the progress report.

Initialisation: ShipMotion leaves initialisation first (ship state at t0); TowCable is
initialised (statics) with that ship state and the nominal set-point; then
HeaveCompensation, whose ``theta_nom`` defaults to the cable's departure angle at t0
(``sheave_angle``: from the sheave, or from the drum in a scene without a sheave; the
static angle, as Westin 2018 used for the simplified algorithms).

Overhead: each FMU reports ``model_wall_time``, the wall time spent in its own model
(Simulation.step_row, MotionSource.evaluate, SetpointAlgorithm.compute). The FMU overhead
is the rest of the loop's wall time (the slaves' Python glue around their models,
pythonfmu's C layer, the master's loop) as a share of the loop's wall time.

Modules, one concern each: :mod:`.instance` (one FMU: instantiate, log, values, step),
:mod:`.config` (what to run, the result, the compensation geometry), :mod:`.master` (the
loop over communication points), :mod:`.loop` (its compiled part), :mod:`.kernels` (the
kernels compiled ahead with the cable's), :mod:`.results` (the files). The TOML
formatting of overrides is :func:`towcable_fmu.scene.format_overrides`.
"""

from .config import CosimConfig, CosimResult, compensation_geometry
from .instance import CosimError, FmuInstance
from .master import run_cosim
from .results import write_results

__all__ = ["CosimConfig", "CosimError", "CosimResult", "FmuInstance", "compensation_geometry", "run_cosim",
           "write_results"]
