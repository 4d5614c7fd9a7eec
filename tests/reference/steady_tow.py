"""Independent steady-towing reference solver (shooting on the cable ODE).

This module does not use any code of ``towcable_fmu``.  It solves the static
equilibrium of a towed cable in a steady current with a lumped towed body at its
lower end, following the hydrodynamic model of Westin (2018), "W(n)" below,
with the corrections listed in ``docs/design.md`` ("Known errors in the references").

Frame: inertial, ``z`` up, gravity ``g = [0, 0, -g]``.  The waterline is the
plane ``z = z_waterline``; points with ``z > z_waterline`` are in air and get
no buoyancy and no drag.

Model
-----
``s`` is the *unstretched* arc length measured from the body (``s = 0``) to the
tow point (``s = L``).  ``T(s)`` is the tension vector: the force that the part
of the cable above ``s`` exerts on the part below it (so ``|T|`` is the
tension and ``T/|T|`` the unit tangent pointing up the cable).  Static
equilibrium and Hooke's law (engineering strain ``eps = |T|/EA``)::

    dT/ds = -f(s)
    dr/ds = (1 + |T|/EA) T/|T|

``f`` [N per metre of unstretched cable] is the sum of

* weight ``mu g`` (``mu`` mass per unstretched length),
* buoyancy ``-rho_f A g`` with ``A = pi d^2/4`` (W(57)), below the waterline only,
* drag (below the waterline only), W(58)-(65) with the docs/design.md corrections::

      V   = V_f(z) - r_dot = V_f(z)           (steady state, r_dot = 0)
      V_t = (V . u_t) u_t,   V_n = V - V_t     (W(59))
      eta = arccos(|V . u_t| / |V|)  in [0, pi/2]
      f_Dn = G * 0.5 rho_f d C_D(Re) |V|^2 f_n(eta) V_n/|V_n|
      f_Dt = G * 0.5 rho_f d C_D(Re) |V|^2 f_t(eta) V_t/|V_t|
      Re   = rho_f d |V_n| / mu                (W(63), normal velocity)

  i.e. the drag acts *along* the relative flow (W(58) has a spurious leading
  minus sign), the tangential part along ``V_t`` (W(58b)'s two sign factors
  cancel), and the total steady drag is ``G`` times the un-amplified drag
  (``G = 1``: no amplification; W(64)-(65) read literally would give
  ``1 + G``).

By default the loads are per metre of *unstretched* cable, as in the ANCF
element integrals ``int_0^L S^T f dp`` of W(70) over the reference length.
With ``stretch_loads=True`` buoyancy and drag are scaled by ``(1 + |T|/EA)``
(per metre of stretched cable, diameter unchanged); the weight is never scaled
(mass is conserved).

Towed body (lumped at ``s = 0``), W(86)-(87) in steady state, plus a constant
lift vector::

    F_b = (m_b - rho_f V_b) g  +  0.5 rho_f (C_D A)_i |V_i| V_i  (component-wise)  +  F_lift

evaluated with the current at the body depth (buoyancy, drag and lift only if
the body is below the waterline).  Body equilibrium gives ``T(0) = -F_b``.

Shooting: the body position ``r_b`` (3 unknowns) is found with
:func:`scipy.optimize.root` so that the integrated upper end ``r(L; r_b)``
lands on the tow point; the ODE is integrated with :func:`scipy.integrate.solve_ivp`
(DOP853, tight tolerances), segment by segment, and restarted at each
waterline crossing (located with an event function), so that the
discontinuous loads are never integrated across.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import integrate, optimize

__all__ = [
    "GRAVITY",
    "RE_FLOOR",
    "fn_bare",
    "ft_bare",
    "fn_faired",
    "ft_faired",
    "LOADING_FUNCTIONS",
    "drag_coefficient",
    "reynolds_number",
    "flow_angle",
    "cable_drag_per_length",
    "uniform_current",
    "flume_current_speed",
    "flume_current",
    "CableSegment",
    "TowedBody",
    "Water",
    "body_force",
    "cable_load_per_length",
    "SteadyTowResult",
    "solve_steady_tow",
    "full_scale_scene",
    "full_scale_case",
    "SPHERE_CD",
    "sphere_drag_coefficient",
    "flume_scene",
    "flume_case",
]

GRAVITY: float = 9.81
"""Gravitational acceleration [m/s^2] (W(57): g = [0, 0, -9.81])."""

RE_FLOOR: float = 1e-3
"""Smallest Reynolds number at which W(61) is evaluated [-].

W(61) diverges like ``8 pi / (Re ln(8/Re))`` as ``Re -> 0``; with ``Re`` based
on the *normal* velocity this happens for flow exactly along the cable, where
the tangential drag ``C_D |V|^2 f_t(0)`` would be infinite.  Evaluating
``C_D(max(Re, RE_FLOOR))`` keeps it finite (``C_D(1e-3) ~ 2.8e3``).  It only
matters where ``|V_n| < RE_FLOOR mu / (rho d)`` (1.2e-7 m/s for the 10 mm
cable): flow within a few 1e-8 rad of the cable axis."""

Vector = NDArray[np.float64]
LoadingSpec = Union[str, tuple[Callable[[float], float], Callable[[float], float]]]


# ---------------------------------------------------------------------------
# Loading functions and drag coefficient
# ---------------------------------------------------------------------------
def fn_bare(eta: ArrayLike) -> NDArray[np.float64]:
    """Normal loading function of a bare cable, W(60a) (Driscoll & Nahon).

    Parameters
    ----------
    eta : array_like
        Angle between the flow and the cable centreline [rad], in ``[0, pi/2]``.

    Returns
    -------
    ndarray
        ``0.5 - 0.1 cos(eta) + 0.1 sin(eta) - 0.4 cos(2 eta) - 0.11 sin(2 eta)`` [-]
        (0 at ``eta = 0``, 1 at ``eta = pi/2``; slightly negative below ~0.14 rad).
    """
    e = np.asarray(eta, dtype=float)
    return 0.5 - 0.1 * np.cos(e) + 0.1 * np.sin(e) - 0.4 * np.cos(2 * e) - 0.11 * np.sin(2 * e)


def ft_bare(eta: ArrayLike) -> NDArray[np.float64]:
    """Tangential loading function of a bare cable, W(60b).

    Parameters
    ----------
    eta : array_like
        Angle between the flow and the cable centreline [rad], in ``[0, pi/2]``.

    Returns
    -------
    ndarray
        ``0.01 (2.009 - 0.3858 eta + 1.9159 eta^2 - 4.1615 eta^3 + 3.5064 eta^4 - 1.1873 eta^5)`` [-].
    """
    e = np.asarray(eta, dtype=float)
    return 0.01 * (2.009 - 0.3858 * e + 1.9159 * e**2 - 4.1615 * e**3 + 3.5064 * e**4 - 1.1873 * e**5)


def fn_faired(eta: ArrayLike) -> NDArray[np.float64]:
    """Normal loading function of a ribbon-faired cable, W(145a).

    Parameters
    ----------
    eta : array_like
        Angle of attack between the flow and the cable [rad], in ``[0, pi/2]``.

    Returns
    -------
    ndarray
        ``0.498609 - 0.2499 cos(eta) + 0.2527 sin(eta) - 0.2487 cos(2 eta)`` [-].
    """
    e = np.asarray(eta, dtype=float)
    return 0.498609 - 0.2499 * np.cos(e) + 0.2527 * np.sin(e) - 0.2487 * np.cos(2 * e)


def ft_faired(eta: ArrayLike) -> NDArray[np.float64]:
    """Tangential loading function of a ribbon-faired cable, W(145b).

    W(145b) is printed as ``f_n``; it is the tangential function (docs/design.md).

    Parameters
    ----------
    eta : array_like
        Angle of attack between the flow and the cable [rad], in ``[0, pi/2]``.

    Returns
    -------
    ndarray
        ``-0.2255 + 0.3417 cos(eta) + 0.255 sin(eta) - 0.0811 sin(2 eta)`` [-].
    """
    e = np.asarray(eta, dtype=float)
    return -0.2255 + 0.3417 * np.cos(e) + 0.255 * np.sin(e) - 0.0811 * np.sin(2 * e)


LOADING_FUNCTIONS: dict[str, tuple[Callable[[ArrayLike], NDArray[np.float64]], Callable[[ArrayLike], NDArray[np.float64]]]] = {
    "bare": (fn_bare, ft_bare),
    "faired": (fn_faired, ft_faired),
}
"""Named ``(f_n, f_t)`` pairs: ``"bare"`` W(60), ``"faired"`` W(145)."""


def drag_coefficient(re: ArrayLike) -> NDArray[np.float64]:
    """Common cable drag coefficient ``C_D(Re)`` of Choo & Casarella, W(61)-(62).

    Parameters
    ----------
    re : array_like
        Reynolds number based on the normal relative velocity, W(63) [-].
        Values below :data:`RE_FLOOR` are raised to it; above ``1e5`` the
        third branch is extrapolated.

    Returns
    -------
    ndarray
        ``8 pi/(Re S) (1 - 0.87 S^-2)`` for ``Re <= 1`` with
        ``S = -0.077215665 + ln(8/Re)``; ``1.45 + 8.55 Re^-0.9`` for
        ``1 < Re < 30``; ``1.1 + 4 Re^-0.5`` for ``Re >= 30`` [-].
    """
    r = np.maximum(np.asarray(re, dtype=float), RE_FLOOR)
    S = -0.077215665 + np.log(8.0 / np.minimum(r, 1.0))
    low = 8.0 * np.pi / (r * S) * (1.0 - 0.87 / S**2)
    mid = 1.45 + 8.55 * r**-0.9
    high = 1.1 + 4.0 * r**-0.5
    return np.where(r <= 1.0, low, np.where(r < 30.0, mid, high))


def reynolds_number(rho: float, d: float, vn: float, mu: float) -> float:
    """Cable Reynolds number W(63), ``rho d |V_n| / mu`` [-].

    Parameters
    ----------
    rho : float
        Fluid density [kg/m^3].
    d : float
        Cable diameter [m].
    vn : float
        Magnitude of the normal relative velocity [m/s].
    mu : float
        Dynamic viscosity [Pa s].
    """
    return float(rho * d * abs(vn) / mu)


def flow_angle(v: ArrayLike, tangent: ArrayLike) -> float:
    """Angle ``eta`` between the flow and the cable axis, folded into ``[0, pi/2]`` [rad].

    Parameters
    ----------
    v : array_like, shape (3,)
        Relative flow velocity [m/s] (non-zero).
    tangent : array_like, shape (3,)
        Cable tangent (any length, either sense).
    """
    v = np.asarray(v, dtype=float)
    t = np.asarray(tangent, dtype=float)
    c = abs(float(v @ t)) / (np.linalg.norm(v) * np.linalg.norm(t))
    return float(np.arccos(min(c, 1.0)))


def cable_drag_per_length(
    v: ArrayLike,
    tangent: ArrayLike,
    d: float,
    rho: float,
    mu: float,
    loading: LoadingSpec = "bare",
    G: float = 1.0,
    cd: float | None = None,
) -> Vector:
    """Steady drag force per unit length on a cable element [N/m].

    ``f = G * 0.5 rho d C_D |V|^2 (f_n(eta) V_n/|V_n| + f_t(eta) V_t/|V_t|)``,
    W(58)-(65) with the docs/design.md corrections (drag along the relative flow,
    ``eta`` folded into ``[0, pi/2]``, total drag ``G`` times the steady drag).

    Parameters
    ----------
    v : array_like, shape (3,)
        Relative flow velocity ``V = V_f - r_dot`` [m/s].
    tangent : array_like, shape (3,)
        Cable tangent (any length, either sense; the result does not depend on its sense).
    d : float
        Cable diameter [m].
    rho : float
        Fluid density [kg/m^3].
    mu : float
        Dynamic viscosity [Pa s].
    loading : {"bare", "faired"} or (f_n, f_t) tuple of callables
        Loading functions of ``eta`` [rad].
    G : float, optional
        Drag amplification factor [-] (total drag = ``G`` x steady drag).
    cd : float or None, optional
        Constant drag coefficient; ``None`` uses :func:`drag_coefficient` of
        the normal Reynolds number for the normal term (W(63)) and of the full
        relative speed for the tangential term (the normal Reynolds number
        vanishes for flow along the cable, where f_t stays finite).

    Returns
    -------
    ndarray, shape (3,)
        Drag force per unit length [N/m].  Zero if ``|V| = 0``; the normal
        (tangential) part is zero when ``|V_n|`` (``|V_t|``) is below
        ``1e-12 |V|`` (its direction is undefined there).
    """
    v = np.asarray(v, dtype=float)
    vmag = float(np.linalg.norm(v))
    out = np.zeros(3)
    if vmag == 0.0:
        return out
    t = np.asarray(tangent, dtype=float)
    u = t / np.linalg.norm(t)
    vt = float(v @ u) * u
    vn = v - vt
    vn_mag = float(np.linalg.norm(vn))
    vt_mag = float(np.linalg.norm(vt))
    eta = float(np.arccos(min(abs(float(v @ u)) / vmag, 1.0)))
    fn, ft = LOADING_FUNCTIONS[loading] if isinstance(loading, str) else loading
    # normal term: C_D of the normal Reynolds number, W(63); tangential term: C_D of the
    # Reynolds number of the full relative speed (the normal one vanishes for axial flow)
    c_n = float(drag_coefficient(rho * d * vn_mag / mu)) if cd is None else float(cd)
    c_t = float(drag_coefficient(rho * d * vmag / mu)) if cd is None else float(cd)
    q = G * 0.5 * rho * d * vmag * vmag
    tiny = 1e-12 * vmag
    if vn_mag > tiny:
        out += q * c_n * float(fn(eta)) * vn / vn_mag
    if vt_mag > tiny:
        out += q * c_t * float(ft(eta)) * vt / vt_mag
    return out


# ---------------------------------------------------------------------------
# Currents
# ---------------------------------------------------------------------------
def uniform_current(v: ArrayLike) -> Callable[[float], Vector]:
    """Depth-independent current ``V_f(z) = v`` [m/s].

    Parameters
    ----------
    v : array_like, shape (3,)
        Flow velocity [m/s], e.g. ``[-2.2, 0, 0]``.
    """
    vv = np.asarray(v, dtype=float).copy()

    def current(z: float) -> Vector:
        return vv

    return current


def flume_current_speed(z: ArrayLike, z_waterline: float) -> NDArray[np.float64]:
    """Mean flume flow velocity of W(140) [m/s].

    ``V_f = -0.5873 (z - z_WL) - 0.3302`` (the x-component; negative: along ``-x``).

    Parameters
    ----------
    z : array_like
        Height in the inertial frame [m].
    z_waterline : float
        Height of the waterline [m] (``-0.46`` in the flume frame whose origin
        is the top of the winch).

    Notes
    -----
    Linear fit of measured points: ``-0.330 m/s`` at the surface, magnitude
    decreasing with depth and crossing zero 0.562 m below the waterline (the
    fit is used as is, without clipping).
    """
    z = np.asarray(z, dtype=float)
    return -0.5873 * (z - z_waterline) - 0.3302


def flume_current(z_waterline: float) -> Callable[[float], Vector]:
    """Current ``V_f(z) = [W(140)(z), 0, 0]`` [m/s] of the flume experiment.

    Parameters
    ----------
    z_waterline : float
        Height of the waterline [m].
    """

    def current(z: float) -> Vector:
        return np.array([float(flume_current_speed(z, z_waterline)), 0.0, 0.0])

    return current


# ---------------------------------------------------------------------------
# Scene description
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class CableSegment:
    """A uniform cable segment.

    Attributes
    ----------
    length : float
        Unstretched length [m].
    diameter : float
        Hydrodynamic (and buoyancy) diameter ``d`` [m]; ``A = pi d^2/4``.
    mass_per_length : float
        Mass per unstretched length ``mu`` [kg/m].
    EA : float
        Axial stiffness [N].
    loading : {"bare", "faired"} or (f_n, f_t) tuple of callables
        Loading functions.
    G : float
        Drag amplification factor [-] (``1``: none).
    cd : float or None
        Constant drag coefficient, or ``None`` for ``C_D(Re)`` of W(61).
    name : str
        Label.
    """

    length: float
    diameter: float
    mass_per_length: float
    EA: float
    loading: LoadingSpec = "bare"
    G: float = 1.0
    cd: float | None = None
    name: str = ""

    @property
    def area(self) -> float:
        """Cross-section ``pi d^2 / 4`` [m^2]."""
        return float(np.pi * self.diameter**2 / 4.0)


@dataclass(frozen=True)
class TowedBody:
    """Lumped towed body (W(86)-(87) in steady state, plus a constant lift).

    Attributes
    ----------
    mass : float
        Mass ``m_b`` [kg].
    volume : float
        Displaced volume ``V_b`` [m^3].
    cd_area : tuple of 3 floats
        ``(C_D A)_i`` for flow along x, y, z [m^2] (sum over the parts of the body).
    lift : tuple of 3 floats
        Constant lift force [N] (applied only when the body is submerged).
    """

    mass: float
    volume: float
    cd_area: tuple[float, float, float] = (0.0, 0.0, 0.0)
    lift: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Water:
    """Fluid and environment.

    Attributes
    ----------
    rho : float
        Water density [kg/m^3].
    mu : float
        Dynamic viscosity [Pa s].
    current : callable or array_like
        ``V_f(z)`` [m/s] as a function of height, or a constant 3-vector.
    z_waterline : float
        Height of the free surface [m]; above it: air, no buoyancy, no drag.
    g : float
        Gravitational acceleration [m/s^2].
    """

    rho: float = 1026.0
    mu: float = 1.2e-3
    current: Callable[[float], Vector] | ArrayLike = (0.0, 0.0, 0.0)
    z_waterline: float = 0.0
    g: float = GRAVITY

    def velocity(self, z: float) -> Vector:
        """Flow velocity at height ``z`` [m/s]."""
        if callable(self.current):
            return np.asarray(self.current(z), dtype=float)
        return np.asarray(self.current, dtype=float)


def body_force(body: TowedBody, water: Water, position: ArrayLike) -> Vector:
    """Total steady external force on the towed body [N] (excluding the cable).

    Parameters
    ----------
    body : TowedBody
    water : Water
    position : array_like, shape (3,)
        Body position [m]; hydrodynamic terms only if ``z < z_waterline``.

    Returns
    -------
    ndarray, shape (3,)
        ``(m g - rho V g) e_z_down + 0.5 rho (C_D A)_i |V_i| V_i + lift``.
    """
    z = float(position[2])
    f = np.array([0.0, 0.0, -body.mass * water.g])
    if z < water.z_waterline:
        f[2] += water.rho * body.volume * water.g
        v = water.velocity(z)  # body at rest: V_rel = V_f
        f += 0.5 * water.rho * np.asarray(body.cd_area, dtype=float) * np.abs(v) * v
        f += np.asarray(body.lift, dtype=float)
    return f


def cable_load_per_length(
    position: ArrayLike,
    tension: ArrayLike,
    segment: CableSegment,
    water: Water,
    submerged: bool | None = None,
    stretch_loads: bool = False,
) -> Vector:
    """Distributed load ``f`` per unit unstretched length on the cable [N/m].

    Parameters
    ----------
    position : array_like, shape (3,)
        Point on the cable [m].
    tension : array_like, shape (3,)
        Tension vector there [N] (gives the tangent and the strain).
    segment : CableSegment
    water : Water
    submerged : bool or None
        Force the wet/dry state (used by the integrator at the waterline);
        ``None``: ``z < z_waterline``.
    stretch_loads : bool
        Scale buoyancy and drag by ``1 + |T|/EA`` (per stretched length).

    Returns
    -------
    ndarray, shape (3,)
        Weight + buoyancy + steady drag [N/m].
    """
    r = np.asarray(position, dtype=float)
    T = np.asarray(tension, dtype=float)
    wet = (r[2] < water.z_waterline) if submerged is None else submerged
    f = np.array([0.0, 0.0, -segment.mass_per_length * water.g])
    if not wet:
        return f
    Tm = float(np.linalg.norm(T))
    scale = 1.0 + Tm / segment.EA if stretch_loads else 1.0
    hyd = np.array([0.0, 0.0, water.rho * segment.area * water.g])
    hyd += cable_drag_per_length(
        water.velocity(r[2]), T, segment.diameter, water.rho, water.mu,
        loading=segment.loading, G=segment.G, cd=segment.cd,
    )
    return f + scale * hyd


# ---------------------------------------------------------------------------
# Result and solver
# ---------------------------------------------------------------------------
@dataclass
class SteadyTowResult:
    """Steady towing equilibrium.

    Arc length ``s`` is the unstretched length measured from the body
    (``s = 0``) to the tow point (``s = L``).

    Attributes
    ----------
    body_position : ndarray, shape (3,)
        Position of the towed body (lower cable end) [m].
    body_force : ndarray, shape (3,)
        External force on the body (weight, buoyancy, drag, lift) [N].
    tension_body_vector : ndarray, shape (3,)
        ``T(0) = -body_force``: force of the cable on the body [N].
    tension_body : float
        ``|T(0)|`` [N].
    tension_top_vector : ndarray, shape (3,)
        ``T(L)``: force of the tow point on the cable [N] (the cable pulls the
        tow point with ``-T(L)``).
    tension_top : float
        ``|T(L)|`` [N].
    top_angle : float
        Angle of the cable at the tow point from the vertical,
        ``arccos(T_z(L)/|T(L)|)`` [rad].
    s : ndarray, shape (n,)
        Unstretched arc length from the body [m] (piece ends included; a
        waterline crossing appears twice, once per piece).
    r : ndarray, shape (n, 3)
        Cable shape ``r(s)`` [m].
    T : ndarray, shape (n, 3)
        Tension vector ``T(s)`` [N].
    submerged : ndarray of bool, shape (n,)
        Wet/dry state of the integration piece each sample belongs to.
    segment_index : ndarray of int, shape (n,)
        Index (into ``segments``, top-to-bottom order) of each sample's segment.
    waterline_s : list of float
        Arc lengths of the waterline crossings [m].
    residual : float
        ``|r(L) - tow_point|`` after the shooting [m].
    segments, body, water, tow_point, stretch_loads
        The inputs.
    pieces : list
        ``(s_start, s_end, OdeSolution, segment_index, submerged)`` for dense evaluation.
    """

    body_position: Vector
    body_force: Vector
    tension_body_vector: Vector
    tension_body: float
    tension_top_vector: Vector
    tension_top: float
    top_angle: float
    s: Vector
    r: NDArray[np.float64]
    T: NDArray[np.float64]
    submerged: NDArray[np.bool_]
    segment_index: NDArray[np.int_]
    waterline_s: list[float]
    residual: float
    segments: list[CableSegment]
    body: TowedBody
    water: Water
    tow_point: Vector
    stretch_loads: bool
    pieces: list = field(repr=False, default_factory=list)

    @property
    def tension(self) -> Vector:
        """Tension magnitude ``|T(s)|`` at the samples [N]."""
        return np.linalg.norm(self.T, axis=1)

    @property
    def length(self) -> float:
        """Total unstretched cable length [m]."""
        return float(sum(seg.length for seg in self.segments))

    @property
    def top_angle_deg(self) -> float:
        """:attr:`top_angle` in degrees."""
        return float(np.degrees(self.top_angle))

    @property
    def body_depth(self) -> float:
        """Depth of the body below the waterline [m]."""
        return float(self.water.z_waterline - self.body_position[2])

    def state_at(self, s: float) -> tuple[Vector, Vector]:
        """Dense-output ``(r(s), T(s))`` at unstretched arc length ``s`` from the body."""
        for s0, s1, sol, _, _ in self.pieces:
            if s0 - 1e-12 <= s <= s1 + 1e-12:
                y = sol(s)
                return y[:3].copy(), y[3:].copy()
        raise ValueError(f"s = {s} outside [0, {self.length}]")


def _segments_from_body(segments: Sequence[CableSegment]) -> list[tuple[int, CableSegment]]:
    """Segments are given top (tow point) first; integrate from the body up."""
    return list(reversed(list(enumerate(segments))))


def _integrate_cable(
    r_b: Vector,
    segments: Sequence[CableSegment],
    body: TowedBody,
    water: Water,
    rtol: float,
    stretch_loads: bool,
    dense: bool,
    max_nfev: int = 200_000,
) -> tuple[Vector, list]:
    """Integrate the cable ODE from the body at ``r_b`` to the top; return the top state and pieces."""
    F_b = body_force(body, water, r_b)
    T0 = -F_b
    L = float(sum(seg.length for seg in segments))
    T_scale = float(np.linalg.norm(T0)) + sum(
        (seg.mass_per_length + water.rho * seg.area) * water.g * seg.length for seg in segments
    )
    atol = np.r_[np.full(3, rtol * L), np.full(3, rtol * max(T_scale, 1e-300))]
    y = np.r_[np.asarray(r_b, dtype=float), T0]
    zwl = water.z_waterline
    wet = bool(y[2] < zwl or (y[2] == zwl and T0[2] < 0.0))
    s0 = 0.0
    pieces: list = []
    nfev = [0]
    for idx, seg in _segments_from_body(segments):
        s_end = s0 + seg.length
        guard = 0
        while s0 < s_end:
            guard += 1
            if guard > 1000:
                raise RuntimeError("too many waterline crossings")

            def rhs(s: float, yy: Vector, seg: CableSegment = seg, wet: bool = wet) -> Vector:
                nfev[0] += 1
                if nfev[0] > max_nfev:
                    raise RuntimeError(
                        f"cable integration exceeded {max_nfev} load evaluations (unstable or "
                        "ill-posed steady state?)")
                T = yy[3:]
                Tm = np.sqrt(T @ T)
                if not Tm > 1e-12 * T_scale:
                    raise RuntimeError(f"cable goes slack at s = {s:.6g} m: no steady taut solution")
                dr = (1.0 + Tm / seg.EA) * T / Tm
                f = cable_load_per_length(yy[:3], T, seg, water, submerged=wet, stretch_loads=stretch_loads)
                return np.r_[dr, -f]

            def crossing(s: float, yy: Vector) -> float:
                return yy[2] - zwl

            crossing.terminal = True  # type: ignore[attr-defined]
            crossing.direction = 1.0 if wet else -1.0  # type: ignore[attr-defined]
            sol = integrate.solve_ivp(
                rhs, (s0, s_end), y, method="DOP853", rtol=rtol, atol=atol,
                events=crossing, dense_output=dense,
            )
            if sol.status < 0:
                raise RuntimeError(f"cable integration failed: {sol.message}")
            if sol.status == 1 and sol.t_events[0].size:
                s_hit = float(sol.t_events[0][0])
                y_hit = sol.y_events[0][0].copy()
                y_hit[2] = zwl
                pieces.append((s0, s_hit, sol.sol, idx, wet, True))
                s0, y, wet = s_hit, y_hit, not wet
            else:
                pieces.append((s0, s_end, sol.sol, idx, wet, False))
                s0, y = s_end, sol.y[:, -1].copy()
        s0 = s_end
    return y, pieces


def solve_steady_tow(
    segments: Sequence[CableSegment],
    body: TowedBody,
    water: Water,
    tow_point: ArrayLike,
    rtol: float = 1e-10,
    stretch_loads: bool = False,
    n_out: int = 2001,
    initial_body_position: ArrayLike | None = None,
) -> SteadyTowResult:
    """Steady equilibrium of a towed cable with a body, by shooting.

    Parameters
    ----------
    segments : sequence of CableSegment
        Cable segments ordered **from the tow point down to the body**.
    body : TowedBody
        Lumped body at the lower end.
    water : Water
        Density, viscosity, current ``V_f(z)``, waterline, gravity.
    tow_point : array_like, shape (3,)
        Fixed upper end of the cable [m].
    rtol : float, optional
        Relative tolerance of the ODE integration (absolute tolerances are
        ``rtol`` times the cable length and times a tension scale); the
        shooting is solved to ``~rtol * L``.
    stretch_loads : bool, optional
        Apply buoyancy and drag per stretched (instead of unstretched) length.
    n_out : int, optional
        Approximate number of output samples along the cable.
    initial_body_position : array_like, optional
        Starting guess; default: hanging straight below the tow point.

    Returns
    -------
    SteadyTowResult

    Raises
    ------
    RuntimeError
        If the shooting does not land on the tow point within ``1e3 rtol L``
        (at least 1e-7 m).
    """
    segs = list(segments)
    if not segs:
        raise ValueError("need at least one cable segment")
    top = np.asarray(tow_point, dtype=float)
    L = float(sum(seg.length for seg in segs))

    def miss(r_b: Vector) -> Vector:
        y, _ = _integrate_cable(r_b, segs, body, water, rtol, stretch_loads, dense=False)
        return y[:3] - top

    r_b = top - np.array([0.0, 0.0, L]) if initial_body_position is None else np.asarray(initial_body_position, float)
    # fixed-point iterations r_b <- r_b - miss(r_b): exact in one step when the
    # loads do not depend on the body position (uniform current, no waterline
    # crossing change); a good start for the Newton-type solve otherwise.
    for _ in range(20):
        m = miss(r_b)
        r_b = r_b - m
        if np.linalg.norm(m) < 1e-3 * L:
            break
    sol = optimize.root(lambda q: miss(q) / L, r_b, method="hybr",
                        options={"xtol": max(rtol, 1e-13), "maxfev": 400})
    r_b = np.asarray(sol.x, dtype=float)
    # polish: a few fixed-point / secant steps (root's xtol is relative)
    for _ in range(5):
        m = miss(r_b)
        if np.linalg.norm(m) <= rtol * L:
            break
        r_b = r_b - m
    y_top, pieces = _integrate_cable(r_b, segs, body, water, rtol, stretch_loads, dense=True)
    residual = float(np.linalg.norm(y_top[:3] - top))
    if residual > max(1e3 * rtol * L, 1e-7):
        raise RuntimeError(f"steady-tow shooting did not converge: miss {residual:.3e} m")

    s_all, y_all, wet_all, seg_all = [], [], [], []
    wl = []
    out_pieces = []
    for s0, s1, dsol, idx, wet, hit in pieces:
        n = max(8, int(np.ceil(n_out * (s1 - s0) / L)))
        ss = np.linspace(s0, s1, n)
        yy = dsol(ss)
        s_all.append(ss)
        y_all.append(yy.T)
        wet_all.append(np.full(n, wet))
        seg_all.append(np.full(n, idx))
        if hit:
            wl.append(float(s1))
        out_pieces.append((s0, s1, dsol, idx, wet))
    s = np.concatenate(s_all)
    Y = np.vstack(y_all)
    F_b = body_force(body, water, r_b)
    T_top = y_top[3:].copy()
    Tt = float(np.linalg.norm(T_top))
    return SteadyTowResult(
        body_position=r_b,
        body_force=F_b,
        tension_body_vector=-F_b,
        tension_body=float(np.linalg.norm(F_b)),
        tension_top_vector=T_top,
        tension_top=Tt,
        top_angle=float(np.arccos(np.clip(T_top[2] / Tt, -1.0, 1.0))),
        s=s,
        r=Y[:, :3],
        T=Y[:, 3:],
        submerged=np.concatenate(wet_all),
        segment_index=np.concatenate(seg_all),
        waterline_s=wl,
        residual=residual,
        segments=segs,
        body=body,
        water=water,
        tow_point=top,
        stretch_loads=stretch_loads,
        pieces=out_pieces,
    )


# ---------------------------------------------------------------------------
# The two reference scenes of the thesis
# ---------------------------------------------------------------------------
def full_scale_scene(
    tow_point: ArrayLike = (0.0, 0.0, 3.4),
    rho: float = 1026.0,
    mu: float = 1.2e-3,
    G: float = 3.54,
    lift: float | None = None,
    g: float = GRAVITY,
) -> tuple[list[CableSegment], TowedBody, Water, Vector]:
    """Full-scale case of W section 5 (Table 8, sections 5.1-5.2).

    * cable 450 m, d = 10 mm, 0.389 kg/m, EA = 117 GPa x 5.8e-5 m^2 = 6.786e6 N;
      top 300 m bare (W(60)), lowest 150 m ribbon-faired (W(145), 145b as f_t),
      ``G = 3.54`` on both;
    * water: rho = 1026 kg/m^3 (Table 3 value, also used here), mu = 1.2e-3 Pa s,
      uniform current [-2.2, 0, 0] m/s, waterline z = 0;
    * body: 250 kg, net weight 445 N in water (volume chosen so that
      ``(250 - rho V) g = 445 N``); cylinder d = 0.3 m, 3 m along x
      (C_D 0.85 on pi 0.15^2 m^2 axially; C_D 1.0 on 0.3 x 3 m^2 along y and
      z) plus hydrofoil 0.5 m^2 (C_D 0.008 along x, 1.17 along z, 0 along y);
      lift ``0.5 rho |V_f|^2 0.5 m^2 0.6`` downward = 744.9 N (docs/design.md: use
      the coefficient; the thesis quotes 722 N);
    * tow point: the top of the winch, ship-frame (-28.8, 0, 3.1 + 0.3) with the
      ship at rest at the origin -> z = 3.4 m; default x = y = 0.

    Parameters
    ----------
    tow_point : array_like, shape (3,)
        Pin point of the cable top [m].
    rho : float
        Water density [kg/m^3].
    mu : float
        Dynamic viscosity [Pa s].
    G : float
        Drag amplification of both cable segments [-].
    lift : float or None
        Downward lift magnitude [N]; ``None``: from the lift coefficient (744.9 N).
    g : float
        Gravity [m/s^2].

    Returns
    -------
    segments, body, water, tow_point
    """
    v = np.array([-2.2, 0.0, 0.0])
    d = 0.010
    EA = 117e9 * 5.8e-5
    segs = [
        CableSegment(300.0, d, 0.389, EA, "bare", G, None, "bare"),
        CableSegment(150.0, d, 0.389, EA, "faired", G, None, "faired"),
    ]
    m_b = 250.0
    net_weight = 445.0
    volume = (m_b * g - net_weight) / (rho * g)
    a_cyl_x = np.pi * 0.15**2
    a_cyl_side = 0.3 * 3.0
    a_foil = 0.5
    cd_area = (
        0.85 * a_cyl_x + 0.008 * a_foil,
        1.0 * a_cyl_side + 0.0 * a_foil,
        1.0 * a_cyl_side + 1.17 * a_foil,
    )
    lift_mag = 0.5 * rho * float(v @ v) * a_foil * 0.6 if lift is None else float(lift)
    body = TowedBody(mass=m_b, volume=volume, cd_area=cd_area, lift=(0.0, 0.0, -lift_mag))
    water = Water(rho=rho, mu=mu, current=uniform_current(v), z_waterline=0.0, g=g)
    return segs, body, water, np.asarray(tow_point, dtype=float)


def full_scale_case(
    tow_point: ArrayLike = (0.0, 0.0, 3.4),
    rho: float = 1026.0,
    mu: float = 1.2e-3,
    G: float = 3.54,
    lift: float | None = None,
    rtol: float = 1e-10,
    stretch_loads: bool = False,
) -> SteadyTowResult:
    """Solve the full-scale steady tow (see :func:`full_scale_scene`).

    Parameters
    ----------
    tow_point, rho, mu, G, lift
        As in :func:`full_scale_scene`.
    rtol : float
        ODE tolerance.
    stretch_loads : bool
        Loads per stretched length (default: per unstretched length).

    Returns
    -------
    SteadyTowResult
    """
    segs, body, water, top = full_scale_scene(tow_point, rho, mu, G, lift)
    return solve_steady_tow(segs, body, water, top, rtol=rtol, stretch_loads=stretch_loads)


SPHERE_CD: float = 0.45
"""Drag coefficient of the flume sphere [-].

Standard drag curve of a smooth sphere at the steady-state sphere Reynolds
number: the flume case gives ``|V_f| = 0.19 m/s`` at the sphere, ``Re = rho d
|V| / mu = 1.65e3``, where the standard curve gives ``C_D = 0.45`` (Morrison's
2013 correlation, :func:`sphere_drag_coefficient`: 0.446; the classical
tabulated curve 0.42-0.45).  The sphere drag (~7e-4 N) is about 9 % of its net
weight in water (7.8e-3 N)."""


def sphere_drag_coefficient(re: ArrayLike) -> NDArray[np.float64]:
    """Standard drag curve of a smooth sphere (F. A. Morrison, 2013 fit) [-].

    ``24/Re + 2.6 (Re/5)/(1 + (Re/5)^1.52) + 0.411 (Re/2.63e5)^-7.94/(1 + (Re/2.63e5)^-8)
    + 0.25 (Re/1e6)/(1 + Re/1e6)``, valid for ``Re < 1e6``.  Used only to
    justify :data:`SPHERE_CD`.

    Parameters
    ----------
    re : array_like
        Sphere Reynolds number ``rho D |V| / mu`` [-].
    """
    r = np.asarray(re, dtype=float)
    return (24.0 / r + 2.6 * (r / 5.0) / (1.0 + (r / 5.0) ** 1.52)
            + 0.411 * (r / 2.63e5) ** -7.94 / (1.0 + (r / 2.63e5) ** -8.0)
            + 0.25 * (r / 1e6) / (1.0 + r / 1e6))


def flume_scene(
    G: float = 1.737,
    sphere_cd: float = SPHERE_CD,
    E: float = 1.40e9,
    rho: float = 1026.0,
    mu: float = 1.2e-3,
    z_waterline: float = -0.46,
    length: float = 1.01,
    g: float = GRAVITY,
) -> tuple[list[CableSegment], TowedBody, Water, Vector]:
    """Flume-tank case of W section 4.3 (Table 3, W(140)).

    Origin at the tow point (top of the winch); waterline 0.46 m below it.
    Cable d = 0.45 mm, 0.2 g/m, E = 1.40 GPa on ``A = pi d^2/4`` (EA = 222.7 N),
    1.01 m from the top, bare loading functions, ``G = 1.737``.  Sphere
    d = 10 mm, 1.33 g, ``C_D`` = :data:`SPHERE_CD` on ``pi (5 mm)^2`` along all
    axes.  Water 1026 kg/m^3, 1.2e-3 Pa s.  Current ``[W(140)(z), 0, 0]``.

    Returns
    -------
    segments, body, water, tow_point
    """
    d = 0.45e-3
    EA = E * np.pi * d**2 / 4.0
    segs = [CableSegment(length, d, 0.2e-3, EA, "bare", G, None, "nylon")]
    ds = 0.010
    a = np.pi * ds**2 / 4.0
    body = TowedBody(mass=1.33e-3, volume=np.pi * ds**3 / 6.0, cd_area=(sphere_cd * a,) * 3)
    water = Water(rho=rho, mu=mu, current=flume_current(z_waterline), z_waterline=z_waterline, g=g)
    return segs, body, water, np.zeros(3)


def flume_case(
    G: float = 1.737,
    sphere_cd: float = SPHERE_CD,
    E: float = 1.40e9,
    rtol: float = 1e-10,
    stretch_loads: bool = False,
) -> SteadyTowResult:
    """Solve the flume steady tow (see :func:`flume_scene`).

    Parameters
    ----------
    G : float
        Cable drag amplification [-].
    sphere_cd : float
        Sphere drag coefficient [-].
    E : float
        Young's modulus of the nylon line [Pa].
    rtol : float
        ODE tolerance.
    stretch_loads : bool
        Loads per stretched length.

    Returns
    -------
    SteadyTowResult
    """
    segs, body, water, top = flume_scene(G=G, sphere_cd=sphere_cd, E=E)
    return solve_steady_tow(segs, body, water, top, rtol=rtol, stretch_loads=stretch_loads)
