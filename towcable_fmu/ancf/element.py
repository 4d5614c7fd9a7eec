"""The 3D gradient-deficient ANCF cable element: shape functions and constant matrices.

Nodal coordinates of one element: ``e = [r(0), r_p(0), r(L), r_p(L)]`` (12 numbers),
with ``r_p = dr/dp`` the slope with respect to the unstretched arc parameter ``p``.
Positions are interpolated by ``r(p) = S(p) e`` with ``S = [N1 I, N2 I, N3 I, N4 I]``.

Deviation from the printed reference (docs/design.md, known errors W(11), W(29), A3): with
slopes ``r_p = dr/dp`` the slope shape functions carry a factor L and the fourth is
``L (xi^3 - xi^2)``; the mass matrix W(12) is consistent with this form.

Every constant matrix here is the scalar 4x4 factor ``m`` of ``m (x) I_3`` (Kronecker
product), which is how the assembly applies them.
"""

from __future__ import annotations

import numpy as np


def shape_functions(xi: np.ndarray, length: float) -> np.ndarray:
    """Shape functions N1..N4 at normalised positions ``xi = p / L``.

    Parameters
    ----------
    xi
        Normalised arc parameter(s) in [0, 1].
    length
        Unstretched element length L [m].

    Returns
    -------
    ndarray, shape (..., 4)
    """
    xi = np.asarray(xi, dtype=float)
    return np.stack([1 - 3 * xi**2 + 2 * xi**3,
                     length * (xi - 2 * xi**2 + xi**3),
                     3 * xi**2 - 2 * xi**3,
                     length * (xi**3 - xi**2)], axis=-1)


def shape_derivatives(xi: np.ndarray, length: float) -> np.ndarray:
    """First derivatives dN/dp [1/m for N1, N3; - for N2, N4], shape (..., 4)."""
    xi = np.asarray(xi, dtype=float)
    return np.stack([(-6 * xi + 6 * xi**2) / length,
                     1 - 4 * xi + 3 * xi**2,
                     (6 * xi - 6 * xi**2) / length,
                     3 * xi**2 - 2 * xi], axis=-1)


def shape_second_derivatives(xi: np.ndarray, length: float) -> np.ndarray:
    """Second derivatives d2N/dp2, shape (..., 4)."""
    xi = np.asarray(xi, dtype=float)
    return np.stack([(-6 + 12 * xi) / length**2,
                     (-4 + 6 * xi) / length,
                     (6 - 12 * xi) / length**2,
                     (6 * xi - 2) / length], axis=-1)


def gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre points and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def trapezoid_points(n: int) -> tuple[np.ndarray, np.ndarray]:
    """``n`` equally spaced points on [0, 1] and their trapezoidal weights (sum 1).

    The reference writes the weights with a factor ``L / N_I`` (W(78), W(104)); the
    weights of ``N_I`` equally spaced points including both ends sum to ``N_I - 1``
    intervals, so the correct factor is ``L / (N_I - 1)``, used here.
    """
    xi = np.linspace(0.0, 1.0, n)
    w = np.full(n, 1.0 / (n - 1))
    w[[0, -1]] *= 0.5
    return xi, w


def _integrate(fa, fb, length: float, order: int = 6) -> np.ndarray:
    """Exact integral over the element of the outer product fa(xi)^T fb(xi) dp (polynomials)."""
    xi, w = gauss_legendre(order)
    a = fa(xi, length)
    b = fb(xi, length)
    return length * np.einsum("g,gi,gj->ij", w, a, b)


def mass_matrix(length: float, mass_per_length: float) -> np.ndarray:
    """Consistent mass matrix factor, W(12)/W(38): mu * int N^T N dp [kg, kg m, kg m^2]."""
    return mass_per_length * _integrate(shape_functions, shape_functions, length)


def bending_matrix(length: float, ei: float) -> np.ndarray:
    """Bending stiffness factor, W(52): EI * int N''^T N'' dp [N/m, N, N m]."""
    return ei * _integrate(shape_second_derivatives, shape_second_derivatives, length)


def damping_matrix(length: float, c: float) -> np.ndarray:
    """Internal damping factor, W(55): c * int N'^T N' dp [N s/m, N s, N s m]."""
    return c * _integrate(shape_derivatives, shape_derivatives, length)


def load_vector(length: float) -> np.ndarray:
    """int N dp: the generalised force of a uniform unit load per length, W(35) [m, m^2]."""
    xi, w = gauss_legendre(4)
    return length * np.einsum("g,gi->i", w, shape_functions(xi, length))
