"""Run one sweep case in the current process (a pool process or a Dask worker).

:func:`run_case` never raises for a failing case: an invalid parameter, a solver that
cannot advance, an FMU that discards a step (any exception of the case) is returned as
a result with status ``"failed"`` and the error message, so that the sweep goes on.
"""

from __future__ import annotations

import dataclasses
import math
import os
import socket
import time
import traceback
from pathlib import Path
from typing import Mapping

import numpy as np

from .spec import Case
from .statistics import compute_statistics, statistic


@dataclasses.dataclass
class CaseResult:
    """Outcome of one case.

    Attributes
    ----------
    case_id
        The case's hash.
    status
        ``"ok"`` or ``"failed"``.
    error
        Error message of a failed case ('' when ok).
    statistics
        Statistic name -> value (NaN for a failed case).
    wall_time
        Wall time of the case [s].
    worker
        ``host:pid`` of the process that ran it.
    series
        The recorded series when the case asked for them, else None.
    cpu_time
        CPU time of the worker process during the case (all its threads) [s]; NaN when
        the case was lost with its worker.
    started
        Wall-clock time at which the case started (``time.time()`` of the worker) [s
        since the epoch]; NaN when lost.
    """

    case_id: str
    status: str
    error: str
    statistics: dict[str, float]
    wall_time: float
    worker: str
    series: dict[str, np.ndarray] | None = None
    cpu_time: float = math.nan
    started: float = math.nan


def simulate(case: Case, fmus: Mapping[str, Path] | None = None) -> dict[str, np.ndarray]:
    """The case's output series (contract names, ``time`` first).

    Scene mode runs the scene's own simulation (:func:`towcable_fmu.models.simulation_from`:
    ANCF, nodal-position or rigid-link, with the scene's ship motion and compensation); cosim mode runs the three FMUs with the overridden scene's
    ``[motion]`` table given to ShipMotion.
    """
    s = case.settings
    if s.mode == "scene":
        from ..models import simulation_from

        return simulation_from(s.scene, case.overrides).run(s.duration, interval=s.interval)
    from ..cosim import CosimConfig, run_cosim
    from ..scene import format_overrides, load_scene

    scene = load_scene(s.scene, case.overrides)
    motion = None
    if getattr(scene, "motion", None):  # (none in a rigid-link scene)
        motion = "[motion]\n" + "\n".join(format_overrides([(k, v)]) for k, v in scene.motion.items())
    config = CosimConfig(scene=s.scene, overrides=case.overrides, duration=s.duration, step=s.step,
                         interval=s.interval, motion=motion, fmu_dir=s.fmu_dir)
    return run_cosim(config, echo=False, fmus=fmus).series


def _rope(case: Case):
    """The case's rope data when a statistic needs it (else None)."""
    if not any(statistic(n).needs_rope for n in case.statistics):
        return None
    from ..rope_life.assessment import scene_rope
    from ..scene import load_scene

    return scene_rope(load_scene(case.settings.scene, case.overrides))


def run_case(case: Case, fmus: Mapping[str, Path] | None = None) -> CaseResult:
    """Run one case and compute its statistics (see the module docstring).

    Parameters
    ----------
    case
        The case.
    fmus
        FMU name -> ``.fmu`` file (cosim mode); default: built or found in ``fmu_dir``.

    Returns
    -------
    CaseResult
        Status ``"ok"`` with the statistics, or ``"failed"`` with the error message.
    """
    worker = f"{socket.gethostname()}:{os.getpid()}"
    started = time.time()
    start = time.perf_counter()
    cpu = time.process_time()
    try:
        series = simulate(case, fmus)
        stats = compute_statistics(series, case.statistics, case.settings.settle, case.settings.fraction,
                                   _rope(case))
    except Exception as exc:  # noqa: BLE001 - every failure of a case is recorded, the sweep goes on
        message = f"{type(exc).__name__}: {exc}".replace("\n", " ")
        if not _is_expected(exc):
            message += " | " + traceback.format_exc(limit=3).replace("\n", " ")
        return CaseResult(case.case_id, "failed", message, {n: math.nan for n in case.statistics},
                          time.perf_counter() - start, worker, cpu_time=time.process_time() - cpu, started=started)
    return CaseResult(case.case_id, "ok", "", stats, time.perf_counter() - start, worker,
                      series if case.keep_series else None, cpu_time=time.process_time() - cpu, started=started)


def _is_expected(exc: Exception) -> bool:
    """Errors of the model (bad input, solver, FMU) carry their own explanation."""
    from ..common.errors import TowcableError

    return isinstance(exc, TowcableError)



def warm_up(case: Case) -> float:
    """Load (or compile) the kernels a case needs, in this process, before timing cases.

    Runs the case's scene for one recording interval (scene mode; in cosim mode only the
    modules are imported). Any error is ignored: the case itself will report it.

    Parameters
    ----------
    case
        A case of the sweep (its scene and overrides choose the kernels).

    Returns
    -------
    float
        Wall time spent [s].
    """
    start = time.perf_counter()
    try:
        if case.settings.mode == "scene":
            from ..models import simulation_from

            for overrides in (case.overrides, ()):
                try:
                    simulation_from(case.settings.scene, overrides).run(case.settings.interval,
                                                                        interval=case.settings.interval)
                    break
                except Exception:  # noqa: BLE001 - an invalid case: warm up with the base scene
                    continue
        else:
            from .. import cosim  # noqa: F401
    except Exception:  # noqa: BLE001 - warming up is optional
        pass
    return time.perf_counter() - start
