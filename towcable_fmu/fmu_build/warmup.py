"""Compile the numerical kernels the FMUs run, by running them: every FMU of the
contract is instantiated and initialised, and takes two communication steps, on every
built-in scene its ``scene`` parameter accepts (the others on their defaults); the
ANCF cable's step for the loader layer is compiled too (not run).

The build runs this in a separate Python (:mod:`towcable_fmu.fmu_build.kernels`) to fill the
kernel cache that an FMU then carries precompiled.
"""

from __future__ import annotations

from importlib import import_module
from typing import Callable

from ..common import contract
from ..builtin_scenes import builtin_scene_names

#: Communication step of the warm-up [s].
STEP = 0.01


#: Prefix of our package names in this copy of the code: ``towcable_<digest>.`` in an
#: FMU's bundle, empty where installed (the contract names the slaves without it).
_PREFIX = __name__.removesuffix("towcable_fmu.fmu_build.warmup")


def _slave_class(spec: contract.FmuSpec):
    module, cls = spec.slave.split(":")
    return getattr(import_module(_PREFIX + module), cls)


def _run(cls, scene: str | None) -> None:
    """Initialise one instance (``scene`` set if given) and take two steps; raise
    RuntimeError if the FMU reports a failure."""
    slave = cls(instance_name="warm-up", resources=None)
    if scene is not None:
        slave.values["scene"] = scene
    slave.setup_experiment(0.0)
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    ok = slave.initialized and all(slave.do_step(k * STEP, STEP) for k in range(2))
    if not ok:
        raise RuntimeError(f"warm-up of {slave.modelName} on scene {scene!r} failed: {slave.failed or 'a step failed'}")
    # the step the loader layer calls in C (an ANCF cable's, towcable_fmu/ancf/native_step.py):
    # compiled here, not run (this slave has no loader layer)
    native, plan = getattr(getattr(slave, "sim", None), "native_step", None), getattr(slave, "_plan", None)
    if native is not None and plan is not None:
        native(int(plan.max()) + 1, plan)


def compile_kernels(report: Callable[[str], None] = print) -> list[str]:
    """Run every FMU on every scene it accepts (see the module docstring); ``report`` gets
    one line per run. Returns the ``<FMU>:<scene>`` names run."""
    done = []
    for spec in contract.fmus().values():
        cls = _slave_class(spec)
        takes_scene = any(var.name == "scene" for var in spec.parameters)
        for scene in (builtin_scene_names() if takes_scene else [None]):
            _run(cls, scene)
            done.append(f"{spec.name}:{scene or 'default'}")
            report(f"compiled for {done[-1]}")
    return done
