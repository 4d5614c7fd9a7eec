"""Plots of run results (matplotlib, non-interactive)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import contract  # noqa: E402

#: Panels: (title, output names) — a panel is drawn when any of its names was recorded.
PANELS = (
    ("Tension", ("tension.top", "tension.sheave", "tension.winch", "tension.towbody", "tension.bottom")),
    ("Contact force", ("contact.sheave_force", "contact.winch_force")),
    ("Towed body depth", ("towbody.z",)),
    ("Towed body track", ("towbody.x",)),
    ("Winch", ("winch.phi", "winch.payout")),
    ("Angles", ("angle.top", "sheave_angle", "contact.wrap_angle")),
)


def plot_run(series: dict[str, np.ndarray], path: Path, title: str = "") -> None:
    """Time-series panels of a run, one per quantity group, saved as PNG.

    Parameters
    ----------
    series
        Output name -> samples, including ``time`` [s].
    path
        PNG file to write.
    title
        Figure title.
    """
    t = series["time"]
    panels = [(name, [k for k in keys if k in series and np.any(series[k] != 0.0)]) for name, keys in PANELS]
    panels = [(name, keys) for name, keys in panels if keys]
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 2.4 * len(panels)), sharex=True, squeeze=False)
    for ax, (name, keys) in zip(axes[:, 0], panels):
        for k in keys:
            ax.plot(t, series[k], label=f"{k} [{contract.unit_of(k)}]", lw=1.0)
        ax.set_title(name, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    axes[-1, 0].set_xlabel("time [s]")
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
