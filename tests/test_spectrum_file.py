"""A directional spectrum from a wavespectra netCDF file (written by wavespectra itself)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from ship_motion import ClosedFormRao, motion_from_config
from ship_motion.spectrum_file import read_wavespectra
from towcable_fmu.common.errors import SceneError

pytest.importorskip("wavespectra")

FREQ = np.arange(0.04, 0.35, 0.005)
DIRS = np.arange(0.0, 360.0, 10.0)


def write_spectra(path, from_directions=(45.0,), spread=20.0):
    """JONSWAP x Cartwright spectra built and written by wavespectra, one per time."""
    from wavespectra.construct import construct_partition

    parts = [construct_partition("jonswap", "cartwright", freq_kwargs={"freq": FREQ, "fp": 0.1, "hs": 2.0},
                                 dir_kwargs={"dir": DIRS, "dm": d, "dspr": spread}) for d in from_directions]
    efth = xr.concat(parts, dim="time").assign_coords(time=np.arange(len(parts)).astype("datetime64[h]"))
    efth.to_dataset(name="efth").spec.to_netcdf(str(path))
    return efth


def test_energy_is_wavespectra_hs(tmp_path):
    """Hs of the file's spectrum as wavespectra computes it (without its high-frequency tail)."""
    from wavespectra import read_netcdf

    write_spectra(tmp_path / "sea.nc")
    spectrum = read_wavespectra(tmp_path / "sea.nc")
    hs = float(read_netcdf(str(tmp_path / "sea.nc")).isel(time=0).spec.hs(tail=False))
    assert hs == pytest.approx(2.0, rel=0.01)
    assert spectrum.significant_height == pytest.approx(hs, rel=1e-6)
    waves = spectrum.components(ship_heading=0.0, seed=1)
    assert 4.0 * math.sqrt(waves.variance) == pytest.approx(hs, rel=1e-6)


@pytest.mark.parametrize("ship_heading, expected", [(45.0, 180.0), (135.0, 270.0), (315.0, 90.0), (225.0, 0.0)])
def test_nautical_coming_from_becomes_our_heading(tmp_path, ship_heading, expected):
    """Waves from the north-east (45 deg): head seas for a ship heading north-east; on the
    starboard beam (travelling to starboard, 270) for one heading south-east; etc."""
    write_spectra(tmp_path / "sea.nc")
    waves = read_wavespectra(tmp_path / "sea.nc").components(ship_heading=ship_heading, seed=1)
    weight = waves.amplitude ** 2
    mean = math.degrees(math.atan2(np.sum(weight * np.sin(waves.heading)), np.sum(weight * np.cos(waves.heading))))
    assert (mean - expected + 180.0) % 360.0 - 180.0 == pytest.approx(0.0, abs=0.5)


def test_file_sea_heave_variance_is_the_sum_over_cells(tmp_path):
    """Equal spacing: the heave variance is sum |H(2 pi f, mu)|^2 E df dd over the file's cells."""
    write_spectra(tmp_path / "sea.nc")
    sea = motion_from_config({"type": "irregular", "spectrum": "file", "spectrum_file": "sea.nc",
                              "spectrum_record": 0, "ship_heading": 100.0, "spacing": "equal", "speed": 0.0},
                             base_dir=tmp_path)
    spectrum = read_wavespectra(tmp_path / "sea.nc", record=0)
    rao = ClosedFormRao()
    energy = spectrum.cell_energy
    expected = 0.0
    for j, theta in enumerate(spectrum.direction):
        mu = math.radians((100.0 - theta - 180.0) % 360.0)
        expected += np.sum(np.abs(rao(2.0 * math.pi * spectrum.frequency, mu, 0.0)[:, 2]) ** 2 * energy[:, j])
    assert sea.response_std()[2] ** 2 == pytest.approx(expected, rel=1e-10)
    assert "directional spectrum sea.nc[0]" in sea.description


def test_several_records_need_spectrum_record(tmp_path):
    write_spectra(tmp_path / "two.nc", from_directions=(45.0, 200.0))
    table = {"type": "irregular", "spectrum": "file", "spectrum_file": "two.nc", "ship_heading": 0.0}
    with pytest.raises(SceneError, match="spectrum_record") as err:
        motion_from_config(table, base_dir=tmp_path)
    assert err.value.key == "motion.spectrum_file"
    with pytest.raises(SceneError) as err:
        motion_from_config({**table, "spectrum_record": 1, "spreading": 3.0}, base_dir=tmp_path)
    assert err.value.key == "motion.spreading"
    with pytest.raises(SceneError) as err:
        motion_from_config({"type": "irregular", "spectrum": "file", "spectrum_file": "two.nc"}, base_dir=tmp_path)
    assert err.value.key == "motion.ship_heading"
    second = motion_from_config({**table, "spectrum_record": 1}, base_dir=tmp_path)
    assert "two.nc[1]" in second.description


def test_keys_the_file_replaces_are_refused(tmp_path):
    """hs, tp, heading and components describe a parametric sea: with a file they are an
    error naming the key, not silently ignored."""
    write_spectra(tmp_path / "sea.nc", from_directions=(45.0,))
    table = {"type": "irregular", "spectrum": "file", "spectrum_file": "sea.nc", "ship_heading": 0.0}
    motion_from_config(table, base_dir=tmp_path)
    for key, value in (("hs", 4.0), ("tp", 12.0), ("heading", 90.0), ("components", 50)):
        with pytest.raises(SceneError, match="absent with spectrum = 'file'") as err:
            motion_from_config({**table, key: value}, base_dir=tmp_path)
        assert err.value.key == f"motion.{key}"
