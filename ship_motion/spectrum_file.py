"""A directional wave spectrum read from a file in wavespectra's netCDF format.

wavespectra (https://github.com/wavespectra/wavespectra) stores E(f, theta) as the
variable ``efth`` [m^2/Hz/deg] with coordinates ``freq`` [Hz] and ``dir`` [deg]; the
directions are nautical, the direction the waves come **from**, clockwise from north;
further dimensions (``time``, ``site``) hold several spectra. The file is read with
``wavespectra.read_netcdf`` (``pip install ".[seas]"``); one spectrum is selected by
``record`` (its index along ``time``, and along ``site`` if any, 0 when there is only one).

Conversion to ours: with the ship's X axis on the compass heading psi_c (clockwise
from north), a component coming from theta travels towards theta + 180 deg, which is
at ``mu = psi_c - theta - 180 deg`` from the ship's X axis counter-clockwise (our
heading: 180 = head seas). Each (frequency, direction) cell is one wave component of
amplitude ``sqrt(2 E df dd)`` with wavespectra's own cell sizes (df = numpy.gradient of
the frequencies, dd = the direction spacing), so the variance of the sea is
wavespectra's ``hs(tail=False)^2 / 16``; its frequency is the cell's (``"equal"``) or
drawn uniformly within [f - df/2, f + df/2] (``"random"``), its phase uniform; both from
``numpy.random.default_rng(seed)``, phases first. Cells with no energy are dropped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from towcable_fmu.common.errors import SceneError

from .spectrum import SPACINGS, WaveComponents


@dataclass(frozen=True)
class DirectionalSpectrumFile:
    """One directional spectrum E(f, theta) of a wavespectra file (module docstring).

    Parameters
    ----------
    frequency
        Frequencies f [Hz], shape (nf,), increasing.
    direction
        Directions theta the waves come from [deg, nautical], shape (nd,), equally spaced.
    density
        E [m^2/Hz/deg], shape (nf, nd).
    label
        The file and record.
    """

    frequency: np.ndarray
    direction: np.ndarray
    density: np.ndarray
    label: str

    @property
    def cell_energy(self) -> np.ndarray:
        """E df dd [m^2] of each cell, shape (nf, nd)."""
        df = np.gradient(self.frequency) if self.frequency.size > 1 else np.ones(1)
        dd = abs(float(self.direction[1] - self.direction[0])) if self.direction.size > 1 else 1.0
        return self.density * df[:, None] * dd

    @property
    def significant_height(self) -> float:
        """4 sqrt(sum E df dd) [m]."""
        return 4.0 * math.sqrt(float(self.cell_energy.sum()))

    @property
    def peak_frequency(self) -> float:
        """Frequency [rad/s] of the largest sum of E over the directions."""
        return 2.0 * math.pi * float(self.frequency[np.argmax(self.density.sum(axis=1))])

    @property
    def description(self) -> str:
        """One line naming the file and its significant height."""
        return (f"directional spectrum {self.label} (Hs {self.significant_height:.3g} m, "
                f"{self.frequency.size} frequencies x {self.direction.size} directions)")

    def components(self, *, ship_heading: float, spacing: str = "random", seed: int = 0) -> WaveComponents:
        """The cells as wave components, headings relative to the ship (module docstring).

        Parameters
        ----------
        ship_heading
            Compass heading psi_c of the ship's X axis [deg], clockwise from north.
        spacing
            ``"random"`` or ``"equal"``.
        seed
            Seed of the phases (and frequencies).
        """
        if spacing not in SPACINGS:
            raise ValueError(f"spacing must be one of {SPACINGS}, got {spacing!r}")
        energy = self.cell_energy
        keep = energy > 0.0
        rng = np.random.default_rng(seed)
        phase = rng.uniform(0.0, 2.0 * math.pi, energy.shape)
        df = np.gradient(self.frequency) if self.frequency.size > 1 else np.zeros(1)
        offset = rng.uniform(-0.5, 0.5, energy.shape) if spacing == "random" else np.zeros(energy.shape)
        frequency = self.frequency[:, None] + offset * df[:, None]
        heading = np.radians(np.mod(ship_heading - self.direction - 180.0, 360.0))
        heading = np.broadcast_to(heading[None, :], energy.shape)
        return WaveComponents(omega=2.0 * math.pi * frequency[keep], amplitude=np.sqrt(2.0 * energy[keep]),
                              phase=phase[keep], heading=heading[keep])


def read_wavespectra(path: str | Path, *, record: int | None = None, key: str = "file") -> DirectionalSpectrumFile:
    """Read one spectrum of a wavespectra netCDF file (module docstring).

    Parameters
    ----------
    path
        The file.
    record
        Index of the spectrum along ``time`` (and ``site``); None: the file must hold one.
    key
        Configuration key naming the file (error messages).

    Raises
    ------
    SceneError
        Naming the file and what is wrong (wavespectra missing, no ``efth``, several records
        but no ``record``, a record out of range, negative or non-finite densities).
    """
    path = Path(path)
    try:
        from wavespectra import read_netcdf
    except ImportError:
        raise SceneError(key, str(path), "wavespectra installed to read spectrum files (pip install "
                         "\".[seas]\")") from None
    if not path.is_file():
        raise SceneError(key, str(path), "an existing wavespectra netCDF file")
    try:
        ds = read_netcdf(str(path)).load()
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise SceneError(key, str(path), f"a wavespectra netCDF file (efth over freq [Hz], dir [deg]): {exc}") from None
    efth = ds["efth"]
    extra = [d for d in efth.dims if d not in ("freq", "dir")]
    counts = [efth.sizes[d] for d in extra]
    if record is None and any(n > 1 for n in counts):
        raise SceneError(key, str(path), "one spectrum, or the key spectrum_record choosing one of the "
                         + " x ".join(f"{n} {d}" for d, n in zip(extra, counts)))
    index = 0 if record is None else record
    for d, n in zip(extra, counts):
        if index >= n and n > 1:
            raise SceneError(key, str(path), f"spectrum_record below {n} (the file's {d} count)")
        efth = efth.isel({d: min(index, n - 1)})
    if "dir" not in efth.dims:
        raise SceneError(key, str(path), "a directional spectrum (efth with a dir dimension)")
    efth = efth.transpose("freq", "dir").sortby("freq").sortby("dir")
    density = np.asarray(efth.values, dtype=float)
    if not np.all(np.isfinite(density)) or np.any(density < 0.0):
        raise SceneError(key, str(path), "finite densities efth >= 0 m^2/Hz/deg")
    return DirectionalSpectrumFile(frequency=np.asarray(efth["freq"].values, dtype=float),
                                   direction=np.asarray(efth["dir"].values, dtype=float), density=density,
                                   label=f"{path.name}[{index}]")
