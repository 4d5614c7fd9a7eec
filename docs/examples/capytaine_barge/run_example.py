"""Worked example: a box barge's RAOs from Capytaine, through the Capytaine and the WAMIT doors,
and the closed-form hull of the same dimensions against them.

Steps (README.md next to this file):

1. the barge's hydrodynamic dataset: ``ship_motion/data/barge_capytaine.nc`` (made by
   ``python -m ship_motion.make_capytaine_barge``; ``--recompute`` here redoes it);
2. its RAOs read by the Capytaine reader and written as a WAMIT ``.4`` file (origin at the
   CG, ULEN 40 m), read back by the WAMIT reader; the short-crested sea of
   ``barge_sea.toml`` through both doors (largest difference printed);
3. the closed-form hull (Jensen et al. 2004, box: C_B = 1) of the same dimensions against
   Capytaine: heave and pitch amplitudes in head seas, heave in beam seas.

Run: ``python docs/examples/capytaine_barge/run_example.py [--recompute] [--output DIR]``
(needs ``pip install ".[capytaine]"``).
"""

from __future__ import annotations

import argparse
import math
import tomllib
from pathlib import Path

import numpy as np

from ship_motion import ClosedFormRao, ShipParticulars, motion_from_config
from ship_motion.make_capytaine_barge import BEAM, DRAUGHT, LENGTH, OUTPUT, main as make_dataset
from ship_motion.rao_files import read_capytaine, write_wamit_4

HERE = Path(__file__).resolve().parent
STUDY_OMEGA = (0.4, 0.6, 0.8, 1.0, 1.2, 1.5, 1.8)


def doors(output: Path) -> float:
    """Largest difference [m or rad] between the motions through the Capytaine and WAMIT doors."""
    table = read_capytaine(OUTPUT, symmetric=True)
    write_wamit_4(output / "barge.4", table, ulen=40.0)
    scene = tomllib.loads((HERE / "barge_sea.toml").read_text())["motion"]
    times = np.linspace(0.0, 600.0, 3001)
    via_capytaine = motion_from_config(scene, base_dir=HERE).evaluate_many(times)
    wamit = {**scene, "rao": {"source": "wamit", "file": str(output / "barge.4"), "ulen": 40.0,
                              "centre_of_gravity": [0.0, 0.0, 0.0]}}
    via_wamit = motion_from_config(wamit).evaluate_many(times)
    std = via_capytaine[:, 0, :].std(axis=0)
    print("short-crested sea of barge_sea.toml, 600 s: std of surge, sway, heave [m], roll, pitch, yaw [deg]:")
    print("  " + ", ".join(f"{v:.4g}" for v in np.concatenate([std[:3], np.degrees(std[3:])])))
    return float(np.abs(via_wamit - via_capytaine).max())


def study() -> None:
    """Closed-form box hull against Capytaine (printed table)."""
    capytaine = read_capytaine(OUTPUT, symmetric=True)
    closed = ClosedFormRao(ShipParticulars(length=LENGTH, beam=BEAM, draught=DRAUGHT, block_coefficient=1.0))
    w = np.array(STUDY_OMEGA)
    head_c, head_j = capytaine(w, math.pi, 0.0), closed(w, math.pi, 0.0)
    beam_c, beam_j = capytaine(w, 0.5 * math.pi, 0.0), closed(w, 0.5 * math.pi, 0.0)
    print("omega [rad/s] | head: heave Capytaine, closed form [m/m] | pitch Capytaine, closed form [deg/m] "
          "| beam: heave Capytaine, closed form [m/m]")
    for i, omega in enumerate(w):
        print(f"{omega:5.2f} | {abs(head_c[i, 2]):.3f} {abs(head_j[i, 2]):.3f} | "
              f"{math.degrees(abs(head_c[i, 4])):.3f} {math.degrees(abs(head_j[i, 4])):.3f} | "
              f"{abs(beam_c[i, 2]):.3f} {abs(beam_j[i, 2]):.3f}")


def main() -> None:
    """Parse the arguments and run the steps."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--recompute", action="store_true", help="recompute the Capytaine dataset")
    parser.add_argument("--output", type=Path, default=Path("out/capytaine_barge"), help="output folder")
    args = parser.parse_args()
    args.output.mkdir(parents=True, exist_ok=True)
    if args.recompute:
        make_dataset()
    print(f"largest difference between the Capytaine and WAMIT doors: {doors(args.output):.3g}")
    study()


if __name__ == "__main__":
    main()
