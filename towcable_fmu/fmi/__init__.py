"""The FMI runtime our three slaves share (ShipMotion, HeaveCompensation, TowCable).

* :mod:`towcable_fmu.fmi.slave` — the pythonfmu base class that registers an FMU's
  variables from the contract (``towcable_fmu/common/contract.toml``) and turns every error into
  a logged message with the status the call should return.

The slaves themselves are thin: ``ship_motion/fmu.py``, ``controllers/fmu.py``,
``towcable_fmu/fmu.py``. Writing the ``.fmu`` archives is the build tool's job
(:mod:`towcable_fmu.fmu_build`, above every slave); where an FMU's code and kernels live
on a machine: :mod:`towcable_fmu.jit.machine_cache`.
"""
