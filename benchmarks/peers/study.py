"""Convergence-study and reporting helpers shared by the peer scripts.

A *ladder* is a list of (n_segments, time_step_s) settings, coarse to fine. Every
setting is run for each frequency; the table shows Tmax/T0 and Tmin/T0 in the full
and the late window, the wall time per simulated second, the change from the previous
setting of the ladder and the error against the reference run (the last setting of
the first ladder, i.e. the finest mesh and step). The *converged* setting is the first
of the first ladder whose Tmax/T0 changed by less than 0.5 % from the setting before;
the *cheap* setting is the fastest run (any ladder, by CPU time) within 1 % of the
reference in Tmax/T0, *cheap_series* the fastest that is also within 1 % RMS in the
tension time series over SERIES_WINDOW. Wall and CPU time are both recorded: the machine (2 cores) may be shared
with other jobs, and CPU time of the (single-threaded) process is the steadier figure.
"""

from __future__ import annotations

import json
import math
import os
import sys
from importlib import metadata

import numpy as np

try:
    from . import snapping_case as case
except ImportError:
    import snapping_case as case  # type: ignore[no-redef]

CONVERGED_TOL = 0.005
CHEAP_TOL = 0.010
SERIES_WINDOW = (0.05, 5.0)
"""[s] window of the time-series error: RMS of (T - T_ref)/T0 on the reference's
samples (linear interpolation). Tmax/T0 alone converges very early on this case;
the series error also sees phase errors of the snaps. The first 50 ms are left out:
Exudyn's constraint force answers the abrupt start (velocity jump on an index-3
position constraint) with a step-to-step oscillation (up to ~0.4 T0 at h = 0.25 ms,
decaying by rho_inf = 0.8 per step) that is not a property of the cable dynamics and
grows as h shrinks; compare_peers.py reports it separately."""


def package_version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "not installed"


def _row(res: dict, ladder: str) -> dict:
    keep = ("peer", "frequency_hz", "n_segments", "time_step_s", "T0", "T0_hand",
            "Tmax_over_T0", "Tmin_over_T0", "Tmax_over_T0_late", "Tmin_over_T0_late",
            "wall_time_s", "sim_time_s")
    row = {k: res[k] for k in keep if k in res}
    for k in ("cpu_time_s", "scheme", "coupling_dt_s", "init_time_s", "newton_iterations", "jacobians",
              "spectral_radius", "cable_drag"):
        if k in res:
            row[k] = res[k]
    row["ladder"] = ladder
    row["wall_per_sim_s"] = res["wall_time_s"] / res["sim_time_s"]
    row["cpu_per_sim_s"] = res.get("cpu_time_s", float("nan")) / res["sim_time_s"]
    return row


HEADER = (f"{'ladder':<12}{'f[Hz]':>6}{'nseg':>5}{'dt[s]':>9}{'T0[N]':>9}"
          f"{'Tmax/T0':>9}{'Tmin/T0':>9}{'late max':>9}{'late min':>9}"
          f"{'wall/sim':>9}{'cpu/sim':>9}{'chg%':>7}{'err%':>7}")


def _fmt(row: dict) -> str:
    chg = row.get("change_pct")
    err = row.get("error_pct")
    return (f"{row['ladder']:<12}{row['frequency_hz']:>6.3f}{row['n_segments']:>5d}"
            f"{row['time_step_s']:>9.2e}{row['T0']:>9.4f}{row['Tmax_over_T0']:>9.4f}"
            f"{row['Tmin_over_T0']:>9.4f}{row['Tmax_over_T0_late']:>9.4f}"
            f"{row['Tmin_over_T0_late']:>9.4f}{row['wall_per_sim_s']:>9.4f}"
            f"{row['cpu_per_sim_s']:>9.4f}"
            f"{'' if chg is None else f'{chg:7.2f}':>7}{'' if err is None else f'{err:7.2f}':>7}")


ERR_HEADER = (f"{'ladder':<12}{'f[Hz]':>6}{'nseg':>5}{'dt[s]':>9}{'Tmax/T0':>9}{'err%':>7}"
              f"{'late%':>7}{'dTmin':>8}{'ser.rms%':>9}{'ser.max%':>9}{'cpu/sim':>9}")


def _fmt_err(r: dict) -> str:
    return (f"{r['ladder']:<12}{r['frequency_hz']:>6.3f}{r['n_segments']:>5d}"
            f"{r['time_step_s']:>9.2e}{r['Tmax_over_T0']:>9.4f}{r['error_pct']:>7.2f}"
            f"{r['error_late_pct']:>7.2f}{r['error_min_abs']:>8.4f}{r['series_rms_pct']:>9.3f}"
            f"{r['series_max_pct']:>9.3f}{r['cpu_per_sim_s']:>9.4f}")


def run_study(run_fn, frequencies, duration: float, ladders: dict, peer: str,
              run_kwargs: dict | None = None) -> dict:
    """Run all ladders for all frequencies; print and return the table + picks."""
    run_kwargs = run_kwargs or {}
    out = {"peer": peer, "duration_s": duration, "rows": [], "converged": {}, "cheap": {},
           "series": {}}
    names = list(ladders)
    for f in frequencies:
        print(f"\n=== {peer}: f = {f} Hz, {duration} s simulated "
              f"(load average before: {os.getloadavg()[0]:.2f}) ===")
        print(HEADER)
        rows_f = []
        series_f = []
        for name in names:
            prev = None
            for n, dt in ladders[name]:
                res = run_fn(f, duration, n, dt, **run_kwargs)
                row = _row(res, name)
                if prev is not None:
                    row["change_pct"] = 100.0 * (row["Tmax_over_T0"] / prev["Tmax_over_T0"] - 1.0)
                    row["change_late_pct"] = 100.0 * (row["Tmax_over_T0_late"]
                                                      / prev["Tmax_over_T0_late"] - 1.0)
                print(_fmt(row), flush=True)
                rows_f.append(row)
                series_f.append((res["time"], res["tension_top"]))
                prev = row
                out["series"][f"{f}_{n}_{dt:g}"] = (res["time"], res["tension_top"])
        i_ref = max(i for i, r in enumerate(rows_f) if r["ladder"] == names[0])
        ref = rows_f[i_ref]
        t_ref, T_ref = series_f[i_ref]
        m = (t_ref >= SERIES_WINDOW[0]) & (t_ref <= SERIES_WINDOW[1])
        for r, (t, T) in zip(rows_f, series_f):
            d = (np.interp(t_ref[m], t, T) - T_ref[m]) / ref["T0"]
            r["series_rms_pct"] = 100.0 * float(np.sqrt(np.mean(d * d)))
            r["series_max_pct"] = 100.0 * float(np.max(np.abs(d)))
            r["error_pct"] = 100.0 * (r["Tmax_over_T0"] / ref["Tmax_over_T0"] - 1.0)
            r["error_late_pct"] = 100.0 * (r["Tmax_over_T0_late"] / ref["Tmax_over_T0_late"] - 1.0)
            r["error_min_abs"] = r["Tmin_over_T0"] - ref["Tmin_over_T0"]
        first = [r for r in rows_f if r["ladder"] == names[0]]
        conv = next((r for r in first[1:] if abs(r["change_pct"]) < 100 * CONVERGED_TOL), None)
        ok = [r for r in rows_f if abs(r["error_pct"]) <= 100 * CHEAP_TOL]
        cheap = min(ok, key=lambda r: r["cpu_per_sim_s"]) if ok else None
        ok_s = [r for r in ok if r["series_rms_pct"] <= 100 * CHEAP_TOL]
        cheap_s = min(ok_s, key=lambda r: r["cpu_per_sim_s"]) if ok_s else None
        print("errors against the reference (last row of the first ladder); series error "
              f"= RMS and max of (T - T_ref)/T0 over {SERIES_WINDOW} s, in %:")
        print(ERR_HEADER)
        for r in rows_f:
            print(_fmt_err(r))
        if conv is not None:
            print(f"converged (<{100*CONVERGED_TOL:.1f} % change): nseg={conv['n_segments']} "
                  f"dt={conv['time_step_s']:.2e} s  Tmax/T0={conv['Tmax_over_T0']:.4f}  "
                  f"Tmin/T0={conv['Tmin_over_T0']:.4f}  wall/sim={conv['wall_per_sim_s']:.4f}  "
                  f"cpu/sim={conv['cpu_per_sim_s']:.4f}")
        else:
            print("NOT converged to 0.5 % within the ladder")
        if cheap is not None:
            print(f"cheapest within {100*CHEAP_TOL:.0f} %: nseg={cheap['n_segments']} "
                  f"dt={cheap['time_step_s']:.2e} s  Tmax/T0={cheap['Tmax_over_T0']:.4f} "
                  f"(err {cheap['error_pct']:+.2f} %)  wall/sim={cheap['wall_per_sim_s']:.4f}  "
                  f"cpu/sim={cheap['cpu_per_sim_s']:.4f}")
        if cheap_s is not None:
            print(f"cheapest within {100*CHEAP_TOL:.0f} % in Tmax/T0 AND series RMS: "
                  f"nseg={cheap_s['n_segments']} dt={cheap_s['time_step_s']:.2e} s  "
                  f"Tmax/T0={cheap_s['Tmax_over_T0']:.4f} (err {cheap_s['error_pct']:+.2f} %, "
                  f"series rms {cheap_s['series_rms_pct']:.2f} %)  "
                  f"wall/sim={cheap_s['wall_per_sim_s']:.4f}  cpu/sim={cheap_s['cpu_per_sim_s']:.4f}")
        out["rows"] += rows_f
        out.setdefault("cheap_series", {})[str(f)] = cheap_s
        out["converged"][str(f)] = conv
        out["cheap"][str(f)] = cheap
        out["reference"] = out.get("reference", {})
        out["reference"][str(f)] = ref
    return out


def sanity_checks(run_fn, results: dict, small_setting: tuple[int, float], peer: str,
                  run_kwargs: dict | None = None) -> None:
    """T0 against the hand value; forced tension amplitude against the closed form."""
    run_kwargs = run_kwargs or {}
    checks = {}
    T0h = case.static_top_tension()
    T0 = results["rows"][0]["T0"]
    checks["T0"] = {"peer": T0, "hand": T0h, "rel_diff": T0 / T0h - 1.0}
    print(f"\nsanity: T0 {peer} = {T0:.4f} N, hand = {T0h:.4f} N "
          f"(sphere {case.sphere_wet_weight():.4f} + cable "
          f"{case.cable_wet_weight_per_length()*case.CABLE_LENGTH:.4f}), "
          f"diff {100*(T0/T0h-1):+.4f} %")
    # small amplitude, low frequency: taut throughout
    n, dt = small_setting
    f, A, win = 0.5, 0.01, (2.0, 14.0)
    res = run_fn(f, 15.0, n, dt, amplitude_m=A, **run_kwargs)
    est = case.linear_estimates(f, A)
    amp = case.forced_amplitude(res["time"], res["tension_top"], f, win)
    checks["small_amplitude"] = {
        "frequency_hz": f, "amplitude_m": A, "setting": [n, dt],
        "forced_amplitude_fit_N": amp, "forced_amplitude_closed_form_N": est["forced_amplitude"],
        "quasistatic_N": est["forced_amplitude_quasistatic"],
        "Tmax_over_T0": res["Tmax_over_T0"], "Tmin_over_T0": res["Tmin_over_T0"],
        "Tmax_over_T0_quasistatic": est["Tmax_over_T0_quasistatic"],
        "start_transient_amplitude_N": est["start_transient_amplitude"],
    }
    print(f"sanity: A={A} m, f={f} Hz: forced tension amplitude (fit over {win} s) "
          f"{amp:.4f} N; closed form m_eff w^2 A/(1-r^2) = {est['forced_amplitude']:.4f} N "
          f"(quasi-static {est['forced_amplitude_quasistatic']:.4f} N)")
    print(f"        Tmax/T0 = {res['Tmax_over_T0']:.4f}, Tmin/T0 = {res['Tmin_over_T0']:.4f}; "
          f"1 + m_eff w^2 A/T0 = {est['Tmax_over_T0_quasistatic']:.4f}, plus the free "
          f"vibration of the abrupt start (k A r/(1-r^2) = "
          f"{est['start_transient_amplitude']:.3f} N = "
          f"{est['start_transient_amplitude']/T0h:.4f} T0)")
    # full amplitude at 0.807 Hz in the late window, if taut there
    conv = results["converged"].get(str(0.807)) or results["reference"].get(str(0.807))
    if conv is not None:
        key = [k for k in results["series"] if k.startswith("0.807_")]
        if key:
            t, T = results["series"][key[-1]]
            win = case.WINDOW_LATE
            amp = case.forced_amplitude(t, T, 0.807, win)
            est = case.linear_estimates(0.807)
            checks["f0.807_late"] = {"forced_amplitude_fit_N": amp,
                                    "forced_amplitude_closed_form_N": est["forced_amplitude"],
                                    "taut_in_window": bool(np.min(T[(t >= win[0])]) > 0)}
            print(f"sanity: A={case.AMPLITUDE} m, f=0.807 Hz, window {win} s: forced amplitude "
                  f"{amp:.3f} N vs closed form {est['forced_amplitude']:.3f} N "
                  f"(quasi-static {est['forced_amplitude_quasistatic']:.3f} N); "
                  f"taut in window: {checks['f0.807_late']['taut_in_window']}")
    results["sanity"] = checks


def save(results: dict, path: str) -> None:
    """Write the table (JSON) and the reference time series (npz, float32, keys
    t_<f>_<nseg>_<dt> and T_<f>_<nseg>_<dt>) next to it."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    series = results.pop("series", {})
    meta = {"python": sys.version.split()[0], "numpy": np.__version__,
            "moordyn": package_version("moordyn"), "exudyn": package_version("exudyn"),
            "cpu_count": os.cpu_count()}
    results["environment"] = meta

    def clean(o):
        if isinstance(o, dict):
            return {k: clean(v) for k, v in o.items()}
        if isinstance(o, (list, tuple)):
            return [clean(v) for v in o]
        if isinstance(o, (np.floating,)):
            return float(o)
        if isinstance(o, (np.integer,)):
            return int(o)
        if isinstance(o, (np.bool_,)):
            return bool(o)
        if isinstance(o, float) and not math.isfinite(o):
            return None
        return o

    with open(path, "w") as fh:
        json.dump(clean(results), fh, indent=1)
    arrays = {}
    wanted = set()
    for pick in ("reference",):  # the references only, to keep the files small
        for f, r in results.get(pick, {}).items():
            if r is not None:
                wanted.add(f"{f}_{r['n_segments']}_{r['time_step_s']:g}")
    for k, (t, T) in series.items():
        if k not in wanted:
            continue
        arrays[f"t_{k}"] = np.asarray(t, dtype=np.float32)
        arrays[f"T_{k}"] = np.asarray(T, dtype=np.float32)
    np.savez_compressed(os.path.splitext(path)[0] + "_series.npz", **arrays)
    results["series"] = series
    print(f"\nwrote {path}")
