"""Shared helpers for the test suite."""

from __future__ import annotations

import pytest


def cable_scene(segments: list[dict], top: dict, bottom: dict | None = None, **sections) -> dict:
    """A scene table (as parsed TOML) with the given cable and extra sections."""
    table = {"cable": {"segments": segments, "top": top}}
    if bottom is not None:
        table["cable"]["bottom"] = bottom
    table.update(sections)
    return table


def segment(length: float, elements: int, *, mu: float = 1.0, EA: float = 1e6, EI: float = 1e-3,
            damping: float = 0.0, diameter: float = 0.01, **extra) -> dict:
    """One cable segment table."""
    seg = {"length": length, "elements": elements, "diameter": diameter, "mass_per_length": mu,
           "EA": EA, "EI": EI, "damping": damping}
    seg.update(extra)
    return seg


@pytest.fixture
def make_sim():
    """Build a Simulation from a scene table."""
    from towcable_fmu.scene import scene_from_table
    from towcable_fmu.ancf.simulation import Simulation

    def _make(table: dict) -> Simulation:
        return Simulation(scene_from_table(table))

    return _make


@pytest.fixture(scope="session")
def fmu_paths(tmp_path_factory):
    """The three FMUs, built once per test session into a temporary folder."""
    from towcable_fmu.fmu_build.build import build_fmus

    return build_fmus(tmp_path_factory.mktemp("fmus"))


@pytest.fixture(scope="session")
def extracted(fmu_paths, tmp_path_factory):
    """Each FMU unzipped into its own folder (name -> folder)."""
    import zipfile

    root = tmp_path_factory.mktemp("extracted")
    out = {}
    for name, path in fmu_paths.items():
        out[name] = root / name
        with zipfile.ZipFile(path) as z:
            z.extractall(out[name])
    return out


@pytest.fixture(scope="session")
def fresh_venv(tmp_path_factory):
    """Python of a new venv with fmpy and the FMUs' requirements file, and nothing of towcable;
    numba and llvmlite at this Python's versions (those the precompiled kernels need)."""
    import os
    import subprocess
    import sys
    from importlib.metadata import version

    from towcable_fmu.fmu_build.build import requirements_text

    venv = tmp_path_factory.mktemp("fresh") / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=600)
    python = venv / "bin" / "python"
    (venv / "requirements.txt").write_text(requirements_text(), encoding="utf-8")
    (venv / "constraints.txt").write_text("".join(f"{name}=={version(name)}\n" for name in ("numba", "llvmlite")))
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "fmpy", "-r", str(venv / "requirements.txt"),
                    "-c", str(venv / "constraints.txt")], check=True, env=env, timeout=1800)
    return python


@pytest.fixture(scope="session")
def host(tmp_path_factory):
    """The C host of the FMU tests (tests/c_host/fmu_host.c), compiled with the system C compiler."""
    import subprocess
    from pathlib import Path

    from towcable_fmu.fmu_build import native

    exe = tmp_path_factory.mktemp("c_host") / "fmu_host"
    sources = sorted(str(p) for p in (Path(__file__).parent / "c_host").glob("*.c"))
    subprocess.run([native.c_compiler(), "-O1", "-g", "-Wall", "-Wextra", "-Werror", f"-I{native.fmi_headers()}",
                    *sources, "-o", str(exe), "-ldl", "-lm"], check=True)
    return exe


@pytest.fixture(scope="session", autouse=True)
def model_kernels():
    """The ANCF and nodal-position kernels compiled once, on every core, before the first
    test needs them (as the command line does on its first run)."""
    from towcable_fmu.models import KERNEL_SOURCES
    from towcable_fmu.jit.parallel_compile import compile_kernels

    assert compile_kernels(KERNEL_SOURCES["ancf"] + KERNEL_SOURCES["nodal_position"]) == []


class TermPart:
    """What one force term adds to the residual and to the iteration matrix of a running
    simulation, frozen at its current state: the system with the term minus the system
    ``without`` it (the same model with the term disabled), over the free coordinates.

    For comparing a term's tangent with central differences of its residual.
    """

    def __init__(self, sim, without) -> None:
        self.model, self.without = sim.model, without
        self.q, self.v, self.a = sim.state.q.copy(), sim.state.v.copy(), sim.state.a.copy()
        self.t, self.ship = sim.time, sim.workspace.ship.copy()
        self.free = sim.model.free_dofs

    def matrix(self, weights: tuple[float, float, float]):
        """The term's part of ``ca M + cv C + cq K`` (dense, free coordinates)."""
        from towcable_fmu.ancf.system import iteration_matrix
        from towcable_fmu.numerics.banded import band_storage, band_to_dense

        m, n = self.model, self.free.size
        out = []
        for model in (m, self.without):
            ab = band_storage(n, m.kl, m.ku)
            iteration_matrix(model, self.q, self.v, self.t, self.ship, *weights, ab)
            out.append(band_to_dense(ab, m.kl, m.ku))
        return out[0] - out[1]

    def residual(self, q, v, a):
        """The term's part of the residual (free coordinates)."""
        import numpy as np

        from towcable_fmu.ancf.system import residual

        with_term, without = np.zeros_like(q), np.zeros_like(q)
        residual(self.model, q, v, a, self.t, self.ship, with_term)
        residual(self.without, q, v, a, self.t, self.ship, without)
        return (with_term - without)[self.free]

    def differences(self, dq: float, dv: float, da: float, a=None):
        """Central differences of the term's residual, each free coordinate moved by dq in
        position, dv in velocity and da in acceleration together (accelerations ``a``,
        default the state's); not divided by the step."""
        import numpy as np

        a = self.a if a is None else a
        n = self.free.size
        fd = np.empty((n, n))
        for j, k in enumerate(self.free):
            e = np.zeros_like(self.q)
            e[k] = 1.0
            fd[:, j] = (self.residual(self.q + dq * e, self.v + dv * e, a + da * e)
                        - self.residual(self.q - dq * e, self.v - dv * e, a - da * e)) / 2.0
        return fd
