"""Response amplitude operators (RAOs): ship motion per metre of wave amplitude.

An RAO is a callable ``rao(omega, heading, speed) -> H`` returning complex transfer
functions H, shape (n, 6), for wave frequencies ``omega`` [rad/s], the wave heading
[rad] relative to the ship and the forward speed [m/s]. The columns are surge, sway,
heave [m/m] and roll, pitch, yaw [rad/m]. For a wave component whose elevation at
the ship's CG is ``a cos(omega_e t + eps)``, the response is
``a |H| cos(omega_e t + eps + arg H)``, with the encounter frequency
``omega_e = omega - omega^2 U cos(mu) / g``.

Heading convention: mu is the angle from the ship's forward axis X to the direction in
which the waves travel, counter-clockwise seen from above (towards port, Y).
mu = 180 deg: head seas (waves travel aft, they come from ahead); 0: following seas;
90: beam seas travelling to port (coming from starboard); 270: coming from port.

Two RAOs are provided:

:class:`ClosedFormRao`
    Heave and pitch from the closed-form expressions of Jensen, Mansour & Olsen
    (2004), "Estimation of ship motions using closed-form expressions", Ocean Eng. 31,
    61-85 (a box-shaped hull of length L, breadth B1 = C_B B and draught T, with
    strip-theory added mass and wave damping of its sections and forward speed through
    alpha = omega_e / omega); their amplitudes are Jensen's, their phases follow from
    writing Jensen's amplitude factors as the complex ratios they are the modulus of.
    Roll is a linear one-degree-of-freedom oscillator excited by the effective wave
    slope. Surge, sway and yaw are zero. Formulas in README.md.
:class:`RaoTable`
    A table of amplitudes and phases from a CSV file, interpolated bilinearly in
    frequency and heading.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike

from towcable_fmu.common.errors import SceneError

from .base import CONFIG_DOF_NAMES, IS_ANGLE
from .csv_table import read_csv_table

#: Gravitational acceleration used by the wave dispersion relation [m/s^2].
GRAVITY = 9.81


class Rao(Protocol):
    """Complex transfer functions of the six DOFs (module docstring)."""

    def __call__(self, omega: ArrayLike, heading: float, speed: float) -> np.ndarray:
        """H(omega), shape (n, 6); heading [rad], speed [m/s]."""

    @property
    def description(self) -> str:
        """One line naming the model and its parameters."""


@dataclass(frozen=True)
class ShipParticulars:
    """Main dimensions of the closed-form hull (defaults: an FFG-7-sized frigate).

    Parameters
    ----------
    length
        Waterline length L [m].
    beam
        Waterline beam B [m].
    draught
        Hull draught T [m] (without sonar dome).
    block_coefficient
        Block coefficient C_B [-]; the box hull's sectional breadth is C_B B.
    roll_period
        Natural roll period T4 [s] (about 2 * 0.38 * B / sqrt(GM_T), IMO A.749).
    roll_damping
        Equivalent linear roll damping ratio zeta4 [-] (wave radiation, hull friction,
        eddies and bilge keels together).
    """

    length: float = 135.0
    beam: float = 14.0
    draught: float = 4.7
    block_coefficient: float = 0.46
    roll_period: float = 10.0
    roll_damping: float = 0.10

    def __post_init__(self) -> None:
        for name in ("length", "beam", "draught", "roll_period", "roll_damping"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be finite and > 0, got {value}")
        if not 0.0 < self.block_coefficient <= 1.0:
            raise ValueError(f"block_coefficient must be in (0, 1], got {self.block_coefficient}")


#: The default frigate (FFG-7 size: displacement C_B L B T rho = 4190 t).
FRIGATE = ShipParticulars()


def _sinc(x: np.ndarray) -> np.ndarray:
    """sin(x) / x."""
    return np.sinc(x / math.pi)


def _pitch_shape(x: np.ndarray) -> np.ndarray:
    """3 (sin x - x cos x) / x^3, the first moment of the hull's wave-phase integral."""
    small = np.abs(x) < 1e-2
    xs = np.where(small, 1.0, x)
    exact = 3.0 * (np.sin(xs) - xs * np.cos(xs)) / xs ** 3
    return np.where(small, 1.0 - x * x / 10.0 + x ** 4 / 280.0, exact)


class ClosedFormRao:
    """Closed-form RAOs of a box-like monohull (module docstring, README.md).

    Parameters
    ----------
    particulars
        Hull dimensions and roll properties.
    """

    def __init__(self, particulars: ShipParticulars = FRIGATE) -> None:
        self.particulars = particulars

    def __call__(self, omega: ArrayLike, heading: float, speed: float) -> np.ndarray:
        p = self.particulars
        w = np.asarray(omega, dtype=float)
        k = w ** 2 / GRAVITY
        cos_mu, sin_mu = math.cos(heading), math.sin(heading)
        alpha = 1.0 - w * speed * cos_mu / GRAVITY          # omega_e / omega
        sign = np.where(alpha >= 0.0, 1.0, -1.0)
        a = np.maximum(np.abs(alpha), 1e-9)
        b1 = p.block_coefficient * p.beam
        kt = k * p.draught
        # far-field wave amplitude ratio of a heaving section of breadth B1, draught T
        wave = 2.0 * np.sin(0.5 * k * b1 * a ** 2) * np.exp(-kt * a ** 2)
        # 1 - omega_e^2 (m + a33) / c33 + i omega_e b33 / c33, with omega_n^2 = g / (2 T)
        denominator = 1.0 - 2.0 * kt * a ** 2 + 1j * sign * wave ** 2 / (k * b1 * a ** 2)
        # sectional excitation / hydrostatic force: Froude-Krylov + diffraction
        excitation = (1.0 - kt) + 1j * sign * wave ** 2 / (k * b1 * a ** 3)
        sigma = 0.5 * k * cos_mu * p.length
        smith = np.exp(-kt)
        vertical = smith * excitation / denominator
        out = np.zeros((w.size, 6), dtype=complex)
        out[:, 2] = vertical * _sinc(sigma)
        out[:, 4] = 1j * k * cos_mu * vertical * _pitch_shape(sigma)
        tuning = alpha * w * p.roll_period / (2.0 * math.pi)    # omega_e / omega_4
        slope = -1j * k * sin_mu * np.exp(-0.5 * kt) * _sinc(sigma)
        out[:, 3] = slope / (1.0 - tuning ** 2 + 2j * p.roll_damping * tuning)
        return out

    @property
    def description(self) -> str:
        p = self.particulars
        return (f"closed-form RAO (Jensen et al. 2004; roll: effective wave slope) L {p.length:g} m, "
                f"B {p.beam:g} m, T {p.draught:g} m, CB {p.block_coefficient:g}, "
                f"roll period {p.roll_period:g} s, roll damping {p.roll_damping:g}")


class RaoTable:
    """Tabulated RAOs, bilinear in wave frequency and heading.

    The real and imaginary parts of H are interpolated (so that the phase needs no
    unwrapping). The heading axis is periodic when the listed headings go all the
    way round (the gap across 360 deg is no wider than the widest gap between listed
    headings); otherwise the heading must lie between the first and last listed one.
    Frequencies outside the table raise ValueError. The table holds for the speed it
    was computed for: the ``speed`` argument is not used.

    Parameters
    ----------
    omega
        Wave frequencies [rad/s], shape (nf,), increasing, nf >= 2.
    heading
        Headings [rad], shape (nh,), increasing within [0, 2 pi).
    values
        Complex H, shape (nf, nh, 6): [m/m] for surge, sway, heave, [rad/m] for the angles.
    label
        Where the table came from.
    """

    def __init__(self, omega: ArrayLike, heading: ArrayLike, values: ArrayLike,
                 label: str = "array") -> None:
        self.omega = np.asarray(omega, dtype=float)
        heading = np.asarray(heading, dtype=float)
        values = np.asarray(values, dtype=complex)
        if (self.omega.ndim != 1 or self.omega.size < 2 or np.any(np.diff(self.omega) <= 0)
                or self.omega[0] < 0.0):
            raise ValueError("RAO frequencies must be >= 0 and strictly increasing (at least 2)")
        if (heading.ndim != 1 or heading.size < 1 or np.any(np.diff(heading) <= 0)
                or heading[0] < 0.0 or heading[-1] >= 2.0 * math.pi):
            raise ValueError("RAO headings must be strictly increasing within [0, 2 pi)")
        if values.shape != (self.omega.size, heading.size, 6):
            raise ValueError(f"RAO values must have shape {(self.omega.size, heading.size, 6)}")
        gaps = np.diff(heading)
        wrap = heading[0] + 2.0 * math.pi - heading[-1]
        self.periodic = heading.size >= 2 and wrap <= gaps.max() * (1.0 + 1e-9)
        if self.periodic:
            heading = np.append(heading, heading[0] + 2.0 * math.pi)
            values = np.concatenate([values, values[:, :1]], axis=1)
        self.heading = heading
        self.values = values
        self.label = label

    @classmethod
    def from_csv(cls, path: str | Path, *, angle_unit: str = "deg",
                 key: str = "file") -> RaoTable:
        """Read a table: columns ``omega`` [rad/s] (or ``frequency``), ``heading`` [deg],
        then ``<dof>_amp`` and ``<dof>_phase`` for any of surge, sway, heave, roll, pitch,
        yaw (missing DOFs are zero). Translational amplitudes in m/m; rotational
        amplitudes in ``angle_unit`` per m; all phases in ``angle_unit``. The rows must
        cover the full grid of listed frequencies times listed headings.

        Raises
        ------
        SceneError
            If the file does not fit this layout.
        """
        path = Path(path)
        names, data = read_csv_table(path, key)
        names = ["omega" if n == "frequency" else n for n in names]
        dof_columns = [f"{d}_{part}" for d in CONFIG_DOF_NAMES for part in ("amp", "phase")]
        allowed = ("a CSV file with columns omega, heading and <dof>_amp, <dof>_phase for "
                   "surge, sway, heave, roll, pitch, yaw (a full frequency x heading grid)")
        unknown = [n for n in names if n not in ("omega", "heading", *dof_columns)]
        present = [d for d in CONFIG_DOF_NAMES if f"{d}_amp" in names and f"{d}_phase" in names]
        unpaired = [d for d in CONFIG_DOF_NAMES if (f"{d}_amp" in names) != (f"{d}_phase" in names)]
        if unknown or unpaired or not present or "omega" not in names or "heading" not in names:
            raise SceneError(key, str(path), allowed + f" (found: {', '.join(names)})")
        column = {n: data[:, i] for i, n in enumerate(names)}
        angle = math.pi / 180.0 if angle_unit == "deg" else 1.0
        freqs, f_index = np.unique(column["omega"], return_inverse=True)
        heads, h_index = np.unique(np.mod(np.radians(column["heading"]), 2.0 * math.pi),
                                   return_inverse=True)
        filled = np.zeros((freqs.size, heads.size), dtype=int)
        np.add.at(filled, (f_index, h_index), 1)
        if np.any(filled != 1) or freqs.size < 2:
            raise SceneError(key, str(path), allowed + " (each frequency-heading pair exactly "
                             "once, at least 2 frequencies)")
        values = np.zeros((freqs.size, heads.size, 6), dtype=complex)
        for j, d in enumerate(CONFIG_DOF_NAMES):
            if d in present:
                amp = column[f"{d}_amp"] * (angle if IS_ANGLE[j] else 1.0)
                values[f_index, h_index, j] = amp * np.exp(1j * angle * column[f"{d}_phase"])
        return cls(freqs, heads, values, label=path.name)

    @property
    def frequency_range(self) -> tuple[float, float]:
        """Lowest and highest tabulated wave frequency [rad/s]."""
        return float(self.omega[0]), float(self.omega[-1])

    def heading_coordinate(self, heading: float) -> float | None:
        """The heading [rad] mapped onto the table's heading axis, or None if not covered."""
        h = heading % (2.0 * math.pi)
        if self.periodic and h < self.heading[0]:
            h += 2.0 * math.pi
        tol = 1e-9
        if h < self.heading[0] - tol or h > self.heading[-1] + tol:
            return None
        return min(max(h, self.heading[0]), self.heading[-1])

    def __call__(self, omega: ArrayLike, heading: float, speed: float) -> np.ndarray:
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        h = self.heading_coordinate(heading)
        if h is None:
            raise ValueError(f"heading {math.degrees(heading):g} deg is not covered by {self.label}")
        lo, hi = self.frequency_range
        if np.any(w < lo) or np.any(w > hi):
            raise ValueError(f"frequencies outside [{lo:g}, {hi:g}] rad/s of {self.label}")
        if self.heading.size == 1:
            column = self.values[:, 0, :]
        else:
            j = min(int(np.searchsorted(self.heading, h, side="right")) - 1, self.heading.size - 2)
            weight = (h - self.heading[j]) / (self.heading[j + 1] - self.heading[j])
            column = (1.0 - weight) * self.values[:, j, :] + weight * self.values[:, j + 1, :]
        out = np.empty((w.size, 6), dtype=complex)
        for d in range(6):
            out[:, d] = (np.interp(w, self.omega, column[:, d].real)
                         + 1j * np.interp(w, self.omega, column[:, d].imag))
        return out

    @property
    def description(self) -> str:
        lo, hi = self.frequency_range
        return (f"RAO table {self.label} ({self.omega.size} frequencies in [{lo:g}, {hi:g}] rad/s, "
                f"{self.heading.size - int(self.periodic)} headings)")
