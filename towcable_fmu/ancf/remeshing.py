"""Remeshing a running ANCF cable: splitting and merging elements on request, and the
spool end's fed element followed as the winch pays out or hauls in (a part of
:class:`~towcable_fmu.ancf.simulation.Simulation`).

The mixin uses the simulation's state (``mesh``, ``model``, ``state``, ``workspace``,
``scene``, ``viv``) and its ``_model_for``, ``_use``, ``_output_array`` and ``outputs``.
"""

from __future__ import annotations

import numpy as np

from ..errors import SceneError, SolverError
from . import genalpha
from .feed import (BOUNDARY_BAND, MERGE_FACTOR, SPLIT_FACTOR, apply_feed, feed_event, material_rates,
                   section_boundaries)
from .model import TAUT_RESIDUAL, Mesh
from .output_kernel import OUTPUT_FIELDS
from .remesh import merge_coordinates, merge_defect, merge_mesh, split_coordinates, split_mesh
from .system import residual

#: The index of ``winch.payout`` among the output fields.
PAYOUT = OUTPUT_FIELDS.index("winch.payout")


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
            If ``element`` or ``xi`` is out of range, or the scene has wake oscillators
            (their states belong to the elements); nothing is changed.
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
        material = None
        feed = self.model.terms.feed
        if feed.enabled and element == feed.element:
            u, du = -feed.radius * st.phi[1], -feed.radius * st.phi[2]
            span = slice(6 * element, 6 * element + 12)
            material = material_rates(st.q[span], st.v[span], st.a[span], old.lengths[element], xi, u, du)
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
            If there is no such pair in one segment, or the scene has wake oscillators;
            nothing is changed.
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
        if self.viv is not None:
            raise SceneError(key, "a scene with wake oscillators", "a scene without them (viv): their states belong "
                             "to the elements")
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

    def _follow_feed(self) -> bool:
        """After a step reported a feed event, remesh a spool end's fed element: split it
        where the next section's cable came in (``BOUNDARY_BAND`` nominal lengths past a
        section boundary: the downstream piece keeps its section, the fed element takes the
        new one); split it when it has grown to SPLIT_FACTOR nominal lengths (one nominal
        element downstream, the rest upstream, where the cable comes in); or merge it with
        the next when it has shrunk to MERGE_FACTOR (with the next section's element when
        its own section is all hauled in: the merged element takes the next section, and
        the last piece of the fed one, at most MERGE_FACTOR of a nominal length, with it).
        False if there is no event (the step failed).

        Raises
        ------
        SolverError
            If the winch hauls in the whole cable, or a section whose cable differs from the
            gear's (it cannot pass over drum and sheave).
        """
        if not feed_event(self.model):
            return False
        feed = self.model.terms.feed
        fed, length, nominal = feed.element, float(self.model.el_len[feed.element]), feed.length_nom
        mesh = self.mesh
        if length >= feed.boundary + BOUNDARY_BAND * nominal:
            boundaries = section_boundaries(np.array([seg.length for seg in self.scene.cable.segments]),
                                            self.scene.winch.gear_segments)
            upper = int(np.argmin(np.abs(boundaries - (np.sum(mesh.lengths[fed + 1:]) + feed.boundary))))
            # the piece downstream, up to the boundary, keeps its section
            self._split(fed, (length - feed.boundary) / length, self.scene.winch.gear_segments + upper)
        elif length >= SPLIT_FACTOR * nominal:
            self._split(fed, (length - nominal) / length)
        elif mesh.n_elements > fed + 1 and mesh.segment_of_element[fed + 1] == mesh.segment_of_element[fed]:
            self._merge(fed)
        elif mesh.n_elements > fed + 1:
            self._check_passes_the_gear(int(mesh.segment_of_element[fed + 1]))
            self._merge(fed, across=True)
        else:
            raise SolverError(f"winch.payout = {float(self._output_array()[PAYOUT]):.6g} m at t = {self.time:.6g} s "
                              f"hauls in the whole cable: the deployed length cannot go below "
                              f"{float(mesh.node_arc[fed]) + MERGE_FACTOR * nominal:.6g} m (the gear and "
                              f"{MERGE_FACTOR:g} of the last element); limit the winch's set-point")
        return True

    def _check_passes_the_gear(self, segment: int) -> None:
        """A section hauled in passes over drum and sheave on the gear's mesh: its cable must
        be the gear's.

        Raises
        ------
        SolverError
            Naming the first property that differs.
        """
        segments, gear = self.scene.cable.segments, self.scene.winch.gear_segments
        name = segments[segment].cable_difference(segments[gear])
        if name is not None:
            raise SolverError(f"winch.payout = {float(self._output_array()[PAYOUT]):.6g} m at t = {self.time:.6g} s "
                              f"hauls cable.segments[{segment}] onto the drum, but its {name} = "
                              f"{getattr(segments[segment], name)!r} differs from the gear's "
                              f"{getattr(segments[gear], name)!r}: it cannot pass over drum and sheave on "
                              "their mesh; limit the winch's set-point")
