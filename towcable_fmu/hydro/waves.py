"""Linear (Airy) wave kinematics in the water: the sea that moves the ship, seen by the
cable and the towed body.

The field is the irregular sea of the scene's ``[motion]`` (:class:`ship_motion.irregular.IrregularSea`):
its components (frequency omega_i, amplitude a_i, phase eps_i, direction mu_i relative to
the ship's x axis), the same realisation (seed) that moves the ship. The frame is the
ship's motion frame, moving with the ship at its speed U along x (the frame the cable
lives in: the tow speed is the current ``-U``), origin at the ship's mean CG on the mean
water level ``surface_z``. A component there is

    eta_i = a_i cos(theta_i),   theta_i = omega_e,i t - k_i (x cos mu_i + y sin mu_i) + eps_i

with the encounter frequency ``omega_e = omega - k U cos mu`` (in deep water the ship's own
``omega - omega^2 U cos mu / g``, taken from the sea, so that the elevation at the origin
is :meth:`~ship_motion.irregular.IrregularSea.wave_elevation`), and ``k`` from the
dispersion relation ``omega^2 = g k tanh(k h)`` (depth h; deep water ``k = omega^2 / g``),
solved once. Particle velocity and the fluid's acceleration (in the earth frame, the
Froude-Krylov pressure gradient of linear theory: frequency omega, not omega_e):

    u_i = a_i omega_i C(z) cos(theta_i) (cos mu_i, sin mu_i),   w_i = -a_i omega_i S(z) sin(theta_i)
    du_i/dt = -a_i omega_i^2 C(z) sin(theta_i) (cos mu_i, sin mu_i),   dw_i/dt = -a_i omega_i^2 S(z) cos(theta_i)

with ``C = cosh(k (z + h)) / sinh(k h)``, ``S = sinh(k (z + h)) / sinh(k h)`` (both ``exp(k z)``
in deep water), z measured from the mean level. All of it is multiplied by the motion's
ramp factor f(t) (the ship's response rises over the same ramp; the acceleration takes
the product rule ``f a + f' u``).

Near the surface (``stretching``): Wheeler's (default) evaluates the kinematics at the
stretched height ``z_s = h (z - eta) / (h + eta)`` (deep water ``z - eta``), which maps the
water column up to the instantaneous surface eta onto the one up to the mean level;
``extrapolation`` uses the linear theory below the mean level and its value plus the
slope at the mean level above it.

Cut-off: the components are sorted by wave number; at a point the sum stops at the first
component whose depth factor C has fallen below :data:`CUTOFF` (C decreases with k at a
given depth), and a point below the reach of the longest component skips the sum (and
the elevation) altogether. A neglected component contributes less than CUTOFF times its
velocity and acceleration amplitudes at the surface.

Neglected: second-order (Stokes, difference-frequency) waves, the diffraction and
radiation by the body and the ship (the cable and the body are small against the wave
length), and the slamming impulse of a body entering the water.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ship_motion.irregular import _REDUCE_MAX as REDUCE_MAX, _sincos as sincos

from ..jit.kernel_cache import njit
from ..scene.model import Scene
from .water import WaterModel, flow

#: Depth factor below which a component is left out of the sum at a point [-]
CUTOFF = 1e-4
#: ``[water] stretching`` names and their codes
STRETCH_WHEELER = 0
STRETCH_EXTRAPOLATION = 1
STRETCHINGS = {"wheeler": STRETCH_WHEELER, "extrapolation": STRETCH_EXTRAPOLATION}
#: Columns of the component table: amplitude [m], wave number k [1/m], direction cos mu
#: and sin mu, frequency omega [rad/s], encounter frequency omega_e [rad/s], phase [rad],
#: exp(-2 k h) and 1 / (1 - exp(-2 k h)) (0 and 1 in deep water)
A, K, CX, CY, OMEGA, OMEGA_E, PHASE, E2, NORM = range(9)
COLUMNS = 9
#: Layout of the output of :func:`wave_at`: elevation eta [m], its slopes d eta/dx and
#: d eta/dy [-], velocity (3) [m/s], acceleration (3) [m/s^2], then (with gradients) the
#: velocity's and the acceleration's derivatives d(.)_c/dx_m, row-major (9 each)
ETA, ETA_X, ETA_Y, VEL, ACC, DVEL, DACC = 0, 1, 2, 3, 6, 9, 18
OUT_SIZE = 27
#: Accumulators per output quantity (velocity 3 + acceleration 3): value, z-slope,
#: x- and y-derivatives of both
_ACC_SIZE = 36


def dispersion(omega: np.ndarray, depth: float | None, gravity: float) -> np.ndarray:
    """Wave numbers k [1/m] of the frequencies ``omega`` [rad/s]: ``omega^2 = g k tanh(k h)``
    (Newton's method on ``x tanh x = omega^2 h / g``, x = k h, from Eckart's approximation, to
    round-off); ``depth`` None: deep water, ``k = omega^2 / g``."""
    omega = np.asarray(omega, dtype=float)
    if depth is None:
        return omega ** 2 / gravity
    alpha = omega ** 2 * depth / gravity
    x = alpha / np.sqrt(np.tanh(alpha))
    for _ in range(50):
        th = np.tanh(x)
        step = (x * th - alpha) / (th + x * (1.0 - th ** 2))
        x = x - step
        if np.all(np.abs(step) <= 1e-14 * x):
            return x / depth
    raise ArithmeticError(f"the dispersion relation did not converge for depth {depth} m")


def component_table(omega: np.ndarray, amplitude: np.ndarray, phase: np.ndarray, heading: np.ndarray,
                    omega_e: np.ndarray | None, speed: float, depth: float | None,
                    gravity: float) -> np.ndarray:
    """The kernels' table (n, :data:`COLUMNS`) of wave components, sorted by wave number.

    Parameters
    ----------
    omega, amplitude, phase, heading
        Frequencies [rad/s], amplitudes [m], phases [rad] and directions of travel
        relative to the ship's x axis [rad], shape (n,).
    omega_e
        Encounter frequencies [rad/s] (the ship's own, used in deep water); None: from k.
    speed
        The ship's speed U [m/s] along x.
    depth
        Water depth h [m]; None: deep water.
    gravity
        g [m/s^2].
    """
    k = dispersion(omega, depth, gravity)
    if omega_e is None or depth is not None:
        omega_e = omega - k * speed * np.cos(heading)
    e2 = np.zeros_like(k) if depth is None else np.exp(-2.0 * k * depth)
    table = np.column_stack([amplitude, k, np.cos(heading), np.sin(heading), omega, omega_e, phase, e2,
                             1.0 / (1.0 - e2)])
    return np.ascontiguousarray(table[np.argsort(k, kind="stable")])


def sea_of(scene: Scene):
    """The scene's irregular sea (:class:`ship_motion.irregular.IrregularSea`; the scene's
    validation has checked that ``[motion]`` is one)."""
    from ship_motion import motion_from_config

    base = Path(scene.base_dir) if scene.base_dir else None
    return motion_from_config(scene.motion, key="motion", base_dir=base)


def scene_waves(scene: Scene) -> tuple[np.ndarray, float, int, float]:
    """The scene's wave field for :class:`~towcable_fmu.hydro.water.WaterModel`: the component
    table, the depth [m] (inf: deep), the stretching code and the ramp time [s]; no
    components with ``waves = "off"``."""
    w = scene.water
    if w is None or w.waves == "off":
        return np.zeros((0, COLUMNS)), math.inf, STRETCH_WHEELER, 0.0
    sea = sea_of(scene)
    waves = sea.waves
    heading = np.full(waves.omega.size, sea.heading) if waves.heading is None else waves.heading
    table = component_table(waves.omega, waves.amplitude, waves.phase, heading, sea.encounter_frequency,
                            sea.speed, w.depth, scene.environment.gravity)
    return table, math.inf if w.depth is None else float(w.depth), STRETCHINGS[w.stretching], sea.ramp


@njit(cache=True, inline="always")
def ramp_factor(t: float, duration: float) -> tuple:
    """The motion's C2 ramp factor f(t) [-] and its rate [1/s] (1, 0 without a ramp)."""
    if duration <= 0.0 or t >= duration:
        return 1.0, 0.0
    x = max(t / duration, 0.0)
    return x ** 3 * (10.0 - 15.0 * x + 6.0 * x * x), 30.0 * x * x * (1.0 - x) ** 2 / duration


@njit(cache=True)
def crest_bound(table: np.ndarray) -> float:
    """The highest crest (and the deepest trough) the components can make, sum |a_i| [m]."""
    total = 0.0
    for i in range(table.shape[0]):
        total += abs(table[i, A])
    return total


@njit(cache=True, inline="always")
def _phases(table: np.ndarray, x: float, y: float, t: float, cs: np.ndarray, sn: np.ndarray) -> tuple:
    """The components' cos and sin of their phase at (x, y) [m] and time t [s], written to
    ``cs`` and ``sn``, and the elevation's sum and slopes without the ramp."""
    n = table.shape[0]
    largest = 0.0
    for i in range(n):
        th = table[i, OMEGA_E] * t - table[i, K] * (table[i, CX] * x + table[i, CY] * y) + table[i, PHASE]
        cs[i] = th
        largest = max(largest, abs(th))
    if largest < REDUCE_MAX:
        for i in range(n):  # (vectorised: no call, no branch)
            cs[i], sn[i] = sincos(cs[i])
    else:
        for i in range(n):
            th = cs[i]
            cs[i] = math.cos(th)
            sn[i] = math.sin(th)
    eta = 0.0
    ex = 0.0
    ey = 0.0
    for i in range(n):
        a, k = table[i, A], table[i, K]
        eta += a * cs[i]
        ex += a * k * table[i, CX] * sn[i]
        ey += a * k * table[i, CY] * sn[i]
    return eta, ex, ey


@njit(cache=True)
def elevation(table: np.ndarray, ramp: float, x: float, y: float, t: float) -> tuple:
    """Free-surface elevation above the mean level and its slopes at (x, y) [m] and time t [s]:
    ``(eta [m], d eta/dx, d eta/dy)``."""
    f0, f1 = ramp_factor(t, ramp)
    work = np.empty(2 * table.shape[0])
    eta, ex, ey = _phases(table, x, y, t, work[:table.shape[0]], work[table.shape[0]:])
    return f0 * eta, f0 * ex, f0 * ey


@njit(cache=True, inline="always")
def scratch_size(table: np.ndarray) -> int:
    """Length of the work array :func:`wave_at` needs."""
    return 2 * table.shape[0] + _ACC_SIZE


@njit(cache=True)
def wave_at(table: np.ndarray, depth: float, stretch: int, ramp: float, crest: float, x: float, y: float, z: float,
            t: float, gradients: bool, work: np.ndarray, out: np.ndarray) -> int:
    """Wave kinematics at the point (x, y, z) [m] (z from the mean level) and time t [s]
    (``crest``: :func:`crest_bound` of the table [m]).

    Writes :data:`OUT_SIZE` values to ``out`` (layout :data:`ETA` ...): the elevation and its
    slopes, the particle velocity [m/s] and the fluid's acceleration [m/s^2], and with
    ``gradients`` their derivatives with respect to the point [1/s, 1/s^2] (the stretched
    height's dependence on the point and on eta included). ``work``: at least
    ``2 n + 36`` floats. Returns the number of components summed for the kinematics
    (0: the point is out of every component's reach, all zero except eta, which is then
    not computed either and left 0)."""
    for j in range(OUT_SIZE):
        out[j] = 0.0
    n = table.shape[0]
    if n == 0:
        return 0
    deep = math.isinf(depth)
    top = crest
    # highest stretched height any elevation can give (Wheeler); for the reach test
    if stretch == STRETCH_WHEELER:
        z_hi = z + top if deep else depth * (z + top) / (depth - top) if depth > top else 0.0
    else:
        z_hi = z
    z_hi = min(z_hi, 0.0)
    k0 = table[0, K]
    if table[0, NORM] * (math.exp(k0 * z_hi) + table[0, E2] * math.exp(-k0 * z_hi)) < CUTOFF:
        return 0
    f0, f1 = ramp_factor(t, ramp)
    cs = work[:n]
    sn = work[n:2 * n]
    acc = work[2 * n:2 * n + _ACC_SIZE]
    eta, ex, ey = _phases(table, x, y, t, cs, sn)
    eta *= f0
    ex *= f0
    ey *= f0
    out[ETA] = eta
    out[ETA_X] = ex
    out[ETA_Y] = ey
    # the height of evaluation z_e <= 0, the extrapolated height above it, and their derivatives
    gx = 0.0
    gy = 0.0
    gz = 1.0
    dz_lin = 0.0
    if stretch == STRETCH_WHEELER:
        if deep:
            z_e = z - eta
            z_eta = -1.0
        else:
            lam = depth / (depth + eta)
            z_e = lam * (z - eta)
            gz = lam
            z_eta = -lam * (depth + z) / (depth + eta)
        gx = z_eta * ex
        gy = z_eta * ey
        above = 0.0
    else:
        above = max(z, 0.0)
        z_e = min(z, 0.0)
        if above > 0.0:
            gz = 0.0
            dz_lin = 1.0
    for j in range(_ACC_SIZE):
        acc[j] = 0.0
    used = 0
    for i in range(n):
        k = table[i, K]
        e = math.exp(k * z_e)
        if deep:
            ch = e
            sh = e
        else:
            far = table[i, E2] / e
            ch = table[i, NORM] * (e + far)
            sh = table[i, NORM] * (e - far)
        if ch < CUTOFF:
            break
        used += 1
        c = cs[i]
        s = sn[i]
        q = table[i, A] * table[i, OMEGA]
        w = table[i, OMEGA]
        dx = table[i, CX]
        dy = table[i, CY]
        # value: u = q (C c dx, C c dy, -S s); a = q w (-C s dx, -C s dy, -S c)
        acc[0] += q * ch * c * dx
        acc[1] += q * ch * c * dy
        acc[2] -= q * sh * s
        acc[3] -= q * w * ch * s * dx
        acc[4] -= q * w * ch * s * dy
        acc[5] -= q * w * sh * c
        if gradients or above > 0.0:  # z-slope: C' = k S, S' = k C
            qk = q * k
            acc[6] += qk * sh * c * dx
            acc[7] += qk * sh * c * dy
            acc[8] -= qk * ch * s
            acc[9] -= qk * w * sh * s * dx
            acc[10] -= qk * w * sh * s * dy
            acc[11] -= qk * w * ch * c
        if gradients:  # horizontal derivatives (d theta/dx_m = -k_m) of the value and of the z-slope
            for m in range(2):
                km = k * (dx if m == 0 else dy)
                b = 12 + 12 * m
                acc[b + 0] += q * km * ch * s * dx
                acc[b + 1] += q * km * ch * s * dy
                acc[b + 2] += q * km * sh * c
                acc[b + 3] += q * w * km * ch * c * dx
                acc[b + 4] += q * w * km * ch * c * dy
                acc[b + 5] -= q * w * km * sh * s
                acc[b + 6] += q * k * km * sh * s * dx
                acc[b + 7] += q * k * km * sh * s * dy
                acc[b + 8] += q * k * km * ch * c
                acc[b + 9] += q * w * k * km * sh * c * dx
                acc[b + 10] += q * w * k * km * sh * c * dy
                acc[b + 11] -= q * w * k * km * ch * s
    for c3 in range(3):
        uv = acc[c3] + above * acc[6 + c3]
        av = acc[3 + c3] + above * acc[9 + c3]
        out[VEL + c3] = f0 * uv
        out[ACC + c3] = f0 * av + f1 * uv
    if gradients:
        g = (gx, gy, gz)
        for c6 in range(6):
            for m in range(3):
                d = acc[6 + c6] * (g[m] + (dz_lin if m == 2 else 0.0))
                if m < 2:
                    b = 12 + 12 * m
                    d += acc[b + c6] + above * acc[b + 6 + c6]
                if c6 < 3:
                    out[DVEL + 3 * c6 + m] += f0 * d
                    out[DACC + 3 * c6 + m] += f1 * d
                else:
                    out[DACC + 3 * (c6 - 3) + m] += f0 * d
    return used


@njit(cache=True, inline="always")
def near(out: np.ndarray, dx: float, dy: float, dz: float) -> tuple:
    """The velocity [m/s] and acceleration [m/s^2] (6-tuple) at a displacement (dx, dy, dz)
    [m] from the point of :func:`wave_at`'s output ``out`` (with gradients), to first order:
    ``u + du/dr d``; the error is at most ``|d|^2 / 2`` times the largest second derivative."""
    return (out[VEL] + out[DVEL] * dx + out[DVEL + 1] * dy + out[DVEL + 2] * dz,
            out[VEL + 1] + out[DVEL + 3] * dx + out[DVEL + 4] * dy + out[DVEL + 5] * dz,
            out[VEL + 2] + out[DVEL + 6] * dx + out[DVEL + 7] * dy + out[DVEL + 8] * dz,
            out[ACC] + out[DACC] * dx + out[DACC + 1] * dy + out[DACC + 2] * dz,
            out[ACC + 1] + out[DACC + 3] * dx + out[DACC + 4] * dy + out[DACC + 5] * dz,
            out[ACC + 2] + out[DACC + 6] * dx + out[DACC + 7] * dy + out[DACC + 8] * dz)


@njit(cache=True, inline="always")
def water_waves(w: WaterModel, x: float, y: float, z: float, t: float, gradients: bool, work: np.ndarray,
                out: np.ndarray) -> int:
    """:func:`wave_at` for the water ``w`` at the point (x, y, z) [m] (z: height, not from
    the mean level)."""
    return wave_at(w.waves, w.wave_depth, w.wave_stretch, w.wave_ramp, w.wave_crest, x, y, z - w.surface_z, t,
                   gradients, work, out)


@njit(cache=True, inline="always")
def surface_height(w: WaterModel, x: float, y: float, t: float) -> tuple:
    """Height of the instantaneous free surface [m] and its slopes at (x, y) [m] and time t
    [s]: ``surface_z`` and zero slopes in still water."""
    if w.waves.shape[0] == 0:
        return w.surface_z, 0.0, 0.0
    eta, ex, ey = elevation(w.waves, w.wave_ramp, x, y, t)
    return w.surface_z + eta, ex, ey



@njit(cache=True)
def flow_at(w: WaterModel, r: np.ndarray, t: float, vf: np.ndarray, af: np.ndarray) -> None:
    """Flow velocity [m/s] and acceleration [m/s^2] at the point ``r`` (3,) [m] and time t
    [s], written to ``vf`` and ``af``: current, turbulence and waves (for a body's centre)."""
    flow(w, r[2], t, vf, af)
    if w.waves.shape[0] > 0:
        kin = np.empty(OUT_SIZE)
        water_waves(w, r[0], r[1], r[2], t, False, np.empty(scratch_size(w.waves)), kin)
        for k in range(3):
            vf[k] += kin[VEL + k]
            af[k] += kin[ACC + k]
