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
    ("Winch", ("winch.phi", "winch.payout", "winch.deployed")),
    ("Angles", ("angle.top", "sheave_angle", "contact.wrap_angle")),
)


def _save(fig, path: Path, title: str) -> None:
    """Title the figure, write it as PNG (creating the folder) and release it."""
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


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
    _save(fig, path, title)


def _time_panel(ax, t: np.ndarray, series: dict[str, np.ndarray], keys: tuple[str, ...], title: str,
                fallback: tuple[str, ...] = ()) -> None:
    """Plot the recorded, non-zero ``keys`` against time (else ``fallback``, else a note)."""
    shown = [k for k in keys if k in series and np.any(series[k] != 0.0)]
    note = ""
    if not shown:
        shown = [k for k in fallback if k in series and np.any(series[k] != 0.0)]
        note = (" (" + ", ".join(keys) + " not modelled in this scene; showing " + ", ".join(shown) + ")"
                if shown else " (" + ", ".join(keys) + " not modelled in this scene)")
    for k in shown:
        ax.plot(t, series[k], label=f"{k} [{contract.unit_of(k)}]", lw=1.0)
    ax.set_title(title + note, fontsize=9)
    ax.set_xlabel("time [s]")
    ax.grid(alpha=0.3)
    if shown:
        ax.legend(fontsize=8, loc="best")


def plot_cosim(series: dict[str, np.ndarray], path: Path, title: str = "") -> None:
    """The four views of a co-simulation: towed-body track, tension at the sheave, sheave
    contact force, winch rotation (with its set-point), saved as PNG.

    Outputs the scene does not model (all zero) are noted in the panel title; the
    tension panel then shows the tension at the cable's top end instead.
    """
    t = series["time"]
    fig, axes = plt.subplots(2, 2, figsize=(12, 7.5))
    ax = axes[0, 0]
    if "towbody.x" in series and np.any(series["towbody.x"] != 0.0):
        ax.plot(series["towbody.x"], series["towbody.z"], lw=1.0)
        ax.plot(series["towbody.x"][:1], series["towbody.z"][:1], "o", ms=4, label="start")
        ax.set_xlabel("towbody.x [m]")
        ax.set_ylabel("towbody.z [m]")
        ax.legend(fontsize=8)
        ax.set_title("Towed-body track (side view, inertial frame)", fontsize=9)
    else:
        ax.set_title("Towed-body track (no towed body in this scene)", fontsize=9)
    ax.grid(alpha=0.3)
    _time_panel(axes[0, 1], t, series, ("tension.sheave",), "Tension at the sheave", fallback=("tension.top",))
    _time_panel(axes[1, 0], t, series, ("contact.sheave_force",), "Sheave contact force")
    _time_panel(axes[1, 1], t, series, ("winch.phi", "winch.phi_sp"), "Winch rotation and set-point",
                fallback=("winch.phi_sp",))
    _save(fig, path, title)


def plot_contact_distribution(distribution: np.ndarray, path: Path, references: dict[int, tuple[str, float]],
                              title: str = "") -> None:
    """Contact force per unit length against the wrap angle, one panel per surface, as PNG.

    Parameters
    ----------
    distribution
        Rows (surface, angle [rad], force per unit length [N/m]) as given by
        :meth:`towcable_fmu.ancf.simulation.Simulation.contact_state`; surface 0 is the winch
        drum, 1 the sheave.
    path
        PNG file to write.
    references
        Surface -> (label, T / R_c [N/m]): the force per unit length of a frictionless
        wrap, tension over centreline radius, drawn as a dashed line.
    title
        Figure title.
    """
    names = {0: "winch drum", 1: "sheave"}
    surfaces = sorted(set(int(s) for s in distribution[:, 0])) or sorted(references)
    fig, axes = plt.subplots(1, max(1, len(surfaces)), figsize=(6 * max(1, len(surfaces)), 3.6), squeeze=False)
    for ax, surface in zip(axes[0], surfaces):
        rows = distribution[distribution[:, 0] == surface]
        order = np.argsort(rows[:, 1])
        ax.plot(np.degrees(rows[order, 1]), rows[order, 2], ".-", ms=3, lw=0.8, label="model")
        if surface in references:
            label, value = references[surface]
            ax.axhline(value, ls="--", color="k", lw=0.8, label=label)
        ax.set_xlabel("angle about the surface axis, from the ship's +Z towards +X [deg]")
        ax.set_ylabel("contact force per length [N/m]")
        ax.set_title(names.get(surface, f"surface {surface}"), fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    _save(fig, path, title)
