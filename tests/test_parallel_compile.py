"""Compiling ahead on every core (towcable_fmu.jit.parallel_compile): the plan respects the
kernels' call graph, a run afterwards compiles nothing, and a failing job costs only time."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numba
import pytest

from towcable_fmu.jit.parallel_compile import Job, compile_kernels, plan

ROOT = Path(__file__).resolve().parent.parent


def _job(name: str, cost: float, needs: tuple[str, ...] = ()) -> Job:
    return Job(name, None, tuple, cost, needs)


def test_plan_starts_a_job_after_its_callees_and_balances_the_rest():
    jobs = [_job("a", 3.0), _job("b", 2.0), _job("c", 1.0, ("a", "b")), _job("d", 2.5)]
    owners = plan(jobs, 2)
    # a on 0 (0-3), b on 1 (0-2), c waits for a: worker 1 (free at 2) starts it at 3 as
    # early as worker 0 would, d then goes to the worker free first (0 at 3 < 1 at 4)
    assert owners == [0, 1, 0, 1] or owners == [0, 1, 1, 0]
    assert owners[:2] == [0, 1]
    assert plan(jobs, 1) == [0, 0, 0, 0]


@pytest.mark.parametrize("kind, least", [("ancf", 10), ("nodal_position", 2)])
def test_model_types_do_not_depend_on_the_scene(kind, least):
    """The premise of compiling from one reference scene: every built-in scene of a model
    kind has the same numba types of its kernels' scene-made arguments (so the same
    compiled kernels)."""
    import importlib

    from towcable_fmu.models import KERNEL_SOURCES, model_kind, simulation_for
    from towcable_fmu.scene import builtin_scene_names, load_scene

    def types(name: str) -> tuple:  # the model, and the ANCF outputs' scene data
        sim = simulation_for(load_scene(name))
        return numba.typeof(sim.model), numba.typeof(getattr(sim, "output_scene", None))

    jobs = importlib.import_module(KERNEL_SOURCES[kind][0])
    reference = types(jobs.REFERENCE_SCENE)
    scenes = [name for name in builtin_scene_names() if model_kind(load_scene(name)) == kind]
    assert len(scenes) >= least
    for name in scenes:
        assert types(name) == reference, name


#: Start of a watched command: ``Watch()`` records the kernels numba compiles in ``compiled``.
_WATCH = """
import sys
from numba.core import event

compiled = []
class Watch(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__qualname__)
    def on_end(self, ev):
        pass
"""

_WATCHED_RUN = _WATCH + """
from towcable_fmu import cli
from towcable_fmu.jit import parallel_compile
ahead = parallel_compile.compile_kernels
def compile_then_watch(*args, **kwargs):
    failures = ahead(*args, **kwargs)
    event.register("numba:compile", Watch())
    return failures
parallel_compile.compile_kernels = compile_then_watch
rc = cli.main(sys.argv[1:])
print("COMPILED DURING THE RUN:", sorted(set(compiled)))
from towcable_fmu.models import KERNEL_SOURCES, model_kind
from towcable_fmu.scene import load_scene
jobs = parallel_compile.load_jobs(KERNEL_SOURCES[model_kind(load_scene(sys.argv[2]))])
extra = {job.name: len(job.kernel._cache._cache_file._load_index()) for job in jobs}
print("JOBS WITH ANOTHER SIGNATURE IN THE CACHE:", sorted(name for name, n in extra.items() if n != 1))
sys.exit(rc)
"""


@pytest.mark.parametrize("scene", ["full_scale", pytest.param("sea_trial_turn_rigid", marks=pytest.mark.slow),
                                   pytest.param("snapping_cable_nodal", marks=pytest.mark.slow)])
def test_first_run_compiles_ahead_on_two_processes_and_nothing_during_the_run(tmp_path, scene):
    """A cold cache: the command line compiles the model's kernels ahead on two processes,
    each job the one signature the run calls; the run itself then compiles none (of ours or
    numba's), and the next run compiles nothing (ANCF; nodal-position cable with a rigid body;
    nodal-position cable on the explicit path)."""
    env = dict(os.environ, TOWCABLE_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=str(ROOT))
    command = [sys.executable, "-c", _WATCHED_RUN, "run", scene, "--duration", "0.2", "--interval", "0.1",
               "--output", str(tmp_path / "out.csv")]
    first = subprocess.run(command, env=env, capture_output=True, text=True, timeout=900)
    assert first.returncode == 0, first.stderr
    cores = len(os.sched_getaffinity(0))
    assert ("compiling the numerical kernels on 2 processes" if cores >= 2 else
            "compiling the numerical kernels (") in first.stderr
    assert "COMPILED DURING THE RUN: []" in first.stdout, first.stdout
    # each job compiled the signature the run uses, and the run no other (a job whose
    # example arguments had other types would compile a kernel nobody calls)
    assert "JOBS WITH ANOTHER SIGNATURE IN THE CACHE: []" in first.stdout, first.stdout
    second = subprocess.run(command, env=env, capture_output=True, text=True, timeout=300)
    assert second.returncode == 0, second.stderr
    assert "compiling" not in second.stderr
    assert "COMPILED DURING THE RUN: []" in second.stdout


def test_a_job_that_fails_to_compile_is_reported_and_the_others_are_done(tmp_path, monkeypatch):
    """One good and one bad kernel on two processes: the failure comes back named, with
    its error, and the good kernel is in the cache."""
    (tmp_path / "some_jobs.py").write_text(textwrap.dedent("""
        import numpy as np
        from numba import njit
        from towcable_fmu.jit.parallel_compile import Job

        @njit(cache=True)
        def good(x):
            return 2.0 * x

        @njit(cache=True)
        def bad(x):
            return x.no_such_attribute

        def kernel_jobs():
            return [Job("good", good, lambda: (1.0,), 1.0), Job("bad", bad, lambda: (np.zeros(2),), 1.0)]
    """))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("PYTHONPATH", str(tmp_path))
    failures = compile_kernels(["some_jobs"], workers=2)  # "good" here, "bad" in the helper
    assert len(failures) == 1 and failures[0].startswith("bad: "), failures
    assert "no_such_attribute" in failures[0]
    import some_jobs

    assert [job.cached() for job in some_jobs.kernel_jobs()] == [True, False]


def test_a_helper_that_dies_is_not_waited_for(tmp_path, monkeypatch):
    """The helper is killed while this process waits for its job: the wait ends, the job
    is reported as not compiled, and the jobs after it are done here."""
    (tmp_path / "dying_jobs.py").write_text(textwrap.dedent("""
        import os
        from numba import njit
        from towcable_fmu.jit.parallel_compile import Job

        @njit(cache=True)
        def first(x):
            return x + 1.0

        @njit(cache=True)
        def lost(x):
            return x + 2.0

        @njit(cache=True)
        def after(x):
            return lost(x) + 3.0

        def _die_in_helper():
            if os.getpid() != int(os.environ["MAIN_PID"]):
                os._exit(3)
            return (1.0,)

        def kernel_jobs():  # planned: first -> main, lost -> helper, after (needs lost) -> main
            return [Job("first", first, lambda: (1.0,), 2.0), Job("lost", lost, _die_in_helper, 2.0),
                    Job("after", after, lambda: (1.0,), 1.0, ("lost",))]
    """))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("PYTHONPATH", str(tmp_path))
    monkeypatch.setenv("MAIN_PID", str(os.getpid()))
    import dying_jobs

    assert plan(dying_jobs.kernel_jobs(), 2) == [0, 1, 0]
    failures = compile_kernels(["dying_jobs"], workers=2)
    assert failures == ["lost: not compiled (helper exited with status 3)"]
    assert [job.cached() for job in dying_jobs.kernel_jobs()] == [True, True, True]  # lost: compiled for after


_WATCHED_COSIM = _WATCH + """
from towcable_fmu import cli
from towcable_fmu.cosim import master
advance = master._Exchange.advance
def watched(self, k_start, k_stop, *args):
    if k_stop > k_start and not getattr(master, "watching", False):  # the clock runs from the first step
        master.watching = True
        event.register("numba:compile", Watch())
    return advance(self, k_start, k_stop, *args)
master._Exchange.advance = watched
rc = cli.main(sys.argv[1:])
print("COMPILED WHILE TIMED:", sorted(set(compiled)))
sys.exit(rc)
"""


def test_first_cosim_compiles_everything_before_its_clock_starts(tmp_path, fmu_paths):
    """A cold kernel cache: ``towcable cosim`` compiles the cable's kernels, the master's
    stepping loop and the light FMUs' kernels ahead, so that its timed loop (the progress
    and the speed it reports) compiles nothing, of ours or numba's."""
    env = dict(os.environ, TOWCABLE_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=str(ROOT))
    fmus = Path(next(iter(fmu_paths.values()))).parent
    command = [sys.executable, "-c", _WATCHED_COSIM, "cosim", "--duration", "0.1", "--compensation",
               "simplified_sheave", "--fmus", str(fmus), "--output", str(tmp_path / "out"), "--no-plot"]
    first = subprocess.run(command, env=env, capture_output=True, text=True, timeout=1200)
    assert first.returncode == 0, first.stderr
    assert "compiling the numerical kernels" in first.stderr
    assert "COMPILED WHILE TIMED: []" in first.stdout, first.stdout
