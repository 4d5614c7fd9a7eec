"""The FMU build tool: packages the three slaves (ShipMotion, HeaveCompensation,
TowCable) as FMI 2.0 archives. It imports every slave; nothing a slave runs imports it.

* :mod:`towcable_fmu.fmu_build.build` — writes the ``.fmu`` archives (metadata from the
  contract, reproducible, GUID from the content) and validates them;
* :mod:`towcable_fmu.fmu_build.bundle` — the copy of our packages each FMU carries, under
  a private package name;
* :mod:`towcable_fmu.fmu_build.runtime` — collects the Python runtime a standalone FMU
  carries;
* :mod:`towcable_fmu.fmu_build.native` — compiles the C loader layer of the Linux binary
  (``csrc/fmu_loader.c``): finds or starts a Python, enforces the FMI 2.0 state machine
  (``csrc/state_machine.c``), relays errors, returns fmi2Error, checks FMU-state bytes,
  serves gets, input sets and compiled steps from the values it shares with the slave
  (``csrc/shared_values.h``);
* :mod:`towcable_fmu.fmu_build.kernels` and :mod:`~towcable_fmu.fmu_build.warmup` — the
  precompiled kernels an FMU carries (every FMU run on every built-in scene);
* :mod:`towcable_fmu.fmu_build.ssp` — the SSP file of the three-FMU system;
* :mod:`towcable_fmu.fmu_build.crosscheck` — the FMI Cross-Check artefacts.

The runtime base of the slaves is :mod:`towcable_fmu.fmi`. The command line of
``build_fmu.py`` is :mod:`towcable_fmu.build_command`; the co-simulation master is
:mod:`towcable_fmu.cosim`.
"""
