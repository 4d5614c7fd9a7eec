"""Write ``ship_motion/data/barge_capytaine.nc``: a box barge's hydrodynamic dataset computed by Capytaine.

The barge: length 40 m, beam 10 m, draught 3 m, freely floating (mass = displaced
water, rho 1025 kg/m^3), centre of mass 0.5 m below the waterline amidships, radii
of gyration 0.35 B (roll) and 0.25 L (pitch, yaw); rigid-body DOFs about a rotation
centre 5 m forward of the centre of mass at the waterline (so that reading it
exercises the transfer to the CG). Deep water; wave frequencies 0.2 to 2.0 rad/s
every 0.1 rad/s; wave directions 0, 45, 90, 135, 180 deg (the barge is port-starboard
symmetric: the reader mirrors them). The dataset is saved by Capytaine's own
``export_dataset`` (netCDF; complex values split into real and imaginary parts).

Run: ``python -m ship_motion.make_capytaine_barge`` (needs ``pip install ".[capytaine]"``;
about a minute).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: Barge dimensions [m]: length, beam, draught.
LENGTH, BEAM, DRAUGHT = 40.0, 10.0, 3.0
#: Centre of mass and rotation centre [m] (x forward, y port, z up, origin amidships at the waterline).
CENTRE_OF_MASS = (0.0, 0.0, -0.5)
ROTATION_CENTRE = (5.0, 0.0, 0.0)
RHO = 1025.0
OMEGA = np.round(np.arange(0.2, 2.0001, 0.1), 10)
DIRECTIONS_DEG = (0.0, 45.0, 90.0, 135.0, 180.0)
OUTPUT = Path(__file__).parent / "data" / "barge_capytaine.nc"


def barge_dataset(rotation_centre: tuple[float, float, float] = ROTATION_CENTRE, omega=OMEGA,
                  directions_deg=DIRECTIONS_DEG):
    """The barge's Capytaine dataset (module docstring), with inertia and hydrostatic stiffness.

    Parameters
    ----------
    rotation_centre
        Point [m] the rigid-body DOFs refer to.
    omega
        Wave frequencies [rad/s].
    directions_deg
        Wave directions [deg].
    """
    import capytaine as cpt
    import xarray as xr

    cpt.set_logging("WARNING")
    mesh = cpt.mesh_parallelepiped(size=(LENGTH, BEAM, DRAUGHT), center=(0.0, 0.0, -DRAUGHT / 2.0),
                                   resolution=(20, 5, 3), missing_sides={"top"})
    mass = RHO * LENGTH * BEAM * DRAUGHT
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=rotation_centre),
                            center_of_mass=CENTRE_OF_MASS, mass=mass)
    # inertia about the centre of mass (radii of gyration), moved to the rotation centre by Huygens-Steiner
    gyration = np.array([0.35 * BEAM, 0.25 * LENGTH, 0.25 * LENGTH])
    arm = np.subtract(CENTRE_OF_MASS, rotation_centre)
    skew = np.array([[0.0, -arm[2], arm[1]], [arm[2], 0.0, -arm[0]], [-arm[1], arm[0], 0.0]])
    inertia = np.zeros((6, 6))
    inertia[:3, :3] = mass * np.eye(3)
    inertia[:3, 3:] = -mass * skew
    inertia[3:, :3] = mass * skew
    inertia[3:, 3:] = mass * np.diag(gyration ** 2) - mass * skew @ skew
    body.inertia_matrix = body.add_dofs_labels_to_matrix(inertia)
    body.hydrostatic_stiffness = body.compute_hydrostatic_stiffness(rho=RHO)
    grid = xr.Dataset(coords={"omega": np.asarray(omega), "wave_direction": np.radians(directions_deg),
                              "radiating_dof": list(body.dofs), "water_depth": [np.inf], "rho": [RHO]})
    return cpt.BEMSolver().fill_dataset(grid, body, hydrostatics=True)


def main() -> None:
    """Compute and save the dataset."""
    import capytaine as cpt

    cpt.export_dataset(OUTPUT, barge_dataset())
    print(f"wrote {OUTPUT}")


if __name__ == "__main__":
    main()
