"""Rigid links against ANCF on the tug-tow system (scenes ``tug_tow`` and ``tug_tow_ancf``).

Run from the repository root: ``python docs/studies/tug_tow/run.py`` (about 3 min on one
core). Runs the rigid-link model with 10, 20 and 40 links, then the ANCF cable with its
top end following the tug track of the 20-link run (written to a time-series CSV), and
writes ``tug_tow.png``, ``tug_tow_taut.png`` and ``results.json`` here.
"""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path

import numpy as np

from towcable_fmu.rigidlink.simulation import RigidLinkSimulation
from towcable_fmu.scene import load_scene
from towcable_fmu.ancf.simulation import Simulation

HERE = Path(__file__).parent
DURATION = 200.0  # [s]: slack start, thrust ramp (0-80 s), approach to the 4 m/s steady tow
INTERVAL = 0.05  # [s]
LINKS = (10, 20, 40)
FAIRLEAD = 3.0  # [m] height of the tug's fairlead above its 'ship' CG in tug_tow_ancf


def run_rigid_link(links: int) -> tuple[dict[str, np.ndarray], float]:
    """Series of ``tug_tow`` with ``links`` links and the wall time [s]."""
    sim = RigidLinkSimulation(load_scene("tug_tow", {"cable.links": links}))
    start = time.perf_counter()
    series = sim.run(DURATION, interval=INTERVAL)
    return series, time.perf_counter() - start


def run_ancf(tug: dict[str, np.ndarray], folder: Path) -> tuple[dict[str, np.ndarray], float]:
    """Series of ``tug_tow_ancf`` with the top end on the given tug track, and the wall time [s]."""
    track = folder / "tug_track.csv"
    zeros = np.zeros_like(tug["time"])
    np.savetxt(track, np.column_stack((tug["time"], tug["ship.x"], zeros, tug["ship.z"] - FAIRLEAD, zeros, zeros,
                                       zeros)), delimiter=",", header="t,x,y,z,roll,pitch,yaw", comments="")
    scene = load_scene("tug_tow_ancf", {"motion": {"type": "time_series", "file": str(track)}})
    sim = Simulation(scene)
    start = time.perf_counter()
    series = sim.run(DURATION, interval=INTERVAL)
    wall = time.perf_counter() - start
    # the top end is pinned on the tug's fairlead: the tug's own columns are the track's
    series["ship.x"] = np.interp(series["time"], tug["time"], tug["ship.x"])
    series["ship.z"] = np.interp(series["time"], tug["time"], tug["ship.z"])
    return series, wall


def _stats(series: dict[str, np.ndarray], length: float, wall: float) -> dict[str, float]:
    t = series["time"]
    steady = t >= DURATION - 20.0
    taut = (t >= 60.0)
    span = np.hypot(series["ship.x"] - series["towbody.x"], series["ship.z"] - series["towbody.z"])
    return {"wall_time_s": wall, "realtime_factor": DURATION / wall,
            "tension_top_max_N": float(series["tension.top"].max()),
            "tension_top_max_time_s": float(t[np.argmax(series["tension.top"])]),
            "tension_top_min_after_60s_N": float(series["tension.top"][taut].min()),
            "tension_top_mean_last20s_N": float(series["tension.top"][steady].mean()),
            "tension_top_std_last20s_N": float(series["tension.top"][steady].std()),
            "tension_top_min_N": float(series["tension.top"].min()),
            "span_over_length_max": float(span.max() / length),
            "barge_speed_end_m_s": float(series["towbody.vx"][-1]),
            "barge_heave_range_last20s_m": float(np.ptp(series["towbody.z"][steady]))}


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs, results = {}, {}
    for n in LINKS:
        series, wall = run_rigid_link(n)
        length = RigidLinkSimulation(load_scene("tug_tow", {"cable.links": n})).length
        runs[f"rigid links, n = {n}"] = series
        results[f"rigid_link_n{n}"] = _stats(series, length, wall)
        print(f"rigid link n = {n}: {wall:.1f} s wall", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        ancf, wall = run_ancf(runs["rigid links, n = 20"], Path(tmp))
    ancf_length = load_scene("tug_tow_ancf").cable.segments[0].length
    runs["ANCF, 20 elements"] = ancf
    results["ancf"] = _stats(ancf, ancf_length, wall)
    print(f"ANCF: {wall:.1f} s wall", flush=True)

    fig, axes = plt.subplots(4, 1, figsize=(9, 11), sharex=True)
    for label, s in runs.items():
        style = {"lw": 1.0} if "ANCF" in label else {"lw": 0.8, "alpha": 0.8}
        axes[0].plot(s["time"], s["tension.top"] / 1e3, label=label, **style)
        span = np.hypot(s["ship.x"] - s["towbody.x"], s["ship.z"] - s["towbody.z"])
        axes[1].plot(s["time"], span, label=label, **style)
        axes[2].plot(s["time"], s["towbody.vx"], label=label, **style)
        axes[3].plot(s["time"], s["towbody.z"], label=label, **style)
    axes[0].set_ylabel("tension at the tug [kN]")
    axes[0].set_yscale("symlog", linthresh=100.0)
    axes[1].axhline(ancf_length, color="k", lw=0.6, ls="--", label="cable length")
    axes[1].set_ylabel("span tug-barge [m]")
    axes[2].set_ylabel("barge speed [m/s]")
    axes[3].set_ylabel("barge fairlead z [m]")
    axes[3].set_xlabel("time [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("tug_tow: rigid links (Gomes & Gomes 2021) against the ANCF cable, same tug track")
    fig.tight_layout()
    fig.savefig(HERE / "tug_tow.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(9, 3.8))
    for label, s in runs.items():
        window = (s["time"] >= 150.0) & (s["time"] <= 200.0)
        ax.plot(s["time"][window], s["tension.top"][window] / 1e3, label=label, lw=0.9)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("tension at the tug [kN]")
    ax.set_title("taut tow at full thrust (150-200 s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(HERE / "tug_tow_taut.png", dpi=110)
    plt.close(fig)

    (HERE / "results.json").write_text(json.dumps(results, indent=2) + "\n", encoding="utf-8")
    print(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
