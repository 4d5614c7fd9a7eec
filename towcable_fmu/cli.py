"""Command line: ``towcable scenes | static | run | cosim | study-compensation | fatigue | sweep | sweep-plot | docs``.

Output names and units follow the variable contract (``contract.toml``); every number
printed is in SI units.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Sequence

from .common import contract
from .jit import kernel_cache
from .common.errors import TowcableError
from .models import KERNEL_SOURCES, model_kind, simulation_for
from .common.run_io import Progress, write_csv
from .scene import builtin_scene_names, load_scene, parse_override


def _overrides(values: Sequence[str] | None) -> list[tuple[str, object]]:
    return [parse_override(v) for v in values or []]


def _simulation(args: argparse.Namespace):
    scene = load_scene(args.scene, _overrides(args.set))
    _compile_kernels(model_kind(scene))
    return simulation_for(scene)


#: The co-simulation's own kernels (the light FMUs' models, the master's loop): compiled with the cable's.
COSIM_KERNEL_SOURCES = ("towcable_fmu.runtime.input_kernels", "towcable_fmu.cosim.kernels")


def _compile_kernels(kind: str, extra: tuple[str, ...] = ()) -> None:
    """Compile the kernels of a model kind (and of the modules ``extra``) on every core if
    they are not cached yet."""
    from .jit.parallel_compile import compile_ahead

    compile_ahead(KERNEL_SOURCES.get(kind, ()) + extra)


def cmd_scenes(args: argparse.Namespace) -> int:
    """List the built-in scenes with their titles."""
    for name in builtin_scene_names():
        print(f"{name:20s} {load_scene(name).title}")
    return 0


def cmd_static(args: argparse.Namespace) -> int:
    """Solve the statics and print the equilibrium summary."""
    sim = _simulation(args)
    start = time.perf_counter()
    out = sim.initialize(statics=True)
    summary = {k: v for k, v in out.items() if not k.startswith(("energy.", "time"))}
    summary.update(sim.statistics())
    summary["solver.wall_time"] = time.perf_counter() - start
    for key in [k for k in summary if k.startswith("solver.") and k not in (
            "solver.statics_iterations", "solver.statics_residual", "solver.statics_wall_time",
            "solver.wall_time")]:
        del summary[key]
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(f"statics of '{args.scene}'")
        for k, v in summary.items():
            print(f"  {k:28s} {v:14.6g} {getattr(sim, 'unit_of', contract.unit_of)(k)}")
    if args.contact_plot:
        _plot_contact(sim, out, Path(args.contact_plot), args.scene)
    return 0


def _plot_contact(sim, out: dict, path: Path, label: str) -> None:
    """The static contact force distribution of a scene with a winch or a sheave."""
    from .common.plots import plot_contact_distribution

    scene = sim.scene
    if model_kind(scene) != "ancf" or (scene.winch is None and scene.sheave is None):
        raise TowcableError(f"--contact-plot: '{label}' has no winch drum or sheave (ANCF scenes with contact only)")
    half_d = 0.5 * scene.cable.segments[0].diameter
    references = {}
    for surface, part, key in ((0, scene.winch, "tension.winch"), (1, scene.sheave, "tension.sheave")):
        if part is not None and key in out:
            references[surface] = (f"{key} / R_c", out[key] / (part.radius + half_d))
    plot_contact_distribution(sim.contact_state()["distribution"], path, references,
                              title=f"{scene.title}: contact in statics")
    print(f"wrote {path}", file=sys.stderr)


def cmd_run(args: argparse.Namespace) -> int:
    """Run a scene in time and write CSV (and optionally a plot)."""
    sim = _simulation(args)
    if args.animate and model_kind(sim.scene) != "ancf":
        raise TowcableError(f"--animate is not available for the model of '{args.scene}' (ANCF scenes only)")
    progress = None if args.quiet else Progress()
    start = time.perf_counter()
    if args.animate:
        from .ancf.frames import run_with_frames

        series, frames = run_with_frames(sim, args.duration, 1.0 / args.fps, interval=args.interval,
                                         progress=progress)
    else:
        series = sim.run(args.duration, interval=args.interval, progress=progress)
    wall = time.perf_counter() - start
    output = Path(args.output)
    output.parent.mkdir(parents=True, exist_ok=True)
    write_csv(output, series)
    if args.plot:
        from .common.plots import plot_run

        plot_run(series, Path(args.plot), title=f"{args.scene}: {sim.scene.title}")
    if args.animate:
        from .animation import write_animation

        write_animation(frames, sim.scene, Path(args.animate), title=str(args.scene))
    if not args.quiet:
        stats = sim.statistics()
        written = [str(f) for f in (args.plot, args.animate) if f]
        print(f"wrote {output} ({len(series['time'])} samples)"
              + (" and " + ", ".join(written) if written else ""), file=sys.stderr)
        print(f"{args.duration:g} s simulated in {wall:.2f} s wall time "
              f"({args.duration / wall:.1f} x real time), {stats['solver.steps']} steps", file=sys.stderr)
    return 0


def cmd_cosim(args: argparse.Namespace) -> int:
    """Co-simulate ShipMotion -> HeaveCompensation -> TowCable through the FMUs (fmpy)."""
    from .cosim import CosimConfig, run_cosim, write_results

    _compile_kernels(model_kind(load_scene(args.scene, _overrides(args.set))), COSIM_KERNEL_SOURCES)
    config = CosimConfig(scene=args.scene, overrides=_overrides(args.set), compensation=args.compensation,
                         duration=args.duration, step=args.step, motion=args.motion, winch_radius=args.winch_radius,
                         phi_nom=args.phi_nom, theta_nom=args.theta_nom,
                         reference_point=tuple(args.reference_point) if args.reference_point else None,
                         interval=args.interval, fmu_dir=args.fmus)
    result = run_cosim(config, progress=None if args.quiet else Progress(), echo=not args.quiet)
    files = write_results(result, Path(args.output), plot=not args.no_plot,
                          title=f"co-simulation of '{args.scene}', compensation {result.parameters['HeaveCompensation']['algorithm']}")
    if args.ssp:
        from .fmu_build.build import ensure_fmus
        from .fmu_build.ssp import write_ssp

        files["ssp"] = write_ssp(args.ssp, ensure_fmus(args.fmus), result.parameters, start_time=0.0,
                                 stop_time=args.duration)
    if not args.quiet:
        t = result.timing
        print(f"wrote {', '.join(str(f) for f in files.values())}", file=sys.stderr)
        print(f"{args.duration:g} s simulated in {t['wall']:.2f} s wall time ({t['realtime_factor']:.1f} x real time, "
              f"{t['steps']} communication steps of {args.step:g} s; initialisation {t['initialisation']:.2f} s)",
              file=sys.stderr)
        print(f"model time {t['model']:.2f} s (TowCable {t['model.TowCable']:.2f} s, ShipMotion "
              f"{t['model.ShipMotion']:.3f} s, HeaveCompensation {t['model.HeaveCompensation']:.3f} s); "
              f"FMU overhead {100 * t['overhead_share']:.1f} % of the wall time", file=sys.stderr)
    return 0


def cmd_study_compensation(args: argparse.Namespace) -> int:
    """Compare heave-compensation algorithms on the full_scale scene in the default sea."""
    from .analysis.compensation_study import run_study

    result = run_study(args.algorithms, duration=args.duration, step=args.step, output_dir=args.output,
                       settle=args.settle, fraction=args.fraction, fmu_dir=args.fmus, verbose=not args.quiet,
                       tension_target=args.tension_target, tension_gain=args.tension_gain)
    print(result.files["table"].read_text(encoding="utf-8"))
    return 0


def cmd_fatigue(args: argparse.Namespace) -> int:
    """Rope life of recorded runs: tension damage, bending along the rope, extremes."""
    from .rope_life.assessment import assess
    from .rope_life.report import write_report
    from .common.run_io import read_csv

    scene = load_scene(args.scene, _overrides(args.set))
    try:
        runs = [(Path(name).name, read_csv(Path(name))) for name in args.results]
        result = assess(scene, runs, signal=args.signal, storm=args.storm, settle=args.settle)
    except (OSError, ValueError) as exc:
        raise TowcableError(str(exc)) from exc
    for path in write_report(result, Path(args.output), str(args.scene)):
        print(f"wrote {path}", file=sys.stderr)
    print((Path(args.output) / "report.md").read_text(encoding="utf-8"))
    return 0


def cmd_docs(args: argparse.Namespace) -> int:
    """Write the reference documentation (scene keys, FMU variables, command line)."""
    from .docs_gen import write_reference

    for path in write_reference(Path(args.output), build_parser()):
        print(f"wrote {path}", file=sys.stderr)
    return 0


def _positive(text: str) -> float:
    value = float(text)
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text}")
    return value


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (exposed for documentation and tests)."""
    parser = argparse.ArgumentParser(prog="towcable", description="Towed-cable simulator (SI units).")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("scenes", help="list the built-in scenes")
    p.set_defaults(func=cmd_scenes)

    def scene_args(p: argparse.ArgumentParser) -> None:
        p.add_argument("scene", help="built-in scene name or path to a scene TOML file")
        p.add_argument("--set", action="append", metavar="KEY=VALUE",
                       help="override a scene value by its dotted key, e.g. solver.time_step=0.005 "
                            "or cable.segments[0].elements=20 (repeatable)")

    p = sub.add_parser("static", help="solve the static equilibrium and print a summary")
    scene_args(p)
    p.add_argument("--json", action="store_true", help="print one flat JSON object keyed by output names")
    p.add_argument("--contact-plot", default=None, metavar="FILE.png",
                   help="PNG of the contact force per length against the wrap angle on the drum and the sheave, "
                        "with tension / radius for comparison")
    p.set_defaults(func=cmd_static)

    p = sub.add_parser("run", help="simulate in time and write CSV time series")
    scene_args(p)
    p.add_argument("--duration", type=_positive, required=True, help="simulated time [s]")
    p.add_argument("--output", required=True, help="CSV file to write (columns named as the outputs)")
    p.add_argument("--interval", type=_positive, default=None, help="output interval [s] (default: scene)")
    p.add_argument("--plot", default=None, help="PNG file with time-series plots")
    p.add_argument("--animate", default=None, metavar="FILE.gif",
                   help="animated GIF of the cable, winch, sheave and towed body (side view and close-up)")
    p.add_argument("--fps", type=_positive, default=10.0,
                   help="animation frames per second of simulated time, rounded to a multiple of the output "
                        "interval; the GIF plays in real time (default 10)")
    p.add_argument("--quiet", action="store_true", help="no progress or summary on stderr")
    p.set_defaults(func=cmd_run)

    from controllers import ALGORITHMS

    p = sub.add_parser("cosim", help="co-simulate ship motion, heave compensation and cable through the three FMUs",
                       description="Builds the FMUs if needed (into --fmus) and runs them with fmpy's low-level "
                                   "FMI 2.0 interface at a fixed communication step. Writes cosim.csv (columns = "
                                   "contract names), summary.json (parameters, geometry, timing) and cosim.png.")
    p.add_argument("--scene", default="full_scale", help="TowCable scene: built-in name or TOML file (default: full_scale)")
    p.add_argument("--compensation", choices=ALGORITHMS, default=None,
                   help="set-point algorithm (default: the scene's [compensation], else none)")
    p.add_argument("--duration", type=_positive, default=60.0, help="simulated time [s] (default 60)")
    p.add_argument("--step", type=_positive, default=0.01, help="communication step [s] (default 0.01)")
    p.add_argument("--output", default="out/cosim", help="output folder (default out/cosim)")
    p.add_argument("--interval", type=_positive, default=None, help="recording interval [s] (default: every step)")
    p.add_argument("--motion", default=None,
                   help="ship motion: 'none', a TOML file or built-in scene with a [motion] table, or TOML text "
                        "(default: the scene's [motion], else the default sea)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene value (repeatable)")
    p.add_argument("--winch-radius", type=_positive, default=None, help="r_w [m] (default: scene [winch], else 0.30)")
    p.add_argument("--phi-nom", type=float, default=None, help="nominal winch rotation [rad] (default: scene [winch], else 3.8)")
    p.add_argument("--theta-nom", type=float, default=None,
                   help="nominal departure angle [rad] (default: the cable's static angle at t0)")
    p.add_argument("--reference-point", type=float, nargs=3, metavar=("X", "Y", "Z"), default=None,
                   help="compensated point, ship frame [m] (default: scene [sheave], else the cable's top attachment)")
    p.add_argument("--fmus", default="fmus", help="folder of the FMUs (built there when missing or stale; default fmus/)")
    p.add_argument("--no-plot", action="store_true", help="do not write cosim.png")
    p.add_argument("--ssp", metavar="FILE", default=None, help="also write the SSP file of this run (the three "
                   "FMUs, their connections and every parameter the master set), for other FMI tools")
    p.add_argument("--quiet", action="store_true", help="no progress or summary on stderr")
    p.set_defaults(func=cmd_cosim)

    from .analysis.compensation_study import DEFAULT_ALGORITHMS, DEFAULT_SETTLE, DEFAULT_TENSION_GAIN

    p = sub.add_parser("study-compensation", help="compare heave-compensation algorithms (towed-body ellipsoid, "
                                                  "tensions, payout) on the full_scale scene",
                       description="Co-simulates the full_scale scene in the default irregular sea once per "
                                   "algorithm (same waves), leaves out the settling time and writes study.md, "
                                   "statistics.csv and plots (track, tension, payout) into --output; prints the "
                                   "table.")
    p.add_argument("--algorithms", nargs="+", choices=ALGORITHMS, default=list(DEFAULT_ALGORITHMS),
                   help="set-point algorithms to compare (default: " + " ".join(DEFAULT_ALGORITHMS) + ")")
    p.add_argument("--duration", type=_positive, default=300.0,
                   help="simulated time per algorithm, settling included [s] (default 300)")
    p.add_argument("--step", type=_positive, default=0.01, help="communication step [s] (default 0.01)")
    p.add_argument("--settle", type=float, default=DEFAULT_SETTLE,
                   help=f"start-up time left out of the statistics [s] (default {DEFAULT_SETTLE:g}: the sea's "
                        "20 s ramp-in plus three time constants of the towed body's mean depth)")
    p.add_argument("--fraction", type=float, default=0.95,
                   help="share of the towed-body positions inside the ellipsoid, in (0, 1] (default 0.95)")
    p.add_argument("--tension-target", type=_positive, default=None,
                   help="constant_tension: the winch's target tension [N] (default: the scene's static tension at "
                        "the winch)")
    p.add_argument("--tension-gain", type=_positive, default=DEFAULT_TENSION_GAIN,
                   help=f"constant_tension: payout rate per newton above the target [m/(s N)] (default "
                        f"{DEFAULT_TENSION_GAIN:g})")
    p.add_argument("--output", default="out/compensation", help="output folder (default out/compensation)")
    p.add_argument("--fmus", default="fmus", help="folder of the FMUs (built there when missing or stale; default fmus/)")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=cmd_study_compensation)

    p = sub.add_parser("fatigue", help="rope life of recorded runs: tension damage, bending along the rope, extremes",
                       description="Reads the CSV of one or more runs of a scene (seeds of the same sea) and writes "
                                   "report.md (tables with methods and sources), bending.png (bending cycles along "
                                   "the rope) and rainflow.png into --output; prints the report.")
    p.add_argument("results", nargs="+", help="CSV files written by 'towcable run' (or cosim.csv)")
    p.add_argument("--scene", required=True, help="the runs' scene: built-in name or TOML file (its rope data)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene value (repeatable)")
    p.add_argument("--signal", default="tension.sheave", help="tension output assessed [N] (default tension.sheave)")
    p.add_argument("--storm", type=_positive, default=10800.0,
                   help="storm duration of the most probable maximum [s] (default 10800: 3 hours)")
    p.add_argument("--settle", type=float, default=0.0, help="start-up time left out [s] (default 0)")
    p.add_argument("--output", default="out/fatigue", help="output folder (default out/fatigue)")
    p.set_defaults(func=cmd_fatigue)

    from .sweep.cli import add_parsers as add_sweep_parsers

    add_sweep_parsers(sub)

    p = sub.add_parser("docs", help="write the reference documentation (scene keys, FMU variables, command line)",
                       description="Generates Markdown from the scene schema, the variable contract and this "
                                   "parser: scene_keys.md, fmu_variables.md, cli.md.")
    p.add_argument("--output", default="docs/reference", help="output folder (default docs/reference)")
    p.set_defaults(func=cmd_docs)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``towcable`` console script."""
    args = build_parser().parse_args(argv)
    kernel_cache.WATCH.notice = kernel_cache.print_compile_notice
    try:
        return args.func(args)
    except TowcableError as exc:
        print(f"towcable: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
