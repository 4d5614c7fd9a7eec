"""The data of the ANCF cable model: its mesh, the compiled model and the motion bundle.

Global coordinates: node ``n`` owns ``x[6n:6n+3] = r`` and ``x[6n+3:6n+6] = r_p``
(shared nodal coordinates embed position and slope continuity, W(123)-(132): 6N+6
coordinates for N elements); element ``e`` uses ``x[6e:6e+12]``. The coordinates of a
rigid load or a rigid towed body follow the cable's (see :mod:`.forces`).
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np

from ..hydro.water import WaterModel


@dataclasses.dataclass(frozen=True)
class Mesh:
    """Element layout of the cable.

    Attributes
    ----------
    lengths
        Unstretched element lengths [m], shape (ne,).
    segment_of_element
        Index of the segment each element belongs to, shape (ne,).
    node_arc
        Unstretched arc length of every node from the top end [m], shape (ne + 1,).
    """

    lengths: np.ndarray
    segment_of_element: np.ndarray
    node_arc: np.ndarray

    @property
    def n_elements(self) -> int:
        """Number of elements."""
        return int(self.lengths.shape[0])

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return self.n_elements + 1


class CableModel(NamedTuple):
    """Everything the compiled kernels need about one cable system (arrays only).

    Sizes: ``ne`` elements, ``nn = ne + 1`` nodes, ``nf`` coordinates (``6 nn`` and those
    of a rigid load or body). The cable's own structure is in the fields; every other
    force on it is a term in ``terms`` (:mod:`towcable_fmu.ancf.forces`).
    """

    el_len: np.ndarray          #: (ne,) unstretched element lengths [m]
    el_ea: np.ndarray           #: (ne,) axial stiffness EA [N]
    el_tension_only: np.ndarray  #: (ne,) bool: no axial force in compression
    el_engineering: np.ndarray  #: (ne,) bool: axial force EA (lambda - 1) (Kelvin-Voigt), else EA eps_G lambda
    el_mass: np.ndarray         #: (ne, 4, 4) mass factor [kg...]
    el_bend: np.ndarray         #: (ne, 4, 4) bending stiffness factor
    el_damp: np.ndarray         #: (ne, 4, 4) internal damping factor
    el_d: np.ndarray            #: (ne,) cable diameter [m]
    el_npts: np.ndarray         #: (ne,) integration points N_I of the distributed loads
    f_const: np.ndarray         #: (nf,) constant generalised load (gravity of cable and point masses) [N]
    node_mass: np.ndarray       #: (nn, 3) lumped mass at node positions, per axis [kg]
    gauss_dn: np.ndarray        #: (ng, 4) dn/dxi of the normalised Hermite functions at Gauss points
    gauss_w: np.ndarray         #: (ng,) Gauss weights on [0, 1]
    free_idx: np.ndarray        #: (nf,) unknown index of each coordinate, -1 if prescribed
    free_dofs: np.ndarray       #: (n,) coordinate index of each unknown
    free_scale: np.ndarray      #: (n,) 1/length of the adjacent elements for positions, 1 for slopes [1/m, -]
    kl: int                     #: sub-diagonals of the iteration matrix
    ku: int                     #: super-diagonals of the iteration matrix
    att_index: np.ndarray       #: (na,) first coordinate of each prescribed triple
    att_kind: np.ndarray        #: (na,) attachment kind (see prescribed.py)
    att_vec: np.ndarray         #: (na, 3) attachment vector
    att_radius: np.ndarray      #: (na,) winch radius for winch attachments [m]
    water: WaterModel           #: water, current and turbulence (``enabled`` False: dry scene)
    gravity: float              #: g [m/s^2]
    terms: tuple                #: the force terms, a ``forces.ForceTerms`` (empty while the model is built)
    #: (2, ne) int64: the Gauss points where a tension-only element is taut, a bit mask per
    #: element, as the last residual (row ``TAUT_RESIDUAL``) and the last iteration matrix
    #: (row ``TAUT_MATRIX``) saw them: Newton refactorises where the two differ
    el_taut: np.ndarray


#: rows of ``CableModel.el_taut``
TAUT_RESIDUAL = 0
TAUT_MATRIX = 1


class Motion(NamedTuple):
    """The state a force term is evaluated at (the acceleration is passed on its own: the
    tangents do not take it)."""

    q: np.ndarray     #: (nf,) coordinates [m, -]
    v: np.ndarray     #: (nf,) their rates [m/s, 1/s]
    t: float          #: time [s]
    ship: np.ndarray  #: (3, 6) ship state at t (moves the winch and sheave surfaces)
