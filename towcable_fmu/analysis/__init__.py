"""Post-processing of simulation results: Calnan's enclosing ellipsoid of the towed-body
track (:mod:`.ellipsoid`) and the heave-compensation study (:mod:`.compensation_study`)."""

from .ellipsoid import Ellipsoid, enclosing_ellipsoid, projected_outline

__all__ = ["Ellipsoid", "enclosing_ellipsoid", "projected_outline"]
