"""Compile a command's kernels on every core the first time it runs (a cold kernel cache).

numba compiles one kernel at a time in a process, and a model's kernels form a small
graph: the ANCF force terms' kernels, the residual and iteration matrix that call them,
its output kernel, then the integrator step that calls the residual and the matrix, then
the recording loop that calls the integrator and the outputs. Run one after the other
they take about 65 s on one core of the 2-core machine class; spread over the cores they
take about 38 s (the longest path through the graph, with both cores busy).

A model lists its kernels as :class:`Job`\\ s (``kernel_jobs()`` of its simulation module:
the kernel, example arguments of the types the run passes, a cost estimate, the jobs it
calls). :func:`compile_kernels` keeps the jobs whose kernels are not in the cache, plans
them over ``workers`` processes (list scheduling by cost, :func:`plan`), starts one helper
Python per extra worker, compiles its own share and waits for the helpers. Each finished
job leaves a marker file; a job whose callee another process compiles waits for that
marker, then finds the callee in the cache. A helper that fails only costs time: what it
left undone is compiled in-process, when the command calls it.

The helpers import the very package files this process runs (the folder holding them
goes first on their module path) and inherit its environment, so they write the same
kernel cache (:mod:`towcable_fmu.jit.kernel_cache`). The copy of the code an FMU carries is
imported under another name and compiles in its own process only (one worker).
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

import numba

from . import kernel_cache
from .kernel_cache import ROOT

#: Polling interval while waiting for another process's job [s].
_POLL = 0.05
#: Script of a helper Python: argv = package folder, job sources, marker folder, this
#: helper's jobs, jobs of the other processes, main process id.
_HELPER = """
import sys
sys.path.insert(0, sys.argv[1])
from towcable_fmu.jit.parallel_compile import helper_main
sys.exit(helper_main(sys.argv[2:]))
"""


@dataclass(frozen=True)
class Job:
    """One kernel to compile, with the argument types a run calls it with.

    Attributes
    ----------
    name
        Unique name (``"ancf.residual"``).
    kernel
        The numba dispatcher (``cache=True``).
    arguments
        Returns example arguments of the types the run passes (built when compiling, not
        when checking the cache).
    cost
        Estimated compile time [s] on one core, for planning only.
    needs
        Names of the jobs whose kernels this one calls (compiled first, or loaded).
    """

    name: str
    kernel: Any
    arguments: Callable[[], tuple]
    cost: float
    needs: tuple[str, ...] = ()

    def cached(self) -> bool:
        """Whether the kernel cache already has this kernel (its index file exists)."""
        cache = getattr(self.kernel, "_cache", None)
        index = getattr(getattr(cache, "_cache_file", None), "_index_path", None)
        return index is None or os.path.exists(index)  # no cache: nothing to prepare

    def compile(self) -> None:
        """Compile the kernel for the argument types (loads it if cached meanwhile)."""
        self.kernel.compile(tuple(numba.typeof(a) for a in self.arguments()))


def load_jobs(sources: Iterable[str]) -> list[Job]:
    """The jobs of each source ``"package.module"`` (its ``kernel_jobs()``), in order (a
    source listed twice, by two model kinds, once)."""
    jobs: list[Job] = []
    for source in dict.fromkeys(sources):
        jobs.extend(importlib.import_module(source).kernel_jobs())
    return jobs


def plan(jobs: Sequence[Job], workers: int) -> list[int]:
    """The worker (0 = this process) of each job: list scheduling in the jobs' order, each
    job to the worker that can finish it first (after its ``needs``), by estimated cost."""
    free = [0.0] * workers
    finish: dict[str, float] = {}
    owners = []
    for job in jobs:
        ready = max((finish[n] for n in job.needs if n in finish), default=0.0)
        worker = min(range(workers), key=lambda w: (max(free[w], ready), w))
        finish[job.name] = free[worker] = max(free[worker], ready) + job.cost
        owners.append(worker)
    return owners


def _marker(folder: Path, name: str, ok: bool) -> Path:
    return folder / f"{name}.{'done' if ok else 'failed'}"


def _wait(folder: Path, names: Iterable[str], alive: Callable[[str], bool]) -> None:
    """Wait until each job of ``names`` has a marker, or the process that owns it is gone."""
    for name in names:
        while not (_marker(folder, name, True).exists() or _marker(folder, name, False).exists()):
            if not alive(name):
                return
            time.sleep(_POLL)


def _run_jobs(jobs: Sequence[Job], others: set[str], folder: Path, alive: Callable[[str], bool]) -> list[str]:
    """Compile ``jobs`` in order, waiting for needs in ``others``; a marker per job (a
    failure's holds the traceback). Returns the failures (name: error)."""
    failures = []
    for job in jobs:
        _wait(folder, [n for n in job.needs if n in others], alive)
        try:
            job.compile()
        except Exception as exc:  # the run compiles it again, and reports a real error then
            failures.append(f"{job.name}: {type(exc).__name__}: {' '.join(str(exc).split())[:400]}")
            _marker(folder, job.name, False).write_text(f"{failures[-1]}\n{traceback.format_exc()}", encoding="utf-8")
        else:
            _marker(folder, job.name, True).touch()
    return failures


def compile_kernels(sources: Sequence[str], workers: int | None = None,
                    notice: Callable[[int, int], None] | None = None) -> list[str]:
    """Compile the jobs of ``sources`` whose kernels are not cached, on ``workers``
    processes (default: the CPUs this process may use).

    Parameters
    ----------
    sources
        Modules with a ``kernel_jobs()`` (see the module docstring).
    workers
        Processes to use, this one included.
    notice
        Called once before compiling, with the number of jobs and of processes.

    Returns
    -------
    list of str
        The jobs that failed to compile here (name: error); they compile again when the
        run calls them.
    """
    jobs = [job for job in load_jobs(sources) if not job.cached()]
    if not jobs:
        return []
    if workers is None:
        workers = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if __name__ != "towcable_fmu.jit.parallel_compile":  # an FMU's copy: helpers would import another name
        workers = 1
    workers = max(1, min(workers, len(jobs)))
    owners = plan(jobs, workers)
    if notice is not None:
        notice(len(jobs), workers)
    with tempfile.TemporaryDirectory(prefix="towcable_compile_") as tmp:
        folder = Path(tmp)
        helpers = {}
        for worker in range(1, workers):
            mine = [job.name for job, owner in zip(jobs, owners) if owner == worker]
            theirs = [job.name for job, owner in zip(jobs, owners) if owner != worker]
            helpers[worker] = subprocess.Popen(
                [sys.executable, "-c", _HELPER, str(ROOT), ",".join(sources), tmp, ",".join(mine),
                 ",".join(theirs), str(os.getpid())], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
        own = [job for job, owner in zip(jobs, owners) if owner == 0]
        others = {job.name for job, owner in zip(jobs, owners) if owner != 0}
        owner_of = {job.name: owner for job, owner in zip(jobs, owners)}

        ended: set[int] = set()

        def running() -> set[int]:
            """The helpers still running; a helper that ended leaves a failed marker for
            each job it did not finish, so that no process waits for them."""
            for worker, proc in helpers.items():
                if worker not in ended and proc.poll() is not None:
                    ended.add(worker)
                    for name in (n for n, w in owner_of.items() if w == worker):
                        if not (_marker(folder, name, True).exists() or _marker(folder, name, False).exists()):
                            _marker(folder, name, False).write_text(
                                f"{name}: not compiled (helper exited with status {proc.returncode})\n",
                                encoding="utf-8")
            return set(helpers) - ended

        failures = _run_jobs(own, others, folder, lambda name: owner_of[name] in running())
        while running():
            time.sleep(_POLL)
        failures += [_marker(folder, name, False).read_text(encoding="utf-8").splitlines()[0]
                     for name, worker in owner_of.items() if worker != 0 and _marker(folder, name, False).exists()]
    return failures


def compile_ahead(sources: Sequence[str], echo: bool = True) -> None:
    """:func:`compile_kernels` for a command: a notice on stderr when it compiles (instead of
    :data:`~towcable_fmu.jit.kernel_cache.WATCH`'s), the time it took, and a warning per
    failure (those kernels then compile as the run calls them)."""
    said = []

    def notice(jobs: int, processes: int) -> None:
        kernel_cache.WATCH.notice = None  # said here, once
        if echo:
            kernel_cache.print_compile_notice(processes)
        said.append(processes)

    start = time.perf_counter()
    failures = compile_kernels(sources, notice=notice)
    for failure in failures:
        print(f"towcable: warning: compiling ahead failed ({failure}); it compiles as the run needs it",
              file=sys.stderr)
    if said and echo:
        print(f"compiled the kernels in {time.perf_counter() - start:.1f} s", file=sys.stderr, flush=True)


def helper_main(argv: Sequence[str]) -> int:
    """Entry point of a helper Python (see :func:`compile_kernels`): exit status 1 if a
    job failed (its marker holds the traceback, which the main process reports)."""
    sources, folder, mine, theirs, main_pid = argv
    jobs = {job.name: job for job in load_jobs(sources.split(","))}
    pid = int(main_pid)

    def alive(name: str) -> bool:  # the main process marks the jobs of a helper that died
        try:
            os.kill(pid, 0)
        except OSError:
            return False
        return True

    own = [jobs[name] for name in mine.split(",") if name]
    return 1 if _run_jobs(own, set(filter(None, theirs.split(","))), Path(folder), alive) else 0
