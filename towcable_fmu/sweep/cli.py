"""Command line of the sweeps: ``towcable sweep SPEC.toml`` and ``towcable sweep-plot``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def cmd_sweep(args: argparse.Namespace) -> int:
    """Run the missing cases of a sweep and print where the table is."""
    from ..models import KERNEL_SOURCES, model_kind
    from ..jit.parallel_compile import compile_ahead
    from ..scene import load_scene
    from .execute import run_sweep
    from .spec import load_spec

    spec = load_spec(args.spec)
    if args.scheduler is None:  # local workers: once here, on every core, not in each worker at the same time
        compile_ahead(KERNEL_SOURCES.get(model_kind(load_scene(spec.settings.scene)), ()), echo=not args.quiet)
    report = run_sweep(spec, workers=args.workers, scheduler=args.scheduler, retry_failed=args.retry_failed,
                       progress=not args.quiet, output=Path(args.output) if args.output else None)
    print(f"{report.table}: {report.total} cases, {report.skipped} were done before, {report.ran} run now "
          f"({report.failed} failed) in {report.wall_time:.1f} s"
          + (f", {report.cases_per_hour:.0f} cases/h" if report.ran else ""), file=sys.stderr)
    if spec.probabilities is not None:
        from .long_term import long_term_damage
        from .store import read_table

        for name, value in long_term_damage(spec, read_table(report.table)).items():
            life = f"{1.0 / value:.4g} years" if value > 0 else "-"
            print(f"long-term {name} (the cases weighted by their probabilities): {value:.4g} 1/year, life {life}")
    return 0


def cmd_sweep_plot(args: argparse.Namespace) -> int:
    """Heat map and/or exceedance curves from a sweep's results."""
    from .plots import plot_exceedance, plot_heatmap

    from .store import find_table

    table = find_table(Path(args.results))
    written = []
    if args.heatmap:
        statistic, x, y = args.heatmap
        out = Path(args.output or table.parent) / f"heatmap_{statistic}_{x}_{y}.png"
        written.append(plot_heatmap(table, statistic, x, y, out))
    if args.exceedance:
        out = Path(args.output or table.parent) / f"exceedance_{args.exceedance}.png"
        written.append(plot_exceedance(table, out, args.exceedance, args.label or ()))
    if not written:
        print("towcable sweep-plot: nothing to do: give --heatmap and/or --exceedance", file=sys.stderr)
        return 2
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0


def _count(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text}")
    return value


def add_parsers(sub: argparse._SubParsersAction) -> None:
    """Register ``sweep`` and ``sweep-plot`` on the ``towcable`` parser."""
    p = sub.add_parser("sweep", help="run a parameter sweep (local processes or a Dask cluster) into one table (CSV or Parquet)",
                       description="Runs every combination of the [parameters] of the sweep file that its "
                                   "results table ([sweep] table: results.csv, or a .parquet file) does not "
                                   "have yet (case id = hash of the full parameter set), "
                                   "on local processes or, with --scheduler, on a Dask distributed cluster; "
                                   "one row per case, appended as cases finish; failed cases are recorded "
                                   "with their error; the sweep goes on.")
    p.add_argument("spec", help="sweep TOML file (see towcable_fmu/example_sweeps/example.toml)")
    p.add_argument("--workers", type=_count, default=None, help="local processes (default: number of CPUs)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="Dask scheduler address, e.g. tcp://127.0.0.1:8786 (needs pip install 'towcable[dask]')")
    p.add_argument("--output", default=None, help="results folder (default: [sweep] output)")
    p.add_argument("--retry-failed", action="store_true", help="run the cases recorded as failed again")
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("sweep-plot", help="heat map of a statistic over two parameters, tension exceedance curves",
                       description="Plots from a sweep's results table (CSV or Parquet); PNG files go next to it "
                                   "(or to --output).")
    p.add_argument("results", help="results table of a sweep (.csv or .parquet), or its folder")
    p.add_argument("--heatmap", nargs=3, metavar=("STATISTIC", "X", "Y"),
                   help="statistic (e.g. tension.sheave.max) over swept parameters X and Y (mean over the others)")
    p.add_argument("--exceedance", nargs="?", const="tension.sheave", default=None, metavar="SIGNAL",
                   help="exceedance curves of SIGNAL (default tension.sheave) per case; needs series = true")
    p.add_argument("--label", nargs="+", default=None, help="parameters named in the exceedance legend")
    p.add_argument("--output", default=None, help="folder for the PNG files (default: the table's folder)")
    p.set_defaults(func=cmd_sweep_plot)
