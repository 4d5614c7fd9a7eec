"""A throw-away force term added the way docs/extending.md says, in a copy of the code:
only the files the guide lists are edited, and the term is a full member of the ANCF
cable (its scene table accepted, refused by the nodal cable through the general rule,
its force in the solution, its output among the outputs, its state saved and restored).

The term is a constant pull ``F`` [N] on the cable's last node, whose work
``pull.work`` [J] the term sums over the solver steps (a state of its own, saved with
the simulation's). Checked against independent statements: the top reaction of a
hanging cable rises by the pull (the whole cable's force balance), and the work of a
constant force is F . (x(t) - x(0)) whatever the path.
"""

from __future__ import annotations

import ast
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: The files the guide (docs/extending.md) lists for a term with an output and a state of
#: its own, and that this test edits; nothing else.
GUIDE_FILES = ("towcable_fmu/ancf/forces/pull.py", "towcable_fmu/ancf/forces/__init__.py",
               "towcable_fmu/scene/model.py", "towcable_fmu/common/contract.toml")

PULL_MODULE = '''"""Force term: a constant pull on the cable's last node (a test's throw-away term)."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ...jit.kernel_cache import njit
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from .hooks import TermHooks

NAME = "pull"
TABLES = ("pull",)


class Data(NamedTuple):
    enabled: bool
    index: int          #: first coordinate of the last node
    force: np.ndarray   #: (3,) the pull [N]


def build(scene: Scene, mesh: Mesh, model: CableModel) -> Data:
    if scene.pull is None:
        return Data(False, 0, np.zeros(3))
    return Data(True, 6 * (mesh.n_nodes - 1), np.array(scene.pull.force, dtype=float))


@njit(cache=True, inline="always")
def residual(term, model, motion, a, first, stop, out):
    if stop == model.el_len.shape[0]:
        for c in range(3):
            out[term.index + c] -= term.force[c]


@njit(cache=True, inline="always")
def tangent(term, model, motion, ca, cv, cq, ab):
    pass  # a constant force


class Hooks(TermHooks):
    OUTPUTS = ("pull.work",)
    STAGGERED = True

    def __init__(self, name: str, scene: Scene, sim: Any) -> None:
        super().__init__(name, scene, sim)
        self.outputs = self.OUTPUTS if scene.pull is not None else ()
        self.STAGGERED = scene.pull is not None
        self.work = 0.0
        self._before = np.zeros(3)

    def reset(self) -> None:
        self.work = 0.0

    def save(self) -> Any:
        return {"work": self.work} if self.term.enabled else None

    def restore(self, saved: Any) -> None:
        if saved is not None:
            self.work = float(saved["work"])

    def before_step(self, h: float) -> None:
        i = self.term.index
        self._before = self.sim.state.q[i:i + 3].copy()

    def after_step(self, h: float) -> None:
        i = self.term.index
        self.work += float(self.term.force @ (self.sim.state.q[i:i + 3] - self._before))

    def values(self) -> list[float]:
        return [self.work]
'''

PULL_TABLE = '''

@dataclasses.dataclass(frozen=True)
class Pull:
    """A constant pull on the cable's last node."""

    force: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="N", length=3, doc="the pull (inertial axes)")


'''

PULL_SIGNAL = '''[signals."pull.work"]
unit = "J"
description = "work done by the pull on the last node since the start"
'''

CHECK = '''
import json, sys
import numpy as np
import towcable_fmu
from towcable_fmu.ancf.simulation import Simulation
from towcable_fmu.common.errors import SceneError
from towcable_fmu.nodal.model import check_scene
from towcable_fmu.scene import load_scene

F = 300.0
result = {"package": towcable_fmu.__file__}
plain = Simulation(load_scene("hanging_cable"))
top0 = plain.initialize()["tension.top"]
scene = load_scene("hanging_cable", {"pull.force": [0.0, 0.0, -F]})
try:
    check_scene(scene)
    result["nodal"] = "accepted"
except SceneError as exc:
    result["nodal"] = str(exc)
sim = Simulation(scene)
out = sim.initialize()
result["names"] = list(sim.names)
result["unit"] = sim.unit_of("pull.work")
result["top_rise"] = out["tension.top"] - top0
x0 = sim.node_positions()[-1].copy()
out = sim.advance(0.3)
result["work"] = out["pull.work"]
result["work_closed_form"] = float(np.array([0.0, 0.0, -F]) @ (sim.node_positions()[-1] - x0))
saved = sim.get_state()
first = sim.advance(0.5)
sim.set_state(json.loads(json.dumps(saved)))
again = sim.advance(0.5)
result["round_trip"] = [first[k] == again[k] for k in ("pull.work", "tension.top", "towbody.z")]
result["moved"] = first["pull.work"] != out["pull.work"]
print(json.dumps(result))
'''


def _insert_lines(path: Path, function: str, lines: list[str]) -> None:
    """Append ``lines`` (indented as the body) at the end of ``function`` in ``path``."""
    text = path.read_text(encoding="utf-8").splitlines(keepends=True)
    node = next(n for n in ast.parse("".join(text)).body if isinstance(n, ast.FunctionDef) and n.name == function)
    text[node.end_lineno:node.end_lineno] = [f"    {line}\n" for line in lines]
    path.write_text("".join(text), encoding="utf-8")


def _add_the_term(root: Path) -> None:
    """The guide's edits, and no other: the module; TERMS and one call in each of
    add_residuals and add_tangents; a table of the scene schema; the output's row of the
    contract."""
    (root / GUIDE_FILES[0]).write_text(PULL_MODULE, encoding="utf-8")
    registry = root / GUIDE_FILES[1]
    text = registry.read_text(encoding="utf-8")
    terms = next(n for n in ast.parse(text).body if isinstance(n, ast.Assign) and n.targets[0].id == "TERMS")
    lines = text.splitlines(keepends=True)
    line = lines[terms.end_lineno - 1]
    lines[terms.end_lineno - 1] = line[:line.rindex(")")] + ", pull)" + line[line.rindex(")") + 1:]
    lines.insert(terms.lineno - 1, "from . import pull\n")
    registry.write_text("".join(lines), encoding="utf-8")
    _insert_lines(registry, "add_residuals", ["if terms.pull.enabled:",
                                              "    pull.residual(terms.pull, model, motion, a, first, stop, out)"])
    _insert_lines(registry, "add_tangents", ["if terms.pull.enabled:",
                                             "    pull.tangent(terms.pull, model, motion, ca, cv, cq, ab)"])
    schema = root / GUIDE_FILES[2]
    text = schema.read_text(encoding="utf-8")
    scene = next(n for n in ast.parse(text).body if isinstance(n, ast.ClassDef) and n.name == "Scene")
    load = next(n for n in scene.body if isinstance(n, ast.AnnAssign) and n.target.id == "load")
    lines = text.splitlines(keepends=True)
    lines.insert(load.end_lineno, '    pull: Pull | None = spec(None, doc="a constant pull on the last node")\n')
    lines.insert(scene.lineno - 1 - len(scene.decorator_list), PULL_TABLE)
    schema.write_text("".join(lines), encoding="utf-8")
    contract = root / GUIDE_FILES[3]
    contract.write_text(contract.read_text(encoding="utf-8").replace("[signals.", PULL_SIGNAL + "[signals.", 1),
                        encoding="utf-8")


# slow: the copy's kernels differ from the installed ones (a new term), so its run compiles
# every ANCF kernel afresh (3-12 min on two cores)
@pytest.mark.slow
def test_a_throw_away_term_needs_only_the_files_the_guide_lists(tmp_path):
    guide = (ROOT / "docs/extending.md").read_text(encoding="utf-8")
    for name in ("ancf/forces/__init__.py", "scene/model.py", "contract.toml"):
        assert name in guide
    root = tmp_path / "code"
    for package in ("towcable_fmu", "ship_motion", "controllers"):
        shutil.copytree(ROOT / package, root / package, ignore=shutil.ignore_patterns("__pycache__"))
    before = {p: p.read_bytes() for p in root.rglob("*") if p.is_file()}
    _add_the_term(root)
    edited = sorted(p.relative_to(root).as_posix() for p in root.rglob("*")
                    if p.is_file() and before.get(p) != p.read_bytes())
    assert edited == sorted(GUIDE_FILES)

    env = {**os.environ, "PYTHONPATH": str(root)}
    run = subprocess.run([sys.executable, "-c", CHECK], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=1800)
    assert run.returncode == 0, run.stderr[-3000:]
    result = json.loads(run.stdout.strip().splitlines()[-1])
    assert result["package"].startswith(str(root))
    assert "pull = '[pull]'" in result["nodal"] and "nodal_position" in result["nodal"]
    assert result["names"][-1] == "pull.work" and result["unit"] == "J"
    assert abs(result["top_rise"] - 300.0) < 1e-3 * 300.0
    assert result["moved"]
    assert abs(result["work"] - result["work_closed_form"]) <= 1e-9 * max(1.0, abs(result["work_closed_form"]))
    assert all(result["round_trip"])
