"""FMI 2.0 packaging of the three models (ShipMotion, HeaveCompensation, TowCable).

* :mod:`towcable_fmu.fmi.slave` — the pythonfmu base class that registers an FMU's
  variables from the contract (``towcable_fmu/contract.toml``) and turns every error into
  a logged message and a clean FMI status;
* :mod:`towcable_fmu.fmi.build` — builds the ``.fmu`` files, writes units and descriptions
  into their modelDescription.xml, validates them (``build_fmu.py`` at the repository root);
* :mod:`towcable_fmu.fmi.ssp` — the SSP file of the three-FMU system;
* :mod:`towcable_fmu.fmi.native` — the C loader layer that lets the FMUs run in hosts
  without Python (``csrc/fmu_loader.c``);
* :mod:`towcable_fmu.fmi.crosscheck` — the FMI Cross-Check artefacts.

The slaves themselves are thin: ``ship_motion/fmu.py``, ``controllers/fmu.py``,
``towcable_fmu/fmu.py``. The co-simulation master is :mod:`towcable_fmu.cosim`.
"""
