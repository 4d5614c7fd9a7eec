"""Command line of ``build_fmu.py``: build, check and package the FMUs.

A command (above the layers it uses): it builds with :mod:`towcable_fmu.fmu_build.build`, and
for ``--ssp`` initialises the default ``towcable cosim`` case through
:mod:`towcable_fmu.cosim` to bind its parameters in the SSP file.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .common import contract
from .fmu_build.build import FmuCheckError, build_fmus, check_fmus
from .fmu_build.runtime import glibc_needed


def write_default_case_ssp(path: Path, fmus: dict[str, Path]) -> Path:
    """The SSP file of the default ``towcable cosim`` case, every parameter the master sets
    bound (the nominal departure angle is the one it resolves at initialisation)."""
    from .cosim import CosimConfig, run_cosim
    from .fmu_build.ssp import write_ssp

    config = CosimConfig()
    first = run_cosim(CosimConfig(duration=config.step, step=config.step), echo=False, fmus=fmus)
    return write_ssp(path, fmus, first.parameters, start_time=config.start_time,
                     stop_time=config.start_time + config.duration)


def main(argv: list[str] | None = None) -> int:
    """Command line of ``build_fmu.py``."""
    parser = argparse.ArgumentParser(prog="build_fmu.py", description="Build the ShipMotion, HeaveCompensation "
                                     "and TowCable FMUs (FMI 2.0 Co-Simulation, pythonfmu) from the contract; "
                                     "each carries the towcable code it runs.")
    parser.add_argument("-o", "--output", default="fmus", help="output folder (default: fmus/)")
    parser.add_argument("--check", action="store_true", help="validate with fmpy validate and fmutool -check")
    parser.add_argument("--standalone", action="store_true", help="also carry a Python runtime (interpreter, "
                        "standard library, numpy, scipy, numba): the FMUs then run in hosts on Linux x86-64 "
                        "machines that have no Python at all")
    parser.add_argument("--ssp", action="store_true", help="also write the SSP file of the system "
                        "(TowedCableSystem.ssp) with the parameters of the default 'towcable cosim' case")
    parser.add_argument("--no-native", action="store_true", help="keep pythonfmu's binary (the FMUs then load "
                        "only in Python hosts and cannot return fmi2Error) instead of compiling the loader layer")
    parser.add_argument("--no-kernels", action="store_true", help="leave out the precompiled kernels (TowCable "
                        "then compiles them at its first use on each machine, a minute or more; the first build of "
                        "a version of the code with them compiles them, minutes, and later builds reuse them)")
    parser.add_argument("--crosscheck", metavar="DIR", help="also write the FMI Cross-Check artefacts (FMU, "
                        "_ref.csv, _in.csv, _ref.opt) under DIR/fmus/2.0/cs/linux64/towcable/<version>/")
    parser.add_argument("names", nargs="*", help="FMUs to build (default: all)")
    args = parser.parse_args(argv)
    if args.standalone and args.no_native:
        parser.error("--standalone needs the loader layer (leave out --no-native)")
    everything = not args.names or set(args.names) == set(contract.fmus())
    if (args.ssp or args.crosscheck) and not everything:
        parser.error("--ssp and --crosscheck need all three FMUs (give no NAME)")
    paths = build_fmus(args.output, args.names or None, native_loader=not args.no_native,
                       standalone=args.standalone, kernels=not args.no_kernels)
    for path in paths.values():
        print(f"built {path} ({path.stat().st_size / 1e6:.1f} MB)")
    if args.standalone:
        import zipfile

        with zipfile.ZipFile(next(iter(paths.values()))) as z:
            needed = glibc_needed({n: z.read(n) for n in z.namelist() if ".so" in n})
        print(f"standalone: Linux x86-64 with glibc {needed} or newer; no Python needed")
    if args.ssp:
        print(f"wrote {write_default_case_ssp(Path(args.output) / 'TowedCableSystem.ssp', paths)}")
    if args.crosscheck:
        from .fmu_build.crosscheck import write_crosscheck

        for folder in write_crosscheck(paths, args.crosscheck).values():
            print(f"wrote {folder}")
    if args.check:
        try:
            check_fmus(paths.values())
        except FmuCheckError as exc:
            print(exc, file=sys.stderr)
            return 1
        print("fmpy validate and fmutool -check: no problems")
    return 0
