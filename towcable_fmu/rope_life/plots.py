"""Figures of a rope-life assessment: bending cycles along the rope and the rainflow
histogram of the tension (matplotlib, non-interactive)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .tension_fatigue import Cycles  # noqa: E402


def plot_bending_along_rope(x: np.ndarray, sheave: np.ndarray, drum: np.ndarray, path: Path, title: str,
                            damage: np.ndarray | None = None) -> Path:
    """Bending cycles per hour along the rope (and the bending damage per year), zoomed on
    the part that bends.

    Parameters
    ----------
    x
        Material points, unstretched distance from the bottom end [m].
    sheave, drum
        Bending cycles per hour over the sheave and onto/off the drum [1/h].
    path
        PNG to write.
    title
        Figure title.
    damage
        Bending damage per year at the points [1/year] (None: no lower panel).
    """
    bent = np.flatnonzero((sheave > 0) | (drum > 0))
    if damage is None:
        fig, ax = plt.subplots(figsize=(8, 4))
    else:
        fig, (ax, lower) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
        lower.plot(x, damage, color="C3")
        lower.set_ylabel("bending damage per year [1/year]")
        lower.set_xlabel("material point: unstretched distance from the bottom end [m]")
        lower.grid(True, alpha=0.3)
    ax.plot(x, sheave, label="over the sheave")
    ax.plot(x, drum, label="onto / off the drum")
    if bent.size:
        margin = max(0.5, 0.1 * (x[bent[-1]] - x[bent[0]]))
        ax.set_xlim(x[bent[0]] - margin, x[bent[-1]] + margin)
    if damage is None:
        ax.set_xlabel("material point: unstretched distance from the bottom end [m]")
    ax.set_ylabel("bending cycles per hour [1/h]")
    ax.set_title(title, fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_rainflow_histogram(cycles: Cycles, breaking_strength: float, path: Path, title: str, bins: int = 40) -> Path:
    """Histogram of the rainflow cycles by tension range over the breaking strength.

    Parameters
    ----------
    cycles
        Rainflow cycles of the tension [N].
    breaking_strength
        Minimum breaking strength [N].
    path
        PNG to write.
    title
        Figure title.
    bins
        Number of range classes.
    """
    fig, ax = plt.subplots(figsize=(8, 4))
    ratio = cycles.ranges / breaking_strength
    if ratio.size:
        ax.hist(ratio, bins=bins, weights=cycles.counts, log=True)
    ax.set_xlabel("tension range R / minimum breaking strength [-]")
    ax.set_ylabel("cycles [-]")
    ax.set_title(title, fontsize=9)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
