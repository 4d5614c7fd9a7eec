"""Staggered coupling of the wake oscillators with the cable integrator.

One wake variable per node of the loaded segments (the nodes at their ends included).
Over a cable step from t_n to t_n+1 = t_n + h:

1. predictor: advance the wake ODEs (:func:`~.oscillator.advance_wake`) from t_n with the
   cable's cross-flow velocity extrapolated from the step start, ``Y'(t) = Y'_n + (t - t_n)
   Y''_n``, and evaluate the A20 loads at t_n+1 from the predicted w', w'';
2. the cable step: the generalised-alpha scheme (Arnold-Bruls form) satisfies the
   equations of motion at t_n+1, with these loads held as a constant external load;
3. corrector: advance the wake ODEs again from t_n, now with Y' interpolated linearly
   between the cable's velocities at t_n and t_n+1; this is the wake state kept.

The loads lag the exact coupled solution by O(h^2) per unit time (the predictor's error);
tests/test_viv.py checks that halving the step changes the lock-in amplitude by less
than 1 %. The load enters the residual as the model's wake term
(:mod:`towcable_fmu.ancf.forces.wake`), a given external load over the step; a scene
without ``[viv]`` has that term disabled.
"""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..common.errors import SceneError
from .model import CableModel, Mesh
from ..scene.model import Viv
from .viv_loads import add_generalised, force_factors, interpolation_table, nodal_forces
from ..viv.oscillator import advance_wake, strouhal_frequency, wake_acceleration


class WakeCoupling:
    """The wake oscillators of a scene's ``[viv]`` table and their loads on the cable.

    Parameters
    ----------
    viv
        The scene's enabled ``[viv]`` table.
    mesh, model
        The cable's mesh (segment of every element) and compiled model (element lengths,
        diameters, integration points; ``model.terms.wake.load``, the wake term's
        generalised load vector [N], is overwritten with the wake load before every cable
        step).
    flow
        Free-stream velocity, the scene's uniform current (3,) [m/s].
    density
        Fluid density [kg/m^3].
    """

    def __init__(self, viv: Viv, mesh: Mesh, model: CableModel, flow: np.ndarray, density: float) -> None:
        lengths = model.el_len
        self.elements = np.flatnonzero(np.isin(mesh.segment_of_element, viv.segments)).astype(np.int64)
        #: cable node index of every wake node, shape (m,)
        self.nodes = np.unique(np.concatenate([self.elements, self.elements + 1])).astype(np.int64)
        local = np.full(lengths.size + 1, -1, dtype=np.int64)
        local[self.nodes] = np.arange(self.nodes.size)
        self.node_a = local[self.elements]
        self.node_b = local[self.elements + 1]
        self.table = interpolation_table(lengths[self.elements], model.el_npts[self.elements])
        self.diameter = float(model.el_d[np.flatnonzero(mesh.segment_of_element == viv.segments[0])[0]])
        flow = np.asarray(flow, dtype=float)
        #: free-stream speed U [m/s]
        self.speed = float(np.linalg.norm(flow))
        self.e_sw = flow / self.speed
        cf = np.asarray(viv.cross_flow, dtype=float)
        cf = cf - (cf @ self.e_sw) * self.e_sw
        self.e_cf = cf / np.linalg.norm(cf)
        #: Strouhal frequency w_st [rad/s], A25
        self.omega = strouhal_frequency(viv.strouhal, self.speed, self.diameter)
        self.k_sw, self.k_cf = force_factors(density, self.speed, self.diameter, viv.strouhal, viv.cd0, viv.cl0)
        self.a1, self.a2, self.a3 = viv.a1, viv.a2, viv.a3
        self._w0 = viv.initial_w
        self._load = model.terms.wake.load
        self._nodes = lengths.size + 1
        m = self.nodes.size
        self.w = np.zeros(m)
        self.wd = np.zeros(m)
        self._yd0 = np.zeros(m)
        self._fnode = np.zeros((m, 3))
        self.reset()

    # ---------------------------------------------------------------- state
    def reset(self) -> None:
        """Wake at its initial value (w = initial_w, w' = 0) and no wake load."""
        self.w[:] = self._w0
        self.wd[:] = 0.0
        self._load[:] = 0.0

    def get_state(self) -> dict[str, Any]:
        """Wake variables and the load in force, JSON-able."""
        return {"w": self.w.tolist(), "wd": self.wd.tolist(), "load": self._load.tolist()}

    def set_state(self, data: Mapping[str, Any]) -> None:
        """Restore :meth:`get_state` data."""
        w = np.asarray(data["w"], dtype=float)
        if w.shape != self.w.shape:
            raise SceneError("state.terms.wake.w", f"{w.size} values", f"{self.w.size} (one per wake node)")
        self.w[:] = w
        self.wd[:] = np.asarray(data["wd"], dtype=float)
        self._load[:] = np.asarray(data["load"], dtype=float)

    # ------------------------------------------------------------- coupling
    def cross_flow_velocity(self, v: np.ndarray) -> np.ndarray:
        """Cross-flow component of a full coordinate-rate vector at the wake nodes, shape (m,)."""
        nn = self._nodes
        return v[:6 * nn].reshape(-1, 6)[self.nodes, :3] @ self.e_cf

    def predict(self, v: np.ndarray, a: np.ndarray, h: float) -> None:
        """Predictor: set the model's load to the A20 load at t_n + h (see the module doc).

        Parameters
        ----------
        v, a
            Full velocities and accelerations of the cable at t_n.
        h
            Step [s].
        """
        yd0 = self.cross_flow_velocity(v)
        yd1 = yd0 + h * self.cross_flow_velocity(a)
        self._yd0[:] = yd0
        w, wd = self.w.copy(), self.wd.copy()
        advance_wake(w, wd, yd0, yd1, h, self.a1, self.a2, self.a3, self.omega, self.diameter)
        wdd = np.empty_like(w)
        wake_acceleration(w, wd, yd1, self.a1, self.a2, self.a3, self.omega, self.diameter, wdd)
        nodal_forces(wd, wdd, self.k_sw, self.k_cf, self.e_sw, self.e_cf, self._fnode)
        self._load[:] = 0.0
        add_generalised(self._fnode, self.elements, self.node_a, self.node_b, self.table, self._load)

    def correct(self, v: np.ndarray, h: float) -> None:
        """Corrector: advance the wake over the step just taken with the cable's velocity
        ``v`` at its end (linear in between)."""
        advance_wake(self.w, self.wd, self._yd0, self.cross_flow_velocity(v), h, self.a1, self.a2, self.a3,
                     self.omega, self.diameter)
