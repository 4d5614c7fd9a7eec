#!/usr/bin/env python
"""Build the three FMUs (ShipMotion, HeaveCompensation, TowCable) into fmus/.

    python build_fmu.py [--output DIR] [--standalone] [--check] [--ssp] [--crosscheck DIR] [--no-native] [--no-kernels] [NAME ...]

The work is done by :func:`towcable_fmu.fmu_build.build.build_fmus` (also used by the tests and
by ``towcable cosim``); the command line is :mod:`towcable_fmu.build_command`. Each FMU
carries the towcable code it runs, TowCable also its numerical kernels precompiled for
x86-64-v3 CPUs (``--no-kernels`` leaves them out); ``--standalone`` also carries a Python runtime, for
hosts on machines without Python. ``--check`` runs ``fmpy validate`` and ``fmutool
-check``; ``--ssp`` writes the SSP file of the default ``towcable cosim`` case;
``--crosscheck DIR`` writes the FMI Cross-Check artefacts; ``--no-native`` leaves out
the loader layer (the FMUs then run only in Python hosts).
"""

import sys

from towcable_fmu.build_command import main

if __name__ == "__main__":
    sys.exit(main())
