"""The ``snapping_cable`` benchmark case: one place for its parameters.

A submerged steel aircraft cable hangs vertically with a sphere at its lower end; its
top end is moved vertically, z_top(t) = z0 + A sin(2 pi f t), starting abruptly at
t = 0 from static equilibrium (the top velocity jumps from 0 to A*omega). The output
is the force in the top support ("top tension") normalised by its static value T0.

Source: Sun et al., *Dynamic modeling of cable towed body using nodal position finite
element method* (conference paper), section 3.1 and Tables 1-2 (the experiment it
cites is on a 1/16 in x 62 ft cable with an 8 in sphere).
The OCR of that paper is damaged in places; every value below says where it comes
from and why it was chosen. All quantities in SI units.

Both peers (``moordyn_snapping.py``, ``exudyn_snapping.py``) read this module, and our
own scene mirrors it. Coordinates: z (MoorDyn) / y (Exudyn 2D) points up, the free
surface is at 0, the cable hangs along -z.
"""

from __future__ import annotations

import math

import numpy as np

# --------------------------------------------------------------------------- fluid
RHO_WATER = 1025.0
"""[kg/m^3] sea-water density (given by the brief; the paper does not state it)."""
G = 9.81
"""[m/s^2] gravitational acceleration."""

# --------------------------------------------------------------------------- cable
CABLE_DIAMETER = 1.6e-3
"""[m] Table 1 (= 1/16 in aircraft cable, 7x7 strands). Used for the drag reference
(D per unit length), the buoyancy and the added mass (A = pi D^2/4), as the paper's
Eqs. (16) and (24) do. The metal area of a 7x7 rope is smaller than pi D^2/4
(0.0112 kg/m / 7850 kg/m^3 = 1.43e-6 m^2 against 2.01e-6 m^2); the difference in
buoyancy is 0.11 N over the whole cable, 0.14 % of T0, so the nominal value is kept."""
CABLE_LENGTH = 18.9
"""[m] unstretched length, Table 1 (= 62 ft)."""
CABLE_MASS_PER_LENGTH = 0.0112
"""[kg/m] mass per unit length in air, Table 1 (column printed "Density (kg/m)")."""
CABLE_EA = 134.2e3
"""[N] axial stiffness, Table 1. Consistent with steel: EA over the metal area
(1.43e-6 m^2) is E = 94 GPa, a normal effective modulus for a 7x7 strand. NOTE: with
this EA the taut cable-sphere system has its axial natural frequency at ~3.7 Hz
(see :func:`natural_frequency_hz`), not near 1.27 Hz as the paper's text suggests
(that would need EA ~ 16 kN, i.e. E ~ 11 GPa, not plausible for steel). We keep the
printed EA; the slack/snap behaviour at 1.27 Hz comes from the abrupt start, see README."""
CABLE_EI = 1.0e-3
"""[N m^2] bending stiffness. Not in the paper (a cable model without bending).
MoorDyn uses EI = 0. The Exudyn ANCF element needs some EI; 1e-3 N m^2 lies between
the strand-slip lower bound (sum of the 49 wires, ~5e-4) and the solid-section upper
bound (~6e-2) of a 1.6 mm steel rope. The cable stays straight in this case, so EI
does no work; sqrt(EI/T0) = 3.6 mm is the bending boundary-layer length."""
CABLE_AXIAL_DAMPING = 10.0
"""[N s] Kelvin-Voigt axial damping BA: axial force N = EA*max(eps, 0) + BA*d(eps)/dt.
The paper has material viscous damping (its Eq. 14, C = c K) but gives no value. We
choose BA = 10 N s: 2.1 % of critical for the cable's own first axial mode (~92 Hz),
0.09 % for the 3.7 Hz sphere-on-spring mode (zeta = BA*omega/(2 EA)). It damps the
unresolvable segment-scale waves excited by the snaps (needed for a convergent
answer; MoorDyn's default RK2 is also unstable without it) but leaves the
low-frequency response undamped. Sensitivity (MoorDyn, 20 segments, dt = 0.1 ms,
whole run): Tmax/T0 at 1.27 Hz = 6.28 (BA = 0; undamped snaps, no converged value
exists), 5.48 (5), 5.36 (10), 5.21 (20), 3.68 (50 N s); at 0.807 Hz 2.27, 2.16,
2.15, 2.13, 2.08. The damping is a real modelling choice, not a numerical knob:
our scene must use the same law and value to be comparable.
The damping term acts also when the cable is slack: this is MoorDyn's law (Line.cpp
applies BA*eps_dot regardless of slack) and Exudyn mirrors it, so a slack cable shows
small negative "tension" (~ -0.5 % of T0) while it shortens."""
CABLE_CD_NORMAL = 1.2
"""[-] normal drag coefficient (Table 1), reference area D per unit length."""
CABLE_CD_TANGENTIAL = 0.01
"""[-] tangential drag coefficient (Table 1). Reference area: pi*D per unit length
(wetted perimeter), MoorDyn's convention; the paper's Eq. (16b) is illegible. The
motion is along the cable, so this is the only cable drag that acts. Small (< 0.5 N)
but it dissipates energy over the whole run: Tmax/T0 at 1.27 Hz is 5.386 with
Cdt = 0, 5.377 with the reference D instead of pi*D, 5.357 as chosen (MoorDyn, 20
segments)."""
CABLE_CA_NORMAL = 1.0
"""[-] normal added-mass coefficient (brief; potential-flow value for a cylinder)."""
CABLE_CA_TANGENTIAL = 0.0
"""[-] tangential added-mass coefficient (usual assumption)."""

# --------------------------------------------------------------------------- sphere
SPHERE_DIAMETER = 0.2032
"""[m] Table 2 (= 8 in)."""
SPHERE_MASS = 12.2
"""[kg] Table 2 (26.9 lb); mean density 2777 kg/m^3 (it sinks)."""
SPHERE_CD = 0.5
"""[-] Table 2; drag on the frontal area pi D^2/4. Plausible for a sphere at
Re = v D / nu ~ 1e5 (subcritical, Cd ~ 0.47-0.5)."""
SPHERE_CA = 0.18
"""[-] Table 2, kept as printed. Potential-flow theory gives 0.5 for a sphere; with
0.5 the effective mass would be 14.45 kg instead of 13.01 kg (+11 %), lowering the
taut natural frequency by ~5 %. Possibly an OCR/print error, but not resolvable."""

# --------------------------------------------------------------------------- excitation
TOP_Z0 = -1.0
"""[m] mean depth of the top end. The paper's rig geometry is not given; 1 m below
the surface keeps every part submerged (no free-surface effects; no waves/current)."""
AMPLITUDE = 0.05
"""[m] amplitude of the vertical top motion (brief; the figure axis that would show it
is destroyed in the OCR)."""
FREQUENCIES_HZ = (0.807, 1.27)
"""[Hz] excitation frequencies of the paper's Figs. 2 and 3."""
WATER_DEPTH = 100.0
"""[m] only for MoorDyn's input (seabed far below the sphere, never touched)."""

DURATION = 15.0
"""[s] simulated time of the benchmark runs."""
WINDOW_FULL = (0.0, 15.0)
"""[s] primary window for Tmax/T0, Tmin/T0: the whole run, including the snaps caused
by the abrupt start (these are deterministic; the later, bouncing regime is more
sensitive to small differences)."""
WINDOW_LATE = (5.0, 15.0)
"""[s] secondary window (after the first seconds). The start transient at the
natural frequency is almost undamped (only sphere drag), so this is not a steady
state; it is reported as a second, harder comparison."""


# --------------------------------------------------------------------------- derived
def cable_area() -> float:
    """[m^2] nominal cross-section pi D^2 / 4 (buoyancy, added mass)."""
    return math.pi * CABLE_DIAMETER**2 / 4.0


def cable_wet_weight_per_length() -> float:
    """[N/m] submerged weight per unstretched length, (mu - rho A) g."""
    return (CABLE_MASS_PER_LENGTH - RHO_WATER * cable_area()) * G


def sphere_volume() -> float:
    """[m^3] pi D^3 / 6."""
    return math.pi * SPHERE_DIAMETER**3 / 6.0


def sphere_frontal_area() -> float:
    """[m^2] pi D^2 / 4."""
    return math.pi * SPHERE_DIAMETER**2 / 4.0


def sphere_wet_weight() -> float:
    """[N] submerged weight of the sphere, (m - rho V) g."""
    return (SPHERE_MASS - RHO_WATER * sphere_volume()) * G


def sphere_added_mass() -> float:
    """[kg] Ca rho V."""
    return SPHERE_CA * RHO_WATER * sphere_volume()


def static_top_tension() -> float:
    """[N] T0 by hand: wet weight of the sphere plus wet weight of the whole cable."""
    return sphere_wet_weight() + cable_wet_weight_per_length() * CABLE_LENGTH


def static_tension(s_from_bottom: np.ndarray | float) -> np.ndarray | float:
    """[N] static tension at unstretched arc length s measured from the sphere."""
    return sphere_wet_weight() + cable_wet_weight_per_length() * np.asarray(s_from_bottom)


def static_stretch_from_top(s_from_top: np.ndarray | float) -> np.ndarray | float:
    """[m] static distance below the top of the material point at unstretched arc
    length s from the top: integral of (1 + T/EA) (linear elastic, exact)."""
    s = np.asarray(s_from_top, dtype=float)
    w, L = cable_wet_weight_per_length(), CABLE_LENGTH
    return s + (sphere_wet_weight() * s + w * (L * s - 0.5 * s * s)) / CABLE_EA


def static_stretched_length() -> float:
    """[m] static length of the hanging cable (top to sphere centre)."""
    return float(static_stretch_from_top(CABLE_LENGTH))


def top_position(t: np.ndarray | float, frequency_hz: float, amplitude: float = AMPLITUDE):
    """[m] prescribed top height z_top(t) = z0 + A sin(2 pi f t) for t >= 0."""
    return TOP_Z0 + amplitude * np.sin(2.0 * np.pi * frequency_hz * np.asarray(t))


def effective_mass() -> float:
    """[kg] mass of the sphere-on-spring mode: sphere + its added mass + 1/3 of the
    cable mass (the classical Rayleigh correction for a spring's own mass)."""
    return SPHERE_MASS + sphere_added_mass() + CABLE_MASS_PER_LENGTH * CABLE_LENGTH / 3.0


def natural_frequency_hz() -> float:
    """[Hz] taut axial natural frequency sqrt(k/m_eff)/(2 pi), k = EA/L."""
    return math.sqrt(CABLE_EA / CABLE_LENGTH / effective_mass()) / (2.0 * math.pi)


def linear_estimates(frequency_hz: float, amplitude: float = AMPLITUDE) -> dict:
    """Closed-form checks from the taut, undamped mass-spring model.

    Returns T0 [N], the forced tension amplitude quasi-static (m_eff w^2 A) and with
    dynamic amplification (/(1 - r^2)), the amplitude of the free vibration that the
    abrupt start excites (k A r / (1 - r^2)), and Tmax/T0 estimates. If the sum of
    the two amplitudes exceeds T0 the cable goes slack (and the linear model stops
    being valid).
    """
    T0 = static_top_tension()
    w = 2.0 * math.pi * frequency_hz
    k = CABLE_EA / CABLE_LENGTH
    m = effective_mass()
    wn = math.sqrt(k / m)
    r = w / wn
    forced_qs = m * w * w * amplitude
    forced = forced_qs / (1.0 - r * r)
    free = k * amplitude * r / (1.0 - r * r)
    return {
        "T0": T0,
        "natural_frequency_hz": wn / (2.0 * math.pi),
        "frequency_ratio": r,
        "forced_amplitude_quasistatic": forced_qs,
        "forced_amplitude": forced,
        "start_transient_amplitude": free,
        "Tmax_over_T0_quasistatic": 1.0 + forced_qs / T0,
        "Tmax_over_T0_steady": 1.0 + forced / T0,
        "slack_expected_at_start": forced + free > T0,
    }


# --------------------------------------------------------------------------- outputs
def tension_metrics(time: np.ndarray, tension: np.ndarray, T0: float,
                    window: tuple[float, float]) -> tuple[float, float]:
    """(Tmax/T0, Tmin/T0) of the samples with window[0] <= t <= window[1]."""
    time = np.asarray(time)
    tension = np.asarray(tension)
    m = (time >= window[0] - 1e-12) & (time <= window[1] + 1e-12)
    if not m.any():
        return float("nan"), float("nan")
    return float(tension[m].max() / T0), float(tension[m].min() / T0)


def forced_amplitude(time: np.ndarray, tension: np.ndarray, frequency_hz: float,
                     window: tuple[float, float]) -> float:
    """[N] amplitude of the tension component at the excitation frequency.

    Least-squares fit of a + b sin(wt) + c cos(wt) + free vibration terms at the
    natural frequency over the window; returns sqrt(b^2 + c^2). Only meaningful while
    the cable stays taut. Used to check the closed form m_eff w^2 A / (1 - r^2).
    """
    time = np.asarray(time)
    m = (time >= window[0]) & (time <= window[1])
    t, y = time[m], np.asarray(tension)[m]
    w = 2.0 * np.pi * frequency_hz
    wn = 2.0 * np.pi * natural_frequency_hz()
    cols = [np.ones_like(t), np.sin(w * t), np.cos(w * t)]
    # the free vibration is at a slightly shifted frequency; a few neighbours absorb it
    for f in np.linspace(0.9, 1.1, 5):
        cols += [np.sin(f * wn * t), np.cos(f * wn * t)]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), y, rcond=None)
    return float(math.hypot(coef[1], coef[2]))


def sample_interval(time_step_s: float, target: float = 5e-4) -> tuple[int, float]:
    """Output sampling: every k-th step, k = max(1, round(target/dt)); returns (k, k*dt).
    About 0.5 ms between samples resolves the snap peaks (rise time ~ 10-50 ms) to
    better than 0.05 %."""
    k = max(1, int(round(target / time_step_s)))
    return k, k * time_step_s


def summary() -> str:
    """Human-readable table of the case (for the scripts' __main__)."""
    lines = [
        f"cable: D={CABLE_DIAMETER*1e3:.2f} mm, L={CABLE_LENGTH} m, mu={CABLE_MASS_PER_LENGTH} kg/m, "
        f"EA={CABLE_EA/1e3:.1f} kN, BA={CABLE_AXIAL_DAMPING} N s, Cdn={CABLE_CD_NORMAL}, "
        f"Cdt={CABLE_CD_TANGENTIAL}, Can={CABLE_CA_NORMAL}",
        f"sphere: D={SPHERE_DIAMETER*1e3:.1f} mm, m={SPHERE_MASS} kg, Cd={SPHERE_CD}, Ca={SPHERE_CA}, "
        f"V={sphere_volume()*1e3:.4f} L, wet weight={sphere_wet_weight():.3f} N",
        f"water rho={RHO_WATER} kg/m^3, g={G} m/s^2; top z0={TOP_Z0} m, A={AMPLITUDE} m",
        f"T0 (hand) = {sphere_wet_weight():.4f} + {cable_wet_weight_per_length()*CABLE_LENGTH:.4f}"
        f" = {static_top_tension():.4f} N; taut natural frequency {natural_frequency_hz():.3f} Hz",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    print(summary())
    for f in FREQUENCIES_HZ:
        print(f, linear_estimates(f))
