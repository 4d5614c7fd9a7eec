"""Sea-trial turn of the nodal-position paper (scene ``sea_trial_turn``): tracks, depth, tension.

Run from the repository root: ``python docs/studies/sea_trial_turn/run.py`` (about 20 s
after the kernels are compiled). Writes ``sea_trial_turn.png`` and ``summary.md`` here.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
DURATION = 1400.0  # [s] acceleration (0-120 s), steady tow, the 270 deg turn (400-1095 s), steady again


def _circle_radius(x: np.ndarray, y: np.ndarray) -> float:
    """Radius [m] of the least-squares circle through the points (x, y) (algebraic fit)."""
    a = np.column_stack([x, y, np.ones_like(x)])
    cx2, cy2, c = np.linalg.lstsq(a, x * x + y * y, rcond=None)[0]
    return float(np.sqrt(c + (cx2 / 2.0) ** 2 + (cy2 / 2.0) ** 2))


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene("sea_trial_turn")
    sim.initialize()
    start = time.perf_counter()
    res = sim.run(DURATION, interval=1.0)
    wall = time.perf_counter() - start
    ship = sim.motion.evaluate_many(res["time"])
    top = np.array(sim.scene.cable.top.position)
    # the tow point: the ship-frame attachment carried by the ship's heading
    yaw = ship[:, 0, 5]
    tow_x = ship[:, 0, 0] + np.cos(yaw) * top[0] - np.sin(yaw) * top[1]
    tow_y = ship[:, 0, 1] + np.sin(yaw) * top[0] + np.cos(yaw) * top[1]

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    ax = axes[0]
    ax.plot(tow_x, tow_y, lw=2.5, label="ship (tow point)")
    ax.plot(res["towbody.x"], res["towbody.y"], lw=1.0, label="towed body")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("horizontal tracks (270 deg turn to port)")
    ax.legend()
    axes[1].plot(res["time"], res["towbody.z"])
    axes[1].set_xlabel("time [s]")
    axes[1].set_ylabel("towed-body depth z [m]")
    axes[1].set_title("depth of the towed body")
    axes[2].plot(res["time"], res["tension.top"] / 1e3)
    axes[2].set_xlabel("time [s]")
    axes[2].set_ylabel("tension at the tow point [kN]")
    axes[2].set_title("tension at the tow point")
    for a in axes[1:]:
        a.axvspan(400.0, 1095.0, color="grey", alpha=0.15, label="turning")
        a.grid(alpha=0.3)
    for a in axes[:1]:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(HERE / "sea_trial_turn.png", dpi=110)

    steady = (res["time"] > 300.0) & (res["time"] < 400.0)
    turning = (res["time"] > 500.0) & (res["time"] < 1095.0)
    radius_ship = _circle_radius(tow_x[turning], tow_y[turning])
    radius_body = _circle_radius(res["towbody.x"][turning], res["towbody.y"][turning])
    lines = ["# Sea-trial turn (scene `sea_trial_turn`)\n\n",
             f"Simulated {DURATION:g} s in {wall:.1f} s wall ({DURATION / wall:.0f} x real time), "
             f"{sim.statistics()['solver.steps']} steps.\n\n",
             "| quantity | steady tow (300-400 s) | during the turn (500-1095 s) |\n|---|---|---|\n",
             f"| towed-body depth [m] | {res['towbody.z'][steady].mean():.1f} | "
             f"{res['towbody.z'][turning].min():.1f} .. {res['towbody.z'][turning].max():.1f} |\n",
             f"| tension at the tow point [kN] | {res['tension.top'][steady].mean() / 1e3:.1f} | "
             f"{res['tension.top'][turning].min() / 1e3:.1f} .. {res['tension.top'][turning].max() / 1e3:.1f} |\n",
             f"\nRadius of the tracks during the turn (least-squares circle): tow point {radius_ship:.0f} m "
             f"(the ship's turning circle U / r = {6.17 / np.radians(0.4):.0f} m), towed body {radius_body:.0f} m.\n"]
    (HERE / "summary.md").write_text("".join(lines), encoding="utf-8")
    print("".join(lines))


if __name__ == "__main__":
    main()
