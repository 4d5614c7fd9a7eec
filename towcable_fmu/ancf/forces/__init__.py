"""The force terms of the ANCF cable: every force beyond the cable's own structure.

Each term is one module with the contract of :mod:`.term` (``NAME``, ``TABLES``, ``Data``,
``build`` and the kernels ``residual`` and ``tangent``) and, if it has outputs, state or
acts between steps, its ``Hooks`` (:mod:`.hooks`); :data:`TERMS` lists them,
:func:`add_residuals` and :func:`add_tangents` call their kernels in that order and
:func:`build_hooks` builds their hooks. To add a term: write its module, add it to
:data:`TERMS` and to both functions here, give it a table in the scene schema and a test
(docs/extending.md walks through an example; tests/test_force_terms.py checks that every
term of :data:`TERMS` is called, in order).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from ...jit.kernel_cache import njit
from ...scene.model import Scene
from ..model import CableModel, Mesh, Motion
from . import contact, feed, hydrodynamics, rigid_link, rigid_load, towbody, wake
from .hooks import TermHooks

#: The term modules, in the order their residuals and tangents are added.
TERMS = (feed, rigid_load, rigid_link, contact, hydrodynamics, towbody, wake)

#: The scene tables the terms model (their ``TABLES``, in the order of :data:`TERMS`).
TABLES = tuple(dict.fromkeys(table for term in TERMS for table in term.TABLES))

#: One field per term (its ``NAME``) holding the term's ``Data``: ``model.terms.contact``.
ForceTerms = NamedTuple("ForceTerms", [(term.NAME, term.Data) for term in TERMS])


def build_terms(scene: Scene, mesh: Mesh, model: CableModel) -> ForceTerms:
    """Every term's data for ``scene`` (``model``: the cable's own model, no terms yet)."""
    return ForceTerms(*(term.build(scene, mesh, model) for term in TERMS))


def build_hooks(scene: Scene, sim: Any) -> tuple[TermHooks, ...]:
    """Every term's hooks in a simulation of ``scene`` (a term without ``Hooks`` gets
    :class:`~.hooks.TermHooks`, which does nothing), in the order of :data:`TERMS`."""
    return tuple(getattr(term, "Hooks", TermHooks)(term.NAME, scene, sim) for term in TERMS)


# The calls are written out, one per term: numba then inlines each term's kernels into the
# assembly at their call site. A generic dispatch (an @overload per term type, with or
# without a literal_unroll loop) doubled the assembly's compile time (residual 36 -> 51 s,
# iteration matrix 22 -> 42 s, measured; these written-out calls: 30 s and 18 s).
@njit(cache=True, inline="always")
def add_residuals(model: CableModel, motion: Motion, a: np.ndarray, first: int, stop: int,
                  out: np.ndarray) -> None:
    """Every enabled term's ``residual`` (elements ``first`` to ``stop - 1``), in the order of :data:`TERMS`."""
    terms = model.terms
    if terms.feed.enabled:
        feed.residual(terms.feed, model, motion, a, first, stop, out)
    if terms.rigid_load.enabled:
        rigid_load.residual(terms.rigid_load, model, motion, a, first, stop, out)
    if terms.rigid_link.enabled:
        rigid_link.residual(terms.rigid_link, model, motion, a, first, stop, out)
    if terms.contact.enabled:
        contact.residual(terms.contact, model, motion, a, first, stop, out)
    if terms.hydrodynamics.enabled:
        hydrodynamics.residual(terms.hydrodynamics, model, motion, a, first, stop, out)
    if terms.towbody.enabled:
        towbody.residual(terms.towbody, model, motion, a, first, stop, out)
    if terms.wake.enabled:
        wake.residual(terms.wake, model, motion, a, first, stop, out)


@njit(cache=True, inline="always")
def add_tangents(model: CableModel, motion: Motion, ca: float, cv: float, cq: float, ab: np.ndarray) -> None:
    """Every enabled term's ``tangent``, in the order of :data:`TERMS`."""
    terms = model.terms
    if terms.feed.enabled:
        feed.tangent(terms.feed, model, motion, ca, cv, cq, ab)
    if terms.rigid_load.enabled:
        rigid_load.tangent(terms.rigid_load, model, motion, ca, cv, cq, ab)
    if terms.rigid_link.enabled:
        rigid_link.tangent(terms.rigid_link, model, motion, ca, cv, cq, ab)
    if terms.contact.enabled:
        contact.tangent(terms.contact, model, motion, ca, cv, cq, ab)
    if terms.hydrodynamics.enabled:
        hydrodynamics.tangent(terms.hydrodynamics, model, motion, ca, cv, cq, ab)
    if terms.towbody.enabled:
        towbody.tangent(terms.towbody, model, motion, ca, cv, cq, ab)
    if terms.wake.enabled:
        wake.tangent(terms.wake, model, motion, ca, cv, cq, ab)
