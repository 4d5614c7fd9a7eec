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

Cut-off: a component is summed at a point only above its reach, the depth below which
its velocity and acceleration amplitudes ``a_i omega_i C_i`` and ``a_i omega_i^2 C_i`` are
both below ``THRESHOLD / n`` of the sea's surface bounds ``sum a_j omega_j`` and
``sum a_j omega_j^2`` (n components): the components left out at a point add up to at most
:data:`THRESHOLD` of those bounds. The table is sorted by reach, so the sum at a point
stops at the first component out of reach, and a point below the reach of every component
skips the sum (and the elevation) altogether.

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

#: The most that the components left out at a point add to the velocity and the
#: acceleration, as a fraction of the sea's surface bounds sum a_i omega_i [m/s] and
#: sum a_i omega_i^2 [m/s^2] [-]
THRESHOLD = 1e-3
#: ``[water] stretching`` names and their codes
STRETCH_WHEELER = 0
STRETCH_EXTRAPOLATION = 1
STRETCHINGS = {"wheeler": STRETCH_WHEELER, "extrapolation": STRETCH_EXTRAPOLATION}
#: Columns of the component table: amplitude [m], wave number k [1/m], direction cos mu
#: and sin mu, frequency omega [rad/s], encounter frequency omega_e [rad/s], phase [rad],
#: exp(-2 k h) and 1 / (1 - exp(-2 k h)) (0 and 1 in deep water), the reach [m] (the height
#: from the mean level below which the component is left out; -inf: nowhere)
A, K, CX, CY, OMEGA, OMEGA_E, PHASE, E2, NORM, REACH = range(10)
COLUMNS = 10
#: Layout of the output of :func:`wave_at`: elevation eta [m], its slopes d eta/dx and
#: d eta/dy [-], velocity (3) [m/s], acceleration (3) [m/s^2], then (with gradients) the
#: velocity's and the acceleration's derivatives d(.)_c/dx_m, row-major (9 each)
ETA, ETA_X, ETA_Y, VEL, ACC, DVEL, DACC = 0, 1, 2, 3, 6, 9, 18
OUT_SIZE = 27


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
    """The kernels' table (n, :data:`COLUMNS`) of wave components, sorted by reach.

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
    norm = 1.0 / (1.0 - e2)
    reach = _reach(omega, np.abs(amplitude), k, e2, norm)
    table = np.column_stack([amplitude, k, np.cos(heading), np.sin(heading), omega, omega_e, phase, e2, norm, reach])
    return np.ascontiguousarray(table[np.argsort(reach, kind="stable")])


def _reach(omega: np.ndarray, amplitude: np.ndarray, k: np.ndarray, e2: np.ndarray, norm: np.ndarray) -> np.ndarray:
    """The components' reach [m] (:data:`REACH`): the height z where the depth factor
    ``C = norm (exp(k z) + e2 exp(-k z))`` falls to the largest value at which both the
    velocity and the acceleration amplitudes are below ``THRESHOLD / n`` of the sea's
    bounds; -inf where the factor stays above it down to the bottom, 0 where the component
    is below it at the surface already (never summed)."""
    speed, acceleration = amplitude * omega, amplitude * omega ** 2
    with np.errstate(divide="ignore"):
        limit = THRESHOLD / omega.size * np.minimum(np.sum(speed) / speed, np.sum(acceleration) / acceleration)
    # norm (u + e2 / u) = limit with u = exp(k z): the root above the bottom (u >= sqrt(e2))
    ratio = limit / norm
    disc = ratio ** 2 - 4.0 * e2
    with np.errstate(invalid="ignore", divide="ignore"):
        z = np.log(0.5 * (ratio + np.sqrt(np.maximum(disc, 0.0)))) / k
    return np.where(disc < 0.0, -np.inf, np.minimum(z, 0.0))


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
    return 2 * table.shape[0]


@njit(cache=True, inline="always")
def _depth_factors(table: np.ndarray, i: int, z: float, deep: bool) -> tuple:
    """Component i's depth factors C and S [-] at the height z <= 0 [m] from the mean level."""
    e = math.exp(table[i, K] * z)
    if deep:
        return e, e
    far = table[i, E2] / e
    return table[i, NORM] * (e + far), table[i, NORM] * (e - far)


@njit(cache=True)
def _sums(table: np.ndarray, used: int, z: float, deep: bool, slopes: bool, cs: np.ndarray, sn: np.ndarray) -> tuple:
    """The sums over the first ``used`` components at the height z <= 0 [m] (phases' cos and
    sin in ``cs``, ``sn``), without the ramp: the velocity (3) [m/s] and acceleration (3)
    [m/s^2], and with ``slopes`` the independent entries of their gradients (both are
    symmetric and trace-free in potential flow): d/dx of u_x, d/dy of u_x, d/dy of u_y,
    d/dz of u_x and u_y [1/s], then the same of the acceleration [1/s^2]."""
    ux = uy = uz = ax = ay = az = 0.0
    uxx = uxy = uyy = uxz = uyz = axx = axy = ayy = axz = ayz = 0.0
    for i in range(used):
        ch, sh = _depth_factors(table, i, z, deep)
        q = table[i, A] * table[i, OMEGA]
        w = table[i, OMEGA]
        dx = table[i, CX]
        dy = table[i, CY]
        qc = q * ch * cs[i]
        qs = q * ch * sn[i]
        rc = q * sh * cs[i]
        rs = q * sh * sn[i]
        # u = (C c dx, C c dy, -S s) q; a = (-C s dx, -C s dy, -S c) q w
        ux += dx * qc
        uy += dy * qc
        uz -= rs
        ax -= w * dx * qs
        ay -= w * dy * qs
        az -= w * rc
        if slopes:  # d theta/dx_m = -k d_m, C' = k S, S' = k C
            k = table[i, K]
            kqs = k * qs
            kqc = w * k * qc
            krc = k * rc
            krs = w * k * rs
            uxx += dx * dx * kqs
            uxy += dx * dy * kqs
            uyy += dy * dy * kqs
            uxz += dx * krc
            uyz += dy * krc
            axx += dx * dx * kqc
            axy += dx * dy * kqc
            ayy += dy * dy * kqc
            axz -= dx * krs
            ayz -= dy * krs
    return (ux, uy, uz, ax, ay, az), (uxx, uxy, uyy, uxz, uyz, axx, axy, ayy, axz, ayz)


@njit(cache=True)
def _slope_derivatives(table: np.ndarray, used: int, cs: np.ndarray, sn: np.ndarray) -> np.ndarray:
    """The horizontal derivatives d/dx_m of the z-slopes of the velocity and the
    acceleration at the mean level (rows m = x, y; columns u_x, u_y, u_z, a_x, a_y, a_z), the
    second derivatives linear extrapolation needs above the mean level."""
    d = np.zeros((2, 6))
    for i in range(used):
        ch, sh = _depth_factors(table, i, 0.0, False)
        q = table[i, A] * table[i, OMEGA]
        w = table[i, OMEGA]
        k = table[i, K]
        dx = table[i, CX]
        dy = table[i, CY]
        c = cs[i]
        s = sn[i]
        for m in range(2):
            qkk = q * k * k * (dx if m == 0 else dy)
            d[m, 0] += qkk * sh * s * dx
            d[m, 1] += qkk * sh * s * dy
            d[m, 2] += qkk * ch * c
            d[m, 3] += qkk * w * sh * c * dx
            d[m, 4] += qkk * w * sh * c * dy
            d[m, 5] -= qkk * w * ch * s
    return d


@njit(cache=True)
def wave_at(table: np.ndarray, depth: float, stretch: int, ramp: float, crest: float, x: float, y: float, z: float,
            t: float, gradients: bool, work: np.ndarray, out: np.ndarray) -> int:
    """Wave kinematics at the point (x, y, z) [m] (z from the mean level) and time t [s]
    (``crest``: :func:`crest_bound` of the table [m]).

    Writes :data:`OUT_SIZE` values to ``out`` (layout :data:`ETA` ...): the elevation and its
    slopes, the particle velocity [m/s] and the fluid's acceleration [m/s^2], and with
    ``gradients`` their derivatives with respect to the point [1/s, 1/s^2] (the stretched
    height's dependence on the point and on eta included). ``work``: at least
    ``2 n`` floats. Returns the number of components summed for the kinematics
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
    if not table[0, REACH] < min(z_hi, 0.0):
        return 0
    f0, f1 = ramp_factor(t, ramp)
    cs = work[:n]
    sn = work[n:2 * n]
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
    used = 0
    while used < n and table[used, REACH] < z_e:
        used += 1
    value, grad = _sums(table, used, z_e, deep, gradients or above > 0.0, cs, sn)
    uxx, uxy, uyy, uxz, uyz, axx, axy, ayy, axz, ayz = grad
    z_slope = (uxz, uyz, -uxx - uyy, axz, ayz, -axx - ayy)
    for c3 in range(3):
        uv = value[c3] + above * z_slope[c3]
        av = value[3 + c3] + above * z_slope[3 + c3]
        out[VEL + c3] = f0 * uv
        out[ACC + c3] = f0 * av + f1 * uv
    if gradients:
        g = (gx, gy, gz + dz_lin)
        horizontal = ((uxx, uxy, uxz, axx, axy, axz), (uxy, uyy, uyz, axy, ayy, ayz))
        second = _slope_derivatives(table, used, cs, sn) if above > 0.0 else np.zeros((2, 6))
        for c6 in range(6):
            for m in range(3):
                d = z_slope[c6] * g[m]
                if m < 2:
                    d += horizontal[m][c6] + above * second[m, c6]
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
