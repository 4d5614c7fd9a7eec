"""One sea for ShipMotion and TowCable: the ``motion.config`` ShipMotion gets (and TowCable
as the item ``motion = {...}`` of its ``overrides``), and the check that the ship's sea and
the waves in TowCable's water are one realisation.

A scene with waves in the water (``[water] waves = "motion"``) takes them from its
``[motion]``; in a co-simulation the ship moves by ShipMotion's parameters instead. The
master (:func:`towcable_fmu.cosim.master.run_cosim`) therefore reduces ShipMotion's sea to
one ``[motion]`` table (:func:`shared_motion_config`), gives its TOML text to both FMUs
(and so to the SSP file), and refuses TowCable ``overrides`` given apart from it that
describe another sea (:func:`sea_mismatch`).
"""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..common import contract
from ..common.errors import SceneError

#: times [s] at which :func:`sea_mismatch` compares the elevations at the ship's reference point
CHECK_TIMES = np.linspace(0.0, 600.0, 601)


def ship_motion_table(ship: Mapping[str, Any]) -> tuple[dict, Any]:
    """The ``[motion]`` table (and its folder) of ShipMotion's parameters ``ship`` (name ->
    value; the contract's start values for the others), read as the FMU reads them."""
    from ship_motion.fmu import motion_table

    defaults = {var.name: var.start for var in contract.fmus()["ShipMotion"].parameters}
    return motion_table({**defaults, **ship})


def shared_motion_config(ship: Mapping[str, Any]) -> str:
    """The ``motion.config`` value of ShipMotion's sea: its own ``motion.config`` if it has
    one, else the table of its individual parameters as TOML text."""
    from ..scene.sea import motion_config_text

    given = str(ship.get("motion.config", "")).strip()
    if given:
        return given
    table, base = ship_motion_table(ship)
    return motion_config_text(table, base)


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and bool(np.array_equal(a, b))


def sea_mismatch(ship: Mapping[str, Any], cable_scene) -> str | None:
    """How ShipMotion's sea (parameters ``ship``) differs from the waves of TowCable's scene
    ``cable_scene``; None when they are one realisation or the scene has no waves.

    Compared: the components (frequencies, amplitudes, phases in their order, headings,
    encounter frequencies) and the ramp; the message names both seas and the largest
    difference of the elevation at the ship's reference point (its mean centre of
    gravity) over :data:`CHECK_TIMES`.
    """
    from ship_motion import IrregularSea, motion_from_config

    from ..hydro.waves import sea_of

    water = getattr(cable_scene, "water", None)
    if water is None or water.waves == "off":
        return None
    table, base = ship_motion_table(ship)
    ship_sea = motion_from_config(table, key="motion", base_dir=base)
    cable_sea = sea_of(cable_scene)
    if not isinstance(ship_sea, IrregularSea):
        return (f"TowCable's water has the waves of {cable_sea.description}, but ShipMotion's motion is "
                f"{ship_sea.description}")
    same = (ship_sea.ramp == cable_sea.ramp and ship_sea.speed == cable_sea.speed
            and all(_same(np.asarray(getattr(ship_sea.waves, k)), np.asarray(getattr(cable_sea.waves, k)))
                    for k in ("omega", "amplitude", "phase"))
            and _same(ship_sea.encounter_frequency, cable_sea.encounter_frequency)
            and ship_sea.heading == cable_sea.heading
            and (ship_sea.waves.heading is None) == (cable_sea.waves.heading is None)
            and (ship_sea.waves.heading is None or _same(ship_sea.waves.heading, cable_sea.waves.heading)))
    if same:
        return None
    eta_ship = ship_sea.wave_elevation(CHECK_TIMES)
    eta_cable = cable_sea.wave_elevation(CHECK_TIMES)
    k = int(np.argmax(np.abs(eta_ship - eta_cable)))
    return (f"ShipMotion's sea ({ship_sea.description}) is not the sea of TowCable's waves "
            f"({cable_sea.description}): at t = {CHECK_TIMES[k]:g} s the elevation at the ship's reference point "
            f"is {eta_ship[k]:.4g} m for the ship and {eta_cable[k]:.4g} m in TowCable's water")


def check_same_sea(ship: Mapping[str, Any], cable: Mapping[str, Any], cable_scene) -> None:
    """Raise if ShipMotion's parameters ``ship`` and TowCable's scene ``cable_scene`` (built
    from TowCable's parameters ``cable``) have different seas.

    Raises
    ------
    SceneError
        Naming TowCable's ``overrides`` and both seas.
    """
    problem = sea_mismatch(ship, cable_scene)
    if problem:
        raise SceneError("TowCable overrides", cable.get("overrides", ""),
                         f"the sea ShipMotion is given (its motion.config or motion.* parameters) as the item "
                         f"'motion = {{...}}'; {problem}")
