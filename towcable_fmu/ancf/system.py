"""Assembly of the cable system: residual and banded iteration matrix.

The equations of motion are written as the residual

    R(q, v, a, t) = M a + C v + K_b q + Q_l(q) - Q_g - Q_ext(q, v, t) = 0

over all coordinates (layout: :mod:`towcable_fmu.ancf.model`); rows of free coordinates
are the equations, rows of prescribed coordinates are the reaction forces. The cable's
own structure (inertia, bending, internal damping, axial force, lumped node masses and
the constant loads) is assembled here; every other force is a term of ``model.terms``
(:mod:`towcable_fmu.ancf.forces`), added term by term: this module names none of them.
Constant element matrices are Kronecker products ``m (x) I_3`` of 4x4 factors and are
applied as such.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from ..numerics.banded import band_add_block
from .axial import at_length, axial_force, axial_tangent, axial_work
from .forces import add_residuals, add_tangents
from .model import TAUT_MATRIX, TAUT_RESIDUAL, CableModel, Motion


@njit(cache=True, inline="always")
def _linear_forces(mass: np.ndarray, damp: np.ndarray, bend: np.ndarray, e: int, q: np.ndarray, v: np.ndarray,
                   a: np.ndarray, base: int, out: np.ndarray) -> None:
    """out[base:base+12] += (M (x) I3) a + (C (x) I3) v + (K_b (x) I3) q for element e."""
    for i in range(4):
        for c in range(3):
            acc = 0.0
            for j in range(4):
                k = base + 3 * j + c
                acc += mass[e, i, j] * a[k] + damp[e, i, j] * v[k] + bend[e, i, j] * q[k]
            out[base + 3 * i + c] += acc


# IR-inlined where a kernel calls it (the Newton iteration): a call of its own, which passes
# the whole model once more, cost about 1.2 us of a 13 us residual (snapping_cable, measured).
@njit(cache=True, inline="always")
def residual(model: CableModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, ship: np.ndarray,
             out: np.ndarray) -> float:
    """Residual of the equations of motion over all coordinates.

    Parameters
    ----------
    model
        The cable system.
    q, v, a
        Full coordinates [m, -], velocities and accelerations (prescribed entries set).
    t
        Time [s].
    ship
        Ship state (3, 6) at time t (moves the winch and sheave surfaces).
    out
        Output residual, shape (nf,) [N, N m].

    Returns
    -------
    float
        Total axial strain energy [J] (a by-product, used for energy outputs).
    """
    return residual_span(model, q, v, a, t, ship, np.intp(0), model.el_len.shape[0], out)


@njit(cache=True)
def residual_span(model: CableModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, t: float, ship: np.ndarray,
                  first: int, stop: int, out: np.ndarray) -> float:
    """The residual with the contributions of elements ``first`` to ``stop - 1`` only.

    The rows of a node are complete when all elements it belongs to are in the span:
    ``(0, 1)`` gives the top node's rows (its support reaction) at the cost of one
    element. Node masses of the span's nodes are included; the terms on the last node or
    on coordinates of their own (a rigid load or body) add their rows when the span ends
    at the last element. Arguments as :func:`residual`; returns the axial strain energy
    of the span [J].
    """
    work = axial_work(model.gauss_dn, model.gauss_w)
    fe = np.empty(12)
    # the model's arrays read once, outside the loops
    f_const, node_mass, el_len, el_ea = model.f_const, model.node_mass, model.el_len, model.el_ea
    tension_only, engineering, el_taut = model.el_tension_only, model.el_engineering, model.el_taut
    mass, damp, bend = model.el_mass, model.el_damp, model.el_bend
    for i in range(out.shape[0]):
        out[i] = -f_const[i]
    energy = 0.0
    for e in range(first, stop):
        base = 6 * e
        _linear_forces(mass, damp, bend, e, q, v, a, base, out)
        length = el_len[e]
        at_length(work, length)
        fe[:] = 0.0
        u, taut = axial_force(q, base, length, el_ea[e], tension_only[e], engineering[e], work, fe)
        energy += u
        el_taut[TAUT_RESIDUAL, e] = taut
        for i in range(12):
            out[base + i] += fe[i]
    for n in range(first, stop + 1):
        for c in range(3):
            out[6 * n + c] += node_mass[n, c] * a[6 * n + c]
    add_residuals(model, Motion(q, v, t, ship), a, first, stop, out)
    return energy


@njit(cache=True)
def iteration_matrix(model: CableModel, q: np.ndarray, v: np.ndarray, t: float, ship: np.ndarray,
                     ca: float, cv: float, cq: float, ab: np.ndarray) -> None:
    """Banded iteration matrix ``ca M + cv C + cq K`` over the free coordinates.

    Parameters
    ----------
    model
        The cable system.
    q, v
        Full coordinates and velocities at which the tangents are evaluated.
    t, ship
        Time [s] and ship state (3, 6).
    ca, cv, cq
        Weights of the mass, damping and stiffness parts.
    ab
        Output band storage (:mod:`towcable_fmu.numerics.banded`), shape (n, 2 kl + ku + 1); overwritten.
    """
    ab[:, :] = 0.0
    # the model's arrays read once, outside the loops
    el_len, el_ea, tension_only, engineering = model.el_len, model.el_ea, model.el_tension_only, model.el_engineering
    mass, damp, bend, el_taut = model.el_mass, model.el_damp, model.el_bend, model.el_taut
    kl, ku, free_idx, node_mass = model.kl, model.ku, model.free_idx, model.node_mass
    ne = el_len.shape[0]
    work = axial_work(model.gauss_dn, model.gauss_w)
    ke = np.empty((12, 12))
    for e in range(ne):
        base = 6 * e
        ke[:, :] = 0.0
        for i in range(4):
            for j in range(4):
                val = ca * mass[e, i, j] + cv * damp[e, i, j] + cq * bend[e, i, j]
                for c in range(3):
                    ke[3 * i + c, 3 * j + c] = val
        length = el_len[e]
        at_length(work, length)
        el_taut[TAUT_MATRIX, e] = axial_tangent(q, base, length, el_ea[e], tension_only[e], engineering[e], work, cq,
                                                ke)
        band_add_block(ab, kl, ku, free_idx, base, ke)
    off = kl + ku
    for n in range(node_mass.shape[0]):
        for c in range(3):
            fi = free_idx[6 * n + c]
            if fi >= 0:
                ab[fi, off] += ca * node_mass[n, c]
    add_tangents(model, Motion(q, v, t, ship), ca, cv, cq, ab)
