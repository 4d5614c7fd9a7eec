"""The fed element: how a winch pays cable out from a spool point and hauls it in.

With ``cable.top.type = "spool"`` the top node is a point fixed on the ship where the cable
leaves its store on the drum. The first ``winch.gear_segments`` segments carry the cable
from there over the drum and the sheaves on a fixed mesh that the cable flows through
(their elements keep their lengths; their nodes are not material points), and the first
element after them, the fed element, covers the material between the gear and the first
material node. The winch feeds material through the gear into it: its unstretched length is

    L(phi) = L_ref + r (phi_ref - phi)

(``r``: the payout radius r_w + d/2; the winch reels in as phi grows), so it grows as the
winch pays out and shrinks as it hauls in; the simulation splits it when it is long and
merges it with the next when it is short (:mod:`towcable_fmu.ancf.remesh`), so the
elements beyond it stay material elements of the nominal length and the mesh follows
the deployed length.

This is the "variable-length end segment at a fixed spool point" of WHOI Cable and
OrcaFlex's line feeding, written for the ANCF element and extended by a fixed (ALE) mesh
over the gear, so the contact with drum and sheave keeps the fine mesh it needs while
hundreds of metres pass (chosen over adding whole elements at a node pinned to the
rotating drum: those insert an element at every nominal length of payout and release a
pinned node each time, where feeding one element changes the mesh only by an exact split).

Material moves through these elements: with ``xi = (p - p0(t)) / L(t)`` on the material
coordinate ``p``, ``dp0/dt = -u`` (``u`` the payout rate [m/s]) and ``dL/dt = u`` for the
fed element (0 for a gear element), the material velocity of ``r = N(xi; L) e`` is
``N de/dt + B e`` with ``B = u ((1 - xi) N_p + N_L)`` (gear: ``u N_p``; ``N_p = dN/dp``,
``N_L = dN/dL``), and the material acceleration is ``N d2e/dt2 + 2 B de/dt + dB/dt e``.
The weak form of the inertia therefore gains ``G de/dt + H e`` with ``G = 2 mu int N^T B dp``
and ``H = mu int N^T dB/dt dp``, scalar 4x4 factors of ``(x) I_3`` like the element's own
matrices; the feed term of :mod:`towcable_fmu.ancf.forces.feed` applies them.

The internal damping (W(55), on the slope rate) acts on the material's slope rate
``N_p de/dt + B_p e`` in the fed element, whose nodes become material at a split (with the
mesh's rate alone the damping would depend on where the splits fall: 2 N jumps in the
tests' veer), and on the slope rate of the mesh, ``N_p de/dt``, in the gear, as in
Exudyn's ALE cable: W(55) damps any rotation of the slope, so on the material it would
brake the cable flowing round a drum or sheave of radius R by about c u theta / R over a
wrap theta (4.7 kN over full_scale_deploy's drum at 1 m/s, against a 2.9 kN tension), an
artefact of the damping law, not a property of the wire.
Drag and added mass use the nodes' velocities (not the feed along the cable: the gear is
in air, and the fed element's tangential drag is small).

:func:`apply_feed` sets the fed element's length, matrices and weight and the transport
terms from the winch state wherever the prescribed kinematics are set from it
(:func:`~towcable_fmu.ancf.prescribed.apply_prescribed`): the length is a prescribed
quantity of the winch like the position of a cable end on the drum.
"""

from __future__ import annotations

import numpy as np

from ..jit.kernel_cache import njit
from .element import shape_derivatives, shape_functions, shape_second_derivatives

#: the fed element is split when it reaches this many nominal element lengths (into the
#: nominal length downstream and the rest at the spool point) ...
SPLIT_FACTOR = 1.5
#: ... and merged with the next element when it is this short (a band of 0.35 L_nom each
#: way, so a winch reversing after an event does not undo it at once)
MERGE_FACTOR = 0.15
#: the fed element is split at a section boundary (bare to faired cable, say) once this many
#: nominal lengths of the next section's cable have come in past it (the same band: a fed
#: element merged across the boundary on the way in holds at most MERGE_FACTOR of them)
BOUNDARY_BAND = 0.35


@njit(cache=True, inline="always")
def _scaled(unit: np.ndarray, length: float, power: float, coefficient: float, out: np.ndarray) -> None:
    """out = coefficient L^power D unit D with D = diag(1, L, 1, L) (slopes are dr/dp)."""
    f = coefficient * length ** power
    for i in range(4):
        si = length if i % 2 else 1.0
        for j in range(4):
            sj = length if j % 2 else 1.0
            out[i, j] = f * si * sj * unit[i, j]


@njit(cache=True, inline="always")
def material_rows(h: np.ndarray, xi: float, length: float, grows: float, u: float, du: float,
                  n: np.ndarray, b: np.ndarray, bdot: np.ndarray, np_: np.ndarray, bp: np.ndarray) -> None:
    """The rows of a fed element at one point, from the Hermite functions there.

    Material enters the element at its start at the payout rate ``u``; the element's
    length grows with it (``grows = 1``: the fed element) or is fixed (``grows = 0``: an
    element of the gear the cable flows through), so ``dL/dt = grows u`` and
    ``d xi/dt = u (1 - grows xi) / L`` at a fixed material point.

    Parameters
    ----------
    h
        (3, 4): h(xi), dh/dxi, d2h/dxi2 of the normalised Hermite functions (slope
        functions without the factor L).
    xi, length
        Normalised position [-] and unstretched length L [m].
    grows
        1.0 or 0.0, as above.
    u, du
        Payout rate [m/s] and its rate [m/s^2].
    n, b, bdot, np_, bp
        (4,) outputs: N, B, dB/dt, N_p = dN/dp and B_p = dB/dp, so that at the material
        point the position is ``N e``, the velocity ``N de/dt + B e``, the acceleration
        ``N d2e/dt2 + 2 B de/dt + dB/dt e`` and the slope rate ``N_p de/dt + B_p e``.
    """
    flow = 1.0 - grows * xi
    xdot = u * flow / length  # d xi / dt at fixed p
    for i in range(4):
        slope = i % 2 == 1
        s = length if slope else 1.0
        n[i] = s * h[0, i]
        npi = h[1, i] if slope else h[1, i] / length          # dN/dp
        npx = h[2, i] if slope else h[2, i] / length          # d(dN/dp)/dxi
        npl = 0.0 if slope else -h[1, i] / length ** 2        # d(dN/dp)/dL
        nl = grows * h[0, i] if slope else 0.0                # dN/dL dL/dt / u
        nlx = grows * h[1, i] if slope else 0.0               # its derivative in xi
        bhat = flow * npi + nl
        dbhat = -grows * xdot * npi + flow * (npx * xdot + npl * grows * u) + nlx * xdot
        np_[i] = npi
        b[i] = u * bhat
        bdot[i] = du * bhat + u * dbhat
        bp[i] = u / length * (-grows * npi + flow * npx + nlx)


@njit(cache=True, inline="always")
def fed_length(f, phi: float) -> float:
    """The fed element's unstretched length [m] at winch rotation ``phi`` [rad] (``f``: the
    feed term's data): L_ref + r (phi_ref - phi)."""
    return f.ref[0] + f.radius * (f.ref[1] - phi)


@njit(cache=True)
def apply_feed(model, phi: np.ndarray) -> None:
    """Set the fed element's length [m], mass, bending and damping matrices and weight,
    and the transport terms of it and of the gear elements before it, from the winch
    state ``phi`` (rotation [rad], rate [rad/s], acceleration [rad/s^2]); nothing without
    a spool end."""
    f = model.terms.feed
    if not f.enabled:
        return
    fed = f.element
    length = fed_length(f, phi[0])
    u = -f.radius * phi[1]
    du = -f.radius * phi[2]
    model.el_len[fed] = length
    _scaled(f.unit_mass, length, 1.0, f.mass_per_length, model.el_mass[fed])
    _scaled(f.unit_bend, length, -3.0, f.ei, model.el_bend[fed])
    _scaled(f.unit_damp, length, -1.0, f.damping, model.el_damp[fed])
    weight = -f.mass_per_length * model.gravity * length
    for i in range(4):
        s = length if i % 2 else 1.0
        model.f_const[6 * fed + 3 * i + 2] = f.base_load[i] + weight * s * f.unit_load[i]
    f.transport[:, :, :, :] = 0.0
    if u == 0.0 and du == 0.0:
        return
    n, b, bdot, np_, bp = np.empty(4), np.empty(4), np.empty(4), np.empty(4), np.empty(4)
    for e in range(fed + 1):
        g, hm = f.transport[e, 0], f.transport[e, 1]
        el_length = model.el_len[e]
        grows = 1.0 if e == fed else 0.0
        for k in range(f.gauss_w.shape[0]):
            material_rows(f.gauss_h[k], f.gauss_x[k], el_length, grows, u, du, n, b, bdot, np_, bp)
            w = f.gauss_w[k] * el_length
            for i in range(4):
                for j in range(4):
                    g[i, j] += w * 2.0 * f.mass_per_length * n[i] * b[j]
                    hm[i, j] += w * (f.mass_per_length * n[i] * bdot[j] + grows * f.damping * np_[i] * bp[j])


@njit(cache=True)
def feed_event(model) -> bool:
    """Whether the fed element has left its band: as long as ``SPLIT_FACTOR`` nominal
    lengths, as short as ``MERGE_FACTOR``, or ``BOUNDARY_BAND`` nominal lengths past a
    section boundary (the simulation then splits or merges it)."""
    f = model.terms.feed
    if not f.enabled:
        return False
    length = model.el_len[f.element]
    return (length >= SPLIT_FACTOR * f.length_nom or length <= MERGE_FACTOR * f.length_nom
            or length >= f.boundary + BOUNDARY_BAND * f.length_nom)


def material_rates(nodal_q: np.ndarray, nodal_v: np.ndarray, nodal_a: np.ndarray, length: float, xi: float,
                   u: float, du: float) -> tuple[np.ndarray, np.ndarray]:
    """The material rates of the (growing) fed element at ``xi``: what a node placed there
    (by a split) moves with.

    Parameters
    ----------
    nodal_q, nodal_v, nodal_a
        The element's coordinates, their rates and accelerations, (12,) each.
    length
        Its unstretched length L [m].
    xi
        Normalised position in (0, 1).
    u, du
        Payout rate [m/s] and its rate [m/s^2].

    Returns
    -------
    velocity, acceleration
        (6,) each: the material velocity [m/s] and slope rate [1/s] at ``xi``, and their
        rates [m/s^2, 1/s^2] (the slope's from a central difference of ``B_p`` in time).
    """
    h = np.stack([shape_functions(xi, 1.0), shape_derivatives(xi, 1.0), shape_second_derivatives(xi, 1.0)])
    e, de, dde = (np.asarray(x, dtype=float).reshape(4, 3) for x in (nodal_q, nodal_v, nodal_a))
    rows = [np.empty(4) for _ in range(5)]
    material_rows(h, xi, length, 1.0, u, du, *rows)
    n, b, bdot, np_, bp = rows
    # dB_p/dt at fixed p: B_p moves with xi (d xi/dt = u (1 - xi) / L), L (dL/dt = u) and u
    step = 1e-6 * length / max(abs(u), 1e-3)
    ends = []
    for sign in (1.0, -1.0):
        s = sign * step
        xi_s = xi + s * u * (1.0 - xi) / length
        h_s = np.stack([shape_functions(xi_s, 1.0), shape_derivatives(xi_s, 1.0), shape_second_derivatives(xi_s, 1.0)])
        other = [np.empty(4) for _ in range(5)]
        material_rows(h_s, xi_s, length + s * u, 1.0, u + s * du, du, *other)
        ends.append(other[4])
    bp_dot = (ends[0] - ends[1]) / (2.0 * step)
    velocity = np.concatenate([n @ de + b @ e, np_ @ de + bp @ e])
    acceleration = np.concatenate([n @ dde + 2.0 * b @ de + bdot @ e, np_ @ dde + 2.0 * bp @ de + bp_dot @ e])
    return velocity, acceleration


def section_boundaries(segment_lengths: np.ndarray, gear: int) -> np.ndarray:
    """Where the cable's sections meet, as material coordinates from the bottom end [m].

    The segments after the gear are the cable's sections, from the top: the first is the
    fed segment, whose cable continues onto the drum. Entry ``k`` is the material
    coordinate where segment ``k - 1`` (above) meets segment ``k`` (below), for
    ``k = gear + 1 ... n - 1`` (index ``k - gear - 1``).
    """
    below = np.cumsum(np.asarray(segment_lengths, dtype=float)[::-1])[::-1]   # from segment k down
    return below[gear + 1:]


def boundary_above(boundaries: np.ndarray, lengths: np.ndarray, fed: int) -> float:
    """The fed element's length [m] at which the next section's cable comes in: the
    nearest section boundary above its downstream node, measured from that node (inf:
    none, the fed section continues onto the drum). ``lengths``: the elements' lengths [m]."""
    node = float(np.sum(lengths[fed + 1:]))      # material coordinate of the downstream node
    above = boundaries[boundaries > node + 1e-9 * max(1.0, node)]
    return float(above.min() - node) if above.size else np.inf
