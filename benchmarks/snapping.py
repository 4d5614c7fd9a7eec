"""Snapping cable: each code's work-precision front over its own choices, ours and the peers'.

The case (``benchmarks/peers/snapping_case.py``; our scenes ``snapping_cable`` and
``snapping_cable_nodal``): a submerged steel cable with a 12.2 kg sphere, top moved
abruptly, z = z0 + 0.05 sin(2 pi f t), at 1.27 Hz (the cable goes slack and snaps taut)
and 0.807 Hz; 15 s. Outputs: T0 and Tmax/T0 of the top tension over the run, and the RMS
of (T - T_ref)/T0 over 0.05-5 s (the snaps' phase).

Each code is swept over its own choices:

* MoorDyn 2.7: every working time scheme (Euler, LEuler, Heun, RK2, RK4, the implicit
  BEuler, Midpoint, ACA (Newmark average acceleration) and Wilson with 1-2 iterations),
  2-40 segments, steps from 4 l/c down (l/c: the time an axial wave takes over a
  segment), stopping at the first step within 1 %; Adams-Bashforth (AB2-4; LAB2-4 are the
  same schemes in 2.7) is defective (``moordyn_ab_defect``) and shown by one run;
* Exudyn: elements and steps (its generalised-alpha);
* ours: every model kind and integrator (ANCF generalised-alpha; nodal-position
  generalised-alpha, RK4 and, where the scene schema offers it, the explicit "leapfrog"),
  elements and steps (the leapfrog: 2-40 elements at 1, 0.7 and 0.5 times the largest
  step it allows on the mesh).

A run is *within 1 %* when its series error and its Tmax/T0 error are both at most 1 %,
against the code's own converged run (its finest setting) and against the common
reference, MoorDyn's converged run (80 segments, RK4, 0.02 ms). Every run is timed once
(the time stepping only; statics excluded); the runs on each code's front (no faster run
with a smaller error against the common reference) are timed twice more and carry the
median of 3.

Run: ``python benchmarks/snapping.py`` (about 45 minutes on a shared 2-core machine, 20 once
the peers' runs are cached, ``--peers-only`` fills the cache; ``--quick``: one frequency,
fewer settings, a few minutes). The peers need ``pip install ".[bench]"``: without them
only our sweep runs. Writes ``results/snapping.md`` and ``results/snapping_work_precision.png``.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import os
import statistics
import sys
import time
from importlib import metadata
from pathlib import Path

import numpy as np

from common import RESULTS, machine_header, markdown_table

sys.path.insert(0, str(Path(__file__).parent / "peers"))
import snapping_case as case  # noqa: E402

DURATION = case.DURATION
FREQUENCIES = (1.27, 0.807)
SERIES_WINDOW = (0.05, 5.0)
#: within this of a reference in series error and in Tmax/T0 [-]
TOLERANCE = 0.01
#: timing repeats of the runs on the fronts (medians)
REPEATS = 3
#: axial wave time over the whole cable, L / c [s]
WAVE_TIME = case.CABLE_LENGTH / math.sqrt(case.CABLE_EA / case.CABLE_MASS_PER_LENGTH)

#: the common reference and MoorDyn's own converged run: (scheme, segments, step [s])
MOORDYN_REFERENCE = ("RK4", 80, 2e-5)
#: MoorDyn's schemes swept and their segment counts; steps are multiples of l/c
MOORDYN_SCHEMES = {"RK4": (2, 3, 5, 10, 20, 40), "ACA1": (2, 3, 5, 10, 20, 40), "RK2": (2, 5, 10, 20),
                   "Heun": (2, 5, 10, 20), "ACA2": (2, 5, 10, 20), "Midpoint1": (2, 5, 10),
                   "Midpoint2": (2, 5, 10), "Wilson2": (2, 5, 10), "BEuler2": (2, 5, 10),
                   "Euler": (2, 5, 10), "LEuler": (2, 5, 10)}
#: step ladder in units of the segment's wave time l/c, largest first
WAVE_FACTORS = (4.0, 2.8, 2.0, 1.4, 1.0, 0.7, 0.5, 0.35, 0.25, 0.18, 0.12)
#: no MoorDyn run with more node-steps than this (segments+1 times steps; the reference excluded)
MOORDYN_MAX_WORK = 3.2e7
#: Exudyn: (elements, steps [s], largest first); its converged run is the last
EXUDYN_ELEMENTS = (2, 5, 10)
EXUDYN_STEPS = (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4)
EXUDYN_REFERENCE = (40, 2.5e-4)
#: ours: model kind -> (scene, integrator, elements, steps [s] largest first, integration points)
OUR_STEPS = (4e-3, 2e-3, 1e-3, 7e-4, 5e-4, 3.5e-4, 2.5e-4)
OURS = {
    "ANCF genalpha": ("snapping_cable", "genalpha", (5, 8, 12, 16, 20), OUR_STEPS, 2),
    "nodal genalpha": ("snapping_cable_nodal", "genalpha", (5, 10, 20), OUR_STEPS, 2),
    "nodal rk4": ("snapping_cable_nodal", "rk4", (2, 5, 10), (2e-3, 1e-3, 5e-4, 3.5e-4), 2),
    "nodal leapfrog": ("snapping_cable_nodal", "leapfrog", (2, 3, 4, 5, 6, 8, 10, 12, 14, 16, 20, 24, 30, 40), None, 2),
}
#: the explicit kind's steps (``None`` above): these fractions of the mesh's largest allowed step
#: (``Scene.explicit_step``: 0.9 times the stability limit)
EXPLICIT_FRACTIONS = (1.0, 0.7, 0.5)
#: each of our kinds' own converged run: (kind, elements, step [s], integration points); the
#: nodal RK4 shares the nodal generalised-alpha's (the same model; RK4 at 40 elements would
#: need hours)
OUR_REFERENCES = {"ANCF genalpha": ("ANCF genalpha", 40, 2.5e-4, 4),
                  "nodal genalpha": ("nodal genalpha", 40, 1.25e-4, 2),
                  "nodal rk4": ("nodal genalpha", 40, 1.25e-4, 2),
                  "nodal leapfrog": ("nodal leapfrog", 80, 1e-5, 2)}
#: the fronts' runs are re-timed up to this error against the common reference [-]
RETIME_BELOW = 0.02
DESCRIPTION = """
The case: `benchmarks/peers/snapping_case.py`; our scenes `snapping_cable` (ANCF) and
`snapping_cable_nodal`, both on the case's laws (Kelvin-Voigt axial force, MoorDyn's drag
convention). 15 s simulated; wall time of the time stepping (statics excluded), one process
at a time. Samples of every code every k-th step, k = max(1, round(0.5 ms / step)) (the
rule of MoorDyn's harness, `snapping_case.sample_interval`: a step above 0.5 ms is sampled
at every step). Errors: *series* = RMS of (T - T_ref)/T0 over 0.05-5 s, *Tmax* = |Tmax/T0 / ref - 1|,
against the code's own converged run (*own*) and against MoorDyn's converged run (80
segments, RK4, 0.02 ms; *common*). A run is within 1 % when both errors are. Sweeps: MoorDyn
over every working 2.7 scheme, 2-40 segments and steps from 4 l/c down to the first within
1 % (l/c the axial wave's time over a segment; an unstable step fails and is counted);
Exudyn (generalised-alpha) over elements and steps; ours over every model kind and
integrator the scene schema offers, elements and steps. Each code's front: its runs with no
faster run of a smaller error (max of series and Tmax) against the common reference; the
fronts' runs below 2 % and each code's fastest within 1 % are timed three times (median). The
peers' runs may come from a cache of earlier sessions (their series do not change): a cached
run's timing is never shown in the tables (those runs are timed again in this session), only
as a faint point of the plot.
""".replace("\n", " ").strip()

#: the peers' runs (their series do not change between sessions) are kept here, keyed by the peer's
#: version and the setting; a cached run's timing is never reported: the runs whose speed the
#: report shows (the fronts, each code's fastest within 1 %) are timed again in the session
PEER_CACHE = Path(os.environ.get("TOWCABLE_BENCH_CACHE", Path.home() / ".cache" / "towcable_bench")) / "snapping"

#: the former benchmark's matched MoorDyn set-up, kept for benchmarks/bounds.py
MATCHED = (20, 0.0002)


# --------------------------------------------------------------------------- single runs
def integrators_available() -> tuple[str, ...]:
    """The integrators our scene schema accepts."""
    import dataclasses

    from towcable_fmu.scene.model import SolverSettings

    field = next(f for f in dataclasses.fields(SolverSettings) if f.name == "integrator")
    return tuple(field.metadata["spec"].choices)


def ours_run(frequency: float, scene: str, integrator: str, elements: int, time_step: float, points: int,
             overrides: dict | None = None) -> dict:
    """One run of our solver on the case: the top tension series, T0 of the still scene and
    the wall time of the time stepping [s] (statics excluded). A run that fails is
    returned with ``failed`` set and infinite errors."""
    from towcable_fmu.models import simulation_for
    from towcable_fmu.scene import load_scene

    common = {"cable.segments[0].elements": elements, "cable.segments[0].integration_points": points,
              "solver.time_step": time_step, "solver.integrator": integrator, **(overrides or {})}
    still = simulation_for(load_scene(scene, {"motion": {"type": "none"}, **common}))
    still.initialize()
    t0 = still.outputs()["tension.top"]  # the static tension, before the abrupt start
    res = {"code": "towcable", "frequency_hz": frequency, "setting": (integrator, elements, time_step, points),
           "T0": t0, "scene": scene, "overrides": overrides or {}}
    try:
        sim = simulation_for(load_scene(scene, {"motion.heave.period": 1.0 / frequency, **common}))
        sim.initialize()
        start = time.perf_counter()
        series = sim.run(DURATION, interval=case.sample_interval(time_step)[1])  # as MoorDyn's harness samples
        wall = time.perf_counter() - start
    except Exception as exc:  # noqa: BLE001 - a failed setting is a result of the sweep
        return {**res, "failed": f"{type(exc).__name__}: {exc}", "wall_time_s": math.nan}
    tension = np.asarray(series["tension.top"])
    if not np.all(np.isfinite(tension)):
        return {**res, "failed": "non-finite tension", "wall_time_s": wall}
    return {**res, "time": np.asarray(series["time"]), "tension_top": tension, "wall_time_s": wall,
            "Tmax_over_T0": float(tension.max() / t0)}


def cached_peer(code: str, frequency: float, setting: tuple, run) -> dict:
    """``run()`` (a peer's run: its result dict), or its result kept in PEER_CACHE from an
    earlier session (marked ``cached``: its wall time is not this session's)."""
    version = metadata.version("moordyn" if code == "MoorDyn" else "exudyn")
    key = hashlib.sha256(repr((code, version, frequency, setting, DURATION)).encode()).hexdigest()[:24]
    path = PEER_CACHE / f"{key}.npz"
    if path.exists():
        with np.load(path, allow_pickle=False) as data:
            res = {k: data[k].item() if data[k].ndim == 0 else data[k] for k in data.files}
        res.update({"code": code, "frequency_hz": frequency, "setting": setting, "cached": True})
        return res
    res = run()
    PEER_CACHE.mkdir(parents=True, exist_ok=True)
    np.savez(path, **{k: v for k, v in res.items() if k not in ("code", "frequency_hz", "setting")})
    return res


def moordyn_run(frequency: float, scheme: str, segments: int, time_step: float, **keywords) -> dict:
    """One MoorDyn run (``peers/moordyn_snapping.run``); a failure or a non-finite series is
    returned with ``failed`` set."""
    from moordyn_snapping import run, silenced

    res = {"code": "MoorDyn", "frequency_hz": frequency, "setting": (scheme, segments, time_step)}
    try:
        with silenced(2):  # a diverging run prints every node
            out = run(frequency, DURATION, segments, time_step, scheme=scheme, **keywords)
    except Exception as exc:  # noqa: BLE001 - MoorDyn raises on diverging states
        return {**res, "failed": f"{type(exc).__name__}: {exc}", "wall_time_s": math.nan, "T0": math.nan}
    res.update({k: out[k] for k in ("T0", "Tmax_over_T0", "time", "tension_top", "wall_time_s")})
    if not (np.all(np.isfinite(out["tension_top"])) and np.isfinite(out["T0"])):
        res["failed"] = "non-finite tension"
    return res


def exudyn_run(frequency: float, elements: int, time_step: float) -> dict:
    """One Exudyn run (``peers/exudyn_snapping.run``)."""
    from exudyn_snapping import run

    res = {"code": "Exudyn", "frequency_hz": frequency, "setting": ("genalpha", elements, time_step)}
    try:
        out = run(frequency, DURATION, elements, time_step)
    except Exception as exc:  # noqa: BLE001 - a failed setting is a result of the sweep
        return {**res, "failed": f"{type(exc).__name__}: {exc}", "wall_time_s": math.nan, "T0": math.nan}
    res.update({k: out[k] for k in ("T0", "Tmax_over_T0", "time", "tension_top", "wall_time_s")})
    return res


def series_error(res: dict, ref: dict) -> float:
    """RMS of (T - T_ref)/T0_ref over SERIES_WINDOW, on the reference's samples [-]."""
    if res.get("failed"):
        return math.inf
    t_ref = np.asarray(ref["time"])
    mask = (t_ref >= SERIES_WINDOW[0]) & (t_ref <= SERIES_WINDOW[1])
    interp = np.interp(t_ref[mask], res["time"], res["tension_top"])
    return float(np.sqrt(np.mean((interp - np.asarray(ref["tension_top"])[mask]) ** 2)) / ref["T0"])


def errors(res: dict, ref: dict) -> tuple[float, float]:
    """(series error, |Tmax/T0 error|) of a run against a reference [-]."""
    if res.get("failed"):
        return math.inf, math.inf
    return series_error(res, ref), abs(res["Tmax_over_T0"] / ref["Tmax_over_T0"] - 1.0)


def within(res: dict, key: str) -> bool:
    """Both errors against the reference ``key`` ('own' or 'common') within TOLERANCE."""
    return max(res[f"series_{key}"], res[f"tmax_{key}"]) <= TOLERANCE


# --------------------------------------------------------------------------- compatibility
def ours(frequency: float, elements: int, time_step: float, points: int, repeats: int = 1) -> dict:
    """Our ANCF scene (``snapping_cable``) at one setting, the median wall time of
    ``repeats`` runs (``benchmarks/bounds.py``)."""
    runs = [ours_run(frequency, "snapping_cable", "genalpha", elements, time_step, points) for _ in range(repeats)]
    res = runs[-1]
    res["wall_time_s"] = float(np.median([r["wall_time_s"] for r in runs]))
    return res


def peer(name: str, frequency: float, segments: int, time_step: float, repeats: int = 1) -> dict:
    """One peer run, MoorDyn RK4 or Exudyn, the median wall time of ``repeats`` runs."""
    runs = [moordyn_run(frequency, "RK4", segments, time_step) if name == "MoorDyn"
            else exudyn_run(frequency, segments, time_step) for _ in range(repeats)]
    res = runs[-1]
    res["wall_time_s"] = float(np.median([r["wall_time_s"] for r in runs]))
    return res


def peers_available() -> dict[str, bool]:
    """Which peer packages are installed."""
    import importlib.util

    return {"MoorDyn": importlib.util.find_spec("moordyn") is not None,
            "Exudyn": importlib.util.find_spec("exudyn") is not None}


# --------------------------------------------------------------------------- sweeps
class Sweep:
    """The runs of one frequency, their errors against their own and the common reference."""

    def __init__(self, frequency: float, common: dict):
        self.frequency = frequency
        self.common = common
        self.runs: list[dict] = []

    def add(self, kind: str, res: dict, own: dict, redo) -> dict:
        """Record a run of the code variant ``kind`` with its errors; ``redo`` re-runs it
        (for the timing repeats)."""
        res["kind"] = kind
        res["series_own"], res["tmax_own"] = errors(res, own)
        res["series_common"], res["tmax_common"] = errors(res, self.common)
        res["walls"] = [] if res.get("cached") else [res["wall_time_s"]]
        res["redo"] = redo
        self.runs.append(res)
        state = res.get("failed") or (f"series {100 * res['series_own']:.2f} % own, "
                                      f"{100 * res['series_common']:.2f} % common; Tmax "
                                      f"{100 * res['tmax_own']:.2f} / {100 * res['tmax_common']:.2f} %")
        print(f"  {self.frequency} Hz {kind} {res['setting']}: {state}, {res['wall_time_s']:.2f} s", file=sys.stderr)
        return res

    def ladder(self, kind: str, own: dict, settings, run, fresh=None) -> None:
        """Run ``settings`` (largest step first) until one is within 1 % of both references;
        ``fresh`` (default ``run``) runs a setting again for its timing (``run`` may be cached)."""
        for setting in settings:
            res = self.add(kind, run(*setting), own, lambda s=setting: (fresh or run)(*s))
            if within(res, "own") and within(res, "common"):
                break

    def time_fronts(self, repeats: int) -> None:
        """Re-time the runs on each kind's front (error against the common reference
        against wall time) to a median of ``repeats``."""
        for kind in sorted({r["kind"] for r in self.runs if "(reference)" not in r["kind"]}):
            candidates = [r for r in front(self.runs, kind, "common")
                          if max(r["series_common"], r["tmax_common"]) <= RETIME_BELOW]
            for res in candidates + [fastest(self.runs, kind, k) for k in ("own", "common")]:
                while res is not None and len(res["walls"]) < repeats:
                    res["walls"].append(res["redo"]()["wall_time_s"])
                if res is not None:
                    res["wall_time_s"] = statistics.median(res["walls"])


def speed(res: dict) -> float:
    """Simulated seconds per wall second."""
    return DURATION / res["wall_time_s"] if res["wall_time_s"] > 0.0 else math.nan


def front(runs: list[dict], kind: str, key: str) -> list[dict]:
    """The runs of ``kind`` with no faster run of a smaller error (max of series and Tmax)
    against the reference ``key``, fastest first."""
    pts = sorted((r for r in runs if r["kind"] == kind and not r.get("failed")), key=lambda r: r["wall_time_s"])
    out, best = [], math.inf
    for r in pts:
        err = max(r[f"series_{key}"], r[f"tmax_{key}"])
        if err < best:
            out.append(r)
            best = err
    return out


def fastest(runs: list[dict], kind: str, key: str) -> dict | None:
    """The fastest run of ``kind`` (a code variant, or a code's name for all its variants)
    within 1 % against the reference ``key``."""
    ok = [r for r in runs if (r["kind"] == kind or r["code"] == kind) and "(reference)" not in r["kind"]
          and not r.get("failed") and within(r, key)]
    return min(ok, key=lambda r: r["wall_time_s"]) if ok else None


def moordyn_sweep(sweep: Sweep, quick: bool) -> None:
    """Every working scheme over segments and steps up to its stability limit."""
    schemes = {"RK4": (2, 5, 20), "ACA1": (5, 20)} if quick else MOORDYN_SCHEMES
    for scheme, segment_counts in schemes.items():
        for n in segment_counts:
            steps = []
            for factor in WAVE_FACTORS:
                dt = float(f"{factor * WAVE_TIME / n:.3g}")
                if (n + 1) * DURATION / dt <= MOORDYN_MAX_WORK:
                    steps.append((scheme, n, dt))
            sweep.ladder(f"MoorDyn {scheme}", sweep.common, steps,
                         lambda s, n, dt: cached_peer("MoorDyn", sweep.frequency, (s, n, dt),
                                                      lambda: moordyn_run(sweep.frequency, s, n, dt)),
                         lambda s, n, dt: moordyn_run(sweep.frequency, s, n, dt))


def moordyn_ab_defect(frequency: float) -> dict:
    """AB2 at a small step next to RK4 at the same setting: MoorDyn 2.7's Adams-Bashforth
    start-up and update formulas are wrong (``peers/README.md``), its answer does not
    approach RK4's as the step shrinks."""
    out = {}
    for scheme in ("AB2", "AB3", "RK4"):
        out[scheme] = cached_peer("MoorDyn", frequency, (scheme, 10, 2e-5),
                                  lambda s=scheme: moordyn_run(frequency, s, 10, 2e-5))
    return out


def our_sweep(sweep: Sweep, kind: str, quick: bool) -> None:
    """One of our model kinds over elements and steps."""
    scene, integrator, element_counts, steps, points = OURS[kind]
    ref_kind, *ref_setting = OUR_REFERENCES[kind]
    own = next((r for r in sweep.runs if r["kind"] == f"{ref_kind} (reference)"), None)
    if own is None:
        ref_scene, ref_integrator = OURS[ref_kind][:2]
        own = ours_run(sweep.frequency, ref_scene, ref_integrator, *ref_setting)
        sweep.add(f"{ref_kind} (reference)", own, own,
                  lambda: ours_run(sweep.frequency, ref_scene, ref_integrator, *ref_setting))
    if quick:
        element_counts = element_counts[1::2]
    for n in element_counts:
        ladder = explicit_steps(scene, n) if steps is None else steps
        sweep.ladder(kind, own, [(n, dt) for dt in ladder],
                     lambda n, dt: ours_run(sweep.frequency, scene, integrator, n, dt, points))


def explicit_steps(scene: str, elements: int) -> tuple[float, ...]:
    """EXPLICIT_FRACTIONS of the largest step the explicit path allows on ``elements``
    elements [s], rounded down to 0.1 us."""
    from towcable_fmu.scene import load_scene

    limit = load_scene(scene, {"cable.segments[0].elements": elements, "solver.integrator": "genalpha"}).explicit_step()
    return tuple(math.floor(f * limit * 1e7) / 1e7 for f in EXPLICIT_FRACTIONS)


def exudyn_sweep(sweep: Sweep, quick: bool) -> None:
    """Exudyn over elements and steps."""
    own = cached_peer("Exudyn", sweep.frequency, ("genalpha",) + EXUDYN_REFERENCE,
                      lambda: exudyn_run(sweep.frequency, *EXUDYN_REFERENCE))
    sweep.add("Exudyn (reference)", own, own, lambda: exudyn_run(sweep.frequency, *EXUDYN_REFERENCE))
    for n in (EXUDYN_ELEMENTS[1::2] if quick else EXUDYN_ELEMENTS):
        sweep.ladder("Exudyn", own, [(n, dt) for dt in EXUDYN_STEPS],
                     lambda n, dt: cached_peer("Exudyn", sweep.frequency, ("genalpha", n, dt),
                                               lambda: exudyn_run(sweep.frequency, n, dt)),
                     lambda n, dt: exudyn_run(sweep.frequency, n, dt))


# --------------------------------------------------------------------------- report
def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--quick", action="store_true", help="one frequency (1.27 Hz), fewer settings")
    p.add_argument("--no-exudyn", action="store_true", help="leave Exudyn out (its runs are the slowest)")
    p.add_argument("--peers-only", action="store_true",
                   help="only fill the peers' cache (PEER_CACHE; no report): their sweeps take most of the time")
    args = p.parse_args(argv)
    available = peers_available()
    if not available["MoorDyn"]:
        raise SystemExit("the common reference is MoorDyn's converged run: pip install '.[bench]'")
    if args.peers_only:
        for f in FREQUENCIES[:1] if args.quick else FREQUENCIES:
            sweep = Sweep(f, cached_peer("MoorDyn", f, MOORDYN_REFERENCE, lambda f=f: moordyn_run(f, *MOORDYN_REFERENCE)))
            moordyn_sweep(sweep, args.quick)
            if available["Exudyn"] and not args.no_exudyn:
                exudyn_sweep(sweep, args.quick)
            moordyn_ab_defect(f)
        return
    kinds = [k for k in OURS if OURS[k][1] in integrators_available()]
    started, load = time.perf_counter(), os.getloadavg()[0]
    sweeps, defects = [], {}
    for f in FREQUENCIES[:1] if args.quick else FREQUENCIES:
        common = cached_peer("MoorDyn", f, MOORDYN_REFERENCE, lambda f=f: moordyn_run(f, *MOORDYN_REFERENCE))
        sweep = Sweep(f, common)
        sweep.add("MoorDyn RK4 (reference)", common, common, lambda f=f: moordyn_run(f, *MOORDYN_REFERENCE))
        for kind in kinds:
            our_sweep(sweep, kind, args.quick)
        moordyn_sweep(sweep, args.quick)
        if available["Exudyn"] and not args.no_exudyn:
            exudyn_sweep(sweep, args.quick)
        sweep.time_fronts(REPEATS)
        sweeps.append(sweep)
        defects[f] = moordyn_ab_defect(f)
    write_report(sweeps, defects, kinds, time.perf_counter() - started, (load, os.getloadavg()[0]))


def _setting(res: dict) -> str:
    a, n, dt = res["setting"][:3]
    return f"{a}, {n} el/seg, {dt * 1e3:.3g} ms"


def _row(res: dict | None) -> list[str]:
    if res is None:
        return ["none within 1 %", "-", "-", "-", "-", "-"]
    return [_setting(res), f"{100 * res['series_own']:.2f}", f"{100 * res['tmax_own']:.2f}",
            f"{100 * res['series_common']:.2f}", f"{100 * res['tmax_common']:.2f}",
            f"{speed(res):.1f} ({len(res['walls'])})"]


def write_report(sweeps: list[Sweep], defects: dict, kinds: list[str], elapsed: float,
                 load: tuple[float, float]) -> None:
    """Markdown tables (fronts, fastest within 1 %, ratios) and the work-precision plot;
    ``load``: the load average at the start and at the end of the sweeps."""
    lines = ["# Snapping cable: work-precision fronts, ours and the peers\n", machine_header(),
             f"- load average {load[0]:.1f} at the start, {load[1]:.1f} at the end, on 2 cores (above 2 the machine "
             f"is shared with other jobs: absolute speeds are low and noisy, the ratios are of runs in the same "
             f"session). Whole benchmark: {elapsed / 60:.0f} min.\n\n",
             DESCRIPTION, "\n",
             f"Our model kinds in this run: {', '.join(kinds)}. "
             "Speed: simulated seconds per wall second (in brackets: the number of timings, median).\n"]
    for sweep in sweeps:
        runs, f = sweep.runs, sweep.frequency
        lines.append(f"\n## f = {f} Hz\n\nMoorDyn's converged run (the common reference): T0 = "
                     f"{sweep.common['T0']:.4f} N, Tmax/T0 = {sweep.common['Tmax_over_T0']:.4f}.\n\n")
        lines.append("### Each code's fastest setting within 1 % (series and Tmax/T0)\n\n")
        table = []
        codes = [k for k in dict.fromkeys(r["kind"] for r in runs) if "(reference)" not in k]
        for kind in codes:
            for key in ("own", "common"):
                table.append([kind, key] + _row(fastest(runs, kind, key)))
        lines.append(markdown_table(["code", "against", "setting", "series own [%]", "Tmax own [%]",
                                     "series common [%]", "Tmax common [%]", "speed"], table))
        lines.append("\n### Ratios: our fastest within 1 % over MoorDyn's fastest within 1 %\n\n")
        table = []
        for key in ("own", "common"):
            md = fastest(runs, "MoorDyn", key)
            for kind in ["towcable"] + kinds:
                mine = fastest(runs, kind, key)
                table.append([kind if kind != "towcable" else "ours, any kind", key,
                              _setting(mine) if mine else "-", _setting(md) if md else "-",
                              f"{speed(mine) / speed(md):.2f}" if mine and md else "-"])
        lines.append(markdown_table(["ours", "against", "our setting", "MoorDyn's setting", "speed ratio"], table))
        lines.append(f"\n### The fronts below {100 * RETIME_BELOW:g} % (error against the common reference)\n\n")
        table = []
        for kind in codes:
            for r in front(runs, kind, "common"):
                if max(r["series_common"], r["tmax_common"]) > RETIME_BELOW:
                    continue
                table.append([kind, _setting(r), f"{100 * r['series_common']:.2f}",
                              f"{100 * r['tmax_common']:.2f}", f"{speed(r):.1f} ({len(r['walls'])})"])
        lines.append(markdown_table(["code", "setting", "series [%]", "Tmax [%]", "speed"], table))
        refs = [r for r in runs if "(reference)" in r["kind"]]
        lines.append("\n### The converged runs against the common reference\n\n")
        lines.append(markdown_table(["run", "setting", "T0 [N]", "Tmax/T0", "series [%]", "Tmax [%]"],
                                    [[r["kind"], _setting(r), f"{r['T0']:.4f}", f"{r['Tmax_over_T0']:.4f}",
                                      f"{100 * r['series_common']:.2f}", f"{100 * r['tmax_common']:.2f}"]
                                     for r in refs]))
        failed = [r for r in runs if r.get("failed")]
        lines.append(f"\n{len(runs)} runs, {len(failed)} failed (unstable settings: "
                     + ", ".join(sorted({r['kind'] for r in failed})) + ").\n" if failed else f"\n{len(runs)} runs.\n")
        ab = defects[f]
        rk4 = ab["RK4"]
        lines.append("\n### MoorDyn 2.7's Adams-Bashforth defect\n\nAt 10 segments and 0.02 ms (1/38 of RK4's "
                     "stable step), against RK4 at the same setting: "
                     + "; ".join(f"{s}: " + (ab[s].get("failed") or f"Tmax/T0 {ab[s]['Tmax_over_T0']:.4g}, series "
                                             f"{100 * series_error(ab[s], rk4):.3g} %")
                                 for s in ("AB2", "AB3"))
                     + f" (RK4: Tmax/T0 {rk4.get('Tmax_over_T0', math.nan):.4f}). The 2.7 source's "
                     "ABScheme::Step applies wrong multistep coefficients (the second-order start-up drops the "
                     "step and flips a sign, the higher orders flip signs), so no step is small enough.\n")
    (RESULTS / "snapping.md").write_text("".join(lines), encoding="utf-8")
    plot(sweeps)


def plot(sweeps: list[Sweep]) -> None:
    """Work-precision plot: every run faint, each code's front as a line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(sweeps), figsize=(6.5 * len(sweeps), 5), squeeze=False)
    for ax, sweep in zip(axes[0], sweeps):
        kinds = [k for k in dict.fromkeys(r["kind"] for r in sweep.runs) if "(reference)" not in k]
        for i, kind in enumerate(kinds):
            color = plt.cm.tab20(i % 20)
            pts = [r for r in sweep.runs if r["kind"] == kind and not r.get("failed")]
            err = [max(r["series_common"], r["tmax_common"], 1e-4) for r in pts]
            ax.loglog(err, [speed(r) for r in pts], ".", color=color, alpha=0.35)
            fr = front(sweep.runs, kind, "common")
            ax.loglog([max(r["series_common"], r["tmax_common"], 1e-4) for r in fr], [speed(r) for r in fr], "-o",
                      color=color, label=kind, markersize=4, linewidth=2 if not kind.startswith("MoorDyn") else 1)
        ax.axvline(TOLERANCE, color="grey", linestyle=":", linewidth=1)
        ax.set_xlim(1e-4, 1.0)
        ax.set_xlabel("max(series, Tmax/T0) error against MoorDyn's converged run [-]")
        ax.set_ylabel("simulated seconds per wall second")
        ax.set_title(f"snapping cable, f = {sweep.frequency} Hz")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(RESULTS / "snapping_work_precision.png", dpi=120)


if __name__ == "__main__":
    main()
