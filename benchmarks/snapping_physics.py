"""Snapping cable: why our converged runs drifted from MoorDyn's, one difference at a time.

Each of our converged runs (ANCF: 40 elements, 0.25 ms, 4 points; nodal: 40 elements,
0.125 ms, generalised-alpha) is compared with MoorDyn's converged run (80 segments, RK4,
0.02 ms) on the whole 15 s: RMS of (T - T_MoorDyn)/T0 over 0.05-5 s (the snaps' phase) and
Tmax/T0 over the run. The scenes follow the case's definitions
(``benchmarks/peers/snapping_case.py``): the Kelvin-Voigt axial law N = EA max(eps, 0) +
BA d(eps)/dt with the engineering strain, and MoorDyn's normal/tangential drag. Each
other row puts back one of our former choices, or removes one remaining difference, so
that its effect shows alone.

Run: ``python benchmarks/snapping_physics.py`` (about 10 minutes; needs MoorDyn,
``pip install ".[bench]"``). Writes ``results/snapping_physics.md``.
"""

from __future__ import annotations

import sys

from common import RESULTS, machine_header, markdown_table
from snapping import FREQUENCIES, moordyn_run, ours_run, series_error

#: our former choices, before issue 39: the formulations' own axial laws and the bare-cable
#: loading functions with the common C_D = 1.2 (0.024 on d along the cable)
FORMER_LAW = {"cable.segments[0].axial_law": "formulation"}
FORMER_DRAG = {"cable.segments[0].loading": "bare", "cable.segments[0].tangential_drag_coefficient": None}
ANCF = ("snapping_cable", "genalpha", 40, 2.5e-4, 4)
NODAL = ("snapping_cable_nodal", "genalpha", 40, 1.25e-4, 2)
#: (label, code, settings, overrides or MoorDyn keywords)
ROWS = [
    ("ANCF, the case's laws (scene default)", "ours", ANCF, {}),
    ("ANCF, former laws (Green strain, bare-cable drag)", "ours", ANCF, {**FORMER_LAW, **FORMER_DRAG}),
    ("ANCF, former axial law only (Green strain: N = EA eps_G lambda)", "ours", ANCF, FORMER_LAW),
    ("ANCF, former drag only (1.2 x 0.020 on d along the cable)", "ours", ANCF, FORMER_DRAG),
    ("ANCF, EI = 1e-5 N m^2 instead of 1e-3 (MoorDyn has none)", "ours", ANCF, {"cable.segments[0].EI": 1e-5}),
    ("ANCF, no cable added mass (C_a = 0)", "ours", ANCF, {"cable.segments[0].added_mass_coefficient": 0.0}),
    ("nodal, the case's laws (scene default)", "ours", NODAL, {}),
    ("nodal, former law (the paper's eq. 13-15: (L/L0) times it) and drag", "ours", NODAL,
     {**FORMER_LAW, **FORMER_DRAG}),
    ("MoorDyn 80 seg, RK4, 0.02 ms (the reference)", "moordyn", (80, 2e-5), {}),
    ("MoorDyn, coupling every 0.1 ms instead of 0.5 ms (top motion piecewise linear)", "moordyn", (80, 2e-5),
     {"coupling_target_s": 1e-4}),
    ("MoorDyn, our former tangential drag (CdAx = 0.024/pi)", "moordyn", (80, 2e-5),
     {"cable_cd_tangential": 0.024 / 3.141592653589793}),
]


def main() -> None:
    lines = ["# Snapping cable: our converged runs against MoorDyn's, one difference at a time\n",
             machine_header(), "\n", __doc__.split("\n\n")[1].replace("\n", " "), "\n"]
    for f in FREQUENCIES:
        ref = moordyn_run(f, "RK4", 80, 2e-5)
        table = []
        for label, code, setting, extra in ROWS:
            if code == "ours":
                res = ours_run(f, *setting, overrides=extra)
            else:
                res = ref if not extra else moordyn_run(f, "RK4", *setting, **extra)
            tmax = res["Tmax_over_T0"] / ref["Tmax_over_T0"] - 1.0
            series = series_error(res, ref)
            print(f"f={f} {label}: series {100 * series:.2f} %, Tmax {100 * tmax:+.2f} %", file=sys.stderr)
            table.append([label, f"{res['T0']:.4f}", f"{res['Tmax_over_T0']:.4f}", f"{100 * tmax:+.2f}",
                          f"{100 * series:.2f}"])
        lines.append(f"\n## f = {f} Hz\n\n")
        lines.append(markdown_table(["run", "T0 [N]", "Tmax/T0", "Tmax vs MoorDyn [%]",
                                     "series vs MoorDyn [%]"], table))
    (RESULTS / "snapping_physics.md").write_text("".join(lines), encoding="utf-8")


if __name__ == "__main__":
    main()
