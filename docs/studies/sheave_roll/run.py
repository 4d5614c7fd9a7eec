"""The roll at which full_scale's cable leaves the sheave's groove (README, contact stiffness).

Run from the repository root: ``python docs/studies/sheave_roll/run.py`` (about half a
minute). The ship is held at a steady roll, raised in steps of 1 deg to 60 deg and of
0.25 deg beyond, each static equilibrium solved from the last one (the ship rolling
slowly), for Table 9's contact stiffness k_N = 1e6 and for 1e8, until the cable is off
the sheave. Beside it the closed-form estimate: the roll at which the two tensions
press on the sheave sideways cot(theta_g/2) times as hard as radially (the V's holding
limit), with the upright departure angle and the drum-to-sheave tangent. Writes
``results.json`` here.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from towcable_fmu.numerics.kinematics import rotation_matrix
from towcable_fmu.ancf.simulation import Simulation

HERE = Path(__file__).parent
STIFFNESSES = (1e6, 1e8)  # [N/m^2.5]
ROLLS = np.concatenate([np.arange(0.0, 60.0, 1.0), np.arange(60.0, 89.0, 0.25)])  # [deg]


def ship_at(roll: float) -> np.ndarray:
    """Ship state (3, 6) at rest at a steady roll [deg]."""
    ship = np.zeros((3, 6))
    ship[0, 3] = math.radians(roll)
    return ship


def side_ratio(roll: float, departure: float, rise: float) -> float:
    """Sideways over radial force of the two tensions on a sheave rolled by ``roll`` [rad]:
    in from the drum in the sheave's plane rising by ``rise``, out at ``departure`` from
    the inertial vertical in the inertial x-z plane [rad]."""
    return math.cos(departure) * math.sin(roll) / math.hypot(
        math.sin(departure) - math.cos(rise), math.cos(departure) * math.cos(roll) + math.sin(rise))


def sweep(stiffness: float) -> dict:
    """Last seated roll, first roll off the sheave, and the closed-form estimate [deg]."""
    sim = Simulation.from_scene("full_scale", {"motion.type": "none", "compensation.algorithm": "none",
                                               "sheave.contact.stiffness": stiffness})
    out = sim.initialize()
    sc = sim.scene
    gap = np.subtract(sc.sheave.position, sc.winch.position)
    rise = math.atan2(gap[2], -gap[0]) - math.asin((sc.winch.radius - sc.sheave.radius) / math.hypot(gap[0], gap[2]))
    departure = out["sheave_angle"]
    cot = 1.0 / math.tan(math.radians(sc.sheave.throat_angle) / 2.0)
    estimate = math.degrees(brentq(lambda r: side_ratio(r, departure, rise) - cot, 0.1, 1.55))
    rows = []
    for roll in ROLLS:
        out = sim.initialize(ship=ship_at(roll), q0=sim.state.q.copy())
        if out["contact.detached"]:
            break
        rot = rotation_matrix(*sim.workspace.ship[0, 3:6])
        force = rot.T @ sim.contact_state()["force"][1]
        rows.append((float(roll), abs(force[1]) / math.hypot(force[0], force[2])))
    return {"stiffness": stiffness, "seated_up_to_deg": rows[-1][0], "off_at_deg": float(roll),
            "side_ratio_at_last_seated": rows[-1][1], "closed_form_deg": estimate,
            "upright_departure_deg": math.degrees(departure), "rise_deg": math.degrees(rise),
            "cot_half_throat": cot, "ratios": rows}


def main() -> None:
    results = [sweep(k) for k in STIFFNESSES]
    (HERE / "results.json").write_text(json.dumps(results, indent=1) + "\n")
    for r in results:
        print(f"k_N = {r['stiffness']:.0e}: seated up to {r['seated_up_to_deg']:.2f} deg, off at "
              f"{r['off_at_deg']:.2f} deg (sideways/radial {r['side_ratio_at_last_seated']:.3f}); closed form "
              f"{r['closed_form_deg']:.1f} deg (departure {r['upright_departure_deg']:.2f} deg)")


if __name__ == "__main__":
    main()
