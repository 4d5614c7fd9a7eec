"""The water as the compiled kernels see it: density, surface, current, turbulence table.

The per-point functions work on scalars and return tuples (no array slicing or
allocation): in numba that is what keeps a point evaluation in the tens of nanoseconds.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..jit.kernel_cache import njit

CURRENT_NONE = 0
CURRENT_UNIFORM = 1
CURRENT_LINEAR = 2
CURRENT_KINDS = {"none": CURRENT_NONE, "uniform": CURRENT_UNIFORM, "linear": CURRENT_LINEAR}


class WaterModel(NamedTuple):
    """Water data for the kernels (``enabled`` False: a dry scene)."""

    enabled: bool
    density: float        #: rho_f [kg/m^3]
    viscosity: float      #: mu [Pa s]
    surface_z: float      #: free-surface height [m]
    gravity: float        #: g [m/s^2] (buoyancy)
    current_kind: int     #: CURRENT_* code
    current_v0: np.ndarray    #: (3,) velocity (at the surface for the linear profile) [m/s]
    current_grad: np.ndarray  #: (3,) change per metre of height [1/s]
    turb_t0: float        #: time of the first turbulence sample [s]
    turb_dt: float        #: sample interval [s]
    turb: np.ndarray      #: (n, 3) turbulent velocity samples [m/s]; n = 0: no turbulence
    waves: np.ndarray     #: (n, 10) wave components (:func:`towcable_fmu.hydro.waves.component_table`); n = 0: none
    wave_depth: float     #: water depth h [m] of the waves' dispersion (inf: deep water)
    wave_stretch: int     #: stretching code (towcable_fmu.hydro.waves.STRETCHINGS)
    wave_ramp: float      #: ramp time [s] of the waves (the motion's)
    wave_crest: float     #: the highest crest and deepest trough of the waves, sum |a_i| [m]
    wave_slope: float     #: the steepest slope of the surface, sum |a_i| k_i [-]


def dry_water() -> WaterModel:
    """The water of a scene without water."""
    return WaterModel(False, 0.0, 1.0, -np.inf, 0.0, CURRENT_NONE, np.zeros(3), np.zeros(3), 0.0, 1.0,
                      np.zeros((0, 3)), np.zeros((0, 10)), np.inf, 0, 0.0, 0.0, 0.0)


def still_water(w: WaterModel) -> WaterModel:
    """``w`` without its turbulence and waves (the steady flow of a static equilibrium)."""
    return w._replace(turb=np.zeros((0, 3)), waves=np.zeros((0, w.waves.shape[1])), wave_crest=0.0,
                      wave_slope=0.0)


@njit(cache=True, inline="always")
def mean_flow(w: WaterModel, z: float) -> tuple[float, float, float]:
    """Mean (steady) current at height z [m/s]."""
    if w.current_kind == CURRENT_NONE:
        return 0.0, 0.0, 0.0
    if w.current_kind == CURRENT_UNIFORM:
        return w.current_v0[0], w.current_v0[1], w.current_v0[2]
    dz = z - w.surface_z
    return (w.current_v0[0] + w.current_grad[0] * dz, w.current_v0[1] + w.current_grad[1] * dz,
            w.current_v0[2] + w.current_grad[2] * dz)


@njit(cache=True, inline="always")
def _hermite_sample(turb: np.ndarray, i: int, k: int, s: float, dt: float) -> tuple[float, float]:
    p0 = turb[i, k]
    p1 = turb[i + 1, k]
    m0 = 0.5 * (p1 - turb[i - 1, k])
    m1 = 0.5 * (turb[i + 2, k] - p0)
    s2 = s * s
    s3 = s2 * s
    val = (2.0 * s3 - 3.0 * s2 + 1.0) * p0 + (s3 - 2.0 * s2 + s) * m0 + (-2.0 * s3 + 3.0 * s2) * p1 + (s3 - s2) * m1
    der = (6.0 * s2 - 6.0 * s) * p0 + (3.0 * s2 - 4.0 * s + 1.0) * m0 + (-6.0 * s2 + 6.0 * s) * p1 + (3.0 * s2 - 2.0 * s) * m1
    return val, der / dt


@njit(cache=True, inline="always")
def turbulence(w: WaterModel, t: float) -> tuple[float, float, float, float, float, float]:
    """Turbulent fluctuation (3) and its time derivative (3) at time t: cubic Hermite through
    the samples with central-difference slopes (continuous velocity and acceleration slope)."""
    n = w.turb.shape[0]
    if n < 4:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    x = (t - w.turb_t0) / w.turb_dt
    i = min(max(int(math.floor(x)), 1), n - 3)
    s = x - i
    vx, ax = _hermite_sample(w.turb, i, 0, s, w.turb_dt)
    vy, ay = _hermite_sample(w.turb, i, 1, s, w.turb_dt)
    vz, az = _hermite_sample(w.turb, i, 2, s, w.turb_dt)
    return vx, vy, vz, ax, ay, az


@njit(cache=True)
def flow(w: WaterModel, z: float, t: float, vel: np.ndarray, acc: np.ndarray) -> None:
    """Flow velocity (mean + turbulence) and its local acceleration at height z and time t,
    written to ``vel`` and ``acc`` (3,) (for code outside the hot loops)."""
    mx, my, mz = mean_flow(w, z)
    tx, ty, tz, ax, ay, az = turbulence(w, t)
    vel[0], vel[1], vel[2] = mx + tx, my + ty, mz + tz
    acc[0], acc[1], acc[2] = ax, ay, az
