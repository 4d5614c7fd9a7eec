"""Rigid-link tug-tow model (Gomes & Gomes 2021: "A new dynamic model of towing cables").

A tug and a towed vessel joined by ``n`` rigid links with elastic, damped joints, in
the vertical plane. One concept per module: :mod:`towcable_fmu.scene.rigid_link` (the
scene tables),
:mod:`.thrust` (the tug's thrust ramp), :mod:`.dynamics` (equations of motion and
link forces for any ``n``), :mod:`.initial` (the parabolic initial shape),
:mod:`.statics` (equilibrium between held vessels), :mod:`.simulation` (the
``Simulation``-like driver used by the command line, imported on demand because it
compiles numba kernels).
"""

from ..scene.rigid_link import RigidLinkScene

__all__ = ["RigidLinkScene"]
