"""Coefficients of Chung & Hulbert's generalised-alpha scheme (form of Arnold & Bruls 2007).

Any formulation's integrator uses them: the ANCF cable's (:mod:`towcable_fmu.ancf.genalpha`)
and the nodal-position cable's (:mod:`towcable_fmu.nodal.integrators`). For the spectral
radius at infinite frequency ``rho_inf``: am = (2 rho - 1)/(rho + 1), af = rho/(rho + 1),
gamma = 1/2 + af - am, beta = (gamma + 1/2)^2 / 4 (second order, unconditionally stable).
"""

from __future__ import annotations

from ..jit.kernel_cache import njit


@njit(cache=True)
def scheme_coefficients(rho_inf: float):
    """(am, af, gamma, beta) of the generalised-alpha scheme for ``rho_inf`` in [0, 1]."""
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 + af - am
    beta = 0.25 * (gamma + 0.5) ** 2
    return am, af, gamma, beta
