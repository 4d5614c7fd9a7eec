"""The machine's kernel cache (towcable_fmu.jit.kernel_cache): keyed by the kernels' sources,
compiled at initialisation and never in the middle of a run, found again by a new process."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from towcable_fmu.jit import kernel_cache
from towcable_fmu.jit.machine_cache import PACKAGES

ROOT = Path(__file__).resolve().parents[1]


def test_digest_follows_the_kernel_and_overload_sources_and_nothing_else(tmp_path):
    for package in PACKAGES:
        shutil.copytree(ROOT / package, tmp_path / package, ignore=shutil.ignore_patterns("__pycache__"))
    kernel_cache.kernel_digest.cache_clear()
    try:
        before = kernel_cache.kernel_digest(tmp_path)
        assert before == kernel_cache.kernel_digest(ROOT)  # the same sources in another folder
        plain = tmp_path / "towcable_fmu" / "cli.py"  # no kernel in it
        assert b"@njit" not in plain.read_bytes()
        plain.write_text(plain.read_text(encoding="utf-8") + "\n# edited\n", encoding="utf-8")
        kernel_cache.kernel_digest.cache_clear()
        assert kernel_cache.kernel_digest(tmp_path) == before
        kernel = tmp_path / "towcable_fmu" / "hydro" / "loading.py"
        assert b"@njit" in kernel.read_bytes()
        kernel.write_text(kernel.read_text(encoding="utf-8") + "\n# edited\n", encoding="utf-8")
        kernel_cache.kernel_digest.cache_clear()
        edited = kernel_cache.kernel_digest(tmp_path)
        assert edited != before
        # a file with only a numba overload (a formulation's part of a protocol a kernel calls)
        overloads = tmp_path / "towcable_fmu" / "numerics" / "overloads_only.py"
        overloads.write_text("@overload(model_residual)\ndef _residual(model, step):\n    return None\n",
                             encoding="utf-8")
        kernel_cache.kernel_digest.cache_clear()
        with_overloads = kernel_cache.kernel_digest(tmp_path)
        assert with_overloads != edited
        overloads.write_text(overloads.read_text(encoding="utf-8") + "# edited\n", encoding="utf-8")
        kernel_cache.kernel_digest.cache_clear()
        assert kernel_cache.kernel_digest(tmp_path) != with_overloads
    finally:
        kernel_cache.kernel_digest.cache_clear()


#: Initialise full_scale and run it for 2 s in a new process; prints the compile seconds
#: of each phase (kernel_cache.WATCH) as JSON.
_PHASES = textwrap.dedent("""
    import json
    from towcable_fmu.jit import kernel_cache
    from towcable_fmu.models import simulation_for
    from towcable_fmu.scene import load_scene

    sim = simulation_for(load_scene("full_scale"))
    sim.initialize()
    initialise = kernel_cache.WATCH.seconds
    sim.run(2.0)
    print(json.dumps({"initialise": initialise, "run": kernel_cache.WATCH.seconds - initialise}))
    """)


def _phases(cache: Path) -> dict[str, float]:
    env = {**os.environ, "TOWCABLE_CACHE_DIR": str(cache)}
    proc = subprocess.run([sys.executable, "-c", _PHASES], capture_output=True, text=True, env=env, timeout=1800,
                          cwd=ROOT)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.slow  # compiles every kernel of full_scale once (1.5-5 min)
def test_kernels_compile_at_initialisation_only_and_once_per_machine(tmp_path):
    first = _phases(tmp_path / "cache")
    assert first["initialise"] > 1.0  # an empty cache: the kernels were compiled ...
    assert first["run"] == 0.0  # ... all of them before the run
    again = _phases(tmp_path / "cache")
    assert again == {"initialise": 0.0, "run": 0.0}  # a new process finds them all
    assert any((tmp_path / "cache" / "kernels").rglob("*.nbi"))


def test_a_kernel_numba_cannot_cache_warns_and_runs(tmp_path, monkeypatch):
    """A kernel of our packages that numba refuses to cache (here: it calls a ctypes
    function pointer, a "dynamic global"; NUMBA_OPT=0 makes some of ours so) gets numba's
    warning, and runs: the locator must give numba's warning what it needs."""
    import ctypes
    import warnings

    from numba.core.errors import NumbaWarning

    from towcable_fmu.jit.kernel_cache import njit

    monkeypatch.setenv("TOWCABLE_CACHE_DIR", str(tmp_path))
    libm = ctypes.CDLL(None)
    cos = libm.cos
    cos.restype, cos.argtypes = ctypes.c_double, [ctypes.c_double]
    source = "def kernel_of_ours(x):\n    return cos(x) + 1.0\n"
    namespace = {"cos": cos}
    exec(compile(source, str(ROOT / "towcable_fmu" / "not_cacheable.py"), "exec"), namespace)
    kernel = njit(cache=True)(namespace["kernel_of_ours"])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert kernel(0.0) == pytest.approx(2.0)
    assert any(issubclass(w.category, NumbaWarning) and "Cannot cache" in str(w.message) for w in caught)


def test_importing_the_package_does_no_work_and_a_kernel_module_installs_the_locator():
    """``import towcable_fmu`` (and its scene and contract modules) imports no numba; the
    first kernel module imported puts our cache locator first and registers the watch."""
    code = textwrap.dedent("""
        import sys
        import towcable_fmu, towcable_fmu.scene, towcable_fmu.common.contract
        assert "numba" not in sys.modules, "numba imported"
        from towcable_fmu.ancf import system
        from numba.core import caching
        impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
        from towcable_fmu.jit.kernel_cache import KernelCacheLocator
        assert impl._locator_classes[0] is KernelCacheLocator
        assert type(system.residual._cache._impl.locator) is KernelCacheLocator
        print("ok")
    """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                          env=dict(os.environ, PYTHONPATH=str(ROOT)), timeout=300)
    assert proc.returncode == 0 and proc.stdout.strip() == "ok", proc.stderr
