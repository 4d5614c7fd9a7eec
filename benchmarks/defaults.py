"""Every built-in scene's default solver settings against the scene's own efficient front.

For each built-in scene (``towcable scenes``) one headline signal, the one a user of the
scene reads (:data:`SCENES`), is recorded at the scene's output interval over a run long
enough to hold the scene's main dynamics:

* reference: every cable segment's elements doubled, the time step divided by 8 and
  ``solver.newton_tol`` divided by 10 (the rigid-link ``tug_tow``: its ``solver.rtol``
  and ``solver.atol`` divided by 1000);
* sweep at the scene's own mesh: time step x 4, 2, 1 (the default), 1/2, 1/4, and x 8
  when x 4 is within 1 %; for ANCF scenes also ``solver.adaptive = true`` at the default
  tolerances with a largest step of 4 x the default (``tug_tow``: rtol and atol x 1000,
  100, 10, 1, 1/10);
* error: RMS over the run of (signal - reference) divided by the reference's mean
  absolute value, or by its RMS for a signal that oscillates about zero;
* speed: simulated seconds per wall second of ``sim.run`` (statics excluded), median of
  3 runs for the default setting, one run for the others, after an untimed short run of
  the scene (kernels loaded);
* verdict: the default is on the front when its error is at most 1 % and no setting of
  the sweep within 1 % is more than 15 % faster (timing noise).

The references were checked once (commit 8d0f62e) against elements x 3, time step / 16
(tug_tow: tolerances / 10^4): below 0.1 % apart except pulley_static_2 and _3 (0.38 and
0.44 %), snapping_cable_nodal (0.26 %) and the VIV scenes (0.50, 1.42, 0.39 and 0.37 %:
the kinetic energy depends on the mesh, not on the step; case 2 is not mesh-converged
to 1 %).

Run: ``nice -n 10 python benchmarks/defaults.py [SCENE ...]`` (about 10 minutes for all
scenes on 2 cores; names: only those scenes). Writes ``results/defaults.md`` and
``results/defaults_work_precision.png``.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field

import numpy as np

from common import RESULTS, machine_header, markdown_table

#: largest RMS error [-] of a setting on the front
TOLERANCE = 0.01
#: a setting counts as faster than the default when its speed exceeds the default's by this factor
NOISE = 1.15
#: timing repeats of the default setting (median)
REPEATS = 3
#: time-step factors of the sweep (x 8 is added when x 4 is within TOLERANCE)
STEP_FACTORS = (4.0, 2.0, 1.0, 0.5, 0.25)
#: tolerance factors of the rigid-link sweep (rtol and atol together)
TOLERANCE_FACTORS = (1000.0, 100.0, 10.0, 1.0, 0.1)


@dataclass(frozen=True)
class Case:
    """What is measured on one scene."""

    #: the output compared with the reference
    signal: str
    #: simulated time [s]
    duration: float
    #: why this signal and this duration
    reason: str
    #: error scale: "mean" (mean absolute value of the reference) or "rms" (its RMS, for a
    #: signal that oscillates about zero)
    scale: str = "mean"


_PULLEY = Case("tension.load", 4.0, "the pull on the load the pulley study compares with the measurements; two "
               "swings after the release")
_VIV_REASON = ("the cable's kinetic energy: the span's vibration, which the VIV study reads as the mid-span "
               "motion (not an output); the wake's growth to its limit cycle")
SCENES = {
    "hanging_cable": Case("tension.top", 30.0, "10 s ramp and two periods of the 0.1 Hz heave"),
    "snapping_cable": Case("tension.top", 5.0, "six periods of the abrupt 1.27 Hz motion, slack and snap "
                           "each period"),
    "snapping_cable_nodal": Case("tension.top", 5.0, "as snapping_cable"),
    "flume_pinned": Case("towbody.y", 10.0, "the sphere's cross-flow motion (the flume study's ellipsoid) in "
                         "the turbulence", "rms"),
    "flume": Case("towbody.y", 10.0, "as flume_pinned, the line on the winch", "rms"),
    "full_scale": Case("tension.sheave", 60.0, "the sheave tension in the default sea: about ten wave periods"),
    "full_scale_deploy": Case("tension.top", 80.0, "the spool tension: the 20 s hold and the first 55 m veered at "
                              "1 m/s while towing (the fed element split every 3.75 m)"),
    "full_scale_recovery": Case("tension.top", 100.0, "the spool tension: 29 m hauled in at 0.5 m/s in the default "
                                "sea and the body lifted out through the crests"),
    "full_scale_pinned": Case("tension.top", 20.0, "the steady tow: no motion, the run stays at the statics"),
    "pulley_static": _PULLEY,
    "pulley_static_2": _PULLEY,
    "pulley_static_3": _PULLEY,
    "pulley_moving": Case("tension.load", 6.0, "the pull on the load (the pulley study); the 2 s ramp and four "
                          "periods of the 1 Hz arm"),
    "sea_trial_turn": Case("tension.top", 600.0, "the tension at the ship's tow point: acceleration to 12 kn, "
                           "steady tow, the first 200 s of the turn"),
    "sea_trial_turn_rigid": Case("tension.top", 600.0, "as sea_trial_turn"),
    "tug_tow": Case("tension.towbody", 30.0, "the tension at the barge through the slack phase to the first "
                    "taut snap; later snaps (1-20 MN peaks) do not converge in the tolerance"),
    "tug_tow_ancf": Case("tension.towbody", 30.0, "as tug_tow"),
    "viv_sheave": Case("energy.kinetic", 15.0, _VIV_REASON),
    "viv_sheave_case2": Case("energy.kinetic", 30.0, _VIV_REASON),
    "viv_sheave_case3": Case("energy.kinetic", 30.0, _VIV_REASON),
    "viv_sheave_case4": Case("energy.kinetic", 30.0, _VIV_REASON),
}


@dataclass
class Run:
    """One setting of a scene: what was asked and what it gave."""

    label: str
    overrides: dict
    #: the step (or tolerance) factor of the setting; None: the adaptive step
    factor: float | None = None
    default: bool = False
    wall: float = float("nan")
    speed: float = float("nan")
    error: float = float("nan")
    stats: dict = field(default_factory=dict)
    series: np.ndarray | None = None
    failure: str = ""


def simulate(name: str, run: Run, duration: float, interval: float, signal: str, repeats: int = 1) -> Run:
    """Time ``run`` on scene ``name`` (median wall time of ``repeats`` runs, statics
    excluded) and keep its signal and statistics; a solver, scene or arithmetic error
    (a compiled kernel's division by zero) is recorded as the run's failure."""
    from towcable_fmu.common.errors import TowcableError
    from towcable_fmu.models import simulation_from

    walls = []
    try:
        for _ in range(repeats):
            sim = simulation_from(name, run.overrides)
            sim.initialize()
            start = time.perf_counter()
            series = sim.run(duration, interval=interval)
            walls.append(time.perf_counter() - start)
    except (TowcableError, ArithmeticError) as exc:
        run.failure = f"{type(exc).__name__}: {str(exc).splitlines()[0]}"
        return run
    run.wall = float(np.median(walls))
    run.speed = duration / run.wall
    run.series = series[signal]
    run.stats = sim.statistics()
    return run


def relative_error(series: np.ndarray, reference: np.ndarray, scale: str) -> float:
    """RMS of the difference over the run divided by the reference's mean absolute value
    (``scale = "mean"``) or its RMS (``"rms"``) [-]."""
    norm = np.mean(np.abs(reference)) if scale == "mean" else np.sqrt(np.mean(reference ** 2))
    return float(np.sqrt(np.mean((series - reference) ** 2)) / norm)


def reference_overrides(scene) -> dict:
    """Overrides of the converged reference of a loaded scene."""
    s = scene.solver
    if not hasattr(s, "time_step"):  # rigid link: tolerances only
        return {"solver.rtol": s.rtol / 1000.0, "solver.atol": s.atol / 1000.0}
    out = {f"cable.segments[{i}].elements": 2 * seg.elements for i, seg in enumerate(scene.cable.segments)}
    out.update({"solver.time_step": s.time_step / 8.0, "solver.newton_tol": s.newton_tol / 10.0})
    return out


def sweep(scene, kind: str) -> list[Run]:
    """The settings of the sweep at the scene's own mesh, the default marked."""
    s = scene.solver
    if kind == "rigid_link":
        return [Run(f"rtol = {s.rtol * f:g} (x{f:g})", {"solver.rtol": s.rtol * f, "solver.atol": s.atol * f},
                    f, f == 1.0) for f in TOLERANCE_FACTORS]
    runs = [Run(f"h = {s.time_step * f:g} s (x{f:g})", {"solver.time_step": s.time_step * f}, f, f == 1.0)
            for f in STEP_FACTORS]
    if kind == "ancf":
        runs.append(Run(f"adaptive, h <= {4.0 * s.time_step:g} s",
                        {"solver.adaptive": True, "solver.time_step": 4.0 * s.time_step}))
    return runs


def coarsest(scene) -> Run:
    """The time step x 8."""
    h = 8.0 * scene.solver.time_step
    return Run(f"h = {h:g} s (x8)", {"solver.time_step": h}, 8.0)


def evaluate(name: str, run: Run, case: Case, interval: float, reference: Run, repeats: int = 1) -> Run:
    """:func:`simulate` ``run`` and measure its error against ``reference``."""
    simulate(name, run, case.duration, interval, case.signal, repeats)
    if not run.failure:
        run.error = relative_error(run.series, reference.series, case.scale)
    print(f"{name}: {run.label}: " + (run.failure or f"{100 * run.error:.3g} %, {run.speed:.4g} x real time"),
          file=sys.stderr, flush=True)
    return run


def measure(name: str) -> dict:
    """Reference and sweep of one scene."""
    from towcable_fmu.models import model_kind
    from towcable_fmu.scene import load_scene

    case = SCENES[name]
    scene = load_scene(name)
    kind = model_kind(scene)
    interval = float(scene.output.interval)
    start = time.perf_counter()
    simulate(name, Run("warm-up", {}), 0.05 * case.duration, interval, case.signal)
    reference = simulate(name, Run("reference", reference_overrides(scene)), case.duration, interval, case.signal)
    done = []
    if not reference.failure:
        for run in sorted(sweep(scene, kind), key=lambda r: not r.default):
            done.append(evaluate(name, run, case, interval, reference, REPEATS if run.default else 1))
            if kind != "rigid_link" and run.factor == 4.0 and run.error <= TOLERANCE:
                done.append(evaluate(name, coarsest(scene), case, interval, reference))
    done.sort(key=lambda r: -r.factor if r.factor is not None else 0.0)
    return {"name": name, "kind": kind, "case": case, "interval": interval, "reference": reference, "runs": done,
            "wall": time.perf_counter() - start}


def verdict(result: dict) -> dict:
    """Is the default within TOLERANCE, and is no sweep setting within it faster by more
    than NOISE? The fastest setting within TOLERANCE."""
    default = next((r for r in result["runs"] if r.default), None)
    if default is None or default.failure:
        return {"default": default, "within": False, "best": None, "front": False}
    ok = [r for r in result["runs"] if not r.failure and r.error <= TOLERANCE]
    best = max(ok, key=lambda r: r.speed) if ok else None
    within = default.error <= TOLERANCE
    front = within and not (best is not None and best.speed > NOISE * default.speed)
    return {"default": default, "within": within, "best": best, "front": front}


def stat(run: Run, key: str) -> object:
    """A solver counter of a run, '-' when the model does not count it."""
    return int(run.stats[key]) if key in run.stats else "-"


def summary_row(res: dict) -> list:
    """A scene's line of the verdict table."""
    v, case = verdict(res), res["case"]
    d, best = v["default"], v["best"]
    if d is None or d.failure:
        failure = f"reference failed: {res['reference'].failure}" if d is None else f"failed: {d.failure}"
        return [res["name"], res["kind"], case.signal, case.duration, failure, "", "", "", "", "?"]
    faster = "none" if best is None else "the default" if best.default else (
        f"{best.label}: {100 * best.error:.3g} %, {best.speed:.4g} x ({best.speed / d.speed:.2f} x the default)")
    return [res["name"], res["kind"], case.signal, case.duration, d.label.split(" (")[0], f"{100 * d.error:.3g}",
            f"{d.speed:.4g}", "yes" if v["within"] else "**no**", faster, "yes" if v["front"] else "**no**"]


def section(res: dict) -> str:
    """A scene's paragraph and table of its sweep."""
    case, ref = res["case"], res["reference"]
    rows = [[r.label + (" (default)" if r.default else ""), f"{100 * r.error:.3g}", f"{r.speed:.4g}",
             f"{r.wall:.3g}", stat(r, "solver.steps"), stat(r, "solver.newton_iterations"),
             stat(r, "solver.jacobian_factorisations")] if not r.failure else
            [r.label, "failed: " + r.failure, "", "", "", "", ""] for r in res["runs"]]
    refined = [f"{key} = {value:g}" for key, value in ref.overrides.items() if "elements" not in key]
    if res["kind"] != "rigid_link":
        refined.append("elements x 2")
    if ref.failure:
        scale, outcome = "", f": failed: {ref.failure}"
    else:
        norm = np.mean(np.abs(ref.series)) if case.scale == "mean" else np.sqrt(np.mean(ref.series ** 2))
        scale, outcome = f" ({norm:.4g})", f" ({ref.wall:.3g} s wall)"
    return (f"\n### {res['name']}\n\n`{case.signal}` over {case.duration:g} s every {res['interval']:g} s "
            f"({case.reason}); error scale: the reference's "
            f"{'mean absolute value' if case.scale == 'mean' else 'RMS'}{scale}. Reference: {', '.join(refined)}"
            f"{outcome}; scene measured in {res['wall']:.0f} s.\n\n"
            + markdown_table(["setting", "error [%]", "x real time", "wall [s]", "steps", "Newton iterations",
                              "factorisations"], rows))


#: The hand-written section of results/defaults.md that a regeneration keeps: the defaults
#: against an earlier commit (``defaults_ab.py``), which this benchmark does not measure.
KEPT_SECTION = "## Before and after"


def kept_section() -> str:
    """The current results/defaults.md's :data:`KEPT_SECTION` up to the next section ("" if none)."""
    path = RESULTS / "defaults.md"
    text = path.read_text(encoding="utf-8") if path.is_file() else ""
    start = text.find("\n" + KEPT_SECTION + "\n")
    if start < 0:
        return ""
    end = text.find("\n## ", start + 1)
    return text[start + 1:end + 1 if end >= 0 else len(text)]


def report(results: list[dict], total: float) -> str:
    """The Markdown of results/defaults.md (with the current file's :data:`KEPT_SECTION`)."""
    return ("# Default solver settings of the built-in scenes against their efficient fronts\n\n" + machine_header()
            + f"\nPer scene: one headline signal over a run holding the scene's main dynamics, at the scene's output "
              "interval. Reference: elements x 2, time step / 8, newton_tol / 10 (tug_tow: rtol and atol / 1000). "
              "Sweep at the scene's mesh: time step x 8 (when x 4 is within 1 %), 4, 2, 1, 1/2, 1/4 and, for ANCF "
              "scenes, the adaptive step at the default tolerances up to 4 x the default step (tug_tow: rtol and "
              "atol x 1000 ... 1/10). Error: RMS of (signal - reference) over the run relative to the reference's "
              "mean absolute value (its RMS for a signal about zero). Speed: simulated seconds per wall second of "
              "the run, statics excluded; median of 3 runs for the default, one run otherwise; one core, "
              "`nice -n 10` on a shared 2-core machine. On the front: error <= 1 % and no setting within 1 % more "
              f"than 15 % faster. The whole benchmark took {total / 60:.1f} min.\n\n"
            + markdown_table(["scene", "model", "signal", "duration [s]", "default", "error [%]", "x real time",
                              "within 1 %", "fastest within 1 %", "on the front"], [summary_row(r) for r in results])
            + "\n![work-precision](defaults_work_precision.png)\n\n" + kept_section() + "## The scenes\n"
            + "".join(section(r) for r in results))


def plot(results: list[dict]) -> None:
    """One log-log panel per scene: error against speed, the default a red star, 1 % dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    cols = 5
    rows = -(-len(results) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols, 2.5 * rows), squeeze=False)
    for ax, res in zip(axes.flat, results):
        ok = [r for r in res["runs"] if not r.failure]
        errors = [max(100 * r.error, 1e-6) for r in ok]  # [%]: an error of zero (a run at rest) drawn at 1e-6
        ax.loglog([r.speed for r in ok], errors, "o", color="C0", ms=4)
        for r, error in zip(ok, errors):
            ax.annotate("adapt." if r.factor is None else f"x{r.factor:g}", (r.speed, error), fontsize=6,
                        xytext=(2, 2), textcoords="offset points")
            if r.default:
                ax.loglog(r.speed, error, "r*", ms=12)
        ax.axhline(100 * TOLERANCE, color="gray", ls="--", lw=0.8)
        ax.set_ylim(min(errors + [100 * TOLERANCE]) / 3.0, max(errors + [100 * TOLERANCE]) * 3.0)
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.set_title(f"{res['name']}: {res['case'].signal}", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3, which="both")
    for ax in axes.flat[len(results):]:
        ax.axis("off")
    fig.supxlabel("simulated seconds per wall second")
    fig.supylabel("RMS error of the headline signal [%]")
    fig.tight_layout()
    fig.savefig(RESULTS / "defaults_work_precision.png", dpi=110)


def main(names: list[str]) -> str:
    """Measure the scenes ``names`` (all built-in scenes when empty), write the report and
    the plot; return the Markdown."""
    from towcable_fmu.scene import builtin_scene_names

    missing = sorted(set(builtin_scene_names()) - set(SCENES))
    if missing:
        raise SystemExit(f"no case in SCENES for the built-in scenes {', '.join(missing)}")
    start = time.perf_counter()
    results = [measure(name) for name in (names or builtin_scene_names())]
    text = report(results, time.perf_counter() - start)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "defaults.md").write_text(text, encoding="utf-8")
    plot(results)
    return text


if __name__ == "__main__":
    print(main(sys.argv[1:]))
