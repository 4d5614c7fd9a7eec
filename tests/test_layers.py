"""The project's modules are layered: no import cycle, the cable formulations (ANCF,
nodal-position, rigid-link) do not import each other, and nothing but the command line
imports the command line. Every import counts, also one inside a function (a deferred
import still makes the module depend on the other)."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("towcable_fmu", "ship_motion", "controllers")
FORMULATIONS = ("towcable_fmu.ancf", "towcable_fmu.nodal", "towcable_fmu.rigidlink")
COMMAND_LINE = ("towcable_fmu.cli", "towcable_fmu.sweep.cli")


def modules() -> dict[str, Path]:
    """Dotted module name -> source file, for every module of the three packages."""
    out = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def imports(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The project modules that module ``name`` imports (anywhere in its source)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")[:len(package.split(".")) - (node.level - 1)] if node.level else []
            prefix = ".".join(base + ([node.module] if node.module else []))
            # "from P import X": the module P.X if X is one, else P itself
            targets = [f"{prefix}.{a.name}" if f"{prefix}.{a.name}" in known else prefix for a in node.names]
        else:
            continue
        for target in targets:
            while target and target not in known:
                target = target.rpartition(".")[0]
            if target and target != name:
                found.add(target)
    return found


def import_graph() -> dict[str, set[str]]:
    known = modules()
    return {name: imports(name, path, known) for name, path in known.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def _in(module: str, package: str) -> bool:
    return module == package or module.startswith(package + ".")


def test_the_graph_sees_deferred_and_relative_imports():
    """The checks below can fail: the graph finds a known deferred import and a relative one."""
    graph = import_graph()
    assert "towcable_fmu.ancf.simulation" in graph["towcable_fmu.models"]  # inside simulation_for
    assert "towcable_fmu.ancf.model" in graph["towcable_fmu.ancf.mesh"]  # from .model import
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_import_cycle():
    assert cycles(import_graph()) == []


def test_the_formulations_do_not_import_each_other():
    graph = import_graph()
    crossing = sorted((m, t) for m, targets in graph.items() for t in targets for own in FORMULATIONS
                      if _in(m, own) and any(_in(t, other) for other in FORMULATIONS if other != own))
    assert crossing == []


def test_only_the_command_line_imports_the_command_line():
    graph = import_graph()
    importers = sorted(m for m, targets in graph.items() for t in targets
                       if t in COMMAND_LINE and m not in COMMAND_LINE)
    assert importers == []
