#!/usr/bin/env python
"""Build the three FMUs (ShipMotion, HeaveCompensation, TowCable) into fmus/.

    python build_fmu.py [--output DIR] [--check] [--ssp] [--crosscheck DIR] [--no-native] [NAME ...]

The work is done by :func:`towcable_fmu.fmi.build.build_fmus` (also used by the tests and
by ``towcable cosim``); variables, units and descriptions come from
``towcable_fmu/contract.toml``. ``--check`` runs ``fmpy validate`` and ``fmutool -check``.
``--crosscheck DIR`` writes the FMI Cross-Check artefacts (:mod:`towcable_fmu.fmi.crosscheck`);
``--no-native`` leaves out the loader layer that lets the FMUs run in hosts without Python
(:mod:`towcable_fmu.fmi.native`).
"""

import sys

from towcable_fmu.fmi.build import build_fmus, check_fmus, ensure_fmus, main  # noqa: F401

if __name__ == "__main__":
    sys.exit(main())
