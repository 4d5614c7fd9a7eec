"""Derived quantities of a cable state: tension along the cable, energies, end angles."""

from __future__ import annotations

import numpy as np
from numba import njit

from .axial import axial_strain_at, slope_derivatives
from .system import CableModel


@njit(cache=True)
def tension_profile(model: CableModel, q: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """Axial force EA * eps (decoupled strain, W(45)) at normalised positions in every element.

    Parameters
    ----------
    model
        The cable system.
    q
        Full coordinates.
    xi
        Normalised positions within an element, shape (k,).

    Returns
    -------
    ndarray, shape (ne, k)
        Tension [N] (negative in compression; zero in compression for tension-only segments).
    """
    ne = model.el_len.shape[0]
    ng = model.gauss_w.shape[0]
    d = np.empty((ng, 4))
    lam = np.empty(ng)
    u = np.empty((ng, 3))
    dn = np.empty(4)
    out = np.empty((ne, xi.shape[0]))
    for e in range(ne):
        length = model.el_len[e]
        slope_derivatives(model.gauss_dn, length, d)
        for k in range(xi.shape[0]):
            x = xi[k]
            dn[0] = -6.0 * x + 6.0 * x * x
            dn[1] = 1.0 - 4.0 * x + 3.0 * x * x
            dn[2] = 6.0 * x - 6.0 * x * x
            dn[3] = 3.0 * x * x - 2.0 * x
            eps = axial_strain_at(q[6 * e:6 * e + 12], length, d, model.gauss_w, lam, u, dn)
            if model.el_tension_only[e] and eps < 0.0:
                eps = 0.0
            out[e, k] = model.el_ea[e] * eps
    return out


@njit(cache=True)
def kinetic_energy(model: CableModel, v: np.ndarray) -> float:
    """Kinetic energy of the cable and the lumped masses [J] (structural mass only)."""
    energy = 0.0
    for e in range(model.el_len.shape[0]):
        base = 6 * e
        for i in range(4):
            for j in range(4):
                mij = model.el_mass[e, i, j]
                for c in range(3):
                    energy += 0.5 * mij * v[base + 3 * i + c] * v[base + 3 * j + c]
    for n in range(model.node_mass.shape[0]):
        for c in range(3):
            energy += 0.5 * model.node_mass[n, c] * v[6 * n + c] ** 2
    return energy


@njit(cache=True)
def bending_energy(model: CableModel, q: np.ndarray) -> float:
    """Bending strain energy 1/2 q^T K_b q [J], W(48) with W(51)."""
    energy = 0.0
    for e in range(model.el_len.shape[0]):
        base = 6 * e
        for i in range(4):
            for j in range(4):
                kij = model.el_bend[e, i, j]
                if kij != 0.0:
                    for c in range(3):
                        energy += 0.5 * kij * q[base + 3 * i + c] * q[base + 3 * j + c]
    return energy


def gravity_energy(model: CableModel, q: np.ndarray) -> float:
    """Potential energy of gravity (and any other constant load) -f_const . q [J]."""
    return float(-model.f_const @ q)


def angle_from_vertical(direction: np.ndarray) -> float:
    """Angle [rad] between a direction and the downward vertical (0 = hanging straight down)."""
    d = np.asarray(direction, dtype=float)
    horizontal = float(np.hypot(d[0], d[1]))
    return float(np.arctan2(horizontal, -d[2]))
