"""Run the cases of a sweep on local processes or a Dask distributed cluster.

The master (this process) owns the results table: workers return a
:class:`~towcable_fmu.sweep.case.CaseResult` and the master appends its row, so rows land
incrementally, each exactly once.

* Local (default): a :class:`concurrent.futures.ProcessPoolExecutor` of ``workers``
  processes (no server), started with the ``spawn`` method and the environment
  :data:`WORKER_ENVIRONMENT` (one thread for OpenBLAS, MKL, OpenMP and numba in each
  worker: a pool has one worker per core, and a second BLAS thread per worker spins on
  the same cores: measured on 2 cores, it multiplied the CPU time of a full-scale case
  by 2.5 to 3).
  Each worker loads the kernels before its first case (:func:`~.case.warm_up`). If a
  worker process dies (killed, out of memory) the pool is broken: the master starts a
  new pool and submits the unfinished cases again, at most ``retries`` times per case.
* Dask (``scheduler="tcp://host:port"``): one task per case, keyed by the case id. When a
  worker dies in the middle of a case the scheduler runs it again on another worker (up
  to ``distributed.scheduler.allowed-failures`` times, then the case is recorded as
  failed with the reason). The workers need ``towcable`` installed and, in cosim mode,
  the FMU folder at the same path. Dask's nanny starts the worker processes with one
  BLAS/OpenMP thread already (``distributed.nanny.pre-spawn-environ``); every worker
  connected when the sweep starts loads the kernels before the cases are submitted.

Resume: cases whose id already has a row are skipped.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import dataclasses
import math
import multiprocessing
import os
import sys
import threading
import time
from pathlib import Path
from typing import Callable, Iterator, Mapping, Sequence, TextIO

from .case import CaseResult, run_case, warm_up
from .spec import Case, SweepSpec
from .store import open_table, write_series

#: Environment of the local worker processes: one thread per numerical library, since the
#: pool itself runs one process per core.
WORKER_ENVIRONMENT: dict[str, str] = {
    "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "NUMBA_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1", "NUMEXPR_NUM_THREADS": "1",
}

_ENVIRONMENT_LOCK = threading.Lock()


@dataclasses.dataclass(frozen=True)
class CaseTiming:
    """Where and how long one case ran (the cases run by this call only).

    Attributes
    ----------
    case_id
        The case.
    status
        ``"ok"`` or ``"failed"``.
    worker
        ``host:pid`` of the process that ran it.
    started
        Wall-clock start (``time.time()`` of the worker) [s since the epoch].
    wall_time
        Wall time of the case [s].
    cpu_time
        CPU time of the worker process during the case [s].
    """

    case_id: str
    status: str
    worker: str
    started: float
    wall_time: float
    cpu_time: float

@dataclasses.dataclass
class SweepReport:
    """What a call of :func:`run_sweep` did.

    Attributes
    ----------
    total
        Cases in the sweep.
    skipped
        Cases already in the table (not run again).
    ran
        Cases run now (ok + failed).
    failed
        Cases run now that failed.
    resubmitted
        Cases submitted again after a worker died (local pool).
    wall_time
        Wall time of the call [s].
    table
        The results table (CSV or Parquet).
    timings
        One entry per case run now, in the order they finished.
    """

    total: int
    skipped: int
    ran: int
    failed: int
    resubmitted: int
    wall_time: float
    table: Path
    timings: list[CaseTiming] = dataclasses.field(default_factory=list)

    @property
    def busy_span(self) -> float:
        """Wall time from the start of the first case to the end of the last one [s] (by
        the workers' clocks: without starting the workers and loading the kernels)."""
        runs = [t for t in self.timings if math.isfinite(t.started)]
        if not runs:
            return math.nan
        return max(t.started + t.wall_time for t in runs) - min(t.started for t in runs)

    @property
    def cases_per_hour(self) -> float:
        """Throughput of the cases run now [1/h]."""
        return 3600.0 * self.ran / self.wall_time if self.wall_time > 0 and self.ran else math.nan


class ProgressLine:
    """Prints ``[done/total] ...`` lines to ``stream`` (one per finished case, at most
    every ``every`` seconds, and the last)."""

    def __init__(self, total: int, every: float = 2.0, stream: TextIO | None = sys.stderr) -> None:
        self.total = total
        self.every = every
        self.stream = stream
        self.start = time.perf_counter()
        self.last = -math.inf
        self.done = 0
        self.failed = 0

    def __call__(self, result: CaseResult) -> None:
        self.done += 1
        self.failed += result.status != "ok"
        now = time.perf_counter()
        if self.stream is None or (now - self.last < self.every and self.done < self.total):
            return
        self.last = now
        elapsed = now - self.start
        rate = self.done / elapsed
        eta = (self.total - self.done) / rate if rate > 0 else math.nan
        self.stream.write(f"[{self.done}/{self.total}] {self.failed} failed, {elapsed:.0f} s elapsed, "
                          f"{3600 * rate:.0f} cases/h, ETA {eta:.0f} s (last: {result.case_id} {result.status}"
                          f"{': ' + result.error[:120] if result.error else ''})\n")
        self.stream.flush()


def run_sweep(spec: SweepSpec, *, workers: int | None = None, scheduler: str | None = None,
              retry_failed: bool = False, retries: int = 2, progress: bool = True,
              output: Path | None = None) -> SweepReport:
    """Run the cases of ``spec`` that the table does not have yet.

    Parameters
    ----------
    spec
        The sweep.
    workers
        Local processes (default: the number of CPUs); ignored with ``scheduler``.
    scheduler
        Address of a Dask distributed scheduler (``tcp://host:port``); None: local pool.
    retry_failed
        Run the cases recorded as failed again (their rows are replaced).
    retries
        Local pool: how often a case is resubmitted after its worker process died.
    progress
        Progress lines on stderr.
    output
        Results folder (default: ``spec.output``).

    Returns
    -------
    SweepReport
        Counts, wall time, the table path and the timings of the cases run now.

    Notes
    -----
    The local worker processes are spawned: they import the caller's main module, so a
    script that calls this function must do so under ``if __name__ == "__main__":``.
    """
    start = time.perf_counter()
    folder = Path(output) if output is not None else spec.output
    table = open_table(folder / spec.table, spec)
    if retry_failed:
        table.drop_failed()
    cases = spec.cases()
    done = table.done()
    todo = [c for c in cases if c.case_id not in done]
    fmus = None
    if spec.settings.mode == "cosim" and todo:
        from ..fmu_build.build import ensure_fmus

        fmus = {k: Path(v).resolve() for k, v in ensure_fmus(spec.settings.fmu_dir).items()}
    line = ProgressLine(len(todo), stream=sys.stderr if progress else None)
    failed = 0
    timings: list[CaseTiming] = []

    def record(case: Case, result: CaseResult) -> None:
        nonlocal failed
        if result.series is not None:
            write_series(folder / "series", case.case_id, result.series)
        if table.append(case, result):
            failed += result.status != "ok"
            timings.append(CaseTiming(case.case_id, result.status, result.worker, result.started,
                                      result.wall_time, result.cpu_time))
            line(result)

    if progress:
        print(f"sweep: {len(cases)} cases, {len(cases) - len(todo)} already in {table.path}, {len(todo)} to run "
              + (f"on the Dask cluster at {scheduler}" if scheduler else f"on {workers or os.cpu_count()} local "
                 "processes"), file=sys.stderr)
    resubmitted = 0
    if todo:
        if scheduler:
            _run_dask(todo, scheduler, fmus, record)
        else:
            resubmitted = _run_local(todo, workers or os.cpu_count() or 1, fmus, record, retries)
    return SweepReport(total=len(cases), skipped=len(cases) - len(todo), ran=len(todo), failed=failed,
                       resubmitted=resubmitted, wall_time=time.perf_counter() - start, table=table.path,
                       timings=timings)


def _lost(case: Case, reason: str) -> CaseResult:
    return CaseResult(case.case_id, "failed", reason, {n: math.nan for n in case.statistics}, 0.0, "")


@contextlib.contextmanager
def worker_environment() -> Iterator[None]:
    """Set :data:`WORKER_ENVIRONMENT` in ``os.environ`` while worker processes start.

    A spawned process inherits the environment at its start and reads these variables
    when it loads numpy/numba; the master's own (already loaded) libraries keep theirs.
    The previous values are restored on exit.
    """
    with _ENVIRONMENT_LOCK:
        saved = {k: os.environ.get(k) for k in WORKER_ENVIRONMENT}
        os.environ.update(WORKER_ENVIRONMENT)
        try:
            yield
        finally:
            for key, value in saved.items():
                if value is None:
                    os.environ.pop(key, None)
                else:
                    os.environ[key] = value


def _init_worker(case: Case | None) -> None:
    """Pool initializer: load the kernels before the first case (not counted in its time)."""
    if case is not None:
        warm_up(case)


def local_pool(workers: int, warm: Case | None = None) -> cf.ProcessPoolExecutor:
    """A process pool for sweep cases: ``spawn`` start method, each worker warmed up with
    ``warm`` (see :func:`~.case.warm_up`).

    Parameters
    ----------
    workers
        Number of processes.
    warm
        A case whose scene the workers load before taking cases; None: no warm-up.

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor
        Its processes start on the first submissions (since Python 3.9 for ``spawn``):
        submit inside :func:`worker_environment` so that they get one thread per library.
    """
    return cf.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                                  initializer=_init_worker, initargs=(warm,))


def _run_local(todo: Sequence[Case], workers: int, fmus: Mapping[str, Path] | None,
               record: Callable[[Case, CaseResult], None], retries: int) -> int:
    """Local process pool; a broken pool (a worker died) is replaced and the unfinished
    cases submitted again. Returns the number of resubmissions."""
    from concurrent.futures.process import BrokenProcessPool

    pending = list(todo)
    attempts = {c.case_id: 0 for c in todo}
    resubmitted = 0
    while pending:
        broken: list[Case] = []
        with local_pool(min(workers, len(pending)), pending[0]) as pool:
            with worker_environment():  # the processes start on the first submissions
                futures = {pool.submit(run_case, case, fmus): case for case in pending}
            for future in cf.as_completed(futures):
                case = futures[future]
                try:
                    result = future.result()
                except BrokenProcessPool:
                    broken.append(case)
                    continue
                record(case, result)
        pending = []
        for case in broken:
            attempts[case.case_id] += 1
            if attempts[case.case_id] > retries:
                record(case, _lost(case, f"worker process died {attempts[case.case_id]} times while running it"))
            else:
                pending.append(case)
                resubmitted += 1
    return resubmitted


def _run_dask(todo: Sequence[Case], scheduler: str, fmus: Mapping[str, Path] | None,
              record: Callable[[Case, CaseResult], None]) -> None:
    """One task per case on the cluster at ``scheduler``; results recorded as they finish."""
    try:
        from distributed import Client, as_completed, wait
    except ImportError:
        from ..common.errors import TowcableError

        raise TowcableError("--scheduler needs Dask: pip install 'towcable[dask]'") from None
    with Client(scheduler, timeout="30s") as client:
        # load the kernels on every connected worker first (a task each, so that the
        # workers' event loops stay free); failures are ignored, the cases report them
        warm = [client.submit(warm_up, todo[0], key=f"towcable-warmup-{i}-{todo[0].case_id}", pure=False,
                              workers=[address], allow_other_workers=True)
                for i, address in enumerate(client.scheduler_info()["workers"])]
        wait(warm)
        del warm
        futures = {client.submit(run_case, case, fmus, key=f"towcable-case-{case.case_id}", pure=False): case
                   for case in todo}
        for future in as_completed(futures):
            case = futures[future]
            try:
                result = future.result()
            except Exception as exc:  # noqa: BLE001 - e.g. KilledWorker after repeated worker deaths
                result = _lost(case, f"{type(exc).__name__}: {exc}".replace("\n", " "))
            record(case, result)
