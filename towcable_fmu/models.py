"""Which simulation class runs a scene: ANCF cable, nodal-position cable or rigid links.

The command line and the ``TowCable`` FMU both call :func:`simulation_for`, so a scene a
user can run from the command line runs in the FMU as well.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Iterable, Mapping

from .runtime.protocol import CableSimulation


def model_kind(scene: Any) -> str:
    """``"rigid_link"``, ``"nodal_position"`` or ``"ancf"``: the model a loaded scene asks for."""
    if getattr(scene, "model", "ancf") == "rigid_link":
        return "rigid_link"
    return scene.cable.formulation


#: Modules listing each model's kernels (``kernel_jobs()``, see
#: :mod:`towcable_fmu.jit.parallel_compile`); a model not listed compiles as it runs.
KERNEL_SOURCES = {"ancf": ("towcable_fmu.ancf.simulation_kernels", "towcable_fmu.runtime.input_kernels"),
                  "nodal_position": ("towcable_fmu.nodal.simulation_kernels", "towcable_fmu.runtime.input_kernels")}


def simulation_from(name_or_path: str | Path,
                    overrides: Mapping[str, Any] | Iterable[tuple[str, Any]] = ()) -> CableSimulation:
    """A new, uninitialised simulation of a built-in scene (by name) or a scene file, with
    dotted-key overrides (see :func:`simulation_for`)."""
    from .scene import load_scene

    return simulation_for(load_scene(name_or_path, overrides))


def simulation_for(scene: Any) -> CableSimulation:
    """A new, uninitialised simulation of a loaded scene (see :func:`model_kind`).

    Returns
    -------
    Simulation, NodalSimulation or RigidLinkSimulation
        Each a :class:`~towcable_fmu.runtime.protocol.CableSimulation`.
    """
    kind = model_kind(scene)
    if kind == "rigid_link":
        from .rigidlink.simulation import RigidLinkSimulation

        return RigidLinkSimulation(scene)
    if kind == "nodal_position":
        from .nodal.simulation import NodalSimulation

        return NodalSimulation(scene)
    from .ancf.simulation import Simulation

    return Simulation(scene)
