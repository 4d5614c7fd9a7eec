"""The project's modules are layered: no import cycle, the cable formulations (ANCF,
nodal-position, rigid-link) do not import each other, and nothing but the command line
imports the command line. Every import counts, also one inside a function (a deferred
import still makes the module depend on the other).

Folders are layered too: every folder (a sub-package of ``towcable_fmu``, or one of its
top-level modules, or the ``ship_motion`` and ``controllers`` packages) has its place in
:data:`LAYERS`, and a module reaches, directly or through other modules, only modules of
its own folder or of a lower layer. A new folder gets its place here."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("towcable_fmu", "ship_motion", "controllers")
FORMULATIONS = ("towcable_fmu.ancf", "towcable_fmu.nodal", "towcable_fmu.rigidlink")
COMMAND_LINE = ("towcable_fmu.cli", "towcable_fmu.sweep.cli")

#: The folders from the bottom up; a folder imports only from the layers below its own
#: (folders of one layer do not import each other).
LAYERS = (
    ("towcable_fmu", "towcable_fmu.common"),
    ("towcable_fmu.builtin_scenes",),
    ("towcable_fmu.jit",),
    ("towcable_fmu.numerics",),
    ("towcable_fmu.fmi",),
    ("ship_motion", "controllers"),
    ("towcable_fmu.scene",),
    ("towcable_fmu.hydro", "towcable_fmu.contact", "towcable_fmu.viv"),
    ("towcable_fmu.runtime",),
    FORMULATIONS,
    ("towcable_fmu.fmu_build",),
    ("towcable_fmu.models", "towcable_fmu.animation", "towcable_fmu.cosim"),
    ("towcable_fmu.analysis", "towcable_fmu.docs_gen", "towcable_fmu.rope_life"),
    ("towcable_fmu.sweep", "towcable_fmu.fmu", "towcable_fmu.build_command"),
    ("towcable_fmu.cli",),
)


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


def folder(module: str) -> str:
    """The folder of a module: ``towcable_fmu.<first part>``, or its top-level package."""
    parts = module.split(".")
    return ".".join(parts[:2]) if parts[0] == "towcable_fmu" and len(parts) > 1 else parts[0]


def layer_of() -> dict[str, int]:
    return {f: i for i, layer in enumerate(LAYERS) for f in layer}


def upward_paths(graph: dict[str, set[str]], layers: dict[str, int]) -> list[list[str]]:
    """For each module, the first chain of imports (direct or through other modules) found
    that reaches a module of another folder not in a lower layer."""
    found = []
    for start in sorted(graph):
        own = folder(start)
        parent = {start: None}
        queue = [start]
        while queue:
            m = queue.pop(0)
            for t in sorted(graph.get(m, ())):
                if t in parent:
                    continue
                parent[t] = m
                if folder(t) != own and layers[folder(t)] >= layers[own]:
                    path = [t]
                    while path[-1] != start:
                        path.append(parent[path[-1]])
                    found.append(path[::-1])
                    queue = []
                    break
                queue.append(t)
    return found


def test_every_folder_has_a_layer():
    layers = layer_of()
    assert sum(len(layer) for layer in LAYERS) == len(layers)  # no folder twice
    assert sorted({folder(m) for m in import_graph()} - set(layers)) == []


def test_the_layer_check_sees_indirect_and_same_layer_imports():
    """It can fail: a chain that climbs through a module of a lower folder, and an import
    between two folders of one layer."""
    layers = {"towcable_fmu.low": 0, "towcable_fmu.mid": 1, "towcable_fmu.high": 2, "towcable_fmu.peer": 2}
    graph = {"towcable_fmu.mid.a": {"towcable_fmu.low.b"}, "towcable_fmu.low.b": {"towcable_fmu.low.c"},
             "towcable_fmu.low.c": {"towcable_fmu.high"}, "towcable_fmu.high": {"towcable_fmu.peer"},
             "towcable_fmu.peer": set()}
    assert upward_paths(graph, layers) == [
        ["towcable_fmu.high", "towcable_fmu.peer"],
        ["towcable_fmu.low.b", "towcable_fmu.low.c", "towcable_fmu.high"],
        ["towcable_fmu.low.c", "towcable_fmu.high"],
        ["towcable_fmu.mid.a", "towcable_fmu.low.b", "towcable_fmu.low.c", "towcable_fmu.high"]]


def test_folders_import_only_downward():
    assert upward_paths(import_graph(), layer_of()) == []


#: Below the scene package (issue 38): the ship motion, the controllers, the FMI runtime
#: base of the slaves, the schema mechanism, the errors and the built-in scene files.
BELOW_THE_SCENE = ("ship_motion", "controllers", "towcable_fmu.fmi", "towcable_fmu.common.schema", "towcable_fmu.common.errors",
                   "towcable_fmu.builtin_scenes")


def test_nothing_below_the_scene_package_reaches_it():
    """Not even through another module: the ship and controller slaves run without it."""
    graph = import_graph()
    upward = sorted((m, t) for m in graph if any(_in(m, low) for low in BELOW_THE_SCENE)
                    for t in reached(graph, m) if _in(t, "towcable_fmu.scene"))
    assert upward == []


def reached(graph: dict[str, set[str]], module: str) -> set[str]:
    """Every module that ``module`` imports, directly or through other modules."""
    seen, todo = set(), [module]
    while todo:
        for target in graph[todo.pop()] - seen:
            seen.add(target)
            todo.append(target)
    return seen


def formulations_reached_from(graph: dict[str, set[str]], package: str) -> list[tuple[str, str]]:
    """(module of ``package``, formulation module it reaches) for every such pair."""
    return sorted((m, t) for m in graph if _in(m, package) for t in reached(graph, m)
                  if any(_in(t, f) for f in FORMULATIONS))


def test_numerics_knows_no_formulation():
    """The solvers in numerics/ (the generalised-alpha scheme, the banded LU, the explicit
    step) receive a model's residual and matrix and import no formulation package, not even
    through another module. The check can fail: an import of the ANCF model two modules away."""
    fake = {"towcable_fmu.numerics.scheme": {"towcable_fmu.jit.kernel_cache"},
            "towcable_fmu.jit.kernel_cache": {"towcable_fmu.ancf.model"}, "towcable_fmu.ancf.model": set()}
    assert formulations_reached_from(fake, "towcable_fmu.numerics") == [
        ("towcable_fmu.numerics.scheme", "towcable_fmu.ancf.model")]
    assert formulations_reached_from(import_graph(), "towcable_fmu.numerics") == []


def calls_of(path: Path) -> set[str]:
    """The names of the functions a module's source calls (``f(...)`` and ``m.f(...)``)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call):
            f = node.func
            found.add(f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else "")
    return found


def test_the_nodal_cable_steps_with_the_generic_solver():
    """The nodal cable's generalised-alpha step calls numerics' Newton step
    (``alpha_step``) and overloads every function of its protocol for its model: the
    iteration is numerics' code, the formulation gives its residual, matrix, start and
    norm. (The ANCF cable's Newton loop is still its own, in ``ancf/genalpha.py``.)"""
    known = modules()
    graph = import_graph()
    name = "towcable_fmu.nodal.integrators"
    assert "towcable_fmu.numerics.alpha_newton" in graph[name]
    assert "alpha_step" in calls_of(known[name])
    tree = ast.parse(known[name].read_text(encoding="utf-8"))
    overloaded = {d.args[0].id for node in ast.walk(tree) if isinstance(node, ast.FunctionDef)
                  for d in node.decorator_list if isinstance(d, ast.Call) and getattr(d.func, "id", "") == "overload_for"}
    assert overloaded == {"model_start", "model_residual", "model_factorize", "model_solve", "model_correct"}
    protocol = ast.parse(known["towcable_fmu.numerics.alpha_newton"].read_text(encoding="utf-8"))
    stubs = {t.id for node in ast.walk(protocol) if isinstance(node, ast.Assign) and isinstance(node.value, ast.Call)
             and getattr(node.value.func, "id", "") == "_protocol" for t in node.targets}
    assert stubs == overloaded
