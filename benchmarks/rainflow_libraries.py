"""The rainflow library of towcable_fmu/rope_life/ chosen by measurement: ``rainflow``
against ``fatpack`` on one random tension history, Miner sums on API RP 2SK's six-strand
exponent (M = 4.09) and times (medians of repeats, both in the same run).

    pip install fatpack        # not a dependency of towcable; rainflow is
    python benchmarks/rainflow_libraries.py [--samples 200000] [--repeats 5] [--output benchmarks/results/rainflow_libraries.md]

fatpack sorts the reversals into k classes before counting (its ``k``, default 64), so its
ranges are rounded to the class width; rainflow counts the signal's own ranges. The
reference sum is rainflow's; fatpack's residue counts as half cycles, as ASTM E1049 does.
"""

from __future__ import annotations

import argparse
import platform
import time
from pathlib import Path

import numpy as np


def tension_history(samples: int, seed: int = 1) -> np.ndarray:
    """A sea-like tension [N]: 60 random-phase waves of 0.06-0.2 Hz about 4 kN, at 20 Hz."""
    rng = np.random.default_rng(seed)
    t = np.arange(samples) * 0.05
    f, a, ph = rng.uniform(0.06, 0.2, 60), rng.rayleigh(1.0, 60), rng.uniform(0, 2 * np.pi, 60)
    return 4000.0 + 300.0 * (a[None, :] * np.sin(2 * np.pi * f[None, :] * t[:, None] + ph)).sum(1) / np.sqrt(60)


def miner_sum_rainflow(y: np.ndarray, m: float) -> float:
    import rainflow

    return float(sum(count * rng ** m for rng, _, count, _, _ in rainflow.extract_cycles(y)))


def miner_sum_fatpack(y: np.ndarray, m: float, k: int) -> float:
    import fatpack

    reversals, _ = fatpack.find_reversals(y, k=k)
    cycles, residue = fatpack.find_rainflow_cycles(reversals)
    full = np.abs(cycles[:, 1] - cycles[:, 0])
    half = np.abs(np.diff(residue))
    return float((full ** m).sum() + 0.5 * (half ** m).sum())


def median_time(fn, repeats: int) -> tuple[float, float]:
    times, value = [], 0.0
    for _ in range(repeats):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times)), value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--output", default="benchmarks/results/rainflow_libraries.md")
    args = parser.parse_args()
    y, m = tension_history(args.samples), 4.09
    t_ref, ref = median_time(lambda: miner_sum_rainflow(y, m), args.repeats)
    rows = [("rainflow", "-", t_ref, ref)]
    for k in (64, 1024, 65536):
        t, value = median_time(lambda k=k: miner_sum_fatpack(y, m, k), args.repeats)
        rows.append(("fatpack", str(k), t, value))
    lines = [f"# rainflow against fatpack ({args.samples} samples, M = {m}, median of {args.repeats})", "",
             f"Machine: {platform.processor() or platform.machine()}, Python {platform.python_version()} "
             "(shared with other jobs: compare the ratios).", "",
             "| library | k | time [ms] | time / rainflow's | Miner sum / rainflow's - 1 |", "|---|---|---|---|---|"]
    for name, k, t, value in rows:
        lines.append(f"| {name} | {k} | {1e3 * t:.1f} | {t / t_ref:.2f} | {value / ref - 1.0:+.2e} |")
    text = "\n".join(lines) + "\n"
    Path(args.output).write_text(text, encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
