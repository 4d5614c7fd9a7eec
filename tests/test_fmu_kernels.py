"""Precompiled kernels in the FMU (issue 17): the first use of TowCable on a new machine
compiles nothing, and gives the numbers of kernels compiled where it runs.

The activation rules are tested in fresh Pythons (they depend on whether numba is
imported yet); the whole claim by moving the FMU: built here, moved to another folder
and run by fmpy in a fresh venv without towcable, with an empty machine cache.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest
from test_fmu_portable import build_machine_paths, clean_env

from towcable_fmu.jit import machine_cache
from towcable_fmu.fmu_build import build, kernels

TARGET = machine_cache.CARRIED_TARGET
V3_FLAGS = "fpu sse2 cx16 lahf_lm popcnt sse4_1 sse4_2 ssse3 avx avx2 bmi1 bmi2 f16c fma abm movbe xsave"


def test_cpu_check_needs_every_x86_64_v3_feature(tmp_path):
    info = tmp_path / "cpuinfo"
    info.write_text(f"processor\t: 0\nflags\t\t: {V3_FLAGS}\n")
    assert machine_cache.cpu_runs_carried_kernels(str(info)) == (os.uname().machine == "x86_64")
    info.write_text(f"flags\t\t: {V3_FLAGS.replace(' avx2', '')}\n")  # an Ivy Bridge: AVX but no AVX2
    assert not machine_cache.cpu_runs_carried_kernels(str(info))
    assert not machine_cache.cpu_runs_carried_kernels(str(tmp_path / "missing"))


def test_paths_are_rewritten_to_the_same_length():
    folder = Path("/home/someone/.cache/towcable/carried/x86-64-v3/code")
    data = b'\x00File "' + str(folder).encode() + b'/towcable_ab/towcable_fmu/x.py", line 3\x00'
    out = kernels.neutral_paths(data, {folder: "resources"})
    assert len(out) == len(data) and b"someone" not in out
    assert out.replace(b"/", b"").count(b".resources") == 1
    assert os.path.normpath(out.split(b'"')[1].decode()) == "resources/towcable_ab/towcable_fmu/x.py"


def _activation(tmp_path: Path, script: str, **env: str) -> dict:
    """Run ``script`` (``use`` = use_carried_kernels of a fake FMU, ``folder`` = its
    resources/kernels) in a fresh Python with an empty machine cache; return the JSON it
    prints."""
    folder = tmp_path / "resources" / "kernels"
    carried = folder / TARGET / "towcable-0123456789abcdef"
    carried.mkdir(parents=True)
    (folder / "TARGET").write_text(TARGET + "\n")
    (carried / "k.nbi").write_bytes(b"index")
    shutil.copy(machine_cache.__file__, tmp_path / "activate.py")
    preamble = textwrap.dedent(f"""
        import json, os, sys
        sys.path.insert(0, {str(tmp_path)!r})
        from pathlib import Path
        from activate import use_carried_kernels as use
        folder = Path({str(folder)!r})
        """)
    proc = subprocess.run([sys.executable, "-c", preamble + textwrap.dedent(script)], capture_output=True, text=True,
                          env=clean_env(TOWCABLE_CACHE_DIR=str(tmp_path / "cache"), **env), timeout=300)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


REPORT = """
    reason = use(folder)
    installed = Path(os.environ["TOWCABLE_CACHE_DIR"], "kernels", "towcable-0123456789abcdef")
    print(json.dumps({"reason": reason, "cpu": os.environ.get("NUMBA_CPU_NAME"),
                      "files": sorted(p.name for p in installed.glob("*")) if installed.is_dir() else None}))
    """


@pytest.mark.skipif(not machine_cache.cpu_runs_carried_kernels(), reason="this CPU cannot run x86-64-v3 code")
def test_carried_kernels_are_installed_and_chosen_before_numba_is_imported(tmp_path):
    got = _activation(tmp_path, REPORT)
    assert got == {"reason": None, "cpu": TARGET, "files": [machine_cache.CARRIED_MARK, "k.nbi"]}


@pytest.mark.skipif(not machine_cache.cpu_runs_carried_kernels(), reason="this CPU cannot run x86-64-v3 code")
def test_an_fmu_of_the_build_without_the_kernels_chooses_their_target(tmp_path):
    """ShipMotion first: it names the target, so TowCable's kernels apply when it comes."""
    got = _activation(tmp_path, "shutil = __import__('shutil'); shutil.rmtree(folder / " + repr(TARGET) + ")\n"
                      + textwrap.dedent(REPORT))
    assert got == {"reason": None, "cpu": TARGET, "files": None}


def test_an_fmu_built_without_kernels_changes_nothing(tmp_path):
    got = _activation(tmp_path, "(folder / 'TARGET').unlink()\n" + textwrap.dedent(REPORT))
    assert got == {"reason": "the FMU carries no precompiled kernels", "cpu": None, "files": None}


def test_carried_kernels_leave_a_numba_imported_for_this_cpu_alone(tmp_path):
    got = _activation(tmp_path, "import numba\n" + textwrap.dedent(REPORT))
    assert got["reason"].startswith("numba was imported before the FMU") and got["cpu"] is None
    assert got["files"] is None


def test_carried_kernels_respect_a_cpu_target_the_user_set(tmp_path):
    got = _activation(tmp_path, REPORT, NUMBA_CPU_NAME="generic")
    assert "NUMBA_CPU_NAME" in got["reason"] and got["cpu"] == "generic" and got["files"] is None


def test_carried_kernels_do_not_replace_kernels_compiled_on_the_machine(tmp_path):
    mine = tmp_path / "cache" / "kernels" / "towcable-0123456789abcdef"
    mine.mkdir(parents=True)
    (mine / "k.nbi").write_bytes(b"compiled here")
    got = _activation(tmp_path, REPORT)
    if machine_cache.cpu_runs_carried_kernels():
        assert "holds kernels compiled on this machine" in got["reason"]
    assert got["cpu"] is None and got["files"] == ["k.nbi"] and (mine / "k.nbi").read_bytes() == b"compiled here"


# ------------------------------------------------------------------ the whole claim
@pytest.fixture(scope="module")
def kernel_fmu(tmp_path_factory):
    """TowCable built with its kernels (compiled into the machine cache if absent), then
    moved to another folder."""
    built = build.build_fmus(tmp_path_factory.mktemp("built"), ["TowCable"], kernels=True)["TowCable"]
    moved = tmp_path_factory.mktemp("moved") / "TowCable.fmu"
    shutil.move(built, moved)
    return moved


RUN = """
    import json, sys, time
    from fmpy import simulate_fmu
    messages = []
    logger = lambda env, name, status, category, message: messages.append(message.decode())
    start = time.perf_counter()
    result = simulate_fmu(sys.argv[1], start_time=0.0, stop_time=0.2, step_size=0.01, output_interval=0.01,
                          output=["tension.sheave", "towbody.z", "winch.phi"], logger=logger, debug_logging=True,
                          start_values={"scene": "full_scale"})
    print(json.dumps({"seconds": time.perf_counter() - start, "log": messages,
                      "numba_cpu": sys.modules["numba"].core.config.CPU_NAME,
                      "out": {n: result[n].tolist() for n in result.dtype.names}}))
    """


def _run(python: Path, fmu: Path, cache: Path, cwd: Path, prelude: str = "") -> dict:
    proc = subprocess.run([str(python), "-c", prelude + textwrap.dedent(RUN), str(fmu)], capture_output=True,
                          text=True, cwd=cwd, env=clean_env(TOWCABLE_CACHE_DIR=str(cache)), timeout=1800)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_towcable_on_a_new_machine_compiles_nothing_and_agrees_with_kernels_compiled_there(kernel_fmu, fresh_venv,
                                                                                        tmp_path):
    with zipfile.ZipFile(kernel_fmu) as z:
        carried = {n: z.read(n) for n in z.namelist() if n.startswith(f"resources/kernels/{TARGET}/")}
    assert any(n.endswith(".nbc") for n in carried)
    for name, data in carried.items():
        for path in build_machine_paths():
            assert path.encode() not in data, (name, path)
        for folder in re.finditer(rb"([\w./+-]*)/(site-packages|python3\.\d+)/", data):  # of any Python
            assert re.fullmatch(rb"[^/]*\./*", folder.group(1)), (name, folder.group(0))  # only ./// + name
    fresh = _run(fresh_venv, kernel_fmu, tmp_path / "fresh-cache", tmp_path)
    assert not any("compiled the numerical kernels" in m for m in fresh["log"]), fresh["log"]
    assert fresh["numba_cpu"] == TARGET
    # numba imported first (as in a Python host that uses it): the kernels are compiled here, for this CPU
    here = _run(fresh_venv, kernel_fmu, tmp_path / "other-cache", tmp_path, prelude="import numba\n")
    compiled = [m for m in here["log"] if "compiled the numerical kernels" in m]
    assert compiled and "precompiled kernels were not used: numba was imported" in compiled[0]
    assert here["numba_cpu"] is None
    for name, series in fresh["out"].items():
        a, b = np.array(series), np.array(here["out"][name])
        assert np.allclose(a, b, rtol=1e-9, atol=1e-9 * (1.0 + np.max(np.abs(b)))), name
    assert np.ptp(fresh["out"]["tension.sheave"]) > 0.0
