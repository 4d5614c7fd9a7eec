"""The force terms of the ANCF cable keep one contract (towcable_fmu/ancf/forces/term.py),
the registry calls every term's kernels in the order of TERMS, a scene enables exactly
the terms it contains, and the assembly names none of them."""

from __future__ import annotations

import ast
import typing
from pathlib import Path

import pytest

from towcable_fmu.ancf import forces
from towcable_fmu.ancf.simulation import Simulation

ROOT = Path(__file__).resolve().parents[1]
RESIDUAL_ARGUMENTS = ("term", "model", "motion", "a", "first", "stop", "out")
TANGENT_ARGUMENTS = ("term", "model", "motion", "ca", "cv", "cq", "ab")


def test_every_term_keeps_the_contract():
    """NAME, Data (a NamedTuple whose first field is ``enabled``), build, and both kernels
    with the contract's arguments."""
    assert forces.ForceTerms._fields == tuple(t.NAME for t in forces.TERMS)
    for module in forces.TERMS:
        data = module.Data
        assert issubclass(data, tuple) and data._fields[0] == "enabled", module.NAME
        assert list(typing.get_type_hints(module.build)) == ["scene", "mesh", "model", "return"], module.NAME
        assert module.residual.py_func.__code__.co_varnames[:7] == RESIDUAL_ARGUMENTS, module.NAME
        assert module.tangent.py_func.__code__.co_varnames[:7] == TANGENT_ARGUMENTS, module.NAME


def _calls_in(function: str) -> list[tuple[str, str, str]]:
    """(module, kernel, term field) of each ``module.kernel(terms.field, ...)`` call in a
    function of towcable_fmu/ancf/forces/__init__.py, in source order."""
    tree = ast.parse((ROOT / "towcable_fmu/ancf/forces/__init__.py").read_text(encoding="utf-8"))
    body = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == function)
    calls = [n for n in ast.walk(body) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)]
    return [(c.func.value.id, c.func.attr, c.args[0].attr) for c in sorted(calls, key=lambda c: c.lineno)]


@pytest.mark.parametrize("function, kernel", [("add_residuals", "residual"), ("add_tangents", "tangent")])
def test_the_registry_calls_every_term_in_order(function, kernel):
    """Each term of TERMS once, with its own data, in the order of TERMS: a term added to
    TERMS but not to these calls (or the reverse) fails here."""
    names = [t.NAME for t in forces.TERMS]
    assert _calls_in(function) == [(name, kernel, name) for name in names]
    assert [t.__name__.rsplit(".", 1)[-1] for t in forces.TERMS] == names   # module file = NAME


@pytest.mark.parametrize("scene, overrides, enabled", [
    ("hanging_cable", {}, set()),
    ("full_scale", {}, {"contact", "hydrodynamics", "towbody"}),
    ("tug_tow_ancf", {}, {"hydrodynamics", "towbody"}),
    ("sea_trial_turn_rigid", {"model": "ancf"}, {"hydrodynamics", "rigid_link"}),
    ("pulley_static", {}, {"contact", "rigid_load"}),
    ("viv_sheave", {}, {"contact", "hydrodynamics", "wake"}),
])
def test_a_scene_enables_the_terms_it_contains(scene, overrides, enabled):
    sim = Simulation.from_scene(scene, overrides)
    on = {name for name, data in zip(sim.model.terms._fields, sim.model.terms) if data.enabled}
    assert on == enabled


def test_the_assembly_names_no_term():
    """system.py imports the registry's two calls only and mentions no term module or term data."""
    source = (ROOT / "towcable_fmu/ancf/system.py").read_text(encoding="utf-8")
    tree = ast.parse(source)
    imported = {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    assert imported == {"__future__", "jit.kernel_cache", "numerics.banded", "axial", "forces", "model"}
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)} | \
        {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    assert not names & ({t.NAME for t in forces.TERMS} | {"contact", "hydro", "body", "rigid", "load", "wake"})


@pytest.mark.parametrize("module", ["simulation", "remeshing", "state_queries"])
def test_the_simulation_names_no_term(module):
    """The ANCF simulation and its two parts reach the terms through their hooks only: no
    term module imported, no term's data read (``model.terms.<name>``), no term named."""
    tree = ast.parse((ROOT / f"towcable_fmu/ancf/{module}.py").read_text(encoding="utf-8"))
    term_names = {t.NAME for t in forces.TERMS}
    imported = {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    assert not {m for m in imported if m and m.startswith("forces.") and m != "forces.hooks"}
    assert not [n for n in ast.walk(tree) if isinstance(n, ast.Attribute) and n.attr == "terms"]
    words = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)} | \
        {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)} | \
        {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)}
    assert not words & (term_names | {"viv", "rigid", "load"})


def test_the_terms_declare_outputs_of_the_contract():
    """Every output a term's hooks declare is a signal of the contract; a term with an
    output outside the compiled kernel computes it in Python (its hooks' ``values``)."""
    from towcable_fmu.common import contract
    from towcable_fmu.ancf.forces.hooks import TermHooks
    from towcable_fmu.ancf.output_kernel import OUTPUT_FIELDS

    for module in forces.TERMS:
        hooks = getattr(module, "Hooks", TermHooks)
        assert set(hooks.OUTPUTS) <= set(contract.signals()), module.NAME
        if set(hooks.OUTPUTS) - set(OUTPUT_FIELDS):
            assert hooks.values is not TermHooks.values, module.NAME


@pytest.mark.parametrize("scene, overrides, declared", [
    ("full_scale", {}, {"towbody": 7, "contact": 8}),
    ("sea_trial_turn_rigid", {"model": "ancf"}, {"rigid_link": 10}),
    ("pulley_static", {}, {"contact": 7, "rigid_load": 3}),
])
def test_the_outputs_of_a_scene_are_the_cables_and_its_terms(scene, overrides, declared):
    """The scene's outputs: the cable's own (and the winch's payout with a winch) and the
    outputs its terms' hooks declare for it, no other."""
    from towcable_fmu.ancf.output_kernel import CABLE_OUTPUTS

    sim = Simulation.from_scene(scene, overrides)
    counts = {h.name: len(h.outputs) for h in sim.hooks if h.outputs}
    assert counts == declared
    terms = [name for h in sim.hooks for name in h.outputs]
    winch = ("winch.payout",) if "winch.payout" in sim.names else ()
    assert sorted(sim.names) == sorted(CABLE_OUTPUTS + winch + tuple(terms))
