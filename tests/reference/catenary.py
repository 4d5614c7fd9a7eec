"""Elastic catenary references (closed form, independent of ``towcable_fmu``).

Two closed-form static solutions of an extensible cable (Hooke's law with
engineering strain, ``ds_stretched = (1 + T/EA) ds``, ``s`` the *unstretched*
arc length):

* :func:`solve_elastic_catenary` -- Irvine's elastic catenary between two
  supports at arbitrary positions in a vertical plane
  (H. M. Irvine, *Cable Structures*, MIT Press 1981, eqs. 2.39-2.40).
* :func:`hanging_cable` -- a vertical cable hanging from a fixed point with a
  weight at its lower end (tension linear in ``s``).

Frame: ``x`` horizontal, ``z`` vertically up, gravity along ``-z``.  The
weight per unit length ``w`` [N/m] is per *unstretched* length (the mass is
conserved when the cable stretches); pass the submerged weight
``(mu - rho_f*A)*g`` for a fully submerged cable.

Derivation used by :func:`solve_elastic_catenary`
-------------------------------------------------
Let support A be at ``(x_A, z_A)`` and B at ``(x_A + l, z_A + h)`` with
``l > 0``.  ``s`` runs from A (``s = 0``) to B (``s = L0``).  ``H`` is the
horizontal tension (constant) and ``V_A`` the upward vertical reaction of
support A on the cable.  Equilibrium of the piece ``[0, s]`` gives the tension
vector (force of the part beyond ``s`` on the part before it)::

    T(s) = (H, w s - V_A),      |T| = sqrt(H^2 + (w s - V_A)^2)

and ``dr/ds = (1 + |T|/EA) T/|T|`` integrates to::

    x(s) = H s/EA + (H/w) [asinh((w s - V_A)/H) + asinh(V_A/H)]
    z(s) = (w s^2/2 - V_A s)/EA + (1/w) [sqrt(H^2 + (w s - V_A)^2) - sqrt(H^2 + V_A^2)]

The two unknowns ``(H, V_A)`` follow from ``x(L0) = l``, ``z(L0) = h``
(solved with :func:`scipy.optimize.root`, initial guess of Peyrot & Goulois,
J. Struct. Div. ASCE 105, 1979).  The vertical reaction at B is
``V_B = w L0 - V_A``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import optimize

__all__ = [
    "ElasticCatenary",
    "HangingCable",
    "solve_elastic_catenary",
    "inextensible_catenary_H",
    "hanging_cable",
]


@dataclass(frozen=True)
class ElasticCatenary:
    """Solution of the elastic catenary between two supports.

    Attributes
    ----------
    L0 : float
        Unstretched cable length [m].
    EA : float
        Axial stiffness [N].
    w : float
        Weight per unit unstretched length [N/m] (``> 0``).
    span : float
        Horizontal distance from support A to support B, ``l > 0`` [m].
    height : float
        Height of B above A, ``h`` [m] (negative if B is lower).
    H : float
        Horizontal tension component [N] (same everywhere).
    V_A : float
        Upward vertical force of support A on the cable [N].
    V_B : float
        Upward vertical force of support B on the cable [N]; ``V_A + V_B = w L0``.
    tension_A, tension_B : float
        Tension magnitudes at the supports [N].
    sag : float
        Maximum vertical distance of the cable below the chord A-B [m].
    s_sag : float
        Unstretched arc length from A where the sag is attained [m].
    stretched_length : float
        Length of the loaded cable [m].
    origin : tuple of float
        Position ``(x_A, z_A)`` of support A [m]; ``x``/``z`` below are
        relative to it unless ``absolute=True`` is passed.
    """

    L0: float
    EA: float
    w: float
    span: float
    height: float
    H: float
    V_A: float
    V_B: float
    tension_A: float
    tension_B: float
    sag: float
    s_sag: float
    stretched_length: float
    origin: tuple[float, float] = field(default=(0.0, 0.0))

    # -- shape and tension as functions of the unstretched arc length from A --
    def vertical_tension(self, s: ArrayLike) -> NDArray[np.float64]:
        """Vertical component of the tension vector at ``s`` [N] (positive up, towards B)."""
        s = np.asarray(s, dtype=float)
        return self.w * s - self.V_A

    def tension(self, s: ArrayLike) -> NDArray[np.float64]:
        """Tension magnitude at unstretched arc length ``s`` from A [N]."""
        return np.hypot(self.H, self.vertical_tension(s))

    def tension_vector(self, s: ArrayLike) -> NDArray[np.float64]:
        """Tension vector ``(T_x, T_z)`` at ``s`` [N], shape ``(..., 2)``; points towards B."""
        tz = self.vertical_tension(s)
        return np.stack([np.full_like(tz, self.H), tz], axis=-1)

    def x(self, s: ArrayLike, absolute: bool = False) -> NDArray[np.float64]:
        """Horizontal position of the point at unstretched arc length ``s`` [m]."""
        s = np.asarray(s, dtype=float)
        H, V, w, EA = self.H, self.V_A, self.w, self.EA
        out = H * s / EA + (H / w) * (np.arcsinh((w * s - V) / H) + np.arcsinh(V / H))
        return out + (self.origin[0] if absolute else 0.0)

    def z(self, s: ArrayLike, absolute: bool = False) -> NDArray[np.float64]:
        """Vertical position of the point at unstretched arc length ``s`` [m]."""
        s = np.asarray(s, dtype=float)
        H, V, w, EA = self.H, self.V_A, self.w, self.EA
        out = (w * s * s / 2.0 - V * s) / EA + (np.hypot(H, w * s - V) - np.hypot(H, V)) / w
        return out + (self.origin[1] if absolute else 0.0)

    def angle_from_horizontal(self, s: ArrayLike) -> NDArray[np.float64]:
        """Inclination of the cable tangent (towards B) above the horizontal [rad]."""
        return np.arctan2(self.vertical_tension(s), self.H)


def _catenary_xz(H: float, V: float, w: float, EA: float, s: float) -> tuple[float, float]:
    x = H * s / EA + (H / w) * (np.arcsinh((w * s - V) / H) + np.arcsinh(V / H))
    z = (w * s * s / 2.0 - V * s) / EA + (np.hypot(H, w * s - V) - np.hypot(H, V)) / w
    return x, z


def solve_elastic_catenary(
    L0: float,
    EA: float,
    w: float,
    span: float,
    height: float,
    origin: tuple[float, float] = (0.0, 0.0),
    xtol: float = 1e-13,
) -> ElasticCatenary:
    """Solve Irvine's elastic catenary between two supports.

    Parameters
    ----------
    L0 : float
        Unstretched cable length [m], ``> 0``.
    EA : float
        Axial stiffness [N], ``> 0`` (use e.g. ``1e15`` for an inextensible cable).
    w : float
        Weight per unit unstretched length [N/m], ``> 0`` (submerged weight
        for a submerged cable).
    span : float
        Horizontal distance between the supports [m], ``> 0``.  For a
        vertical cable use :func:`hanging_cable`.
    height : float
        Height of support B above support A [m] (any sign).
    origin : tuple of float, optional
        Absolute position ``(x_A, z_A)`` of support A [m].
    xtol : float, optional
        Relative tolerance on ``(H, V_A)`` passed to the root finder.

    Returns
    -------
    ElasticCatenary
        Horizontal tension, reactions, support tensions, sag and the shape
        ``x(s), z(s)`` and tension ``T(s)`` as functions of the unstretched arc
        length from A.

    Raises
    ------
    ValueError
        On non-physical input.
    RuntimeError
        If the boundary conditions are not met to ``1e-9 * L0``.
    """
    if not (L0 > 0 and EA > 0 and w > 0 and span > 0):
        raise ValueError(f"need L0, EA, w, span > 0; got L0={L0}, EA={EA}, w={w}, span={span}")
    l, h = float(span), float(height)
    W = w * L0

    # Initial guess (Peyrot & Goulois 1979), written for our sign of V_A.
    if L0 ** 2 <= l ** 2 + h ** 2:  # taut: cable shorter than the chord
        lam = 0.2
    else:
        lam = np.sqrt(3.0 * ((L0 ** 2 - h ** 2) / l ** 2 - 1.0))
    H0 = abs(w * l / (2.0 * lam))
    V0 = 0.5 * w * (L0 - h * np.cosh(lam) / np.sinh(lam))

    # Unknowns scaled: q = (ln(H/W), V_A/W) keeps H > 0 and is O(1).
    def resid(q: NDArray[np.float64]) -> NDArray[np.float64]:
        H = W * np.exp(q[0])
        V = W * q[1]
        x, z = _catenary_xz(H, V, w, EA, L0)
        return np.array([(x - l) / L0, (z - h) / L0])

    q0 = np.array([np.log(H0 / W), V0 / W])
    sol = optimize.root(resid, q0, method="hybr", options={"xtol": xtol})
    if not sol.success or np.max(np.abs(resid(sol.x))) > 1e-9:
        # fall back on Levenberg-Marquardt from the same guess
        sol = optimize.root(resid, q0, method="lm", options={"xtol": xtol, "ftol": 1e-15})
    res = resid(sol.x)
    if np.max(np.abs(res)) > 1e-9:
        raise RuntimeError(f"elastic catenary did not converge: residual {res}")
    H = float(W * np.exp(sol.x[0]))
    V_A = float(W * sol.x[1])
    V_B = W - V_A

    # Sag: h x/l - z is maximal where the cable slope equals the chord slope,
    # T_z(s*) = H h / l  ->  s* = (V_A + H h/l)/w (clipped to the cable).
    s_star = float(np.clip((V_A + H * h / l) / w, 0.0, L0))
    x_s, z_s = _catenary_xz(H, V_A, w, EA, s_star)
    sag = float(h * x_s / l - z_s)

    # Stretched length: L0 + (1/EA) * integral of |T| ds (closed form).
    def _int_T(s: float) -> float:  # antiderivative of sqrt(H^2 + (w s - V)^2)
        u = w * s - V_A
        return (u * np.hypot(H, u) + H * H * np.arcsinh(u / H)) / (2.0 * w)

    stretched = L0 + (_int_T(L0) - _int_T(0.0)) / EA
    return ElasticCatenary(
        L0=float(L0), EA=float(EA), w=float(w), span=l, height=h,
        H=H, V_A=V_A, V_B=float(V_B),
        tension_A=float(np.hypot(H, V_A)), tension_B=float(np.hypot(H, V_B)),
        sag=sag, s_sag=s_star, stretched_length=float(stretched),
        origin=(float(origin[0]), float(origin[1])),
    )


def inextensible_catenary_H(L0: float, w: float, span: float, height: float) -> float:
    """Horizontal tension of the classical inextensible catenary [N].

    Solves ``sqrt(L0^2 - h^2) = (2H/w) sinh(w l / (2H))`` with
    :func:`scipy.optimize.brentq`.  Independent of :func:`solve_elastic_catenary`
    (used to check its large-``EA`` limit).

    Parameters
    ----------
    L0 : float
        Cable length [m]; must exceed the chord ``sqrt(l^2 + h^2)``.
    w : float
        Weight per unit length [N/m].
    span, height : float
        Horizontal and vertical distance between the supports [m].

    Returns
    -------
    float
        Horizontal tension ``H`` [N].
    """
    l, h = float(span), float(height)
    target = np.sqrt(L0 ** 2 - h ** 2)
    if not target > l:
        raise ValueError("inextensible catenary needs L0 > chord length")

    # in terms of a = w l / (2H): sinh(a)/a = target/l, monotone in a > 0
    ratio = target / l

    def g(a: float) -> float:
        return np.sinh(a) / a - ratio

    hi = 1.0
    while g(hi) < 0:
        hi *= 2.0
    a = optimize.brentq(g, 1e-12, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    return float(w * l / (2.0 * a))


@dataclass(frozen=True)
class HangingCable:
    """Vertical elastic cable hanging from a fixed point with an end weight.

    ``s`` is the unstretched arc length measured from the top (``0 <= s <= L0``).

    Attributes
    ----------
    L0 : float
        Unstretched length [m].
    EA : float
        Axial stiffness [N].
    w : float
        Weight per unit unstretched length [N/m] (submerged weight if submerged).
    end_weight : float
        Net weight of the end mass [N] (``m g`` or its weight in water).
    top : float
        Height of the suspension point [m].
    top_tension : float
        ``end_weight + w L0`` [N].
    stretched_length : float
        ``L0 + (end_weight L0 + w L0^2 / 2) / EA`` [m].
    bottom_z : float
        Height of the lower end, ``top - stretched_length`` [m].
    """

    L0: float
    EA: float
    w: float
    end_weight: float
    top: float
    top_tension: float
    stretched_length: float
    bottom_z: float

    def tension(self, s: ArrayLike) -> NDArray[np.float64]:
        """Tension at unstretched distance ``s`` below the top [N]: ``F + w (L0 - s)``."""
        s = np.asarray(s, dtype=float)
        return self.end_weight + self.w * (self.L0 - s)

    def z(self, s: ArrayLike) -> NDArray[np.float64]:
        """Height of the point ``s`` below the top [m].

        ``z(s) = top - s - (F s + w (L0 s - s^2/2)) / EA``.
        """
        s = np.asarray(s, dtype=float)
        F, w = self.end_weight, self.w
        return self.top - s - (F * s + w * (self.L0 * s - 0.5 * s * s)) / self.EA


def hanging_cable(L0: float, EA: float, w: float, end_weight: float, top: float = 0.0) -> HangingCable:
    """Vertical cable hanging under its own weight and an end weight.

    Parameters
    ----------
    L0 : float
        Unstretched length [m].
    EA : float
        Axial stiffness [N].
    w : float
        Weight per unit unstretched length [N/m].
    end_weight : float
        Net weight hanging at the lower end [N] (``>= -0``; a buoyant end
        would make the cable slack where ``T < 0``).
    top : float, optional
        Height of the suspension point [m].

    Returns
    -------
    HangingCable
        Linear tension profile ``T(s) = F + w (L0 - s)`` and the stretched shape.
    """
    if not (L0 > 0 and EA > 0):
        raise ValueError("need L0 > 0 and EA > 0")
    if end_weight < 0 or end_weight + w * L0 < 0:
        raise ValueError("the hanging cable would be in compression")
    stretch = (end_weight * L0 + 0.5 * w * L0 ** 2) / EA
    return HangingCable(
        L0=float(L0), EA=float(EA), w=float(w), end_weight=float(end_weight), top=float(top),
        top_tension=float(end_weight + w * L0), stretched_length=float(L0 + stretch),
        bottom_z=float(top - L0 - stretch),
    )
