"""A force term's part of a running ANCF simulation outside the compiled step.

The compiled kernels of a term (:mod:`.term`) cover the step; some terms also give
outputs, keep a state of their own, act between steps or answer a query. A term module
declares that in a class ``Hooks``, a subclass of :class:`TermHooks` (a term without one
gets :class:`TermHooks`, which does nothing). The simulation
(:class:`~towcable_fmu.ancf.simulation.Simulation`) builds one per term of
:data:`~towcable_fmu.ancf.forces.TERMS`, in that order, and calls them in loops: it
names no term.

Outputs: ``OUTPUTS`` lists every output the term can give (rows of the contract,
``towcable_fmu/common/contract.toml``); ``outputs``, set when the hooks are built, those the
scene has. An output that is a field of the compiled output kernel
(:data:`~towcable_fmu.ancf.output_kernel.OUTPUT_FIELDS`) is computed there; any other is
computed in Python by :meth:`TermHooks.values` (the run then records one sample at a time).
"""

from __future__ import annotations

import weakref
from typing import Any

import numpy as np

from ...scene.model import Scene


class TermHooks:
    """The hooks of a term (all defaults do nothing).

    Parameters
    ----------
    name
        The term's ``NAME`` (its data: ``sim.model.terms.<name>``, see :attr:`term`).
    scene
        The scene, read here only (when the simulation is built).
    sim
        The simulation; its ``model`` (the terms' data built) and its scene's mesh
        ``_mesh`` are set.
    """

    #: Every output the term can give, in the order it reports them (rows of the contract).
    OUTPUTS: tuple[str, ...] = ()
    #: The term's element lengths change during a run (the simulation's mesh follows the model's);
    #: only such a term has events for :meth:`handle_event`.
    MOVES_MESH = False
    #: The term acts between solver steps (:meth:`before_step`, :meth:`after_step`): the
    #: simulation steps one solver step at a time and records in Python.
    STAGGERED = False

    def __init__(self, name: str, scene: Scene, sim: Any) -> None:
        self.name = name
        # held weakly: the simulation holds its hooks, and a cycle would keep both (the whole
        # model) alive until the garbage collector's next pass
        self._sim = weakref.ref(sim)
        #: The outputs of :data:`OUTPUTS` this scene has.
        self.outputs: tuple[str, ...] = ()
        #: Fields of :class:`~towcable_fmu.ancf.output_kernel.OutputScene` the term sets (what
        #: its compiled outputs need of the scene).
        self.output_scene: dict[str, Any] = {}

    @property
    def sim(self) -> Any:
        """The simulation the hooks belong to."""
        return self._sim()

    @property
    def term(self) -> Any:
        """The term's data in the simulation's current model (``model.terms.<name>``)."""
        return getattr(self.sim.model.terms, self.name)

    # ---------------------------------------------------------------- outputs
    def values(self) -> list[float]:
        """The term's outputs that the compiled output kernel does not give, at the current
        state, in the order of :attr:`outputs`."""
        return []

    # ------------------------------------------------------------------ state
    def reset(self) -> None:
        """At initialisation, before the initial state is laid out."""

    def statics_loads(self, model: Any) -> np.ndarray | None:
        """The constant loads [N] of ``model``'s statics when the term changes them (a load
        held at rest until the run starts); None: the model's own."""
        return None

    def start(self, phi: float) -> None:
        """At initialisation, with the winch rotation the run starts from [rad] (may refuse it:
        :class:`~towcable_fmu.common.errors.SceneError`)."""

    def save(self) -> Any:
        """The term's state beyond the state arrays, JSON-able (None: none)."""
        return None

    def adopt(self, saved: Any) -> None:
        """Before a saved state's arrays are checked: make the model the saved state's
        (``saved``: what :meth:`save` gave, None if nothing)."""

    def restore(self, saved: Any) -> None:
        """Restore what :meth:`save` gave (None: nothing was saved)."""

    def rebuilt(self, model: Any, lengths: np.ndarray, phi_ref: float) -> None:
        """The model was built again for element lengths ``lengths`` [m] at winch rotation
        ``phi_ref`` [rad] (a remesh): set the term's data that follows the run."""

    # ------------------------------------------------------------------ steps
    def before_step(self, h: float) -> None:
        """Before a solver step of ``h`` [s] (:attr:`STAGGERED` terms)."""

    def after_step(self, h: float) -> None:
        """After an accepted solver step of ``h`` [s] (:attr:`STAGGERED` terms)."""

    def handle_event(self) -> bool:
        """After a step stopped at an event: act on it (remesh) and return True, or return
        False if the event is not the term's."""
        return False

    def remesh(self, key: str) -> None:
        """Before elements are split or merged (``key``: the method's name): refuse it with a
        :class:`~towcable_fmu.common.errors.SceneError` if the term's state cannot follow."""

    def new_node_rates(self, element: int, xi: float) -> tuple[np.ndarray, np.ndarray] | None:
        """The velocity and acceleration (6,) a node inserted at ``xi`` of ``element`` takes,
        if the term moves material there (None: the element's interpolation)."""
        return None

    def failure_hint(self) -> str:
        """What a failed step may be due to, as "; ..." (empty: nothing to say)."""
        return ""
