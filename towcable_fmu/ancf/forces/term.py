"""The contract of a force term, and the one way a term writes into the iteration matrix.

A force term is one module of this package with

* ``NAME``: its field in :class:`~towcable_fmu.ancf.forces.ForceTerms` (``model.terms.NAME``);
* ``TABLES``: the scene tables it models (dotted keys, ``("towbody", "towbody.lift")``): the
  ANCF cable accepts a scene with them, a formulation that does not list them refuses it
  (:func:`towcable_fmu.runtime.tables.reject_unmodelled`);
* ``Data``: a ``NamedTuple`` of arrays and scalars whose first field is ``enabled``;
* ``build(scene, mesh, model) -> Data``: the term's data from the scene (``model`` is the
  cable's own model, its ``terms`` still empty); a scene without the term gets
  ``enabled = False``;
* two compiled entry points:

  - ``residual(term, model, motion, a, first, stop, out)``: add the term's part of the
    residual ``R = M a + ... - Q_ext`` (an external force enters with a minus sign) of
    the elements ``first`` to ``stop - 1`` to ``out`` [N, N m]; a term on the last node
    or on coordinates of its own adds its rows when ``stop`` is the number of elements;
  - ``tangent(term, model, motion, ca, cv, cq, ab)``: add its part of
    ``ca dR/da + cv dR/dv + cq dR/dq`` to the band storage ``ab`` through
    :func:`add_element_block` or :func:`add_block`.

Both are called only when ``term.enabled``, by :func:`towcable_fmu.ancf.forces.add_residuals`
and :func:`~towcable_fmu.ancf.forces.add_tangents`, which the assembly
(:mod:`towcable_fmu.ancf.system`) calls: the assembly names no term, and a term costs a
flag test in a scene that lacks it. What a term adds to a run beyond these kernels (outputs,
a state of its own, work between steps) is its ``Hooks`` (:mod:`.hooks`).
"""

from __future__ import annotations

import numpy as np

from ...jit.kernel_cache import njit
from ...numerics.banded import band_add_block, band_add_scattered
from ..model import CableModel


@njit(cache=True, inline="always")
def add_element_block(model: CableModel, e: int, block: np.ndarray, ab: np.ndarray) -> None:
    """Add a 12x12 block over element ``e``'s coordinates to the band storage ``ab``."""
    band_add_block(ab, model.kl, model.ku, model.free_idx, 6 * e, block)


@njit(cache=True, inline="always")
def add_block(model: CableModel, coords: np.ndarray, block: np.ndarray, ab: np.ndarray) -> None:
    """Add a square block over the coordinates ``coords`` (int array) to the band storage ``ab``."""
    band_add_scattered(ab, model.kl, model.ku, model.free_idx, coords, block)
