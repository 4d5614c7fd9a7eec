"""Assembling scattered RAO rows (frequency, heading, DOF, H) into a full grid."""

from __future__ import annotations

import math

import numpy as np

from towcable_fmu.common.errors import SceneError


def assemble_grid(omega: np.ndarray, heading: np.ndarray, dof: np.ndarray, h: np.ndarray, lines: np.ndarray,
                  *, key: str, path: str, layout: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The grid of RAOs given row by row.

    Parameters
    ----------
    omega, heading, dof, h, lines
        One entry per row: wave frequency [rad/s], heading [rad], DOF index 0..5, complex
        H, and the row's line number in the file (for error messages).
    key, path, layout
        The configuration key, the file and a description of its layout (error messages).

    Returns
    -------
    omega : ndarray (nf,), heading : ndarray (nh,) within [0, 2 pi), values : ndarray (nf, nh, 6)
        DOFs that no row gives are zero.

    Raises
    ------
    SceneError
        If a (frequency, heading, DOF) is given twice, a DOF given for some pairs is
        missing for others, or fewer than 2 frequencies are given.
    """
    freqs, f_index = np.unique(omega, return_inverse=True)
    heads, h_index = np.unique(np.round(np.mod(heading, 2.0 * math.pi), 12), return_inverse=True)
    given = np.zeros((freqs.size, heads.size, 6), dtype=int)
    values = np.zeros((freqs.size, heads.size, 6), dtype=complex)
    for row, (i, j, d) in enumerate(zip(f_index, h_index, dof)):
        if given[i, j, d]:
            raise SceneError(key, path, f"{layout}: each frequency, heading and DOF once (line {lines[row]} "
                             f"repeats frequency {freqs[i]:.6g} rad/s, heading {math.degrees(heads[j]):.6g} deg, "
                             f"DOF {d + 1})")
        given[i, j, d] = 1
        values[i, j, d] = h[row]
    present = np.any(given, axis=(0, 1))
    missing = np.argwhere((given == 0) & present)
    if missing.size:
        i, j, d = missing[0]
        raise SceneError(key, path, f"{layout}: a full grid of frequencies x headings for each DOF (DOF {d + 1} is "
                         f"missing at frequency {freqs[i]:.6g} rad/s, heading {math.degrees(heads[j]):.6g} deg)")
    if freqs.size < 2:
        raise SceneError(key, path, f"{layout}: at least 2 wave frequencies")
    return freqs, heads, values
