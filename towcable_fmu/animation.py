"""Animated GIF of a run: the cable over the sheave and winch, and the towed body.

Two panels: the side view (x-z) of the whole system, and a close-up of the winch and
sheave where the scene has them (else the plan view x-y). The drum and the sheave are
drawn at their positions on the moving ship, the drum with a spoke at the winch
rotation. Frames come from :func:`towcable_fmu.ancf.frames.run_with_frames`.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.animation import FuncAnimation, PillowWriter  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

from .ancf.frames import Frames  # noqa: E402
from .numerics.kinematics import rotation_matrix  # noqa: E402
from .scene.model import Scene  # noqa: E402


def surface_centres(frames: Frames, position: tuple[float, ...]) -> np.ndarray:
    """Inertial positions [m], shape (k, 3), of a point fixed in the ship frame at
    ``position`` [m] (the drum or sheave centre), one per frame."""
    local = np.asarray(position, dtype=float)
    return np.array([pose[:3] + rotation_matrix(pose[3], pose[4], pose[5]) @ local for pose in frames.ship])


def _drum_spokes(frames: Frames, scene: Scene, centres: np.ndarray) -> np.ndarray:
    """End of the drum's spoke [m], shape (k, 3): the cable attachment at rotation phi,
    measured from the top of the drum towards the ship's +X."""
    radius = scene.winch.radius
    out = np.empty_like(centres)
    for k, (pose, phi) in enumerate(zip(frames.ship, frames.winch_phi)):
        rot = rotation_matrix(pose[3], pose[4], pose[5])
        out[k] = centres[k] + rot @ (radius * np.array([np.sin(phi), 0.0, np.cos(phi)]))
    return out


def _equal_view(ax, xs: np.ndarray, ys: np.ndarray, margin: float = 0.05, least: float = 1e-9) -> None:
    """Limits that show every point of ``xs``, ``ys`` [m] at equal scale on both axes
    (the shorter side widened to the panel's shape, each side at least ``least`` [m]);
    call after the layout is fixed."""
    x0, x1 = float(np.min(xs)), float(np.max(xs))
    y0, y1 = float(np.min(ys)), float(np.max(ys))
    width = max((x1 - x0) * (1.0 + 2.0 * margin), least)
    height = max((y1 - y0) * (1.0 + 2.0 * margin), least)
    box = ax.get_position()
    fig_w, fig_h = ax.figure.get_size_inches()
    shape = (box.height * fig_h) / (box.width * fig_w)  # panel height / width
    width, height = max(width, height / shape), max(height, width * shape)
    ax.set_xlim(0.5 * (x0 + x1) - 0.5 * width, 0.5 * (x0 + x1) + 0.5 * width)
    ax.set_ylim(0.5 * (y0 + y1) - 0.5 * height, 0.5 * (y0 + y1) + 0.5 * height)


def _surfaces(frames: Frames, scene: Scene) -> list[tuple[str, np.ndarray, float]]:
    """The winch drum and the sheave of the scene: (name, centres [m] (k, 3), radius [m])."""
    out = []
    if scene.winch is not None:
        out.append(("winch", surface_centres(frames, scene.winch.position), scene.winch.radius))
    if scene.sheave is not None:
        out.append(("sheave", surface_centres(frames, scene.sheave.position), scene.sheave.radius))
    return out


def _close_up_box(surfaces: list[tuple[str, np.ndarray, float]]) -> tuple[np.ndarray, np.ndarray]:
    """Corners (x, z) [m] of a square around every position of the drum and sheave, at
    least six radii wide."""
    ring = np.concatenate([np.concatenate([c - r, c + r]) for _, c, r in surfaces])[:, [0, 2]]
    size = max(6.0 * max(r for _, _, r in surfaces), float(np.ptp(ring, axis=0).max()))
    middle = 0.5 * (ring.min(axis=0) + ring.max(axis=0))
    return middle[0] + np.array([-0.5, 0.5]) * size, middle[1] + np.array([-0.5, 0.5]) * size


def write_animation(frames: Frames, scene: Scene, path: Path, title: str = "", dpi: int = 72) -> int:
    """Draw the frames and save them as an animated GIF that plays in real time.

    Parameters
    ----------
    frames
        Snapshots of the run (at least one).
    scene
        The scene that was run (winch, sheave, towed body, water surface).
    path
        GIF file to write (folders are created).
    title
        Text before the time in the figure title.
    dpi
        Resolution [dots per inch] of the 10 x 4.5 inch figure.

    Returns
    -------
    int
        The number of frames written.
    """
    surfaces = _surfaces(frames, scene)
    spokes = _drum_spokes(frames, scene, surfaces[0][1]) if scene.winch is not None else None
    line = frames.centreline
    shown = line if frames.load is None else np.concatenate([line, frames.load[:, None, :]], axis=1)
    fig, (side, second) = plt.subplots(1, 2, figsize=(10, 4.5), gridspec_kw={"width_ratios": [3, 2]})
    panels = [(side, (0, 2), "side view")]
    if surfaces:
        panels.append((second, (0, 2), " and ".join(name for name, _, _ in surfaces)))
        box = _close_up_box(surfaces)
    else:
        panels.append((second, (0, 1), "plan view"))
        box = (shown[..., 0], shown[..., 1])
    artists = []
    for ax, (i, j), name in panels:
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("z [m]" if j == 2 else "y [m]")
        ax.grid(alpha=0.3)
        if scene.water is not None and j == 2:  # the free surface
            ax.axhline(scene.water.surface_z, color="tab:blue", lw=0.8, ls="--")
        circles = [ax.add_patch(Circle(tuple(centres[0, [i, j]]), r, fill=False, lw=1.2,
                                       color="tab:red" if name == "sheave" else "tab:green"))
                   for name, centres, r in surfaces] if j == 2 else []
        artists.append((i, j, ax.plot([], [], color="k", lw=1.2)[0], circles,
                        ax.plot([], [], color="tab:green", lw=1.0)[0],
                        ax.plot([], [], "o", color="tab:orange", ms=6)[0],
                        ax.plot([], [], color="tab:purple", lw=2.0)[0]))
    heading = fig.suptitle("")

    def draw(k: int) -> None:
        for i, j, cable, circles, spoke, body, load in artists:
            cable.set_data(line[k, :, i], line[k, :, j])
            for circle, (_, centres, _) in zip(circles, surfaces):
                circle.center = (centres[k, i], centres[k, j])
            if spokes is not None and circles:
                centre = surfaces[0][1][k]
                spoke.set_data([centre[i], spokes[k, i]], [centre[j], spokes[k, j]])
            if scene.towbody is not None:
                body.set_data([frames.nodes[k, -1, i]], [frames.nodes[k, -1, j]])
            if frames.load is not None:
                load.set_data([frames.nodes[k, -1, i], frames.load[k, i]], [frames.nodes[k, -1, j], frames.load[k, j]])
        heading.set_text(f"{title}   t = {frames.time[k]:7.2f} s")

    fig.tight_layout()
    _equal_view(side, shown[..., 0], shown[..., 2])
    _equal_view(second, *box, least=0.1 * float(np.ptp(shown[..., 2])))  # a plan view of a hanging cable
    count = frames.time.size
    animation = FuncAnimation(fig, draw, frames=count, blit=False)
    fps = 1.0 / frames.interval if count > 1 else 1.0
    path.parent.mkdir(parents=True, exist_ok=True)
    animation.save(str(path), writer=PillowWriter(fps=fps), dpi=dpi)
    plt.close(fig)
    return count
