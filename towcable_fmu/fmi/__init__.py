"""FMI 2.0 packaging of the three models (ShipMotion, HeaveCompensation, TowCable).

* :mod:`towcable_fmu.fmi.slave` — the pythonfmu base class that registers an FMU's
  variables from the contract (``towcable_fmu/contract.toml``) and turns every error into
  a logged message with the status the call should return;
* :mod:`towcable_fmu.fmi.build` — writes the ``.fmu`` archives (metadata from the
  contract, reproducible, GUID from the content) and validates them;
* :mod:`towcable_fmu.fmi.bundle` — the copy of our packages each FMU carries, under a
  private package name;
* :mod:`towcable_fmu.fmi.runtime` — the Python runtime a standalone FMU carries;
* :mod:`towcable_fmu.fmi.native` — the C loader layer of the Linux binary
  (``csrc/fmu_loader.c``): finds or starts a Python, enforces the FMI 2.0 state machine
  (``csrc/state_machine.c``), relays errors, returns fmi2Error, checks FMU-state bytes;
* :mod:`towcable_fmu.fmi.ssp` — the SSP file of the three-FMU system;
* :mod:`towcable_fmu.fmi.crosscheck` — the FMI Cross-Check artefacts.

The slaves themselves are thin: ``ship_motion/fmu.py``, ``controllers/fmu.py``,
``towcable_fmu/fmu.py``. Where an FMU's code and kernels live on a machine:
:mod:`towcable_fmu.machine_cache`. The command line of ``build_fmu.py`` is
:mod:`towcable_fmu.build_command`; the co-simulation master is :mod:`towcable_fmu.cosim`.
"""
