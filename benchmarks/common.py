"""Shared helpers of the benchmarks: machine facts, timing, Markdown tables."""

from __future__ import annotations

import datetime
import os
import platform
import statistics
import subprocess
import sys
import time
from importlib import metadata
from pathlib import Path
from typing import Callable, Sequence

RESULTS = Path(__file__).parent / "results"


def machine_header() -> str:
    """Markdown lines naming the machine, versions and date of a measurement."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    versions = []
    for pkg in ("numpy", "scipy", "numba", "towcable"):
        try:
            versions.append(f"{pkg} {metadata.version(pkg)}")
        except metadata.PackageNotFoundError:
            pass
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                                cwd=Path(__file__).parent, check=False).stdout.strip()
    except OSError:
        commit = ""
    return (f"- date: {datetime.date.today().isoformat()}\n"
            f"- machine: {cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}\n"
            f"- Python {platform.python_version()}; {', '.join(versions)}\n"
            f"- commit: {commit or 'unknown'}\n")


def median_time(fn: Callable[[], object], repeats: int = 3) -> tuple[float, object]:
    """Median wall time [s] of ``repeats`` calls and the last result."""
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def per_call_us(fn: Callable[[], object], min_time: float = 0.2) -> float:
    """Median time of one call [us] over batches lasting about ``min_time`` seconds."""
    fn()
    n = 1
    while True:
        start = time.perf_counter()
        for _ in range(n):
            fn()
        elapsed = time.perf_counter() - start
        if elapsed > 0.02:
            break
        n *= 4
    batches = max(3, int(min_time / elapsed))
    samples = []
    for _ in range(batches):
        start = time.perf_counter()
        for _ in range(n):
            fn()
        samples.append((time.perf_counter() - start) / n)
    return 1e6 * statistics.median(samples)


def markdown_table(headers: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """A Markdown table; floats are printed with 4 significant digits."""
    def cell(x: object) -> str:
        return f"{x:.4g}" if isinstance(x, float) else str(x)
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(cell(x) for x in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def run_python(code: str, env: dict | None = None) -> float:
    """Wall time [s] of a fresh Python process running ``code``."""
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], check=True, env={**os.environ, **(env or {})})
    return time.perf_counter() - start


def scene_time_step(scene: str) -> float:
    """A built-in scene's own time step [s] (what its settings ship with)."""
    from towcable_fmu.scene import load_scene

    return float(load_scene(scene).solver.time_step)


def timed_scene_runs(scene: str, overrides: dict, duration: float, interval: float,
                     repeats: int = 1) -> tuple[float, dict, dict]:
    """Median wall time [s] of ``repeats`` runs of a scene (statics excluded), the last
    run's series and its solver statistics."""
    import numpy as np

    from towcable_fmu.ancf.simulation import Simulation

    results = []
    for _ in range(repeats):
        sim = Simulation.from_scene(scene, overrides)
        sim.initialize()
        start = time.perf_counter()
        series = sim.run(duration, interval=interval)
        results.append((time.perf_counter() - start, series, sim.statistics()))
    return float(np.median([r[0] for r in results])), results[-1][1], results[-1][2]


def relative_rms_errors(series: dict, ref: dict, names: Sequence[str]) -> dict[str, float]:
    """RMS of each series' difference to the reference, relative to the reference's mean
    magnitude, or for a depth (``towbody.z``) to its RMS motion about its mean."""
    import numpy as np

    out = {}
    for name in names:
        diff = np.sqrt(np.mean((series[name] - ref[name]) ** 2))
        scale = np.std(ref[name]) if name == "towbody.z" else np.mean(np.abs(ref[name]))
        out[name] = float(diff / scale)
    return out
