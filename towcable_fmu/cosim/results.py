"""A co-simulation's files: ``cosim.csv``, ``summary.json`` and the plots."""

from __future__ import annotations

import json
from pathlib import Path


from ..common import contract
from .config import CosimResult


# ---------------------------------------------------------------------------- results
def write_results(result: CosimResult, outdir: str | Path, plot: bool = True, title: str = "") -> dict[str, Path]:
    """Write ``cosim.csv`` (columns = contract names), ``summary.json`` (parameters,
    geometry, timing) and ``cosim.png`` (plots) into ``outdir``."""
    from ..common.run_io import write_csv

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    files = {"csv": outdir / "cosim.csv", "summary": outdir / "summary.json"}
    write_csv(files["csv"], result.series)
    summary = {"parameters": result.parameters, "geometry": result.geometry, "timing": result.timing,
               "units": {name: contract.unit_of(name) for name in result.series}}
    files["summary"].write_text(json.dumps(summary, indent=2, default=str), encoding="utf-8")
    if plot:
        from ..common.plots import plot_cosim

        files["plot"] = outdir / "cosim.png"
        plot_cosim(result.series, files["plot"], title=title)
    return files
