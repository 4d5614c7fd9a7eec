"""The stable step of the explicit (leapfrog) nodal cable: lumped masses, axial stiffness
and Kelvin-Voigt damping with the velocity lagged by half a step.

One degree of freedom x'' = -omega^2 x - 2 zeta omega v, stepped by leapfrog with the damping
on the half-step velocity v_{n+1/2} = (x_{n+1} - x_n)/dt, has the characteristic equation
lambda^2 + (W^2 + 2 zeta W - 2) lambda + 1 - 2 zeta W = 0 (W = omega dt); its roots stay in
the unit circle while W <= 2 (sqrt(1 + zeta^2) - zeta) (Jury's conditions; the other one,
W <= 1/zeta, is always looser). In the form that also holds without stiffness,

    dt <= 4 / (sqrt(4 omega^2 + D^2) + D),   D = 2 zeta omega,

which is 2/omega undamped and 2/D with no stiffness (a slack cable: the damping alone).

The chain: node i carries the lumped mass m_i (half of each adjacent element's mu L0, the end
mass at the last node; the added mass acts normal to the cable and does not load the axial
modes, so it is left out: a lighter node is the safe side), each element the stiffness
k = EA/L0 and damping b = BA/L0 between its nodes. Gershgorin's theorem bounds the
eigenvalues of M^-1 K by max_i 2 (k_a + k_b)/m_i and those of M^-1 C by max_i 2 (b_a + b_b)/m_i
(a, b the node's elements); for one material C = (BA/EA) K and the modes decouple, so the node
with the largest omega_i^2 = 2 (k_a + k_b)/m_i and D_i = 2 (b_a + b_b)/m_i sets the step. A
uniform mesh gives omega = 2 c/l, c = sqrt(EA/mu), zeta = BA/(l sqrt(EA mu)) and, slack,
dt <= mu l^2/(2 BA) (looser than the taut limit, so the taut one governs always).

Not in the bound (covered by :data:`SAFETY`): the tangent stiffness of the element law,
EA (1 + 2 eps)/L0 (0.6 % more at a strain of 0.3 %), the geometric stiffness T/L of the
lateral modes (T << EA) and the lagged drag's linearised damping rho C_D d |v| per length.
"""

from __future__ import annotations

import numpy as np

#: The explicit path steps at most SAFETY times the limit of :func:`step_limit`.
SAFETY = 0.9


def step_limit(L0: np.ndarray, EA: np.ndarray, BA: np.ndarray, mu: np.ndarray, end_mass: float) -> float:
    """The leapfrog's stability limit [s] of a chain of elements from a prescribed top node.

    Parameters
    ----------
    L0, EA, BA, mu
        Per element: unstretched length [m], axial stiffness [N], axial damping [N s] and mass
        per length [kg/m], from the top.
    end_mass
        Mass lumped at the last node [kg] (towed body, bottom mass).

    Returns
    -------
    float
        The step [s] at which the fastest node's leapfrog becomes unstable (module docstring).
    """
    half = 0.5 * mu * L0
    mass = np.concatenate([half, [0.0]]) + np.concatenate([[0.0], half])
    mass[-1] += end_mass
    k, b = EA / L0, BA / L0
    stiff = np.concatenate([k, [0.0]]) + np.concatenate([[0.0], k])
    damp = np.concatenate([b, [0.0]]) + np.concatenate([[0.0], b])
    omega2 = 2.0 * stiff[1:] / mass[1:]  # the free nodes
    d = 2.0 * damp[1:] / mass[1:]
    return float(np.min(4.0 / (np.sqrt(4.0 * omega2 + d * d) + d)))
