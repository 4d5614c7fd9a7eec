"""Nodal-position finite elements for the cable (Sun et al., "Dynamic modeling of cable
towed body using nodal position finite element method"): straight two-node elements
whose unknowns are the nodal positions, a lumped towed body (or a rigid 6-DOF body,
:mod:`.rigid_body`) at the free end, a top end held on the ship.

Modules: :mod:`.model` (scene -> compiled data), :mod:`.element` (one element's loads),
:mod:`.assembly` (residual over the mesh, matrices by coloured differences),
:mod:`.integrators` (generalised-alpha and the paper's RK4), :mod:`.statics`,
:mod:`.simulation` (the run interface of :class:`towcable_fmu.ancf.simulation.Simulation`).
"""
