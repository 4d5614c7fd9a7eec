"""The Capytaine door: a box barge's dataset computed by Capytaine (ship_motion/make_capytaine_barge.py,
committed as ship_motion/data/barge_capytaine.nc), its RAOs by capytaine.post_pro.rao."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from ship_motion import motion_from_config
from ship_motion.rao import GRAVITY
from ship_motion.rao_files import read_capytaine, write_wamit_4
from towcable_fmu.common.errors import SceneError

pytest.importorskip("capytaine")

BARGE = Path(__file__).resolve().parents[1] / "ship_motion" / "data" / "barge_capytaine.nc"


def test_long_waves_the_barge_follows_the_surface():
    """At 0.2 rad/s (wave length 1540 m, 38 barge lengths) heave = 1, pitch = i k cos(mu) and
    roll = -i k sin(mu) at the CG (the surface's elevation and slopes, our phase convention):
    Capytaine's exp(-i omega t) conjugated, its rotation centre moved to the CG."""
    table = read_capytaine(BARGE, symmetric=True)
    assert table.heading.size - int(table.periodic) == 8
    k = table.omega[0] ** 2 / GRAVITY
    mu = table.heading[:8]
    h = table.values[0, :8]
    np.testing.assert_allclose(h[:, 2], 1.0, atol=0.005)
    np.testing.assert_allclose(h[:, 4], 1j * k * np.cos(mu), atol=0.05 * k)
    np.testing.assert_allclose(h[:, 3], -1j * k * np.sin(mu), atol=0.05 * k)


def test_transfer_to_cg_against_capytaine_about_the_cg(tmp_path):
    """The committed dataset's DOFs are about a rotation centre 5 m forward of the CG; Capytaine
    solving the same barge with its DOFs about the CG gives the RAOs our transfer computes."""
    import capytaine as cpt

    from ship_motion.make_capytaine_barge import CENTRE_OF_MASS, barge_dataset

    omega, directions = [0.5, 0.9, 1.4], [45.0, 135.0]
    cpt.export_dataset(tmp_path / "cg.nc", barge_dataset(rotation_centre=CENTRE_OF_MASS, omega=omega,
                                                         directions_deg=directions))
    about_cg = read_capytaine(tmp_path / "cg.nc")
    moved = read_capytaine(BARGE)
    for j, d in enumerate(directions):
        expected = about_cg.values[:, j]
        got = moved(np.array(omega), math.radians(d), 0.0)
        np.testing.assert_allclose(got, expected, atol=1e-6 * np.abs(expected).max())


def test_same_barge_through_capytaine_and_wamit_doors(tmp_path):
    """The Capytaine RAOs written as a WAMIT .4 file (origin at the CG, ULEN 40 m, 9 digits) and
    read back: the same irregular short-crested motion to round-off."""
    table = read_capytaine(BARGE, symmetric=True)
    write_wamit_4(tmp_path / "barge.4", table, ulen=40.0)
    sea = {"type": "irregular", "hs": 2.0, "tp": 8.0, "heading": 160.0, "speed": 0.0, "components": 60,
           "spreading": 6.0, "directions": 12, "omega_min": 0.25, "omega_max": 1.9, "seed": 2}
    times = np.linspace(0.0, 200.0, 401)
    via_capytaine = motion_from_config({**sea, "rao": {"source": "capytaine", "file": str(BARGE),
                                                       "symmetric": True}}).evaluate_many(times)
    via_wamit = motion_from_config({**sea, "rao": {"source": "wamit", "file": str(tmp_path / "barge.4"),
                                                   "ulen": 40.0, "centre_of_gravity": [0.0, 0.0, 0.0]}}
                                   ).evaluate_many(times)
    scale = np.abs(via_capytaine).max(axis=(0, 1))
    assert np.all(scale[[2, 3, 4]] > 0.0)
    assert np.all(np.abs(via_wamit - via_capytaine).max(axis=(0, 1)) <= 1e-7 * scale + 1e-15)


def test_dataset_without_hydrostatics_is_an_error_naming_what_is_missing(tmp_path):
    import xarray

    from capytaine.io.xarray import merge_complex_values, separate_complex_values

    with xarray.open_dataset(BARGE) as raw:
        ds = merge_complex_values(raw.load()).drop_vars("hydrostatic_stiffness")
    separate_complex_values(ds).to_netcdf(tmp_path / "bad.nc")
    with pytest.raises(SceneError, match="missing: hydrostatic_stiffness") as err:
        motion_from_config({"type": "irregular", "rao": {"source": "capytaine", "file": "bad.nc"}},
                           base_dir=tmp_path)
    assert err.value.key == "motion.rao.file"
