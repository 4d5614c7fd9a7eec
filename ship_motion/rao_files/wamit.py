"""WAMIT's motion RAO output, the ``.4`` file.

Layout (WAMIT User Manual, "Output files", numeric option 4): one line per period,
heading and mode, seven numbers::

    PER  BETA  I  |Xi|  phase(Xi)  Re(Xi)  Im(Xi)

- PER: the wave period [s] (WAMIT's default output, IPEROUT = 1) or the frequency
  [rad/s] (IPEROUT = 2), as the key ``first_column`` declares; rows with PER <= 0
  (WAMIT's zero- and infinite-frequency limits) are skipped.
- BETA: wave heading [deg], the direction the waves travel measured from the body's
  x axis counter-clockwise (ours: 180 deg = head seas when x points to the bow).
- I: mode 1..6 (surge, sway, heave, roll, pitch, yaw) of one body (a multi-body file,
  I > 6, is an error).
- Non-dimensional: ``Xi_bar = Xi / (A / ULEN^n)`` with n = 0 for the translations and
  n = 1 for the rotations (WAMIT's length scale ULEN [m], set in its ``.frc``/``.cfg``
  and printed in its ``.out`` file, not in the ``.4`` file: the key ``ulen`` declares
  it). So the rotations are per unit ``A / ULEN`` (not per unit wave slope k A); here
  translations [m/m] = Xi_bar, rotations [rad/m] = Xi_bar / ULEN.
- Phase: WAMIT's time factor is ``exp(+i omega t)`` and the phase is the lead over the
  incident wave elevation at the origin of the body coordinates; the motions are those
  of that origin (rotations about it). The reader uses Re and Im (the modulus and
  phase columns must agree with them) and moves the RAOs to the CG
  (:mod:`ship_motion.rao_files.conventions`; the key ``centre_of_gravity`` gives the CG
  in WAMIT's body coordinates).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from towcable_fmu.common.errors import SceneError

from ..rao import RaoTable
from .conventions import SourceFrame, mirror_half_range, move_to_cg
from .grid import assemble_grid

#: What the first column of a ``.4`` file can be.
FIRST_COLUMNS: tuple[str, ...] = ("period", "frequency")

_LAYOUT = "a WAMIT .4 file (lines of PER BETA I |Xi| phase Re Im)"


def read_wamit_4(path: str | Path, *, ulen: float, centre_of_gravity: tuple[float, float, float],
                 first_column: str = "period", symmetric: bool = False, key: str = "file") -> RaoTable:
    """Read a WAMIT ``.4`` file into our RAOs at the CG (module docstring).

    Parameters
    ----------
    path
        The file.
    ulen
        WAMIT's length scale ULEN [m].
    centre_of_gravity
        The CG in WAMIT's body coordinates [m].
    first_column
        ``"period"`` [s] or ``"frequency"`` [rad/s].
    symmetric
        The hull is symmetric port-starboard: the headings given are mirrored.
    key
        Configuration key naming the file (error messages).

    Raises
    ------
    SceneError
        Naming the file, the line and the layout, if the file does not fit it.
    """
    path = Path(path)
    if not path.is_file():
        raise SceneError(key, str(path), "an existing WAMIT .4 file")
    if first_column not in FIRST_COLUMNS:
        raise SceneError(key, first_column, "first_column one of " + ", ".join(FIRST_COLUMNS))
    rows, lines = [], []
    with path.open(encoding="utf-8") as handle:
        for number, line in enumerate(handle, start=1):
            fields = line.split()
            if not fields:
                continue
            try:
                values = [float(f.replace("D", "E").replace("d", "e")) for f in fields]
            except ValueError:
                raise SceneError(key, str(path), f"{_LAYOUT}; line {number} is not numbers: {line.strip()!r}") from None
            if len(values) != 7 or not all(map(math.isfinite, values)):
                raise SceneError(key, str(path), f"{_LAYOUT}; line {number} has {len(values)} fields, not 7 "
                                 "finite numbers")
            mode = values[2]
            if mode != int(mode) or not 1 <= mode <= 6:
                raise SceneError(key, str(path), f"{_LAYOUT} of one body, mode I in 1..6; line {number} has I = "
                                 f"{values[2]:g}")
            h = complex(values[5], values[6])
            polar = values[3] * np.exp(1j * math.radians(values[4]))
            if abs(h - polar) > 1e-4 * max(values[3], 1e-12) + 1e-9:
                raise SceneError(key, str(path), f"{_LAYOUT} whose modulus and phase agree with Re and Im (line "
                                 f"{number})")
            if values[0] <= 0.0:
                continue
            rows.append(values)
            lines.append(number)
    if not rows:
        raise SceneError(key, str(path), f"{_LAYOUT} with at least one line of a positive period")
    data = np.array(rows)
    omega = 2.0 * math.pi / data[:, 0] if first_column == "period" else data[:, 0]
    dof = data[:, 2].astype(int) - 1
    rotation = dof >= 3
    h = (data[:, 5] + 1j * data[:, 6]) / np.where(rotation, ulen, 1.0)
    freqs, heads, values = assemble_grid(omega, np.radians(data[:, 1]), dof, h, np.array(lines), key=key,
                                         path=str(path), layout=_LAYOUT)
    if symmetric:
        heads, values = mirror_half_range(heads, values)
    frame = SourceFrame(rao_origin=(0.0, 0.0, 0.0), phase_origin=(0.0, 0.0),
                        centre_of_gravity=tuple(centre_of_gravity))
    return RaoTable(freqs, heads, move_to_cg(freqs, heads, values, frame), label=path.name)


def write_wamit_4(path: str | Path, table: RaoTable, *, ulen: float, digits: int = 9) -> None:
    """Write RAOs given at the body origin in WAMIT's ``.4`` layout (period first).

    For tests and examples: ``table``'s values are taken as the RAOs of WAMIT's body
    origin with phases relative to the wave there (our convention otherwise).

    Parameters
    ----------
    path
        The file to write.
    table
        The RAOs; the listed headings are written (a periodic table's closing column is not).
    ulen
        WAMIT's length scale ULEN [m].
    digits
        Significant digits of the numbers.
    """
    n_heading = table.heading.size - int(table.periodic)
    fmt = f"{{:.{digits - 1}E}}"
    with Path(path).open("w", encoding="utf-8") as handle:
        for i in np.argsort(-table.omega):
            period = 2.0 * math.pi / table.omega[i]
            for j in range(n_heading):
                for d in range(6):
                    h = table.values[i, j, d] * (ulen if d >= 3 else 1.0)
                    numbers = [period, math.degrees(table.heading[j]), None, abs(h),
                               math.degrees(np.angle(h)), h.real, h.imag]
                    text = [fmt.format(v) if v is not None else f"{d + 1:d}" for v in numbers]
                    handle.write(" ".join(text) + "\n")
