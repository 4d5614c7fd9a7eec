"""Derived quantities of a cable state: tension along the cable, energies, end angles."""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from .axial import at_length, axial_strains, axial_work, energy_of_strain, tension_of_strain
from .model import CableModel
from .system import residual_span

#: Entries of the array returned by :func:`summary`.
SUMMARY_FIELDS = ("reaction_top", "reaction_bottom", "tension_first", "tension_last", "tension_max",
                  "tension_min", "energy_kinetic", "energy_strain", "energy_gravity")


@njit(cache=True)
def tension_profile(model: CableModel, q: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """Axial force at normalised positions in every element.

    The force transmitted by the cable is the derivative of the strain energy
    ``EA/2 eps^2`` with respect to the stretched length: ``T = EA eps lambda`` with the
    decoupled Green strain ``eps`` (W(45)) and the stretch ``lambda = sqrt(1 + 2 eps)``;
    it is the force a support reacts with, and equals ``EA eps`` to first order. A segment
    with the Kelvin-Voigt law carries ``EA (lambda - 1)`` (:func:`.axial.tension_of_strain`).

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
    work = axial_work(model.gauss_dn, model.gauss_w)
    nk = xi.shape[0]
    dn = np.empty((nk, 4))
    for k in range(nk):
        x = xi[k]
        dn[k, 0] = -6.0 * x + 6.0 * x * x
        dn[k, 1] = 1.0 - 4.0 * x + 3.0 * x * x
        dn[k, 2] = 6.0 * x - 6.0 * x * x
        dn[k, 3] = 3.0 * x * x - 2.0 * x
    eps = np.empty(nk)
    out = np.empty((ne, nk))
    for e in range(ne):
        length = model.el_len[e]
        at_length(work, length)
        axial_strains(q, 6 * e, length, work, dn, eps)
        for k in range(nk):
            ek = eps[k]
            if model.el_tension_only[e] and ek < 0.0:
                ek = 0.0
            out[e, k] = tension_of_strain(model.el_ea[e], ek, model.el_engineering[e])
    return out


# The energies and the summary are IR-inlined into their only callers (summary, and
# output_kernel.output_values): a kernel of its own would be one more library for the
# caller to link and optimise again, with all the code beneath it.
@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def gravity_energy(model: CableModel, q: np.ndarray) -> float:
    """Potential energy of gravity (and any other constant load) -f_const . q [J]."""
    energy = 0.0
    for i in range(q.shape[0]):
        energy -= model.f_const[i] * q[i]
    return energy


@njit(cache=True, inline="always")
def summary(model: CableModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, ship: np.ndarray,
            xi: np.ndarray, r: np.ndarray, energies: bool) -> np.ndarray:
    """The scalar outputs of a state in one compiled pass (order: :data:`SUMMARY_FIELDS`).

    Reactions are the magnitudes of the residual at the end nodes' position rows
    (zero at a free end), evaluated over the end elements only; the tension extremes
    are taken over ``xi`` in every element; ``r`` (shape (nf,)) is scratch. Without
    ``energies`` the three energies are NaN and not computed (nor the strains at the
    Gauss points they integrate).
    """
    out = np.zeros(len(SUMMARY_FIELDS))
    ne = model.el_len.shape[0]
    last = 6 * (model.node_mass.shape[0] - 1)  # the last node (extra coordinates of a load or body follow)
    first = np.intp(0)  # a typed index, not a literal: one compiled residual_span serves every caller
    if model.free_idx[0] < 0:
        residual_span(model, q, v, a, t, ship, first, first + 1, r)
        out[0] = np.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2)
    if model.free_idx[last] < 0:
        residual_span(model, q, v, a, t, ship, ne - 1, ne, r)
        out[1] = np.sqrt(r[last] ** 2 + r[last + 1] ** 2 + r[last + 2] ** 2)
    ng = model.gauss_w.shape[0] if energies else 0
    nk = xi.shape[0]
    work = axial_work(model.gauss_dn, model.gauss_w)
    dn = np.empty((nk + ng, 4))  # rows: the output points xi, then the Gauss points (for the strain energy)
    for k in range(nk):
        x = xi[k]
        dn[k, 0] = -6.0 * x + 6.0 * x * x
        dn[k, 1] = 1.0 - 4.0 * x + 3.0 * x * x
        dn[k, 2] = 6.0 * x - 6.0 * x * x
        dn[k, 3] = 3.0 * x * x - 2.0 * x
    for k in range(ng):
        for j in range(4):
            dn[nk + k, j] = model.gauss_dn[k, j]
    eps = np.empty(nk + ng)
    t_max, t_min, axial = -np.inf, np.inf, 0.0
    for e in range(ne):
        length = model.el_len[e]
        ea = model.el_ea[e]
        at_length(work, length)
        axial_strains(q, 6 * e, length, work, dn, eps)
        for k in range(nk + ng):
            ek = eps[k]
            if model.el_tension_only[e] and ek < 0.0:
                ek = 0.0
            if k < nk:
                tension = tension_of_strain(ea, ek, model.el_engineering[e])
                t_max = max(t_max, tension)
                t_min = min(t_min, tension)
                if e == 0 and k == 0:
                    out[2] = tension
                if e == ne - 1 and k == nk - 1:
                    out[3] = tension
            else:
                axial += model.gauss_w[k - nk] * length * energy_of_strain(ea, ek, model.el_engineering[e])
    out[4] = t_max
    out[5] = t_min
    if energies:
        out[6] = kinetic_energy(model, v)
        out[7] = axial + bending_energy(model, q)
        out[8] = gravity_energy(model, q)
    else:
        out[6:9] = np.nan
    return out


@njit(cache=True)
def point_on_cable(model: CableModel, q: np.ndarray, e: int, xi: float) -> np.ndarray:
    """Position [m], unit direction and tension [N] at normalised position xi of element e.

    Returns
    -------
    ndarray, shape (7,)
        x, y, z, u_x, u_y, u_z, tension.
    """
    length = model.el_len[e]
    work = axial_work(model.gauss_dn, model.gauss_w)
    at_length(work, length)
    dn = np.empty((1, 4))
    dn[0, 0] = -6.0 * xi + 6.0 * xi * xi
    dn[0, 1] = 1.0 - 4.0 * xi + 3.0 * xi * xi
    dn[0, 2] = 6.0 * xi - 6.0 * xi * xi
    dn[0, 3] = 3.0 * xi * xi - 2.0 * xi
    eps = np.empty(1)
    base = 6 * e
    axial_strains(q, base, length, work, dn, eps)
    if model.el_tension_only[e] and eps[0] < 0.0:
        eps[0] = 0.0
    n = (1.0 - 3.0 * xi**2 + 2.0 * xi**3, length * (xi - 2.0 * xi**2 + xi**3), 3.0 * xi**2 - 2.0 * xi**3,
         length * (xi**3 - xi**2))
    out = np.zeros(7)
    for c in range(3):
        out[c] = n[0] * q[base + c] + n[1] * q[base + 3 + c] + n[2] * q[base + 6 + c] + n[3] * q[base + 9 + c]
        out[3 + c] = (dn[0, 0] / length * q[base + c] + dn[0, 1] * q[base + 3 + c]
                      + dn[0, 2] / length * q[base + 6 + c] + dn[0, 3] * q[base + 9 + c])
    norm = np.sqrt(out[3] ** 2 + out[4] ** 2 + out[5] ** 2)
    for c in range(3):
        out[3 + c] /= max(norm, 1e-300)
    out[6] = tension_of_strain(model.el_ea[e], eps[0], model.el_engineering[e])
    return out


@njit(cache=True)
def element_tension(model: CableModel, q: np.ndarray, e: int) -> float:
    """Mean axial force over element e [N]: the Gauss average of EA eps lambda (or of
    EA (lambda - 1) with the Kelvin-Voigt law).

    Inside an element bent around a pulley the pointwise decoupled strain oscillates by a
    per cent or so about its mean (a cubic does not follow a circle exactly); the mean
    is the robust measure of the force the element carries.
    """
    length = model.el_len[e]
    ng = model.gauss_w.shape[0]
    work = axial_work(model.gauss_dn, model.gauss_w)
    at_length(work, length)
    eps = np.empty(ng)
    axial_strains(q, 6 * e, length, work, model.gauss_dn, eps)
    total = 0.0
    for g in range(ng):
        ek = eps[g]
        if model.el_tension_only[e] and ek < 0.0:
            ek = 0.0
        total += model.gauss_w[g] * tension_of_strain(model.el_ea[e], ek, model.el_engineering[e])
    return total
