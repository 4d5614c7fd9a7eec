"""Empirical loading functions and the Reynolds-dependent drag coefficient of a cable.

* Bare cable, W(60) (Driscoll & Nahon): normal f_n and tangential f_t as functions of
  the angle eta in [0, pi/2] between the relative flow and the cable.
* Ribbon-faired cable, W(145) (Folb & Nelligan); W(145b) is the tangential function
  f_t (the reference prints it as f_n).
* The loading functions of the nodal-position paper (Sun et al., "Dynamic modeling of
  cable towed body using nodal position finite element method", eqs. 28-29; the OCR is
  damaged, read as below), meant with a constant C_D equal to the paper's drag factor D:
  bare, eq. 28: f_n = sin^2 a, f_t = -0.019 + 0.0239 cos a + 0.02 sin a + 0.001 cos 2a
  (f_t is 0.0059 along the flow and 0 across it); faired, eq. 29: f_n = g(a) sin a,
  f_t = g(a) cos a with g = 0.273 + 0.827 a^2 below 30 deg and g = sin a above (the two
  branches meet at 30 deg: 0.273 + 0.827 (pi/6)^2 = 0.4997).
* Normal and tangential drag as MoorDyn writes it (the snapping case's definition):
  f_n = sin^2 a on the reference d with the normal C_D, f_t = pi cos^2 a with the
  tangential C_Dt (reference pi d, the wetted perimeter): per unit length
  rho d C_D |V_n| V_n / 2 + rho pi d C_Dt |V_t| V_t / 2. The drag kernels apply C_Dt
  to the tangential term of this kind (:func:`towcable_fmu.hydro.cable.drag`).
* C_D(Re), W(61)-(63) (Choo & Casarella), with Re from the normal relative speed.
  At Re -> 0 the first branch diverges; the coefficient is evaluated at no less than
  ``RE_MIN`` (the drag itself goes to zero with the speed).
"""

from __future__ import annotations

import math

from ..jit.kernel_cache import njit

BARE = 0
FAIRED = 1
SUN_BARE = 2
SUN_FAIRED = 3
NORMAL_TANGENTIAL = 4
LOADINGS = {"bare": BARE, "faired": FAIRED, "sun2011_bare": SUN_BARE, "sun2011_faired": SUN_FAIRED,
            "normal_tangential": NORMAL_TANGENTIAL}

#: Smallest Reynolds number at which C_D(Re) is evaluated.
RE_MIN = 1e-3

# All IR-inlined (inline="always") into their callers, the plain kernels
# towcable_fmu.hydro.cable.drag and drag_jacobian, each compiled once: calls to them from the point
# loops would cost run time (a call spills every floating-point value the caller holds).
# The branch helpers called as kernels would compile a specialisation per literal branch.


@njit(cache=True, inline="always")
def loading_functions(kind: int, cos_eta: float, sin_eta: float) -> tuple[float, float]:
    """(f_n, f_t) of the loading functions ``kind`` (module docstring).

    Parameters
    ----------
    kind
        One of BARE, FAIRED, SUN_BARE, SUN_FAIRED, NORMAL_TANGENTIAL.
    cos_eta, sin_eta
        Cosine and sine of the angle eta in [0, pi/2] between the relative flow and the
        cable (both >= 0; passing them avoids inverse trigonometry in the hot loop).
    """
    cos2 = 2.0 * cos_eta * cos_eta - 1.0
    sin2 = 2.0 * sin_eta * cos_eta
    if kind == SUN_BARE:
        return sin_eta * sin_eta, max(-0.019 + 0.0239 * cos_eta + 0.02 * sin_eta + 0.001 * cos2, 0.0)
    if kind == SUN_FAIRED:
        eta = math.atan2(sin_eta, cos_eta)
        g = 0.273 + 0.827 * eta * eta if eta < math.pi / 6.0 else sin_eta
        return g * sin_eta, g * cos_eta
    if kind == NORMAL_TANGENTIAL:
        return sin_eta * sin_eta, math.pi * cos_eta * cos_eta
    if kind == BARE:
        eta = math.atan2(sin_eta, cos_eta)
        fn = 0.5 - 0.1 * cos_eta + 0.1 * sin_eta - 0.4 * cos2 - 0.11 * sin2
        ft = 0.01 * (2.009 + eta * (-0.3858 + eta * (1.9159 + eta * (-4.1615 + eta * (3.5064 - 1.1873 * eta)))))
    else:
        fn = 0.498609 - 0.2499 * cos_eta + 0.2527 * sin_eta - 0.2487 * cos2
        ft = -0.2255 + 0.3417 * cos_eta + 0.255 * sin_eta - 0.0811 * sin2
    return fn, ft


@njit(cache=True, inline="always")
def loading_slopes(kind: int, cos_eta: float, sin_eta: float) -> tuple[float, float]:
    """(df_n/deta, df_t/deta) [1/rad] of the loading functions ``kind`` (arguments as
    :func:`loading_functions`).

    At the faired nodal-position function's break (30 deg) the slope is that of the branch
    :func:`loading_functions` takes there (the upper one). The bare nodal-position f_t is
    clamped at zero only against rounding at 90 deg (the polynomial is positive below), so
    its slope is the polynomial's, the one-sided slope at 90 deg.
    """
    cos2 = 2.0 * cos_eta * cos_eta - 1.0
    sin2 = 2.0 * sin_eta * cos_eta
    if kind == SUN_BARE:
        return sin2, -0.0239 * sin_eta + 0.02 * cos_eta - 0.002 * sin2
    if kind == SUN_FAIRED:
        eta = math.atan2(sin_eta, cos_eta)
        if eta < math.pi / 6.0:
            g = 0.273 + 0.827 * eta * eta
            dg = 1.654 * eta
        else:
            g = sin_eta
            dg = cos_eta
        return dg * sin_eta + g * cos_eta, dg * cos_eta - g * sin_eta
    if kind == NORMAL_TANGENTIAL:
        return sin2, -math.pi * sin2
    if kind == BARE:
        eta = math.atan2(sin_eta, cos_eta)
        dfn = 0.1 * sin_eta + 0.1 * cos_eta + 0.8 * sin2 - 0.22 * cos2
        dft = 0.01 * (-0.3858 + eta * (3.8318 + eta * (-12.4845 + eta * (14.0256 - 5.9365 * eta))))
    else:
        dfn = 0.2499 * sin_eta + 0.2527 * cos_eta + 0.4974 * sin2
        dft = -0.3417 * sin_eta + 0.255 * cos_eta - 0.1622 * cos2
    return dfn, dft


@njit(cache=True, inline="always")
def _cd_branch(re: float, branch: int) -> float:
    if branch == 0:
        s = -0.077215665 + math.log(8.0 / re)
        return 8.0 * math.pi / (re * s) * (1.0 - 0.87 / (s * s))
    if branch == 1:
        return 1.45 + 8.55 * re ** -0.9
    return 1.1 + 4.0 / math.sqrt(re)


@njit(cache=True, inline="always")
def drag_coefficient(re: float) -> float:
    """Common drag coefficient C_D(Re) of a cable, W(61)-(62).

    The three branches of W(61) do not meet (C_D jumps by 1.7 % at Re = 1, from 9.83 to
    10.0, and by 1.1 % at Re = 30); such a jump can leave no exact equilibrium and makes
    Newton cycle. Within a factor ``RE_BLEND`` of each break point the neighbouring
    branches are blended smoothly in log Re; elsewhere the formula is exactly the
    reference's.
    """
    re = max(re, RE_MIN)
    k = _re_range(re)
    return _cd_branch(re, k // 2) if k % 2 == 0 else _blend(re, k // 2)


@njit(cache=True, inline="always")
def _re_range(re: float) -> int:
    """Where Re lies: 2k on branch k of W(61), 2k + 1 in the blend of branches k and k + 1."""
    if re >= _HI[1]:
        return 4
    if re > _LO[1]:
        return 3
    if re >= _HI[0]:
        return 2
    if re > _LO[0]:
        return 1
    return 0


@njit(cache=True, inline="always")
def _blend(re: float, k: int) -> float:
    s = (math.log(re) - math.log(_LO[k])) / (math.log(_HI[k]) - math.log(_LO[k]))
    w = s * s * (3.0 - 2.0 * s)
    return (1.0 - w) * _cd_branch(re, k) + w * _cd_branch(re, k + 1)


@njit(cache=True, inline="always")
def _cd_branch_slope(re: float, branch: int) -> float:
    """Re dC_D/dRe of one branch of W(61)."""
    if branch == 0:
        s = -0.077215665 + math.log(8.0 / re)
        return 8.0 * math.pi / re * (0.87 * (s - 3.0) / s**4 - (s - 1.0) / (s * s))
    if branch == 1:
        return -7.695 * re ** -0.9
    return -2.0 / math.sqrt(re)


@njit(cache=True, inline="always")
def drag_coefficient_slope(re: float) -> float:
    """Slope of :func:`drag_coefficient` in log Re, ``Re dC_D/dRe`` [-] (0 below ``RE_MIN``,
    where the coefficient is held constant; at a break point of the blend, the slope of
    the branch :func:`drag_coefficient` takes there)."""
    if re < RE_MIN:
        return 0.0
    k = _re_range(re)
    return _cd_branch_slope(re, k // 2) if k % 2 == 0 else _blend_slope(re, k // 2)


@njit(cache=True, inline="always")
def _blend_slope(re: float, k: int) -> float:
    span = math.log(_HI[k]) - math.log(_LO[k])
    s = (math.log(re) - math.log(_LO[k])) / span
    w = s * s * (3.0 - 2.0 * s)
    dw = 6.0 * s * (1.0 - s) / span  # dw / dlog(Re)
    return ((1.0 - w) * _cd_branch_slope(re, k) + w * _cd_branch_slope(re, k + 1)
            + dw * (_cd_branch(re, k + 1) - _cd_branch(re, k)))


#: Half-width of the blending zone around each break point (Re = 1 and 30), as a factor on Re.
RE_BLEND = 1.1
_LO = (1.0 / RE_BLEND, 30.0 / RE_BLEND)
_HI = (1.0 * RE_BLEND, 30.0 * RE_BLEND)
