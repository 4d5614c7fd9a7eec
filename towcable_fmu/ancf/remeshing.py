"""Remeshing a running ANCF cable: splitting and merging elements on request or when a
term asks for it after a step (a spool end's fed element, followed as the winch pays out
or hauls in: :class:`towcable_fmu.ancf.forces.feed.Hooks`); a part of
:class:`~towcable_fmu.ancf.simulation.Simulation`.

The mixin uses the simulation's state (``mesh``, ``model``, ``state``, ``workspace``,
``hooks``) and its ``_model_for``, ``_use`` and ``outputs``.
"""

from __future__ import annotations

import numpy as np

from ..common.errors import SceneError
from . import genalpha
from .feed import apply_feed
from .model import TAUT_RESIDUAL, Mesh
from .remesh import merge_coordinates, merge_defect, merge_mesh, split_coordinates, split_mesh
from .system import residual


class Remeshing:
    """Splitting and merging elements of the running cable."""

    def split_element(self, element: int, xi: float = 0.5) -> dict[str, float]:
        """Split element ``element`` at normalised position ``xi`` in (0, 1) during a run,
        without disturbing the cable: the new node takes the value and slope of the
        element's cubic there (:mod:`towcable_fmu.ancf.remesh`), for the coordinates,
        velocities, accelerations and the integrator's auxiliary accelerations. The shape,
        the velocities and the kinetic, bending and gravity energies are unchanged; the
        tension (the decoupled axial strain) and the loads integrated on each element's
        grid of points (contact, drag) change by their discretisation error, now on the
        finer elements. The fed element of a spool end gives the new node the material's
        velocity and acceleration there (:func:`~towcable_fmu.ancf.feed.material_rates`):
        the node is material from then on. The next step factorises its matrix afresh.
        A state saved before the split restores across it with a spool end (its state
        carries the mesh); otherwise :meth:`set_state` refuses it (another model).

        Returns
        -------
        dict
            Outputs after the split.

        Raises
        ------
        SceneError
            If ``element`` or ``xi`` is out of range, or a term's state cannot follow (wake
            oscillators: their states belong to the elements); nothing is changed.
        """
        return self._split(element, xi)

    def _split(self, element: int, xi: float, first_segment: int | None = None) -> dict[str, float]:
        """:meth:`split_element`, the first piece in ``first_segment`` if given (a section
        boundary of a spool end's cable)."""
        old = self.mesh
        try:
            mesh = split_mesh(old, element, xi, first_segment)
        except ValueError as exc:
            raise SceneError("split_element", (element, xi), str(exc)) from None
        st = self.state
        material = next((rates for rates in (h.new_node_rates(element, xi) for h in self.hooks)
                         if rates is not None), None)
        new = slice(6 * (element + 1), 6 * (element + 2))  # the new node's coordinates

        def transfer(name: str, x: np.ndarray) -> np.ndarray:
            y = split_coordinates(x, old, element, xi)
            if material is not None and name != "q":  # the new node moves with the material
                grid = split_coordinates(st.a, old, element, xi)[new]
                y[new] = {"v": material[0], "a": material[1], "abar": y[new] + material[1] - grid}[name]
            return y
        return self._remesh("split_element", mesh, transfer)

    def merge_elements(self, element: int) -> dict[str, float]:
        """Merge elements ``element`` and ``element + 1`` (of one segment) into one during a
        run: the node between them is dropped (:mod:`towcable_fmu.ancf.remesh`). Exact when
        the two form one cubic (a split undone); otherwise the merged element misses the
        dropped node by ``merge_defect`` (returned as ``remesh.position_defect`` [m] and
        ``remesh.slope_defect`` [-] beside the outputs). The next step factorises afresh.

        Raises
        ------
        SceneError
            If there is no such pair in one segment, or a term's state cannot follow (wake
            oscillators); nothing is changed.
        """
        return self._merge(element)

    def _merge(self, element: int, across: bool = False) -> dict[str, float]:
        """:meth:`merge_elements`; with ``across``, also two elements of different segments
        (the merged one in the second's)."""
        old = self.mesh
        try:
            mesh = merge_mesh(old, element, across)
        except ValueError as exc:
            raise SceneError("merge_elements", element, str(exc)) from None
        position, slope = merge_defect(self.state.q, old, element)
        out = self._remesh("merge_elements", mesh, lambda name, x: merge_coordinates(x, old, element))
        return {**out, "remesh.position_defect": position, "remesh.slope_defect": slope}

    def _remesh(self, key: str, mesh: Mesh, transfer) -> dict[str, float]:
        """Move the running cable onto ``mesh``: the model rebuilt for it, every coordinate
        array of the state through ``transfer(name, old vector) -> new vector``, the matrix
        factorised afresh by the next step; the outputs after."""
        self._require_initialized()
        for hooks in self.hooks:
            hooks.remesh(key)
        st, ship = self.state, self.workspace.ship.copy()
        model = self._model_for(mesh, float(st.phi[0]))
        state = genalpha.new_state(model)
        for name in ("q", "v", "a", "abar"):
            getattr(state, name)[:] = transfer(name, getattr(st, name))
        for name in ("phi", "clock", "stats"):
            getattr(state, name)[:] = getattr(st, name)
        state.jac[:] = st.jac
        state.jac[genalpha.JAC_VALID] = 0.0  # the matrix of the old mesh: factorise afresh
        self._use(mesh, model, state)
        self.workspace.ship[:, :] = ship
        apply_feed(model, state.phi)
        residual(model, state.q, state.v, state.a, self.time, self.workspace.ship, self.workspace.r)
        state.taut[:] = model.el_taut[TAUT_RESIDUAL]  # the taut points of the new elements
        return self.outputs()

    def _after_event(self) -> bool:
        """After a step stopped at an event (a spool end's fed element out of its band), the
        term whose event it is remeshes (:meth:`~towcable_fmu.ancf.forces.hooks.TermHooks.handle_event`).
        False if no term had an event (the step failed). Only a term that moves the mesh has
        events: a scene without one pays nothing here at every call."""
        return any(hooks.handle_event() for hooks in self._remeshing)
