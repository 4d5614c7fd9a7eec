"""All scalar outputs of a cable state in one compiled call.

Passing the :class:`~towcable_fmu.ancf.system.CableModel` from Python into a compiled
function costs several microseconds (numba unboxes every array of the tuple), and
building the outputs in Python costs more; the outputs a co-simulation reads at every
communication point, and that :meth:`towcable_fmu.ancf.simulation.Simulation.run` records
at every sample, are therefore computed here in a single call, under the names of
docs/design.md ("Output names"). :class:`OutputLayout` says which of them a scene has.
"""

from __future__ import annotations

import math
from typing import Iterable, NamedTuple

import numpy as np

from ..jit.kernel_cache import njit
from .measures import element_tension, point_on_cable, summary
from .model import CableModel
from .forces.contact import elements
from .forces.contact_quadrature import new_summary, surface_summary
from ..contact.surfaces import SHEAVE, WINCH
from ..hydro.towbody import body_force
from ..numerics.kinematics import rotation_matrix
from ..hydro.rigid_body import angular_kinematics, tow_point_state
from .feed import apply_feed
from .prescribed import apply_prescribed
from ..runtime.drive import evaluate_drive
from .genalpha import CLOCK_TIME, FEED_EVENT
from ..numerics.hermite import step_weights
from .genalpha import advance as genalpha_advance

#: Entries of the array returned by :func:`output_values`, SI units.
OUTPUT_FIELDS = ("tension.top", "tension.bottom", "tension.max", "tension.min", "angle.top",
                 "tension.towbody", "towbody.x", "towbody.y", "towbody.z", "towbody.vx", "towbody.vy", "towbody.vz",
                 "contact.winch_force", "contact.sheave_force", "energy.contact", "tension.winch", "sheave_angle",
                 "tension.sheave", "contact.wrap_angle", "contact.detached",
                 "energy.kinetic", "energy.strain", "energy.gravity", "winch.phi", "winch.payout",
                 "towbody.roll", "towbody.pitch", "towbody.yaw", "winch.deployed")
_FIELD = {name: k for k, name in enumerate(OUTPUT_FIELDS)}
#: The fields :attr:`OutputScene.energies` switches.
ENERGY_FIELDS = ("energy.kinetic", "energy.strain", "energy.gravity")
#: The cable's own outputs (the force terms declare theirs, :mod:`towcable_fmu.ancf.forces.hooks`).
CABLE_OUTPUTS = ("tension.top", "tension.bottom", "tension.max", "tension.min", "angle.top", "energy.kinetic",
                 "energy.strain", "energy.gravity", "winch.phi")
#: The order the outputs are reported in (docs/design.md); any other output follows, in
#: the order it is declared.
_ORDER = ("tension.top", "tension.bottom", "tension.max", "tension.min", "angle.top",
          "tension.towbody", "towbody.x", "towbody.y", "towbody.z", "towbody.vx", "towbody.vy", "towbody.vz",
          "towbody.roll", "towbody.pitch", "towbody.yaw",
          "contact.winch_force", "contact.sheave_force", "energy.contact", "tension.winch", "sheave_angle",
          "tension.sheave", "contact.wrap_angle", "contact.detached",
          "energy.kinetic", "energy.strain", "energy.gravity", "winch.phi", "winch.payout", "winch.deployed")


class OutputScene(NamedTuple):
    """What the outputs need of the scene besides the model (built once per simulation)."""

    #: Normalised positions per element where the tension extremes are sampled.
    xi: np.ndarray
    #: Mass of the lumped towed body [kg] (the cable's last node carries it, with the
    #: cable's end mass if the scene has one); negative: no lumped towed body (a rigid
    #: body, ``model.terms.rigid_link.enabled``, reports from its own coordinates).
    body_mass: float
    #: The cable's top end is on a winch drum.
    has_winch: bool
    #: Sheave centre in the ship frame [m], shape (3,); NaN: no sheave.
    sheave_position: np.ndarray
    #: Radius r_w + d/2 [m] for the payout r (phi_nom - phi).
    payout_radius: float
    #: Nominal winch rotation [rad].
    phi_nom: float
    #: The energies (:data:`ENERGY_FIELDS`) are computed (else NaN: for a caller that reads
    #: none of them, :meth:`~towcable_fmu.ancf.simulation.Simulation.only_outputs`).
    energies: bool = True


class Recording(NamedTuple):
    """What :func:`advance_recording` records, and how it samples."""

    scene: OutputScene     #: what the outputs need of the scene
    index: np.ndarray      #: (k,) intp: the fields of OUTPUT_FIELDS to record (none: only step)
    rows: np.ndarray       #: (samples, k) receives them
    finite: bool           #: stop at the first sample with a non-finite output
    interpolate: bool      #: read samples inside a step from its interpolant (else land on each)
    t_land: float          #: with ``interpolate``: the integrator does not step past this [s]


class OutputLayout:
    """Which outputs a scene has, in the order :meth:`Simulation.outputs` reports them.

    Parameters
    ----------
    names
        The scene's outputs: the cable's own and those its force terms declare
        (:mod:`towcable_fmu.ancf.forces.hooks`), in any order; they are reported in the
        order of docs/design.md, any other after them in the order given.
    """

    def __init__(self, names: Iterable[str]) -> None:
        names = tuple(dict.fromkeys(names))
        rank = {name: k for k, name in enumerate(_ORDER)}
        ordered = sorted(names, key=lambda n: (rank.get(n, len(_ORDER)), names.index(n)))
        #: Output names of the scene.
        self.names: tuple[str, ...] = tuple(ordered)
        #: Positions in :attr:`names` of the fields of :func:`output_values`, and those fields.
        self.compiled = np.array([k for k, n in enumerate(ordered) if n in _FIELD], dtype=np.intp)
        self.index = np.array([_FIELD[n] for n in ordered if n in _FIELD], dtype=np.intp)
        #: Positions in :attr:`names` of the outputs computed in Python (not fields of the kernel).
        self.python = np.array([k for k, n in enumerate(ordered) if n not in _FIELD], dtype=np.intp)


@njit(cache=True, inline="always")
def _in_ship_plane(rot: np.ndarray, ux: float, uy: float, uz: float) -> tuple:
    """The ship-frame X and Z components of an inertial direction (its projection on the
    plane of the drum and the sheave)."""
    return (rot[0, 0] * ux + rot[1, 0] * uy + rot[2, 0] * uz,
            rot[0, 2] * ux + rot[1, 2] * uy + rot[2, 2] * uz)


@njit(cache=True, inline="always")
def _departure_angle(ux: float, uz: float) -> float:
    """Angle of an inertial direction (x, z components) from the inertial downward
    vertical in the x-z plane, positive towards -x (trailing aft) [rad]: the departure
    angle theta of the compensation algorithms W(1)-(2), which combine it with inertial
    displacements."""
    return math.atan2(-ux, -uz)


# A kernel of its own, called by advance_recording (Simulation reads the outputs of a state
# through that): the first run compiles it in parallel with the integrator
# (towcable_fmu.jit.parallel_compile).
@njit(cache=True)
def output_values(model: CableModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, phi: np.ndarray, t: float,
                  ship: np.ndarray, scene: OutputScene, r: np.ndarray) -> np.ndarray:
    """The outputs of a state (order: :data:`OUTPUT_FIELDS`).

    Parameters
    ----------
    model, q, v, a, t, ship
        The cable system and its state at time t [s] with the ship state (3, 6).
    phi
        Winch state (rotation [rad], rate, acceleration, ...).
    scene
        What the outputs need of the scene (:class:`OutputScene`).
    r
        Scratch, shape (nf,).

    Returns
    -------
    ndarray
        ``tension.top``/``tension.bottom`` are the support reactions at a prescribed end
        (the consistent nodal force), else the axial force from the strain;
        ``tension.towbody`` is the force the cable exerts on the body (the body's own
        mass times acceleration minus its own weight and hydrodynamic force: an end mass
        on the same node belongs to the cable; for a rigid body the force in the link to
        its tow point); a rigid body's ``towbody.x/y/z`` and
        velocities are those of its CG, and its kinetic energy, weight and link strain
        energy are included in the energies. The contact fields
        follow :meth:`~towcable_fmu.ancf.simulation.Simulation.outputs`. Fields a scene does
        not model are NaN, and so are the energies without ``scene.energies``.
    """
    out = np.full(len(OUTPUT_FIELDS), np.nan)
    (reaction_top, reaction_bottom, t_first, t_last, t_max, t_min, kinetic, strain,
     gravity) = summary(model, q, v, a, t, ship, scene.xi, r, scene.energies)
    last = 6 * (model.node_mass.shape[0] - 1)
    top = reaction_top if model.free_idx[0] < 0 else max(t_first, 0.0)
    bottom = reaction_bottom if model.free_idx[last] < 0 else max(t_last, 0.0)
    out[0] = top
    out[1] = bottom
    out[2] = max(t_max, top, bottom)
    out[3] = t_min
    out[4] = math.atan2(math.sqrt(q[3] ** 2 + q[4] ** 2), -q[5])
    body_mass = scene.body_mass
    if body_mass >= 0.0:
        hydro = np.zeros(3)
        if model.terms.towbody.enabled:
            body_force(model.water, model.terms.towbody, q[last:last + 3], v[last:last + 3], a[last:last + 3], t, hydro)
        hydro[2] -= body_mass * model.gravity
        total = 0.0
        for c in range(3):
            total += (body_mass * a[last + c] - hydro[c]) ** 2
            out[6 + c] = q[last + c]
            out[9 + c] = v[last + c]
        out[5] = math.sqrt(total)
    if model.terms.rigid_link.enabled:
        kinetic, strain, gravity = _rigid_values(model, q, v, a, out, kinetic, strain, gravity)
    out[20] = kinetic
    out[21] = strain
    out[22] = gravity
    out[23] = phi[0]
    out[24] = scene.payout_radius * (scene.phi_nom - phi[0])
    if model.terms.feed.enabled:
        out[28] = model.el_len.sum()
    if model.terms.contact.enabled:
        _contact_values(model, q, v, ship, scene.has_winch, scene.sheave_position, top, out)
    return out


# IR-inlined into its only caller: a kernel of its own would be one more library for the
# caller to link and optimise again, with all the code beneath it.
@njit(cache=True, inline="always")
def _rigid_values(model: CableModel, q: np.ndarray, v: np.ndarray, a: np.ndarray, out: np.ndarray,
                  kinetic: float, strain: float, gravity: float) -> tuple:
    """A rigid towed body's CG, velocity, attitude and link force into ``out``; returns the
    energies with the body's kinetic energy, weight and link strain energy added [J]."""
    link = model.terms.rigid_link
    i = link.index
    p = i - 6
    b = link.body
    xt, vt, at = np.empty(3), np.empty(3), np.empty(3)
    tow_point_state(b, q[i:i + 6], v[i:i + 6], a[i:i + 6], xt, vt, at)
    _, _, w, _ = angular_kinematics(q[i:i + 6], v[i:i + 6], a[i:i + 6])
    force = 0.0
    stretch = 0.0
    for c in range(3):
        d = q[p + c] - xt[c]
        f = link.k * d + link.c * (v[p + c] - vt[c])
        force += f * f
        stretch += d * d
        out[6 + c] = q[i + c]
        out[9 + c] = v[i + c]
        out[25 + c] = q[i + 3 + c]
        kinetic += 0.5 * b.mass * v[i + c] ** 2
        for k in range(3):
            kinetic += 0.5 * w[c] * b.inertia[c, k] * w[k]
    out[5] = math.sqrt(force)
    return kinetic, strain + 0.5 * link.k * stretch, gravity + b.mass * model.gravity * q[i + 2]


@njit(cache=True, inline="always")  # (as _rigid_values)
def _contact_values(model: CableModel, q: np.ndarray, v: np.ndarray, ship: np.ndarray, has_winch: bool,
                    sheave_position: np.ndarray, top: float, out: np.ndarray) -> None:
    """Contact forces, departure tensions and angle, wrap and detachment into ``out``."""
    summary = new_summary(0, False)  # no distribution, no angular span: the outputs read neither
    surface_summary(model.terms.contact, elements(model), q, v, ship, summary)
    force, ends, lowest, energy = summary.force, summary.ends, summary.lowest, summary.energy
    out[12] = math.sqrt(force[WINCH, 0] ** 2 + force[WINCH, 1] ** 2 + force[WINCH, 2] ** 2)
    out[13] = math.sqrt(force[SHEAVE, 0] ** 2 + force[SHEAVE, 1] ** 2 + force[SHEAVE, 2] ** 2)
    out[14] = energy[0] + energy[1]
    rot = rotation_matrix(ship[0, 3], ship[0, 4], ship[0, 5])
    last_el = model.el_len.shape[0] - 1
    has_sheave = not np.isnan(sheave_position[0])
    if has_winch:
        e = int(ends[WINCH, 2])
        # the force carried just off the drum: the mean over the next element
        out[15] = element_tension(model, q, min(e + 1, last_el)) if e >= 0 else top
        if not has_sheave:  # the cable departs from the drum: its angle plays the sheave's role
            leave = point_on_cable(model, q, max(e, 0), ends[WINCH, 3] if e >= 0 else 0.0)
            out[16] = _departure_angle(leave[3], leave[5])
    if has_sheave:
        e0, xi0 = int(ends[SHEAVE, 0]), ends[SHEAVE, 1]
        e, xe = int(ends[SHEAVE, 2]), ends[SHEAVE, 3]
        if e < 0:  # not touching: where the cable passes closest to the sheave
            best = np.inf
            node = 0
            for n in range(model.node_mass.shape[0]):
                dist = 0.0
                for c in range(3):
                    centre = ship[0, c] + (rot[c, 0] * sheave_position[0] + rot[c, 1] * sheave_position[1]
                                           + rot[c, 2] * sheave_position[2])
                    dist += (q[6 * n + c] - centre) ** 2
                if dist < best:
                    best = dist
                    node = n
            e, xe = (node, 0.0) if node <= last_el else (node - 1, 1.0)
        leave = point_on_cable(model, q, e, xe)
        # the force carried just off the sheave: the mean over the next element
        out[17] = element_tension(model, q, min(e + 1, last_el))
        out[16] = _departure_angle(leave[3], leave[5])
        out[18] = 0.0
        if e0 >= 0:  # the wrap: how far the cable turns in the sheave's plane between meeting and leaving it
            ux, uz = _in_ship_plane(rot, leave[3], leave[4], leave[5])
            meet = point_on_cable(model, q, e0, xi0)
            u0x, u0z = _in_ship_plane(rot, meet[3], meet[4], meet[5])
            out[18] = abs(math.atan2(u0x * uz - u0z * ux, u0x * ux + u0z * uz))
        out[19] = 1.0 if lowest[SHEAVE] > 0.0 else 0.0


@njit(cache=True, inline="always")
def _interpolate_state(model: CableModel, st, ws, t: float, drive_t: np.ndarray, drive_x: np.ndarray) -> None:
    """The state at time t [s] inside the last accepted step, into ``ws.qs``, ``vs``, ``as_``,
    ``phis`` and ``ships``: cubic Hermite in the coordinates from their values and rates at
    both ends (error O(h^4), below the scheme's own O(h^2)), rates its derivative,
    accelerations linear; the prescribed ends follow the ship and the winch exactly."""
    t0 = ws.step_start[0]
    h = st.clock[CLOCK_TIME] - t0
    s = (t - t0) / h
    h00, h10, h01, h11, d00, d10, d01, d11 = step_weights(s, h)
    for i in range(st.q.shape[0]):
        q0, v0, q1, v1 = ws.q0[i], ws.v0[i], st.q[i], st.v[i]
        ws.qs[i] = h00 * q0 + h10 * h * v0 + h01 * q1 + h11 * h * v1
        ws.vs[i] = d00 * q0 + d10 * v0 + d01 * q1 + d11 * v1
        ws.as_[i] = (1.0 - s) * ws.a0[i] + s * st.a[i]
    ws.phis[0] = h00 * ws.phi0[0] + h10 * h * ws.phi0[1] + h01 * st.phi[0] + h11 * h * st.phi[1]
    ws.phis[1] = d00 * ws.phi0[0] + d10 * ws.phi0[1] + d01 * st.phi[0] + d11 * st.phi[1]
    for j in range(2, 4):
        ws.phis[j] = (1.0 - s) * ws.phi0[j] + s * st.phi[j]
    evaluate_drive(drive_t, drive_x, t, ws.ships)
    apply_prescribed(model.att_index, model.att_kind, model.att_vec, model.att_radius, ws.ships, ws.phis,
                     ws.qs, ws.vs, ws.as_)
    apply_feed(model, ws.phis)


@njit(cache=True)
def advance_recording(model: CableModel, opt, st, ws, samples: np.ndarray, drive_t: np.ndarray,
                      drive_x: np.ndarray, rec: Recording) -> int:
    """Advance through the sample times and record the outputs ``rec.index`` of
    :func:`output_values` (the scene's, :class:`OutputLayout`) at each.

    One compiled call for a whole block of samples (no Python between them). ``rec.rows``
    (len(samples), len(index)) receives the outputs; ``opt``, ``st``, ``ws`` are the
    solver options, state and workspace of :mod:`towcable_fmu.ancf.genalpha`. It is
    the one kernel :class:`~towcable_fmu.ancf.simulation.Simulation` steps with: with no
    ``index`` it only steps (no outputs are computed), and one sample at the current
    time reads the outputs of the state.

    Sampling: without ``rec.interpolate`` the steps land on every sample time. With it the
    integrator keeps its own step size and never passes ``rec.t_land`` [s] (where it lands):
    a sample inside a step reads the state interpolated in that step
    (:func:`_interpolate_state`), so the output interval does not change the steps. The
    state may then end up to one step past the last sample (the next block's drive table
    must start at ``ws.step_start``).

    Returns
    -------
    int
        The number of samples reached: ``len(samples)``, or the index of the sample whose
        step failed (the state is then the last accepted step) or, with ``finite``, whose
        outputs are not finite (``rec.finite``), or the first sample after a step that
        took a spool end's fed element out of its band
        (:data:`~towcable_fmu.ancf.genalpha.FEED_EVENT`: the caller tells the cases
        apart with :func:`~towcable_fmu.ancf.feed.feed_event`, remeshes and goes on).
    """
    scene, index, rows, finite, interpolate, t_land = rec
    k = 0
    event = False  # a step reached a feed event: record the samples it passed, then return
    while k < samples.shape[0]:
        t_s = samples[k]
        t = st.clock[CLOCK_TIME]
        tol = 1e-12 * max(1.0, abs(t_s))
        if t_s > t + tol:
            if event:
                return k
            target = t_land if interpolate else t_s
            status = genalpha_advance(model, opt, st, ws, target, drive_t, drive_x, interpolate)
            if status != 0 and status != FEED_EVENT:
                return k
            event = status == FEED_EVENT
            continue
        k += 1
        if index.shape[0] == 0:
            continue
        if t_s >= t - tol:
            q, v, a, phi, ship = st.q, st.v, st.a, st.phi, ws.ship
        else:
            _interpolate_state(model, st, ws, t_s, drive_t, drive_x)
            q, v, a, phi, ship = ws.qs, ws.vs, ws.as_, ws.phis, ws.ships
        values = output_values(model, q, v, a, phi, t_s, ship, scene, ws.r)
        if t_s < t - tol:
            apply_feed(model, st.phi)  # back to the step's end
        for j in range(index.shape[0]):
            rows[k - 1, j] = values[index[j]]
            if finite and not np.isfinite(rows[k - 1, j]):
                return k - 1
    return samples.shape[0]
