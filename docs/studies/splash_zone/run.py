"""Recovery through the splash zone with and without wave kinematics (issue 42 item 5).

The built-in scene ``full_scale_recovery_waves`` (``full_scale_recovery`` with
``[water] waves = "motion"``) and the same scene in still water (``water.waves = "off"``:
the ship moves in the same sea, the water around the cable and the body is still), for
the seeds :data:`SEEDS` of the sea. Per run, 110 s sampled every 0.05 s:

* the cable force on the body (``tension.towbody``) and at the spool (``tension.top``):
  mean, standard deviation, largest and smallest;
* slack events: the cable force on the body falling below :data:`SLACK_SHARE` of the
  body's submerged weight (down-crossings);
* the body's vertical fluid force ``F_z`` (buoyancy, drag, Froude-Krylov and added-mass
  inertia, :func:`towcable_fmu.hydro.towbody.body_force` at the integrator's state) and its
  dynamic part ``F_z - rho g V s_0`` (``s_0``: the submerged fraction below the mean level,
  the still-water buoyancy where the body is), over the splash-zone passage (from the
  first time the body's centre rises above ``z = -H_s`` to its last time in the water);
* the hand estimate of the simplified method of DNV-RP-H103 section 4.3 for the same
  body and sea (:func:`simplified_method`), an order-of-magnitude check.

Writes ``results.json``, the table ``results.md`` and the plots ``recovery.png`` next to
this file. Run: ``nice -n 5 python docs/studies/splash_zone/run.py`` (about 2 min CPU).
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from towcable_fmu.hydro.towbody import body_force
from towcable_fmu.hydro.waves import sea_of, surface_height
from towcable_fmu.models import simulation_for
from towcable_fmu.scene import load_scene

HERE = Path(__file__).resolve().parent
SCENE = "full_scale_recovery_waves"
SEEDS = (22, 1, 2, 3, 4)
DURATION, INTERVAL = 110.0, 0.05
#: a slack event: the cable force on the body below this share of its submerged weight
SLACK_SHARE = 0.1
#: the sheave in the ship frame [m] (the scene's [sheave] position: the crane tip)
SHEAVE = (-36.8, 0.0, 3.7)


def run_case(seed: int, waves: str) -> dict[str, np.ndarray]:
    """One recovery: the outputs, the body's vertical fluid force and the surface above it.

    The force is :func:`~towcable_fmu.hydro.towbody.body_force`, the model's own, at the
    recorded position and velocity, with the acceleration from central differences of the
    recorded velocity (it enters only the added-mass term)."""
    scene = load_scene(SCENE, {"motion.seed": seed, "water.waves": waves})
    sim = simulation_for(scene)
    series = sim.run(DURATION, interval=INTERVAL)
    body, water = sim.model.terms.towbody, sim.model.water
    t = series["time"]
    r = np.column_stack([series[f"towbody.{c}"] for c in "xyz"])
    v = np.column_stack([series[f"towbody.v{c}"] for c in "xyz"])
    a = np.gradient(v, t, axis=0)
    rec = {name: series[name] for name in ("time", "tension.towbody", "tension.top", "towbody.z", "towbody.vz")}
    rec.update(fz=np.empty(t.size), fz_still=np.empty(t.size), surface=np.empty(t.size))
    force = np.empty(3)
    for k in range(t.size):
        body_force(water, body, r[k], v[k], a[k], float(t[k]), force)
        rec["fz"][k] = force[2]
        s0 = min(max((water.surface_z - r[k, 2]) / body.height + 0.5, 0.0), 1.0)
        rec["fz_still"][k] = water.density * water.gravity * body.volume * s0
        rec["surface"][k] = surface_height(water, r[k, 0], r[k, 1], float(t[k]))[0]
    return rec


def down_crossings(x: np.ndarray, level: float) -> int:
    """Number of times ``x`` falls below ``level``."""
    below = x < level
    return int(np.count_nonzero(below[1:] & ~below[:-1]) + (1 if below[0] else 0))


def case_statistics(rec: dict[str, np.ndarray], hs: float, height: float, submerged_weight: float) -> dict:
    """The table's statistics of one run."""
    z, t = rec["towbody.z"], rec["time"]
    wet = (rec["surface"] - z) / height + 0.5 > 0.0
    start = int(np.argmax(z > -hs)) if np.any(z > -hs) else z.size - 1
    last_wet = max(int(np.flatnonzero(wet)[-1]), start)
    zone = slice(start, last_wet + 1)
    body, top = rec["tension.towbody"], rec["tension.top"]
    dyn = rec["fz"] - rec["fz_still"]
    k_dyn = start + int(np.argmax(np.abs(dyn[zone])))
    return {"lifted_out": bool(not wet[-1]), "zone_crest": float(rec["surface"][zone].max()),
            "body_mean": float(body.mean()), "body_std": float(body.std()), "body_max": float(body.max()),
            "body_min": float(body.min()), "top_max": float(top.max()), "top_std": float(top.std()),
            "slack_events": down_crossings(body, SLACK_SHARE * submerged_weight),
            "zone_start": float(t[start]), "zone_end": float(t[last_wet]),
            "zone_body_max": float(body[zone].max()), "zone_body_min": float(body[zone].min()),
            "zone_fz_max": float(rec["fz"][zone].max()), "zone_fz_min": float(rec["fz"][zone].min()),
            "zone_dyn_peak": float(dyn[k_dyn]), "zone_dyn_peak_time": float(t[k_dyn]),
            "zone_dyn_std": float(dyn[zone].std())}


def simplified_method(scene, sheave_velocity_amplitude: float, hoist_speed: float,
                      amplitude: float | None = None) -> dict[str, float]:
    """DNV-RP-H103 section 4.3 (simplified method) for the body and the scene's sea, vertical.

    Kinematics of the characteristic wave (amplitude ``2 H_s``, period ``T_z``) at the
    depth ``d`` of the centroid of the submerged part (half the body at the surface); the
    relative velocity ``v_r = v_c + sqrt(v_ct^2 + v_w^2)`` (hoisting speed and the crane tip's
    vertical velocity amplitude); the forces
    drag ``F_D = 1/2 rho C_D A_p v_r^2``, slamming ``F_slam = 1/2 rho C_s A_s v_r^2`` (C_s = 5),
    mass ``F_M = sqrt(((rho V + A33) a_w)^2 + ((M + A33) a_ct)^2)``, varying buoyancy
    ``F_rho = rho g dV`` (dV: half the volume, the body half-way through the surface, the
    crest engulfing and the trough baring it) and the characteristic hydrodynamic force
    ``F_hyd = sqrt((F_D + F_slam)^2 + (F_M - F_rho)^2)``; ``F_hyd_no_slam`` leaves the
    slamming out (the model has none). ``amplitude``: the wave amplitude [m] instead of
    ``2 H_s``.
    """
    sea = sea_of(scene)
    hs, tp, gamma = (float(scene.motion.get(k, d)) for k, d in (("hs", 3.25), ("tp", 9.7), ("gamma", 3.3)))
    tz = tp * (0.6673 + 0.05037 * gamma - 0.006230 * gamma ** 2 + 0.0003341 * gamma ** 3)  # JONSWAP Tz/Tp
    rho, g = scene.water.density, scene.environment.gravity
    body = scene.towbody
    volume = scene.towbody_volume()
    a33 = rho * volume * body.added_mass_coefficient[2]
    cda = sum(p.area[2] * p.drag_coefficient[2] for p in body.parts)
    area = sum(p.area[2] for p in body.parts)
    d = 0.25 * body.height
    zeta = 2.0 * hs if amplitude is None else amplitude
    omega = 2.0 * math.pi / tz
    decay = math.exp(-omega ** 2 * d / g)
    v_w, a_w = zeta * omega * decay, zeta * omega ** 2 * decay
    v_ct = sheave_velocity_amplitude
    a_ct = v_ct * omega
    v_r = hoist_speed + math.hypot(v_ct, v_w)
    f_d = 0.5 * rho * cda * v_r ** 2
    f_slam = 0.5 * rho * 5.0 * area * v_r ** 2
    f_m = math.hypot((rho * volume + a33) * a_w, (body.mass + a33) * a_ct)
    f_rho = rho * g * 0.5 * volume
    f_hyd = math.hypot(f_d + f_slam, f_m - f_rho)
    f_no_slam = math.hypot(f_d, f_m - f_rho)
    return {"F_hyd_no_slam": f_no_slam, "hs": hs, "tz": tz, "zeta_a": zeta, "d": d, "v_w": v_w, "a_w": a_w,
            "v_ct": v_ct, "a_ct": a_ct,
            "v_c": hoist_speed, "v_r": v_r, "volume": volume, "a33": a33, "cda": cda, "slam_area": area,
            "F_D": f_d, "F_slam": f_slam, "F_M": f_m, "F_rho": f_rho, "F_hyd": f_hyd,
            "F_static_min": body.net_weight, "components": int(sea.waves.omega.size)}


def sheave_vertical_velocity(scene, seed: int) -> np.ndarray:
    """Vertical velocity [m/s] of the sheave (the crane tip) over the run, small-angle rigid body."""
    motion = sea_of(load_scene(SCENE, {"motion.seed": seed}))
    state = motion.evaluate_many(np.arange(0.0, DURATION, INTERVAL))  # (n, 3, 6)
    x, y, _ = SHEAVE
    return state[:, 1, 2] + y * state[:, 1, 3] - x * state[:, 1, 4]


def table(stats: dict, hand: dict) -> str:
    """The Markdown table of the results."""
    rows = ["| seed | waves | lifted out | body force mean [N] | std [N] | max [N] | min [N] | slack events "
            "| spool max [N] "
            "| splash zone [s] | zone body max [N] | zone body min [N] | F_z max [N] | F_z min [N] "
            "| dynamic F_z peak [N] (t [s]) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for key, s in stats.items():
        seed, waves = key.split("/")
        rows.append(f"| {seed} | {waves} | {'yes' if s['lifted_out'] else 'NO'} | {s['body_mean']:.0f} | "
                    f"{s['body_std']:.0f} | {s['body_max']:.0f} | "
                    f"{s['body_min']:.0f} | {s['slack_events']} | {s['top_max']:.0f} | "
                    f"{s['zone_start']:.1f}-{s['zone_end']:.1f} | {s['zone_body_max']:.0f} | "
                    f"{s['zone_body_min']:.0f} | {s['zone_fz_max']:.0f} | {s['zone_fz_min']:.0f} | "
                    f"{s['zone_dyn_peak']:.0f} ({s['zone_dyn_peak_time']:.1f}) |")
    summary = ["", "| over the seeds | waves off | waves on |", "|---|---|---|"]
    for label, key, fn in (("body force std [N], mean", "body_std", np.mean),
                           ("body force max [N], largest", "body_max", np.max),
                           ("body force min [N], smallest", "body_min", np.min),
                           ("slack events, total", "slack_events", np.sum),
                           ("spool tension max [N], largest", "top_max", np.max),
                           ("|dynamic F_z| peak in the splash zone [N], largest", "zone_dyn_peak",
                            lambda v: np.max(np.abs(v)))):
        cells = [fn([s[key] for k, s in stats.items() if k.endswith("/" + w)]) for w in ("off", "motion")]
        summary.append(f"| {label} | {cells[0]:.0f} | {cells[1]:.0f} |")
    standard, realised = hand
    hand_rows = ["", "| DNV-RP-H103 4.3, simplified method | zeta_a = 2 H_s | zeta_a = the largest crest above the "
                 "body in the runs |", "|---|---|---|"]
    for key, unit in (("hs", "m"), ("tz", "s"), ("zeta_a", "m"), ("d", "m"), ("v_w", "m/s"), ("a_w", "m/s^2"),
                      ("v_ct", "m/s"), ("a_ct", "m/s^2"), ("v_c", "m/s"), ("v_r", "m/s"), ("volume", "m^3"),
                      ("a33", "kg"), ("cda", "m^2"), ("slam_area", "m^2"), ("F_D", "N"), ("F_slam", "N"),
                      ("F_M", "N"), ("F_rho", "N"), ("F_hyd", "N"), ("F_hyd_no_slam", "N"), ("F_static_min", "N")):
        hand_rows.append(f"| {key} [{unit}] | {standard[key]:.3g} | {realised[key]:.3g} |")
    return "\n".join(rows + summary + hand_rows) + "\n"


def plot(records: dict, seed: int, path: Path) -> None:
    """Body force, dynamic vertical fluid force and heights over the run of one seed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
    for waves, style in (("off", "C0"), ("motion", "C3")):
        rec = records[f"{seed}/{waves}"]
        label = "waves on" if waves == "motion" else "still water"
        axes[0].plot(rec["time"], rec["tension.towbody"], style, lw=0.8, label=label)
        axes[1].plot(rec["time"], rec["fz"] - rec["fz_still"], style, lw=0.8, label=label)
        axes[2].plot(rec["time"], rec["towbody.z"], style, lw=0.8, label=f"body centre, {label}")
    rec = records[f"{seed}/motion"]
    axes[2].plot(rec["time"], rec["surface"], "k", lw=0.6, label="surface above the body (waves on)")
    axes[0].set_ylabel("cable force on body [N]")
    axes[1].set_ylabel("dynamic vertical\nfluid force [N]")
    axes[2].set_ylabel("height [m]")
    axes[2].set_xlabel("time [s]")
    axes[2].set_ylim(-8, 4)
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    fig.suptitle(f"full_scale_recovery, seed {seed}: with and without wave kinematics")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> int:
    start = time.process_time()
    scene = load_scene(SCENE)
    records, stats = {}, {}
    hs = float(scene.motion.get("hs", 3.25))
    submerged_weight = scene.towbody.net_weight
    v_ct = []
    for seed in SEEDS:
        v = sheave_vertical_velocity(scene, seed)
        v_ct.append(2.0 * float(v[int(round(20.0 / INTERVAL)):].std()))  # significant amplitude after the ramp
        for waves in ("off", "motion"):
            key = f"{seed}/{waves}"
            records[key] = run_case(seed, waves)
            stats[key] = case_statistics(records[key], hs, scene.towbody.height, submerged_weight)
            print(f"{key}: {stats[key]}", file=sys.stderr)
    crest = max(st["zone_crest"] for key, st in stats.items() if key.endswith("/motion"))
    hand = (simplified_method(scene, float(np.mean(v_ct)), hoist_speed=0.5),
            simplified_method(scene, float(np.mean(v_ct)), hoist_speed=0.5, amplitude=crest))
    hand_json = dict(zip(("2 Hs", "largest crest"), hand))
    (HERE / "results.json").write_text(json.dumps({"cases": stats, "simplified_method": hand_json,
                                                   "cpu_seconds": time.process_time() - start}, indent=1))
    (HERE / "results.md").write_text(table(stats, hand))
    plot(records, SEEDS[0], HERE / "recovery.png")
    print(f"CPU {time.process_time() - start:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
