"""Parameter sweeps: spec validation and expansion, statistics, the results table (CSV and
Parquet), resume, failed cases, the local workers' environment, a worker killed in a local
pool and on a real Dask cluster, plots, a small run of the example sweep."""

from __future__ import annotations

import csv
import dataclasses
import math
import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from towcable_fmu.sweep import STATISTICS, SpecError, compute_statistics, load_spec, run_sweep
from towcable_fmu.sweep.spec import spec_from_table
from towcable_fmu.sweep.store import read_table

#: A full-scale sweep small enough for the tests: 2 s per case (statics + 40 steps).
SPEC = """
[sweep]
scene = "full_scale"
duration = {duration}
settle = 0.5
interval = 0.05
output = "{output}"
series = true

[fixed]
"sheave.contact.stiffness" = 1e8

[parameters]
hs = [1.0, 3.0]
"solver.time_step" = [0.02, -1.0]
"""


def write_spec(tmp_path: Path, duration: float = 2.0, **extra) -> Path:
    path = tmp_path / "sweep.toml"
    text = SPEC.format(duration=duration, output=(tmp_path / "out").as_posix())
    for key, value in extra.items():
        text = text.replace("[parameters]\n", f"[parameters]\n{key} = {value}\n")
    path.write_text(text, encoding="utf-8")
    return path


def check_complete(table: Path, spec) -> list[dict[str, str]]:
    """The table has exactly one row per case of the spec."""
    rows = read_table(table)
    ids = [r["case_id"] for r in rows]
    assert len(ids) == len(set(ids)), "duplicate rows"
    assert set(ids) == {c.case_id for c in spec.cases()}
    return rows


@pytest.fixture(scope="module", autouse=True)
def kernels():
    """Compile (or load) the kernels in this process first: the spawned pool processes and
    Dask workers then find them in numba's cache."""
    from towcable_fmu.ancf.simulation import Simulation

    Simulation.from_scene("full_scale").run(0.1)


# ---------------------------------------------------------------------------- spec
def table(**parameters) -> dict:
    return {"sweep": {"scene": "full_scale", "duration": 10.0}, "parameters": parameters}


def test_ranges_expand_with_the_stop_included_and_every_combination_is_a_case():
    spec = spec_from_table(table(hs={"start": 1.0, "stop": 2.0, "step": 0.5}, tp={"start": 6, "stop": 12, "num": 4},
                                 compensation=["none", "rigorous_sheave"]))
    assert spec.parameters["hs"] == [1.0, 1.5, 2.0]
    assert spec.parameters["tp"] == pytest.approx([6.0, 8.0, 10.0, 12.0])
    cases = spec.cases()
    assert len(cases) == 3 * 4 * 2
    assert len({c.case_id for c in cases}) == len(cases)
    assert cases[0].values == {"hs": 1.0, "tp": 6.0, "compensation": "none"}
    assert ("motion.hs", 1.0) in cases[0].overrides and ("compensation.algorithm", "none") in cases[0].overrides


def test_case_id_is_the_hash_of_the_full_parameter_set():
    base = spec_from_table(table(hs=[2, 3]))
    same = spec_from_table(table(hs=[2.0, 3.0]))
    assert [c.case_id for c in base.cases()] == [c.case_id for c in same.cases()]
    longer = spec_from_table({"sweep": {"scene": "full_scale", "duration": 20.0}, "parameters": {"hs": [2, 3]}})
    fixed = spec_from_table({**table(hs=[2, 3]), "fixed": {"motion.tp": 8.0}})
    ids = {c.case_id for c in base.cases()}
    assert ids.isdisjoint(c.case_id for c in longer.cases())
    assert ids.isdisjoint(c.case_id for c in fixed.cases())


def test_alias_G_sets_the_drag_amplification_of_every_segment():
    case = spec_from_table(table(G=[2.5])).cases()[0]
    keys = [k for k, v in case.overrides if v == 2.5]
    assert keys == [f"cable.segments[{i}].drag_amplification" for i in range(5)]  # full_scale has 5 segments


@pytest.mark.parametrize("doc, key, value, allowed", [
    (table(hs={"start": 1.0, "stop": 2.0, "step": -0.5}), "parameters.hs.step", "-0.5", "sign of stop - start"),
    (table(hs={"start": 1.0, "stop": 2.0}), "parameters.hs", "'start'", "exactly the keys"),
    (table(hs=[]), "parameters.hs", "[]", "non-empty list"),
    (table(wave=[1.0]), "parameters.wave", "[1.0]", "dotted scene key"),
    ({"sweep": {"mode": "fast"}}, "sweep.mode", "'fast'", "'scene' or 'cosim'"),
    ({"sweep": {"duration": 10.0, "settle": 10.0}}, "sweep.settle", "10.0", "[0, duration = 10)"),
    ({"sweep": {"statistics": ["tension.max"]}}, "sweep.statistics[0]", "'tension.max'", "tension.sheave.max"),
    ({"sweep": {"workers": 2}}, "sweep.workers", "2", "one of"),
    ({"sweep": {"scene": "no_such_scene"}}, "sweep.scene", "'no_such_scene'", "built-in scene"),
    ({"sweep": {"table": "results.xlsx"}}, "sweep.table", "'results.xlsx'", ".csv or .parquet"),
    ({"sweep": {"table": "out/results.csv"}}, "sweep.table", "'out/results.csv'", "without a folder"),
])
def test_invalid_spec_names_key_value_and_what_is_allowed(doc, key, value, allowed):
    with pytest.raises(SpecError) as info:
        spec_from_table(doc)
    message = str(info.value)
    assert message.startswith(f"{key} = ") and value in message and allowed in message


# ---------------------------------------------------------------------------- statistics
def test_statistics_on_a_known_series():
    t = np.arange(0.0, 10.0 + 1e-9, 0.5)
    tension = 1000.0 + 100.0 * t
    detached = (t >= 6.0) & (t < 8.0)  # 4 samples of 0.5 s
    slack = np.where(t == 9.0, -5.0, 50.0)
    # the towed body visits the six vertices of an octahedron of radius 2 m from t = 7.5 s
    body = np.zeros((t.size, 3))
    vertices = 2.0 * np.vstack([np.eye(3), -np.eye(3)]) + [10.0, 0.0, -60.0]
    body[t < 7.5] = [50.0, 50.0, 50.0]
    body[t >= 7.5] = vertices
    series = {"time": t, "tension.sheave": tension, "contact.detached": detached.astype(float), "tension.min": slack,
              "towbody.x": body[:, 0], "towbody.y": body[:, 1], "towbody.z": body[:, 2]}
    stats = compute_statistics(series, ["tension.sheave.max", "tension.sheave.min", "tension.sheave.mean",
                                        "contact.detached.time", "slack.time", "tension.min.min",
                                        "contact.wrap_angle.mean"], settle=2.0)
    assert stats["tension.sheave.max"] == pytest.approx(2000.0)
    assert stats["tension.sheave.min"] == pytest.approx(1200.0)  # the window starts at t = 2 s
    assert stats["tension.sheave.mean"] == pytest.approx(1600.0)
    assert stats["contact.detached.time"] == pytest.approx(2.0)
    assert stats["slack.time"] == pytest.approx(0.5)
    assert stats["tension.min.min"] == -5.0
    assert math.isnan(stats["contact.wrap_angle.mean"])  # signal missing
    # all six points on a sphere of radius 2 m: the 95 % ellipsoid is that sphere
    volume = compute_statistics(series, ["ellipsoid.volume"], settle=7.5)["ellipsoid.volume"]
    assert volume == pytest.approx(4.0 / 3.0 * math.pi * 2.0 ** 3, rel=1e-9)


# ---------------------------------------------------------------------------- the table
def test_table_drops_a_torn_last_line_and_duplicates(tmp_path):
    from towcable_fmu.sweep.case import CaseResult
    from towcable_fmu.sweep.store import ResultTable

    spec = load_spec(write_spec(tmp_path))
    cases = spec.cases()
    path = tmp_path / "out" / "results.csv"
    tab = ResultTable(path, spec)
    result = CaseResult(cases[0].case_id, "ok", "", {n: 1.0 for n in STATISTICS}, 0.1, "here")
    assert tab.append(cases[0], result) and not tab.append(cases[0], result)
    with open(path, "a", encoding="utf-8") as fh:
        fh.write(path.read_text(encoding="utf-8").splitlines()[1] + "\n")  # a duplicate row
        fh.write(cases[1].case_id + ",ok,3")  # cut off by an interruption
    again = ResultTable(path, spec)
    assert again.done() == {cases[0].case_id}
    assert len(read_table(path)) == 1


def test_parquet_table_is_typed_drops_duplicates_and_survives_a_torn_rewrite(tmp_path):
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    from towcable_fmu.sweep.case import CaseResult
    from towcable_fmu.sweep.store import ParquetTable, open_table

    spec = dataclasses.replace(load_spec(write_spec(tmp_path)), table="results.parquet")
    cases = spec.cases()
    path = tmp_path / "out" / "results.parquet"
    tab = open_table(path, spec)
    assert isinstance(tab, ParquetTable) and pq.read_table(path).num_rows == 0
    ok = CaseResult(cases[0].case_id, "ok", "", {n: 1.5 for n in STATISTICS}, 0.1, "here")
    bad = CaseResult(cases[1].case_id, "failed", "SceneError: no", {n: math.nan for n in STATISTICS}, 0.0, "here")
    assert tab.append(cases[0], ok) and tab.append(cases[1], bad) and not tab.append(cases[0], ok)
    data = pq.read_table(path)
    assert data.num_rows == 2 and data.column_names == tab.columns
    assert data.schema.field("tension.sheave.max [N]").type == pa.float64()
    assert data.schema.field("hs").type == pa.float64() and data.schema.field("case_id").type == pa.string()
    assert data.column("tension.sheave.max [N]").to_pylist() == [1.5, None]  # NaN of a failed case: null
    rows = read_table(path)
    assert rows[1]["error"] == "SceneError: no" and rows[1]["tension.sheave.max [N]"] == "" and rows[0]["hs"] == "1"
    # a duplicate row (written by hand) is dropped on opening; a temporary file left by an
    # interrupted rewrite is ignored (the table itself is replaced atomically)
    pq.write_table(pa.concat_tables([data, data.slice(0, 1)]), path)
    (path.parent / "results.parquet.tmp").write_bytes(b"PAR1 torn")
    again = open_table(path, spec)
    assert again.done() == {cases[0].case_id, cases[1].case_id} and pq.read_table(path).num_rows == 2
    assert again.drop_failed() == 1 and pq.read_table(path).column("case_id").to_pylist() == [cases[0].case_id]
    path.write_bytes(b"not parquet")
    with pytest.raises(SpecError, match="a readable Parquet file"):
        open_table(path, spec)


# ---------------------------------------------------------------------------- local runs
def test_local_workers_start_with_one_thread_per_numerical_library():
    """The pool's processes are spawned with OMP/OPENBLAS/MKL/NUMBA_NUM_THREADS = 1 (a second
    OpenBLAS thread per worker multiplied the CPU time of a case by 2.5-3 on 2 cores); the master's
    environment is left as it was."""
    from towcable_fmu.sweep.execute import WORKER_ENVIRONMENT, local_pool, worker_environment

    before = {k: os.environ.get(k) for k in WORKER_ENVIRONMENT}
    with local_pool(1) as pool:
        with worker_environment():
            env = {k: pool.submit(os.getenv, k) for k in WORKER_ENVIRONMENT}
            tasks = pool.submit(os.listdir, "/proc/self/task")
        env, tasks = {k: v.result(timeout=120) for k, v in env.items()}, tasks.result(timeout=120)
    assert env == WORKER_ENVIRONMENT
    assert len(tasks) == 1  # numpy (OpenBLAS) is loaded in the worker (by the sweep modules): no extra thread
    assert {k: os.environ.get(k) for k in WORKER_ENVIRONMENT} == before


def test_report_has_cpu_and_wall_time_per_case(local_sweep):
    tmp, spec, report = local_sweep
    assert len(report.timings) == 4 and len({t.case_id for t in report.timings}) == 4
    for t in report.timings:
        assert t.wall_time >= 0 and math.isfinite(t.started) and 0 <= t.cpu_time
        if t.status == "ok":
            assert t.cpu_time > 0
    assert 0 < report.busy_span <= report.wall_time


def test_parquet_sweep_resumes_without_duplicates(tmp_path):
    pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    from towcable_fmu.cli import main

    spec = dataclasses.replace(load_spec(write_spec(tmp_path)), table="results.parquet")
    first = run_sweep(spec, workers=2, progress=False)
    path = spec.output / "results.parquet"
    assert first.table == path and (first.ran, first.failed) == (4, 2)
    rows = check_complete(path, spec)
    ok = [r for r in rows if r["status"] == "ok"]
    assert len(ok) == 2 and all(float(r["tension.sheave.max [N]"]) > 0 for r in ok)
    # lose the last row (as if the sweep had been interrupted before it): only it runs again
    data = pq.read_table(path)
    lost = data.column("case_id")[-1].as_py()
    pq.write_table(data.slice(0, 3), path)
    again = run_sweep(spec, workers=1, progress=False)
    assert (again.skipped, again.ran) == (3, 1)
    rows = check_complete(path, spec)
    assert rows[-1]["case_id"] == lost
    assert run_sweep(spec, workers=1, progress=False).ran == 0
    # the plots read Parquet alike (the folder has only results.parquet)
    assert main(["sweep-plot", str(spec.output), "--heatmap", "tension.sheave.max", "hs", "solver.time_step",
                 "--exceedance"]) == 0
    assert (spec.output / "exceedance_tension.sheave.png").stat().st_size > 5000

@pytest.fixture(scope="module")
def local_sweep(tmp_path_factory):
    """The 4-case sweep (2 failing) on 2 local processes, then resumed after losing a row."""
    tmp = tmp_path_factory.mktemp("sweep")
    spec = load_spec(write_spec(tmp))
    first = run_sweep(spec, workers=2, progress=False)
    return tmp, spec, first


def test_local_sweep_records_every_case_and_the_failures(local_sweep):
    tmp, spec, report = local_sweep
    rows = check_complete(spec.output / "results.csv", spec)
    assert (report.total, report.ran, report.failed) == (4, 4, 2)
    for row in rows:
        if row["solver.time_step"] == "-1":
            assert row["status"] == "failed"
            assert "solver.time_step = -1.0 is invalid" in row["error"] and row["tension.sheave.max [N]"] == ""
        else:
            assert row["status"] == "ok" and row["error"] == ""
            assert row["fixed.sheave.contact.stiffness"] == "100000000" and row["scene"] == "full_scale"


def test_statistics_match_the_series_and_the_statics(local_sweep):
    from towcable_fmu.ancf.simulation import Simulation

    tmp, spec, _ = local_sweep
    sim = Simulation.from_scene("full_scale", {"sheave.contact.stiffness": 1e8, "motion.hs": 1.0})
    static = sim.initialize()["tension.sheave"]
    for row in read_table(spec.output / "results.csv"):
        if row["status"] != "ok":
            continue
        with open(spec.output / "series" / f"{row['case_id']}.csv", newline="") as fh:
            data = list(csv.DictReader(fh))
        t = np.array([float(r["time"]) for r in data])
        tension = np.array([float(r["tension.sheave"]) for r in data])[t >= 0.5]
        assert float(row["tension.sheave.max [N]"]) == pytest.approx(tension.max(), rel=1e-9)
        # the CSV holds 10 significant digits: each value is off by at most 5e-10 |T|, and a
        # standard deviation moves by no more than the largest change of a value
        assert abs(float(row["tension.sheave.std [N]"]) - tension.std()) <= 5e-10 * np.abs(tension).max()
        # 2 s after the start in a sea that ramps in over 20 s the cable is near its statics
        assert float(row["tension.sheave.mean [N]"]) == pytest.approx(static, rel=0.01)


def test_interrupted_sweep_runs_only_the_missing_cases(local_sweep):
    tmp, spec, _ = local_sweep
    path = spec.output / "results.csv"
    lines = path.read_text(encoding="utf-8").splitlines(keepends=True)
    lost = lines[-1].split(",")[0]
    path.write_text("".join(lines[:-1]) + lines[-1][:25], encoding="utf-8")  # the last row torn
    report = run_sweep(spec, workers=1, progress=False)
    assert (report.skipped, report.ran) == (3, 1)
    rows = check_complete(path, spec)
    assert rows[-1]["case_id"] == lost
    assert run_sweep(spec, workers=1, progress=False).ran == 0


def test_retry_failed_reruns_only_failed_cases(local_sweep):
    tmp, spec, _ = local_sweep
    report = run_sweep(spec, workers=1, progress=False, retry_failed=True)
    assert (report.ran, report.failed) == (2, 2)
    check_complete(spec.output / "results.csv", spec)


def test_cosim_sweep_gives_each_case_its_own_sea(tmp_path, fmu_paths):
    """Cosim mode: the overridden [motion] reaches ShipMotion. With the same seed the ship's
    heave is linear in the wave height, so H_s = 4 m moves the ship 4 times as far as 1 m."""
    doc = {"sweep": {"mode": "cosim", "scene": "full_scale", "duration": 1.0, "settle": 0.2, "interval": 0.05,
                     "step": 0.01, "output": str(tmp_path / "out"), "series": True,
                     "fmu_dir": str(Path(fmu_paths["TowCable"]).parent)},
            "fixed": {"motion.ramp": 0.0}, "parameters": {"hs": [1.0, 4.0]}}
    spec = spec_from_table(doc)
    report = run_sweep(spec, workers=2, progress=False)
    assert (report.ran, report.failed) == (2, 0)
    rows = check_complete(spec.output / "results.csv", spec)
    heave = {}
    for row in rows:
        assert row["mode"] == "cosim" and row["status"] == "ok", row["error"]
        with open(spec.output / "series" / f"{row['case_id']}.csv", newline="") as fh:
            heave[row["hs"]] = np.array([float(r["ship.z"]) for r in csv.DictReader(fh)])
    assert np.ptp(heave["1"]) > 1e-3
    np.testing.assert_allclose(heave["4"] - heave["4"][0], 4.0 * (heave["1"] - heave["1"][0]), rtol=1e-6,
                               atol=1e-9)


def _kill_soon(find_pids, when_busy, timeout: float = 120.0) -> list[int]:
    """Kill (SIGKILL) the first process that ``when_busy`` reports busy; returns its pid."""
    killed: list[int] = []
    deadline = time.monotonic() + timeout
    while not killed and time.monotonic() < deadline:
        for pid in when_busy(find_pids()):
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)
            break
        time.sleep(0.05)
    return killed


def test_local_worker_killed_mid_case_is_retried(tmp_path):
    import psutil

    # 300 s simulated: a case takes two seconds or more (full_scale runs about 110 x real time)
    spec = load_spec(write_spec(tmp_path, duration=300.0))
    me = psutil.Process()
    reports = []
    thread = threading.Thread(target=lambda: reports.append(run_sweep(spec, workers=2, progress=False)))
    thread.start()
    table = spec.output / "results.csv"

    def workers() -> list:
        return [p for p in me.children() if "spawn_main" in " ".join(p.cmdline())]

    def busy(procs) -> list[int]:
        # both workers warm up alike, then take a case each: once the first (failing, a few
        # milliseconds) case has its row, the other worker is in the middle of a case of 300 s
        # simulated (two seconds or more); kill a worker that keeps using CPU half a second later
        # and has not finished a case meanwhile (on a loaded machine the other case can end
        # within that half second: its worker is idle then, not mid-case)
        if not table.exists() or len(table.read_text(encoding="utf-8").splitlines()) < 2:
            return []
        used = {p.pid: sum(p.cpu_times()[:2]) for p in procs}
        time.sleep(0.5)
        finished = {(r.get("worker") or ":").split(":")[1] for r in read_table(table) if r.get("status") == "ok"}
        return [p.pid for p in procs if p.is_running() and sum(p.cpu_times()[:2]) > used[p.pid] + 0.05
                and str(p.pid) not in finished]

    killed = _kill_soon(workers, busy)
    thread.join(timeout=300)
    assert killed and reports and reports[0].resubmitted >= 1
    rows = check_complete(spec.output / "results.csv", spec)
    assert sum(r["status"] == "ok" for r in rows) == 2
    assert all(r["worker"].split(":")[1] != str(killed[0]) for r in rows if r["status"] == "ok")


# ---------------------------------------------------------------------------- Dask
def test_dask_cluster_sweep_survives_a_killed_worker(tmp_path):
    distributed = pytest.importorskip("distributed")

    spec = load_spec(write_spec(tmp_path, duration=300.0, seed="[1, 2]"))  # a case takes two seconds or more
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None, scheduler_port=0) as cluster, \
            distributed.Client(cluster) as client:
        reports = []
        thread = threading.Thread(target=lambda: reports.append(
            run_sweep(spec, scheduler=cluster.scheduler_address, progress=False)))
        thread.start()

        seen: dict[str, float] = {}

        def busy(pids: dict[str, int]) -> list[int]:
            # a worker that has been processing a case for half a second is in the middle of it
            now = time.monotonic()
            active = {w for w, keys in client.processing().items()
                      if any(str(k).startswith("towcable-case-") for k in keys)}  # not warming up
            for w in list(seen):
                if w not in active:
                    del seen[w]
            for w in active:
                seen.setdefault(w, now)
            return [pids[w] for w in active if w in pids and now - seen[w] > 0.5]

        killed = _kill_soon(lambda: client.run(os.getpid), busy)
        thread.join(timeout=300)
    assert killed and reports
    assert (reports[0].ran, reports[0].failed) == (8, 4)
    rows = check_complete(spec.output / "results.csv", spec)
    assert sum(r["status"] == "ok" for r in rows) == 4
    assert all(r["worker"].split(":")[1] != str(killed[0]) for r in rows if r["status"] == "ok")


# ---------------------------------------------------------------------------- plots and CLI
def test_heatmap_grid_averages_over_the_other_parameters():
    from towcable_fmu.sweep.plots import heatmap_grid

    rows = [{"case_id": str(i), "status": s, "hs": hs, "heading": hd, "seed": sd, "x [N]": v}
            for i, (s, hs, hd, sd, v) in enumerate([
                ("ok", "1", "90", "1", "10"), ("ok", "1", "90", "2", "20"), ("ok", "2", "90", "1", "30"),
                ("failed", "2", "90", "2", ""), ("ok", "1", "180", "1", "50"), ("failed", "2", "180", "1", "")])]
    xs, ys, mean, count = heatmap_grid(rows, "x", "hs", "heading")
    assert (xs, ys) == (["1", "2"], ["90", "180"])
    np.testing.assert_array_equal(count, [[2, 1], [1, 0]])
    assert mean[0, 0] == 15.0 and mean[0, 1] == 30.0 and mean[1, 0] == 50.0 and math.isnan(mean[1, 1])
    with pytest.raises(SpecError, match="--statistic = 'y'"):
        heatmap_grid(rows, "y", "hs", "heading")


def test_exceedance_curve():
    from towcable_fmu.sweep.plots import exceedance

    levels, share = exceedance(np.array([3.0, 1.0, 4.0, 2.0]))
    np.testing.assert_array_equal(levels, [4.0, 3.0, 2.0, 1.0])
    np.testing.assert_array_equal(share, [0.25, 0.5, 0.75, 1.0])


def test_sweep_plot_command_writes_heatmap_and_exceedance(local_sweep, capsys):
    from towcable_fmu.cli import main

    tmp, spec, _ = local_sweep
    out = tmp / "plots"
    assert main(["sweep-plot", str(spec.output), "--heatmap", "tension.sheave.max", "hs", "solver.time_step",
                 "--exceedance", "--output", str(out)]) == 0
    for name in ("heatmap_tension.sheave.max_hs_solver.time_step.png", "exceedance_tension.sheave.png"):
        assert (out / name).stat().st_size > 5000
    assert main(["sweep-plot", str(spec.output), "--heatmap", "nope", "hs", "seed"]) == 2
    assert "--statistic = 'nope' is invalid" in capsys.readouterr().err


EXAMPLE = Path(__file__).parents[1] / "towcable_fmu" / "example_sweeps" / "example.toml"


def test_example_spec_is_valid():
    spec = load_spec(EXAMPLE)
    assert len(spec.cases()) == 18 and spec.settings.duration == 120.0


def test_example_sweep_in_small_runs_and_plots(tmp_path):
    """The example sweep with 2 s cases and 2 x 2 x 2 of its values (the full one, 18 cases of
    120 s, is run by hand: README, Sweeps); then its heat map and exceedance curves."""
    from towcable_fmu.cli import main

    full = load_spec(EXAMPLE)
    spec = dataclasses.replace(full, settings=dataclasses.replace(full.settings, duration=2.0, settle=0.5),
                               parameters={"hs": [1.5, 5.0], "heading": [90.0, 180.0],
                                           "compensation": full.parameters["compensation"]},
                               output=tmp_path / "example")
    report = run_sweep(spec, workers=2, progress=False)
    assert (report.ran, report.failed) == (8, 0)
    rows = check_complete(spec.output / "results.csv", spec)
    assert {r["compensation"] for r in rows} == {"none", "simplified_sheave"}
    assert all(float(r["contact.sheave_force.max [N]"]) > 0 for r in rows)
    assert main(["sweep-plot", str(spec.output), "--heatmap", "tension.sheave.max", "hs", "heading",
                 "--exceedance", "--label", "hs", "compensation"]) == 0
    for name in ("heatmap_tension.sheave.max_hs_heading.png", "exceedance_tension.sheave.png"):
        assert (spec.output / name).stat().st_size > 5000


# ---------------------------------------------------------------------------- every model kind
@pytest.mark.parametrize("scene", ["snapping_cable_nodal", "tug_tow", "full_scale"])
def test_scene_mode_sweeps_run_every_model_kind_with_any_signal_statistic(tmp_path, scene):
    """A sweep runs the scene's own model (nodal-position, rigid-link, ANCF): every case ok,
    and its generic statistics equal the same reductions of an independent run of that
    scene with the case's overrides."""
    from towcable_fmu.models import simulation_from

    doc = {"sweep": {"scene": scene, "duration": 0.6, "settle": 0.2, "interval": 0.02, "output": str(tmp_path),
                     "statistics": ["tension.top.max", "tension.top.p90", "towbody.x.mean"]},
           "parameters": {"environment.gravity": [9.81, 9.6]}}
    spec = spec_from_table(doc)
    assert spec.units == {"tension.top.max": "N", "tension.top.p90": "N", "towbody.x.mean": "m"}
    report = run_sweep(spec, workers=1, progress=False)
    rows = check_complete(report.table, spec)
    assert [r["status"] for r in rows] == ["ok", "ok"], [r["error"] for r in rows]
    for row, case in zip(sorted(rows, key=lambda r: float(r["environment.gravity"]), reverse=True), spec.cases()):
        series = simulation_from(scene, case.overrides).run(0.6, interval=0.02)
        window = series["time"] >= 0.2 - 1e-12
        top = series["tension.top"][window]
        assert float(row["tension.top.max [N]"]) == pytest.approx(top.max(), rel=1e-9)
        assert float(row["tension.top.p90 [N]"]) == pytest.approx(np.percentile(top, 90.0), rel=1e-9)
        assert float(row["towbody.x.mean [m]"]) == pytest.approx(series["towbody.x"][window].mean(), rel=1e-9)


def test_a_statistic_of_a_signal_the_scene_lacks_names_the_signals_it_has():
    with pytest.raises(SpecError) as info:
        spec_from_table({"sweep": {"scene": "tug_tow", "duration": 10.0, "statistics": ["tension.sheave.max"]}})
    message = str(info.value)
    assert message.startswith("sweep.statistics[0] = 'tension.sheave.max'")
    assert "no signal tension.sheave" in message and "tension.towbody" in message and "cable.span" in message


def test_the_default_statistics_are_those_the_scene_has_signals_for():
    assert spec_from_table({"sweep": {"scene": "full_scale"}}).statistics == tuple(STATISTICS)
    tug = spec_from_table({"sweep": {"scene": "tug_tow"}}).statistics
    assert tug == ("tension.min.min", "slack.time", "towbody.z.std")  # no sheave, no contact, no towbody.y


def test_a_segment_alias_on_a_scene_without_cable_segments_is_a_spec_error():
    with pytest.raises(SpecError) as info:
        spec_from_table({"sweep": {"scene": "tug_tow"}, "parameters": {"G": [1.0, 2.0]}})
    assert str(info.value).startswith("parameters.G = 'G'") and "no segments" in str(info.value)


def test_percentiles_and_reductions_of_any_signal():
    t = np.arange(0.0, 101.0)
    series = {"time": t, "tension.towbody": t.copy(), "towbody.z": -t}
    names = ["tension.towbody.p99", "tension.towbody.p99.9", "tension.towbody.p0", "tension.towbody.p100",
             "towbody.z.std", "tension.towbody.mean"]
    stats = compute_statistics(series, names, settle=0.0)
    # values 0, 1, ..., 100: the NN-th percentile (linear interpolation) is NN
    assert stats["tension.towbody.p99"] == pytest.approx(99.0)
    assert stats["tension.towbody.p99.9"] == pytest.approx(99.9)
    assert (stats["tension.towbody.p0"], stats["tension.towbody.p100"]) == (0.0, 100.0)
    assert stats["towbody.z.std"] == pytest.approx(math.sqrt((101 ** 2 - 1) / 12.0))  # discrete uniform
    assert stats["tension.towbody.mean"] == pytest.approx(50.0)
    for bad in ("tension.towbody.p101", "tension.towbody.median", "max"):
        with pytest.raises(SpecError) as info:
            spec_from_table({"sweep": {"scene": "full_scale", "statistics": [bad]}})
        assert "SIGNAL.max, .min, .mean, .std or .pNN" in str(info.value)


@pytest.mark.parametrize("scene", ["snapping_cable_nodal", "tug_tow"])
def test_cosim_mode_sweeps_run_the_other_model_kinds(tmp_path, fmu_paths, scene):
    """Cosim mode over a nodal-position and a rigid-link scene: every case ok, and its
    statistics are those of the scene's own simulation driven by the same motion (the FMU
    sees the ship through ShipMotion at 10 ms communication steps: close, not equal)."""
    from towcable_fmu.models import simulation_from

    doc = {"sweep": {"mode": "cosim", "scene": scene, "duration": 0.6, "settle": 0.2, "interval": 0.02,
                     "step": 0.01, "output": str(tmp_path / "out"),
                     "statistics": ["tension.top.max", "tension.top.mean"],
                     "fmu_dir": str(Path(fmu_paths["TowCable"]).parent)},
           "parameters": {"environment.gravity": [9.81, 9.6]}}
    spec = spec_from_table(doc)
    report = run_sweep(spec, workers=1, progress=False)
    rows = check_complete(report.table, spec)
    assert [r["status"] for r in rows] == ["ok", "ok"], [r["error"] for r in rows]
    for row, case in zip(sorted(rows, key=lambda r: float(r["environment.gravity"]), reverse=True), spec.cases()):
        series = simulation_from(scene, case.overrides).run(0.6, interval=0.02)
        top = series["tension.top"][series["time"] >= 0.2 - 1e-12]
        assert float(row["tension.top.max [N]"]) == pytest.approx(top.max(), rel=0.02)
        assert float(row["tension.top.mean [N]"]) == pytest.approx(top.mean(), rel=0.02)
