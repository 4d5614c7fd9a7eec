"""Capytaine's hydrodynamic dataset (netCDF), RAOs by Capytaine's own post-processing.

Capytaine (https://github.com/capytaine/capytaine) saves the xarray dataset of a
computation with ``capytaine.export_dataset(path, dataset)`` as netCDF (complex
variables split along a ``complex`` dimension, merged back by
``capytaine.io.xarray.merge_complex_values``). The RAOs are computed from it by
``capytaine.post_pro.rao`` (the dataset must hold ``inertia_matrix`` and
``hydrostatic_stiffness``; one body with the six rigid-body DOFs Surge, Sway, Heave,
Roll, Pitch, Yaw).

Capytaine's conventions and their conversion:

- time factor ``exp(-i omega t)``: a complex amplitude X means ``Re X exp(-i omega t)``,
  so ours is its complex conjugate;
- per unit incident wave amplitude, phase relative to the incident wave at the origin
  of the global frame (x, y) = (0, 0);
- ``wave_direction`` [rad]: the direction the waves travel from the x axis, counter-
  clockwise (as ours when the mesh's x axis points to the bow, y to port, z up);
- rigid-body DOFs: translations of the ``rotation_center`` and rotations about it; the
  CG is the dataset's ``center_of_mass``. The reader moves the RAOs there (with the
  dataset's ``wavenumber`` for the phase in finite depth).

Needs ``pip install ".[capytaine]"``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from towcable_fmu.common.errors import SceneError

from ..rao import RaoTable
from .conventions import SourceFrame, mirror_half_range, move_to_cg

#: Capytaine's names of the rigid-body DOFs, in our order.
DOFS: tuple[str, ...] = ("Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw")
#: Variables and coordinates the reader needs.
REQUIRED: tuple[str, ...] = ("excitation_force", "added_mass", "radiation_damping", "inertia_matrix",
                             "hydrostatic_stiffness", "rotation_center", "center_of_mass")


def read_capytaine(path: str | Path, *, symmetric: bool = False, key: str = "file") -> RaoTable:
    """Read a Capytaine netCDF dataset into our RAOs at its centre of mass (module docstring).

    Parameters
    ----------
    path
        The netCDF file.
    symmetric
        The hull is port-starboard symmetric: the wave directions given are mirrored.
    key
        Configuration key naming the file (error messages).

    Raises
    ------
    SceneError
        If capytaine is not installed or the dataset lacks what the RAOs need.
    """
    path = Path(path)
    try:
        import capytaine.post_pro
        import xarray
        from capytaine.io.xarray import merge_complex_values
    except ImportError:
        raise SceneError(key, str(path), "capytaine installed to read its datasets (pip install "
                         "\".[capytaine]\")") from None
    if not path.is_file():
        raise SceneError(key, str(path), "an existing Capytaine dataset (netCDF)")
    try:
        with xarray.open_dataset(path) as raw:
            ds = merge_complex_values(raw.load())
    except (OSError, ValueError, TypeError) as exc:
        raise SceneError(key, str(path), f"a netCDF file written by capytaine.export_dataset ({exc})") from None
    missing = [name for name in REQUIRED if name not in ds.variables]
    if missing:
        raise SceneError(key, str(path), "a Capytaine dataset with " + ", ".join(REQUIRED) + " (missing: "
                         + ", ".join(missing) + "; inertia_matrix and hydrostatic_stiffness are set on the "
                         "body before solving)")
    dofs = [str(d) for d in ds["radiating_dof"].values]
    if sorted(dofs) != sorted(DOFS):
        raise SceneError(key, str(path), "a Capytaine dataset of one body with the DOFs " + ", ".join(DOFS)
                         + f" (found: {', '.join(dofs)})")
    for name in ("forward_speed", "water_depth", "rho", "g"):
        if name in ds.dims and ds.sizes[name] > 1:
            raise SceneError(key, str(path), f"a Capytaine dataset with one value of {name} (select one)")
    ds = ds.squeeze(drop=False)
    speed = float(ds["forward_speed"]) if "forward_speed" in ds.variables else 0.0
    if speed != 0.0:
        raise SceneError(key, str(path), f"a Capytaine dataset at zero forward speed (found {speed:g} m/s)")
    rao = capytaine.post_pro.rao(ds).transpose("omega", "wave_direction", "radiating_dof")
    values = np.conj(rao.sel(radiating_dof=list(DOFS)).values)
    omega = np.asarray(rao["omega"].values, dtype=float)
    order = np.argsort(omega)
    heading = np.mod(np.asarray(rao["wave_direction"].values, dtype=float), 2.0 * math.pi)
    h_order = np.argsort(heading)
    omega, heading, values = omega[order], heading[h_order], values[order][:, h_order]
    finite = "water_depth" in ds.variables and np.isfinite(float(ds["water_depth"]))
    wavenumber = np.asarray(ds["wavenumber"].values, dtype=float)[order] if finite else None
    frame = SourceFrame(rao_origin=tuple(map(float, ds["rotation_center"].values)), phase_origin=(0.0, 0.0),
                        centre_of_gravity=tuple(map(float, ds["center_of_mass"].values)))
    values = move_to_cg(omega, heading, values, frame, wavenumber)
    if symmetric:
        heading, values = mirror_half_range(heading, values)
    return RaoTable(omega, heading, values, label=path.name)
