"""Converting tabulated RAOs from a source's conventions to ours.

Ours (:mod:`ship_motion.rao`, README "Conventions"): complex H per unit wave amplitude,
time factor ``exp(+i omega t)`` (a wave ``a cos(omega t + eps)`` at the CG gives the
response ``a |H| cos(omega t + eps + arg H)``: the phase is a lead over the wave
elevation at the CG), translations [m/m] of the CG, rotations [rad/m], ship axes X
forward, Y port, Z up, the heading mu the direction the waves travel measured from X
towards Y (180 deg = head seas).

A source gives the translations of its RAO origin P and the phases relative to the
wave elevation at its phase origin O. For small rotations theta = (roll, pitch, yaw)
a rigid body's point C moves by ``xi_C = xi_P + theta x (r_C - r_P)``; and a deep-water
wave of heading mu, ``eta(x, y) = Re a exp(i (omega t - k (x cos mu + y sin mu)))``
with ``k = omega^2 / g``, reaches C with the phase ``-k (r_C - r_O) . (cos mu, sin mu)``
relative to O, so ``H_C = H_O exp(+i k (r_C - r_O) . (cos mu, sin mu))``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..rao import GRAVITY, RaoTable

#: Columns that change sign when the ship is mirrored in its XZ plane (y -> -y): sway, roll, yaw.
_MIRROR_SIGN = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])


@dataclass(frozen=True)
class SourceFrame:
    """Where a source's RAOs are referred to, in the source's body axes (X forward, Y port, Z up).

    Parameters
    ----------
    rao_origin
        Point whose translations the source tabulates [m].
    phase_origin
        Point (x, y) at which the source's wave elevation has phase zero [m].
    centre_of_gravity
        The ship's CG [m], the point of our RAOs.
    """

    rao_origin: tuple[float, float, float]
    phase_origin: tuple[float, float]
    centre_of_gravity: tuple[float, float, float]


def move_to_cg(omega: ArrayLike, heading: ArrayLike, values: ArrayLike, frame: SourceFrame,
               wavenumber: ArrayLike | None = None) -> np.ndarray:
    """RAOs of the source's origin (module docstring) moved to the CG.

    Parameters
    ----------
    omega
        Wave frequencies [rad/s], shape (nf,).
    heading
        Headings [rad], shape (nh,).
    values
        Complex H in our phase convention relative to the source's phase origin, shape
        (nf, nh, 6): [m/m] translations of the RAO origin, [rad/m] rotations.
    frame
        The source's points.
    wavenumber
        Wave numbers k [rad/m], shape (nf,), in finite depth; None: deep water, omega^2 / g.

    Returns
    -------
    ndarray, shape (nf, nh, 6)
        H of the CG, phases relative to the wave elevation at the CG.
    """
    w = np.asarray(omega, dtype=float)
    mu = np.asarray(heading, dtype=float)
    out = np.array(values, dtype=complex)
    arm = np.asarray(frame.centre_of_gravity, dtype=float) - np.asarray(frame.rao_origin, dtype=float)
    out[..., 0:3] += np.cross(out[..., 3:6], arm)
    shift = np.asarray(frame.centre_of_gravity[:2], dtype=float) - np.asarray(frame.phase_origin, dtype=float)
    k = w ** 2 / GRAVITY if wavenumber is None else np.asarray(wavenumber, dtype=float)
    lead = np.outer(k, shift[0] * np.cos(mu) + shift[1] * np.sin(mu))
    return out * np.exp(1j * lead)[..., None]


def mirror_half_range(heading: ArrayLike, values: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Complete the headings of a hull symmetric about its XZ plane (port-starboard).

    The mirror image of heading mu is -mu, with sway, roll and yaw of opposite sign.

    Parameters
    ----------
    heading
        Headings [rad], shape (nh,), within [0, 2 pi).
    values
        H, shape (nf, nh, 6).

    Returns
    -------
    heading, values
        The union of the given and the mirrored headings (sorted; a mirrored heading
        that is already given is not repeated), and their H.
    """
    mu = np.mod(np.asarray(heading, dtype=float), 2.0 * math.pi)
    h = np.asarray(values, dtype=complex)
    mirrored = np.mod(-mu, 2.0 * math.pi)
    new = np.array([not np.any(np.isclose(m, mu, atol=1e-9) | np.isclose(abs(m - mu), 2.0 * math.pi, atol=1e-9))
                    for m in mirrored], dtype=bool)
    all_mu = np.concatenate([mu, mirrored[new]])
    all_h = np.concatenate([h, h[:, new, :] * _MIRROR_SIGN], axis=1)
    order = np.argsort(all_mu)
    return all_mu[order], all_h[:, order, :]


def from_modulus_phase(modulus: ArrayLike, phase_deg: ArrayLike, *, lag: bool) -> np.ndarray:
    """Complex H = modulus exp(+-i phase) from a phase [deg] given as a lead or as a lag."""
    sign = -1.0 if lag else 1.0
    return np.asarray(modulus, dtype=float) * np.exp(sign * 1j * np.radians(phase_deg))


def mirrored(table: RaoTable) -> RaoTable:
    """``table`` with its headings mirrored (:func:`mirror_half_range`), for a port-starboard symmetric hull."""
    n = table.heading.size - int(table.periodic)
    heading, values = mirror_half_range(table.heading[:n], table.values[:, :n])
    return RaoTable(table.omega, heading, values, label=table.label)
