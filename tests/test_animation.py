"""Animation of a run: frames come from the simulation, the GIF has one image per frame."""

from __future__ import annotations

import csv

import numpy as np
import pytest
from PIL import Image

from towcable_fmu.animation import surface_centres, write_animation
from towcable_fmu.cli import main
from towcable_fmu.ancf.frames import Frames, frame_stride, run_with_frames
from towcable_fmu.numerics.kinematics import rotation_matrix
from towcable_fmu.ancf.simulation import Simulation


def gif_frames(path) -> tuple[int, list[int]]:
    """Number of images in a GIF and their durations [ms]."""
    with Image.open(path) as im:
        durations = []
        for k in range(im.n_frames):
            im.seek(k)
            durations.append(im.info["duration"])
        return im.n_frames, durations


#: A step that divides the frame interval: the frames' pieces then take the steps a run
#: without frames takes (with the scene's 8 ms, 0.1 s is 12.5 steps and the pieces would cut
#: a step at every frame: a different, equally valid discretisation, not the same run)
FLUME_STEP = {"solver.time_step": 0.005}


@pytest.fixture(scope="module")
def flume_run():
    """One second of the flume scene (winch, towed body) with frames every 0.1 s."""
    sim = Simulation.from_scene("flume", FLUME_STEP)
    series, frames = run_with_frames(sim, 1.0, 0.1, interval=0.05)
    return sim, series, frames


def test_frames_start_at_the_statics_and_follow_the_run(flume_run):
    sim, series, frames = flume_run
    np.testing.assert_allclose(frames.time, np.linspace(0.0, 1.0, 11), atol=1e-12)
    reference = Simulation.from_scene("flume", FLUME_STEP)
    reference.initialize()
    np.testing.assert_array_equal(frames.nodes[0], reference.node_positions())
    plain = reference.run(1.0, interval=0.05)
    # the same outputs as a run without frames, and the last frame is its final state. The
    # pieces land exactly on the frame times, where the single run's time has accumulated
    # round-off: the two differ by round-off carried through Newton's tolerance, which acts
    # on the balance of the largest forces (or the largest values of the unit), not on each
    # signal's own size (a free end's 8 mN tension differs by 1e-11 N in a cable pulling 32 mN)
    assert list(series) == list(plain)
    scale = {}
    for name in plain:
        unit = reference.unit_of(name)
        scale[unit] = max(scale.get(unit, 0.0), float(np.abs(plain[name]).max()))
    for name in plain:
        np.testing.assert_allclose(series[name], plain[name], rtol=1e-9, atol=1e-9 * scale[reference.unit_of(name)],
                                   err_msg=name)
    np.testing.assert_allclose(frames.nodes[-1], reference.node_positions(), rtol=1e-9, atol=1e-12)
    # the cable moved between the frames, and the centreline passes through the nodes
    assert np.abs(frames.nodes[-1] - frames.nodes[0]).max() > 1e-4
    np.testing.assert_array_equal(frames.centreline[:, ::4], frames.nodes)
    assert frames.winch_phi[0] == pytest.approx(sim.scene.winch.phi_nom)


def test_gif_has_one_image_per_frame_played_in_real_time(flume_run, tmp_path):
    sim, _, frames = flume_run
    path = tmp_path / "flume.gif"
    assert write_animation(frames, sim.scene, path, title="flume") == 11
    count, durations = gif_frames(path)
    assert count == 11
    assert all(d == 100 for d in durations)


def test_surfaces_move_with_the_ship():
    pose = np.array([10.0, -2.0, 0.5, 0.1, -0.2, 0.7])
    frames = Frames(time=np.zeros(1), nodes=np.zeros((1, 2, 3)), centreline=np.zeros((1, 2, 3)),
                    ship=pose[None, :], winch_phi=np.zeros(1), load=None)
    local = (-3.0, 0.5, 2.0)
    expected = pose[:3] + rotation_matrix(0.1, -0.2, 0.7) @ np.array(local)
    np.testing.assert_allclose(surface_centres(frames, local)[0], expected, rtol=1e-12)
    assert not np.allclose(expected, pose[:3] + np.array(local))


def test_frame_interval_is_a_multiple_of_the_output_interval():
    assert frame_stride(0.1, 0.05) == 2
    assert frame_stride(0.1, 0.3) == 1
    assert frame_stride(0.26, 0.05) == 5


def test_run_command_writes_the_animation_and_the_full_csv(tmp_path):
    out, gif = tmp_path / "run.csv", tmp_path / "run.gif"
    assert main(["run", "pulley_static", "--duration", "0.4", "--interval", "0.02", "--output", str(out),
                 "--animate", str(gif), "--fps", "10", "--quiet"]) == 0
    with open(out, encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    assert len(rows) == 1 + 21
    assert "load.angle" in rows[0]
    assert gif_frames(gif)[0] == 5


def test_frames_of_a_rigid_load_hold_its_centre_of_inertia():
    sim = Simulation.from_scene("pulley_static")
    _, frames = run_with_frames(sim, 0.2, 0.1, interval=0.05)
    assert frames.nodes.shape == (3, sim.mesh.n_nodes, 3)
    assert frames.load.shape == (3, 3)
    link = np.linalg.norm(frames.load - frames.nodes[:, -1], axis=1)
    np.testing.assert_allclose(link, sim.scene.load.length_pi, rtol=1e-2)
