"""The scene: typed, validated description of one towed-cable system.

Each class is one TOML table of a scene file; every field declares its unit, default
and allowed range (see :mod:`towcable_fmu.common.schema`). Cross-field rules live in
``validate`` methods and raise :class:`~towcable_fmu.common.errors.SceneError` as well.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..common.errors import SceneError
from ..numerics.explicit_step import SAFETY, step_limit
from ..common.schema import spec
from ..builtin_scenes import BASED_ON_DOC


@dataclasses.dataclass(frozen=True)
class Environment:
    """Gravity and the inertial frame."""

    gravity: float = spec(9.81, unit="m/s^2", ge=0.0, doc="gravitational acceleration (acts along -z)")


@dataclasses.dataclass(frozen=True)
class Rope:
    """What the rope is made of, for its life (towcable_fmu/rope_life/): the minimum breaking
    strength and the construction, which selects the tension-tension T-N curve N R^M = K
    of API RP 2SK (3rd ed., 2005; the curves of ISO 19901-7), R the tension range over the
    breaking strength; optionally its bending endurance over the sheave."""

    breaking_strength: float = spec(unit="N", gt=0.0, doc="minimum breaking strength (MBS) of the rope")
    construction: str = spec("six_strand", choices=("six_strand", "spiral_strand"),
                             doc="six_strand: six- or multi-strand rope (API RP 2SK: M = 4.09, K = 231); "
                                 "spiral_strand: spiral strand (M = 5.05, K = 166); the curves at a mean "
                                 "load of 0.3 MBS")
    bending_cycles: float | None = spec(None, unit="-", gt=0.0,
                                        doc="bending endurance: simple bending cycles to discard at bending_tension "
                                            "over the scene's sheave (e.g. from Feyrer's discard model, eq. 3.55 of "
                                            "'Wire Ropes', or the rope maker); with bending_tension and "
                                            "bending_exponent it gives the bending damage along the rope (absent: "
                                            "cycles counted, no damage)")
    bending_tension: float | None = spec(None, unit="N", gt=0.0, doc="the tension S_0 of bending_cycles")
    bending_exponent: float | None = spec(None, unit="-", gt=0.0,
                                          doc="p of the endurance at other tensions, N = bending_cycles (S_0 / S)^p "
                                              "(Feyrer's collective method, eq. 3.93: p = b_1 + b_3 lg(D/d) of his "
                                              "endurance equation)")

    def validate(self, key: str) -> None:
        """The bending endurance is given whole or not at all."""
        given = [n for n in ("bending_cycles", "bending_tension", "bending_exponent") if getattr(self, n) is not None]
        if given and len(given) < 3:
            missing = [n for n in ("bending_cycles", "bending_tension", "bending_exponent") if n not in given]
            raise SceneError(f"{key}.{missing[0]}", None, "a value: bending_cycles, bending_tension and "
                                                          "bending_exponent go together")


@dataclasses.dataclass(frozen=True)
class Segment:
    """A run of cable with uniform properties, meshed with equal ANCF elements."""

    length: float = spec(unit="m", gt=0.0, doc="unstretched length of the segment")
    elements: int = spec(unit="-", ge=1, le=5000, doc="number of equal ANCF elements")
    diameter: float = spec(unit="m", gt=0.0, doc="hydrodynamic (outer) diameter d")
    mass_per_length: float = spec(unit="kg/m", gt=0.0, doc="mass per unit unstretched length")
    EA: float = spec(unit="N", gt=0.0, doc="axial stiffness (Young's modulus times area)")
    EI: float = spec(unit="N m^2", ge=0.0, doc="bending stiffness")
    damping: float = spec(0.0, unit="N s", ge=0.0,
                          doc="internal damping coefficient c of the Rayleigh dissipation W(54)-(55)")
    integration_points: int = spec(10, unit="-", ge=2, le=100,
                                   doc="N_I: equally spaced trapezoidal points per element for distributed loads")
    compression: bool = spec(True, doc="true: the axial stiffness also acts in compression (the reference's "
                                       "model); false: tension-only material, a slack cable carries no load")
    axial_law: str = spec("formulation", choices=("formulation", "kelvin_voigt"),
                          doc="axial force law. formulation: the cable formulation's own (ANCF: Green strain, "
                              "N = EA eps_G lambda, Rayleigh damping W(55) on the slope rate; nodal_position: "
                              "the paper's eqs. 13-15, N = (L/L0) (EA eps + c EA deps/dt)); kelvin_voigt: "
                              "N = EA eps + damping deps/dt with the engineering strain eps = L/L0 - 1 "
                              "(MoorDyn's law and the snapping case's; the ANCF keeps W(55), which is this "
                              "damping for a straight element)")
    loading: str = spec("bare", choices=("bare", "faired", "sun2011_bare", "sun2011_faired", "normal_tangential"),
                        doc="drag loading functions: bare cable W(60), ribbon-faired W(145), the "
                            "nodal-position paper's bare and faired eqs. 28-29 (use with drag_coefficient), or "
                            "normal_tangential: drag_coefficient on the normal flow (reference d) and "
                            "tangential_drag_coefficient on the flow along the cable (reference pi d), "
                            "MoorDyn's convention")
    drag_coefficient: float | None = spec(None, unit="-", gt=0.0,
                                          doc="constant common drag coefficient C_D; default: C_D(Re) of W(61)-(63)")
    tangential_drag_coefficient: float | None = spec(None, unit="-", ge=0.0,
                                                     doc="C_Dt on the flow along the cable, per wetted perimeter "
                                                         "pi d (loading = 'normal_tangential' only): drag "
                                                         "rho pi d C_Dt |V_t| V_t / 2 per unit length")
    drag_amplification: float = spec(1.0, unit="-", ge=0.0, le=10.0,
                                     doc="G of W(64): the mean (steady) drag is G times the steady drag "
                                         "(1: no amplification; docs/design.md)")
    added_mass_coefficient: float = spec(1.0, unit="-", ge=0.0, le=10.0,
                                         doc="C_m: added mass acts normal to the cable only, W(66)-(75)")
    fluid_loads: bool = spec(True, doc="false: the segment carries no fluid loads at all (drag, buoyancy, added "
                                       "mass), e.g. the parts of a wire in the lee of a structure (appendix A: "
                                       "wind on the span between the sheaves only)")
    name: str = spec("", doc="label used in plots and messages")
    rope: Rope | None = spec(None, doc="rope data for its life: breaking strength and construction (absent: the "
                                       "segment has no rope life)")

    def cable_difference(self, other: "Segment") -> str | None:
        """The first property of the cable itself (not of its loads) in which this segment
        differs from ``other``: what cable paid out over a winch's gear must share with it
        (None: the same cable)."""
        for name in ("diameter", "mass_per_length", "EA", "EI", "damping", "axial_law"):
            if getattr(self, name) != getattr(other, name):
                return name
        return None

    def validate(self, key: str) -> None:
        """Cross-field checks: the normal/tangential drag needs both constant coefficients."""
        if self.loading == "normal_tangential":
            if self.drag_coefficient is None:
                raise SceneError(f"{key}.drag_coefficient", None, "a constant C_D > 0 (required with loading = "
                                                                  "'normal_tangential')")
            if self.tangential_drag_coefficient is None:
                raise SceneError(f"{key}.tangential_drag_coefficient", None,
                                 "a constant C_Dt >= 0 (required with loading = 'normal_tangential')")
        elif self.tangential_drag_coefficient is not None:
            raise SceneError(f"{key}.tangential_drag_coefficient", self.tangential_drag_coefficient,
                             "absent unless loading = 'normal_tangential'")


@dataclasses.dataclass(frozen=True)
class End:
    """Boundary condition at one end of the cable."""

    type: str = spec("free", choices=("pinned", "clamped", "free", "winch", "spool"),
                     doc="pinned: position prescribed, slope free; clamped: position and slope "
                         "prescribed; free: no constraint (a towed body may hang there); winch: fixed "
                         "to the winch drum at its rotation phi, W(120) (top end only); spool: the point "
                         "'position' where the cable leaves its store on the winch, which pays it out "
                         "and hauls it in through the first element (top end only; winch.stored_length; "
                         "towcable_fmu/ancf/feed.py)")
    frame: str = spec("inertial", choices=("inertial", "ship"),
                      doc="frame of 'position': fixed in the inertial frame or moving with the ship")
    position: tuple[float, ...] | None = spec(None, unit="m", length=3,
                                              doc="attachment point (inertial or ship body coordinates); for a "
                                                  "free top end: where it starts (inertial frame)")
    slope: tuple[float, ...] | None = spec(None, unit="-", length=3,
                                           doc="clamped ends: cable direction leaving the end, pointing into "
                                               "the cable (normalised)")
    mass: float = spec(0.0, unit="kg", ge=0.0,
                       doc="point mass lumped at a free end (at the bottom beside a [towbody], e.g. a clump "
                           "weight: part of the cable, not of the body whose pull tension.towbody reports)")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        if self.type == "winch" and self.position is not None:
            raise SceneError(f"{key}.position", list(self.position), "no position for a winch end (the drum "
                                                                     "and its rotation place it)")
        if self.type in ("pinned", "clamped", "spool") and self.position is None:
            raise SceneError(f"{key}.position", None, f"a list of 3 numbers [m] (required for type = '{self.type}')")
        if self.mass > 0.0 and self.type != "free":
            raise SceneError(f"{key}.mass", self.mass, "0 unless the end is free (a held end carries no mass)")
        if self.type == "clamped":
            if self.slope is None:
                raise SceneError(f"{key}.slope", None, "a list of 3 numbers (required for type = 'clamped')")
            if math.hypot(*self.slope) == 0.0:
                raise SceneError(f"{key}.slope", list(self.slope), "a non-zero direction")


@dataclasses.dataclass(frozen=True)
class InitialShape:
    """Rough initial shape handed to the statics solver."""

    shape: str = spec("auto", choices=("auto", "straight", "sag"),
                      doc="auto: 'sag' between two prescribed ends, else 'straight'; straight: along "
                          "'direction' from the top end (with a prescribed bottom end: along the chord, "
                          "compressed or stretched to fit); sag: a parabola between the two ends. A cable "
                          "on a winch is first wrapped around the drum and over the sheave, then continues "
                          "along 'direction'")
    direction: tuple[float, ...] = spec([0.0, 0.0, -1.0], unit="-", length=3,
                                        doc="direction of a straight initial cable from its top end")
    sag_direction: tuple[float, ...] = spec([0.0, 0.0, -1.0], unit="-", length=3,
                                            doc="direction in which a 'sag' shape bulges")


@dataclasses.dataclass(frozen=True)
class Cable:
    """The cable: its segments from the top end to the bottom end, and end conditions."""

    segments: tuple[Segment, ...] = spec(doc="segments from the top (first node) to the bottom (last node)")
    top: End = spec(End(type="pinned", position=(0.0, 0.0, 0.0)), doc="end at the first node")
    bottom: End = spec(End(), doc="end at the last node")
    initial: InitialShape = spec(InitialShape(), doc="rough initial shape for the statics solver")
    formulation: str = spec("ancf", choices=("ancf", "nodal_position"),
                            doc="older alias of the top-level key model (ancf or nodal_position): write model = "
                                "'nodal_position' at the top of the scene instead; given with model, the two must "
                                "agree. The loaded scene carries the model kind here")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        if self.bottom.type == "free" and self.bottom.position is not None:
            raise SceneError(f"{key}.bottom.position", list(self.bottom.position),
                             "no position for a free bottom end (the initial shape places it)")
        if self.bottom.type in ("winch", "spool"):
            raise SceneError(f"{key}.bottom.type", self.bottom.type, "a winch at the top end only")
        if self.top.type == "free" and self.bottom.type != "free":
            raise SceneError(f"{key}.top.type", "free", "'pinned' or 'clamped' (the cable hangs from its top end; "
                                                        "to hold only the lower end, swap the ends)")
        if self.initial.shape == "sag" and self.bottom.type == "free":
            raise SceneError(f"{key}.initial.shape", "sag", "'straight' or 'auto' when the bottom end is free")

    @property
    def n_elements(self) -> int:
        """Total number of elements."""
        return sum(s.elements for s in self.segments)

    @property
    def length(self) -> float:
        """Total unstretched length [m]."""
        return sum(s.length for s in self.segments)


@dataclasses.dataclass(frozen=True)
class ContactLaw:
    """Penalty contact after Hunt and Crossley, W(93): force per unit length
    ``k delta^n (1 + D d(delta)/dt)`` along the surface normal, never pulling."""

    stiffness: float = spec(1e6, unit="N/m^(1+n)", gt=0.0,
                            doc="k_N (the reference quotes it in N/m; with delta in m and n = 1.5)")
    exponent: float = spec(1.5, unit="-", ge=1.0, le=3.0, doc="n")
    damping: float = spec(0.0, unit="s/m", ge=0.0, doc="D")


@dataclasses.dataclass(frozen=True)
class Winch:
    """The winch drum (a cylinder about the ship's Y axis, W(99)) and its PD drive W(136)."""

    position: tuple[float, ...] = spec(unit="m", length=3, doc="drum centre s_w in the ship body frame")
    radius: float = spec(unit="m", gt=0.0, doc="drum radius r_w; the cable centreline wraps at r_w + d/2")
    phi_nom: float = spec(unit="rad", doc="nominal rotation of the cable end from the top of the drum, "
                                          "increasing towards +X (reels in)")
    kp: float = spec(unit="1/s^2", ge=0.0, doc="proportional gain k_1 of the PD drive")
    kd: float = spec(unit="1/s", ge=0.0, doc="derivative gain k_2 of the PD drive")
    contact: ContactLaw = spec(ContactLaw(), doc="cable-drum contact")
    stored_length: float | None = spec(None, unit="m", ge=0.0,
                                       doc="cable stored on the drum at phi_nom (a spool end): the most the winch "
                                           "pays out; winch.payout = (r_w + d/2) (phi_nom - phi) is unstretched "
                                           "cable")
    gear_segments: int = spec(0, unit="-", ge=0,
                              doc="spool end: the segments (from the top) that carry the cable from the spool over "
                                  "the drum and sheaves, a fixed mesh the paid-out cable flows through; the first "
                                  "element of the next segment grows and splits as the winch pays out (their "
                                  "cable is the fed segment's)")
    program_times: tuple[float, ...] = spec([], unit="s",
                                            doc="times of a payout program (increasing): the set-point follows "
                                                "program_payout piecewise linearly and holds after the last time "
                                                "(none: the set-point phi_nom, or the compensation's)")
    program_payout: tuple[float, ...] = spec([], unit="m", doc="winch.payout at program_times")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        times, payout = np.asarray(self.program_times, dtype=float), np.asarray(self.program_payout, dtype=float)
        if times.size != payout.size:
            raise SceneError(f"{key}.program_payout", list(self.program_payout),
                             f"{times.size} values, one per program time")
        if times.size and not (np.all(np.isfinite(times)) and np.all(np.isfinite(payout))):
            raise SceneError(f"{key}.program_times", list(self.program_times), "finite times and payouts")
        if np.any(np.diff(times) <= 0.0):
            raise SceneError(f"{key}.program_times", list(self.program_times), "increasing times [s]")


@dataclasses.dataclass(frozen=True)
class Sheave:
    """The sheave: a grooved wheel about the ship's Y axis (W(94)-(102)), or a plain pulley."""

    position: tuple[float, ...] = spec(unit="m", length=3, doc="sheave centre s_s in the ship body frame")
    radius: float = spec(unit="m", gt=0.0, doc="radius to the root of the groove")
    shape: str = spec("groove", choices=("groove", "cylinder"),
                      doc="groove: two walls meeting at the groove centre, W(100); cylinder: a plain pulley")
    groove_depth: float = spec(0.01, unit="m", gt=0.0, doc="h_g: no force above this height, W(101)")
    throat_angle: float = spec(60.0, unit="deg", gt=0.0, lt=180.0, doc="theta_g: angle between the walls")
    rim_width: float = spec(0.02, unit="m", ge=0.0,
                            doc="width of each flange top beside the groove opening (a cable out of the groove "
                                "rests there or slides off the side)")
    contact: ContactLaw = spec(ContactLaw(), doc="cable-sheave contact")


@dataclasses.dataclass(frozen=True)
class Viv:
    """Vortex-induced vibration: a wake oscillator per node of the loaded segments
    (Westin 2018 appendix A, eqs. A19-A20, after Bai and Qin and Facchinetti), coupled to
    the cable's cross-flow velocity; see :mod:`towcable_fmu.viv`. The flow is the scene's
    uniform current (the fluid of ``[water]``, air for a wind load)."""

    segments: tuple[int, ...] = spec(unit="-", ge=0, doc="indices (0-based, from the top) of the segments whose "
                                                         "nodes carry wake oscillators and whose elements feel A20")
    enabled: bool = spec(True, doc="false: the table is kept but no wake oscillators run")
    cross_flow: tuple[float, ...] = spec([0.0, 0.0, 1.0], unit="-", length=3,
                                         doc="cross-flow direction (its part normal to the flow is used): the "
                                             "lift A20b acts along it and its velocity drives A19")
    a1: float = spec(0.3, unit="-", gt=0.0, le=10.0, doc="wake damping parameter a_1 of A19")
    a2: float = spec(0.2, unit="-", gt=0.0, le=10.0, doc="wake nonlinearity a_2 of A19 (limit cycle "
                                                         "amplitude 2/sqrt(3 a_2))")
    a3: float = spec(12.0, unit="-", ge=0.0, le=1000.0, doc="coupling a_3 of A19 (0: the wake ignores the cable)")
    strouhal: float = spec(0.2, unit="-", gt=0.0, lt=1.0, doc="Strouhal number St: omega_st = 2 pi St U / d, A25")
    cd0: float = spec(0.2, unit="-", ge=0.0, le=10.0, doc="oscillating drag coefficient C_D0 of A20a")
    cl0: float = spec(0.3, unit="-", ge=0.0, le=10.0, doc="oscillating lift coefficient C_L0 of A20b")
    initial_w: float = spec(0.1, unit="-", doc="wake variable w at the start (w' = 0), the same at every node")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        if not self.segments:
            raise SceneError(f"{key}.segments", [], "at least one segment index")
        if len(set(self.segments)) != len(self.segments):
            raise SceneError(f"{key}.segments", list(self.segments), "distinct segment indices")
        if math.hypot(*self.cross_flow) == 0.0:
            raise SceneError(f"{key}.cross_flow", list(self.cross_flow), "a non-zero direction")


@dataclasses.dataclass(frozen=True)
class Current:
    """Mean flow of the water."""

    type: str = spec("none", choices=("none", "uniform", "linear"),
                     doc="none: still water; uniform: 'velocity' everywhere; linear: 'velocity' at the "
                         "surface changing by 'gradient' per metre of height (the flume profile W(140))")
    velocity: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="m/s", length=3,
                                       doc="flow velocity (at the surface for 'linear')")
    gradient: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="1/s", length=3,
                                       doc="'linear': change of the flow velocity per metre of height z")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        if self.type != "linear" and any(self.gradient):
            raise SceneError(f"{key}.gradient", list(self.gradient), "zeros unless type = 'linear'")


@dataclasses.dataclass(frozen=True)
class Turbulence:
    """Turbulent fluctuation of the flow: white noise through a Chebyshev type II low-pass
    filter, scaled to the given standard deviation per axis (section 4.3), uniform in space."""

    std: tuple[float, ...] = spec(unit="m/s", length=3, ge=0.0, doc="standard deviation per axis")
    cutoff: float = spec(2.0, unit="Hz", gt=0.0, doc="stop-band edge of the low-pass filter")
    order: int = spec(4, unit="-", ge=1, le=12, doc="filter order")
    attenuation: float = spec(80.0, unit="dB", gt=0.0, doc="stop-band attenuation")
    sample_rate: float = spec(100.0, unit="Hz", gt=0.0, doc="rate of the generated series (interpolated in between)")
    seed: int = spec(0, unit="-", ge=0, doc="random seed: the same seed gives the same series")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        if not self.cutoff < 0.5 * self.sample_rate:
            raise SceneError(f"{key}.cutoff", self.cutoff, f"< sample_rate / 2 = {0.5 * self.sample_rate:g} Hz")


@dataclasses.dataclass(frozen=True)
class Water:
    """The water: properties, free surface, current."""

    density: float = spec(1025.0, unit="kg/m^3", gt=0.0, doc="density rho_f")
    viscosity: float = spec(1.2e-3, unit="Pa s", gt=0.0, doc="dynamic viscosity mu (for the Reynolds number)")
    surface_z: float = spec(0.0, unit="m", doc="height z of the (flat) free surface; below it is water")
    current: Current = spec(Current(), doc="mean flow")
    turbulence: Turbulence | None = spec(None, doc="turbulent fluctuation of the flow (absent: none)")
    waves: str = spec("off", choices=("off", "motion"),
                      doc="wave kinematics on the cable and the towed body: off (still water, flat surface at "
                          "surface_z), or motion (the irregular sea of [motion], the realisation that moves the "
                          "ship; ANCF cable only)")
    depth: float | None = spec(None, unit="m", gt=0.0,
                               doc="water depth below surface_z for the waves' finite-depth dispersion "
                                   "(absent: deep water)")
    stretching: str = spec("wheeler", choices=("wheeler", "extrapolation"),
                           doc="wave kinematics near the surface: wheeler (stretched to the instantaneous "
                               "surface) or extrapolation (linear above the mean level)")


@dataclasses.dataclass(frozen=True)
class BodyPart:
    """One part of a towed body's drag: projected areas and drag coefficients per axis."""

    area: tuple[float, ...] = spec(unit="m^2", length=3, ge=0.0,
                                   doc="areas projected on the planes normal to x, y, z")
    drag_coefficient: tuple[float, ...] = spec(unit="-", length=3, ge=0.0, doc="drag coefficient per axis")
    name: str = spec("", doc="label")


@dataclasses.dataclass(frozen=True)
class Lift:
    """A lift force of constant direction (a hydrofoil of fixed attitude, section 5.2):
    magnitude 1/2 rho A C_L (V_rel . axis)^2 along 'direction'."""

    area: float = spec(unit="m^2", gt=0.0, doc="planform area A")
    coefficient: float = spec(unit="-", ge=0.0, doc="lift coefficient C_L (magnitude)")
    direction: tuple[float, ...] = spec([0.0, 0.0, -1.0], unit="-", length=3, doc="direction of the lift force")
    axis: tuple[float, ...] = spec([1.0, 0.0, 0.0], unit="-", length=3,
                                   doc="flow direction that makes lift (the foil's chord, fixed in space)")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        for name in ("direction", "axis"):
            if not any(getattr(self, name)):
                raise SceneError(f"{key}.{name}", list(getattr(self, name)), "a non-zero direction")


@dataclasses.dataclass(frozen=True)
class RigidBody:
    """Rigid-body data of a towed body with ``model = "rigid"`` (6 degrees of freedom;
    towcable_fmu/hydro/rigid_body.py, for both cable formulations). Body axes: x forward,
    y port, z up, origin at the centre of gravity (CG); attitude R = Rz(yaw) Ry(pitch) Rx(roll). The body's mass,
    volume, drag parts and added-mass coefficients are the keys of [towbody], read in
    body axes."""

    inertia: tuple[float, ...] = spec(unit="kg m^2", length=3, gt=0.0,
                                      doc="moments of inertia J_xx, J_yy, J_zz about the CG (body axes)")
    tow_point: tuple[float, ...] = spec(unit="m", length=3,
                                        doc="cable attachment (a spherical joint: the cable's last node) "
                                            "relative to the CG (body axes)")
    inertia_products: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="kg m^2", length=3,
                                               doc="off-diagonal entries J_xy, J_xz, J_yz of the inertia tensor "
                                                   "about the CG (J_xy = -integral of x y dm); the tensor must "
                                                   "be positive definite")
    buoyancy_centre: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="m", length=3,
                                              doc="centre of buoyancy relative to the CG (body axes)")
    drag_centre: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="m", length=3,
                                          doc="point where the drag of the parts acts and the relative flow is "
                                              "taken (centre of pressure), relative to the CG (body axes)")
    linear_damping: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="N s/m", length=3, ge=0.0,
                                             doc="linear damping per body axis, force -c u of the flow velocity "
                                                 "relative to the body u, at the drag centre (in water)")
    added_inertia: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="kg m^2", length=3, ge=0.0,
                                            doc="rotational added inertia per body axis (in water)")
    rotational_drag: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="N m s^2", length=3, ge=0.0,
                                              doc="quadratic rotational drag per body axis: moment -k |w| w of "
                                                  "the angular velocity w (in water)")
    rotational_damping: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="N m s", length=3, ge=0.0,
                                                 doc="linear rotational damping per body axis: moment -c w "
                                                     "(in water)")
    attitude: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="rad", length=3,
                                       doc="initial roll, pitch, yaw; the Euler angles are the body's rotation "
                                           "coordinates, so the pitch must stay away from +-pi/2 (checked)")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        jxx, jyy, jzz = self.inertia
        jxy, jxz, jyz = self.inertia_products
        minors = (jxx, jxx * jyy - jxy * jxy,
                  jxx * (jyy * jzz - jyz * jyz) - jxy * (jxy * jzz - jyz * jxz) + jxz * (jxy * jyz - jyy * jxz))
        if not all(m > 0.0 for m in minors):
            raise SceneError(f"{key}.inertia_products", list(self.inertia_products),
                             "products that leave the inertia tensor positive definite")
        if not abs(self.attitude[1]) < 1.4:
            raise SceneError(f"{key}.attitude[1]", self.attitude[1], "a pitch with |pitch| < 1.4 rad (Euler angles "
                                                                     "are singular at +-pi/2)")


@dataclasses.dataclass(frozen=True)
class TowBody:
    """A towed body at the bottom end of the cable: lumped, W(85)-(92) (default), or a
    rigid 6-DOF body (``model = "rigid"``, either cable formulation)."""

    mass: float = spec(unit="kg", gt=0.0, doc="mass m_b")
    volume: float | None = spec(None, unit="m^3", ge=0.0, doc="displaced volume V (or give 'net_weight')")
    height: float = spec(0.0, unit="m", ge=0.0,
                         doc="lumped body: the height over which it passes through the water surface (its "
                             "buoyancy, drag, lift and added mass grow with the submerged fraction of it; 0: a "
                             "point, wet or dry all at once)")
    net_weight: float | None = spec(None, unit="N",
                                    doc="weight minus buoyancy in water; sets the volume to "
                                        "(m_b g - net_weight) / (rho_f g)")
    added_mass_coefficient: tuple[float, ...] = spec([0.0, 0.0, 0.0], unit="-", length=3, ge=0.0,
                                                     doc="C_m,b per axis (inertial axes; body axes for a rigid "
                                                         "body): added mass rho_f V C_m,b, W(89)")
    parts: tuple[BodyPart, ...] = spec([], doc="drag parts; the drag per axis (inertial axes; body axes for a "
                                               "rigid body) is the sum of their C_D A, W(87)")
    lift: Lift | None = spec(None, doc="constant-direction lift (lumped body only)")
    name: str = spec("towbody", doc="label")
    model: str = spec("lumped", choices=("lumped", "rigid"),
                      doc="lumped: a point mass at the last node, W(85)-(92); rigid: a 6-DOF rigid body hanging "
                          "from its tow point ([towbody.rigid]; nodal-position cable: the last node is the tow "
                          "point; ANCF cable: a stiff link joins the last node to it)")
    rigid: RigidBody | None = spec(None, doc="rigid-body data (required exactly when model = 'rigid')")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        if self.volume is not None and self.net_weight is not None:
            raise SceneError(f"{key}.net_weight", self.net_weight, "absent when 'volume' is given")
        if (self.model == "rigid") != (self.rigid is not None):
            raise SceneError(f"{key}.rigid", "[towbody.rigid]" if self.rigid is not None else None,
                             "a table exactly when model = 'rigid'")
        if self.model == "rigid" and self.lift is not None:
            raise SceneError(f"{key}.lift", "[towbody.lift]", "absent with model = 'rigid' (not modelled)")
        if self.model == "rigid" and self.height > 0.0:
            raise SceneError(f"{key}.height", self.height, "0 with model = 'rigid' (its own hydrodynamics)")


@dataclasses.dataclass(frozen=True)
class RigidLoad:
    """A rigid load hanging from the bottom end, in the plane of its swing (section 4.1,
    W(138)-(139)): described by the attachment point P (the cable's last node, a
    spherical joint) and its centre of inertia I, with the mass matrix of W(138) and a
    stiff elastic link between P and I, W(139)."""

    mass: float = spec(unit="kg", gt=0.0, doc="m_L")
    length_pi: float = spec(unit="m", gt=0.0, doc="L_PI: distance from the attachment to the centre of inertia")
    length_pg: float = spec(unit="m", gt=0.0, doc="L_PG: distance from the attachment to the centre of gravity")
    stiffness: float = spec(1e6, unit="N", gt=0.0, doc="k_L: axial stiffness of the link P-I (per unit strain)")
    held: bool = spec(False, doc="true: the statics hold the load at rest with the cable along "
                                 "cable.initial.direction (the holder carries the weight's component normal "
                                 "to it) and the run starts as the load is let go (the release of Westin "
                                 "2018, section 4.1); false: the statics let the load hang")

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        if not self.length_pg <= self.length_pi:
            raise SceneError(f"{key}.length_pg", self.length_pg, f"<= length_pi = {self.length_pi:g} m")


@dataclasses.dataclass(frozen=True)
class SolverSettings:
    """Time integration: generalised-alpha with Newton on a banded Jacobian."""

    time_step: float = spec(0.01, unit="s", gt=0.0, le=10.0, doc="nominal (maximum) time step h")
    integrator: str = spec("genalpha", choices=("genalpha", "rk4", "leapfrog"),
                           doc="genalpha: implicit generalised-alpha with Newton; rk4: explicit classical "
                               "Runge-Kutta with fixed steps (model = 'nodal_position' only); "
                               "leapfrog: explicit, lumped masses, one force evaluation per step, time_step at "
                               "most 0.9 times the mesh's stability limit (nodal_position with a lumped body only; "
                               "towcable_fmu/nodal/explicit.py)")
    rho_inf: float = spec(0.8, unit="-", ge=0.0, le=1.0,
                          doc="spectral radius at infinite frequency (1: no numerical damping)")
    adaptive: bool = spec(False, doc="adapt the step to keep the local error estimate below rtol/atol")
    rtol: float = spec(1e-5, unit="-", gt=0.0, lt=1.0,
                       doc="local error tolerance of a step (adaptive mode): a position's error against atol + rtol "
                           "times its element's length (a strain-like measure, independent of where the origin "
                           "is), a slope's against rtol + atol per metre")
    atol: float = spec(1e-6, unit="m", gt=0.0, doc="absolute local error tolerance of a position (adaptive mode)")
    newton_tol: float = spec(1e-8, unit="-", gt=0.0, le=1e-2,
                             doc="Newton stops when the estimated remaining correction (positions relative "
                                 "to the element length, slopes absolute) is below this; the tension error "
                                 "it allows is about EA times this")
    max_newton_iterations: int = spec(8, unit="-", ge=1, le=100,
                                      doc="Newton iterations a step may take before it is retried (with a fresh "
                                          "Jacobian, then half the step)")
    jacobian_max_age: int = spec(100, unit="-", ge=1, doc="steps a factorised Jacobian may be reused")
    min_time_step: float = spec(1e-7, unit="s", gt=0.0, doc="a step that fails below this size is an error")
    locate_events: bool = spec(True, doc="a step in which a tension-only element (compression = false) goes taut "
                                         "or slack is taken again, shortened to end at that instant (ANCF cable)")


@dataclasses.dataclass(frozen=True)
class StaticsSettings:
    """Equilibrium solver (pseudo-transient continuation with Newton)."""

    enabled: bool = spec(True, doc="solve the statics before a run to start from equilibrium")
    tolerance: float = spec(1e-8, unit="-", gt=0.0, lt=1.0,
                            doc="converged when the largest out-of-balance force is below tolerance times the "
                                "load scale (total weight, drag and tension)")
    max_iterations: int = spec(400, unit="-", ge=1, doc="iteration limit")


@dataclasses.dataclass(frozen=True)
class OutputSettings:
    """What a run records."""

    interval: float = spec(0.05, unit="s", gt=0.0, doc="time between recorded output samples")


@dataclasses.dataclass(frozen=True)
class Scene:
    """A complete scene: everything a simulation needs."""

    cable: Cable = spec(doc="the cable")
    title: str = spec("", doc="one-line title")
    description: str = spec("", doc="what the scene is and where its numbers come from")
    environment: Environment = spec(Environment(), doc="gravity")
    water: Water | None = spec(None, doc="water (absent: the scene is in air, no hydrodynamics)")
    winch: Winch | None = spec(None, doc="winch drum and drive (the cable's top end is on it: type 'winch')")
    sheave: Sheave | None = spec(None, doc="sheave or pulley the cable runs over")
    idlers: tuple[Sheave, ...] = spec([], doc="further sheaves or pulleys (fixed in the ship frame, axis along the "
                                              "ship's Y) the cable runs over after [sheave], in order: contact "
                                              "only, the sheave outputs report [sheave]")
    compensation: dict | None = spec(None, doc="heave-compensation set-point algorithm for runs driven by the "
                                               "scene's own motion (see controllers/README.md); winch radius, "
                                               "phi_nom and the sheave position default to the scene's")
    towbody: TowBody | None = spec(None, doc="lumped towed body at the bottom end (bottom must be free)")
    load: RigidLoad | None = spec(None, doc="rigid load swinging from the bottom end (bottom must be free)")
    viv: Viv | None = spec(None, doc="vortex-induced vibration by wake oscillators (absent: none)")
    motion: dict | None = spec(None, doc="ship motion (see ship_motion/README.md); none: the ship is still")
    solver: SolverSettings = spec(SolverSettings(), doc="time integration")
    statics: StaticsSettings = spec(StaticsSettings(), doc="equilibrium solver")
    output: OutputSettings = spec(OutputSettings(), doc="recording")
    base_dir: str = spec("", doc="folder against which relative file paths are resolved "
                                 "(default: the scene file's folder, or the working directory)")
    based_on: str = spec("", doc=BASED_ON_DOC)

    @property
    def model(self) -> str:
        """The model kind, the scene's top-level ``model`` key: "ancf" or "nodal_position"."""
        return self.cable.formulation

    def _check_spool(self) -> None:
        """A spool end stores cable on the drum, and the gear carries the fed segment's cable."""
        if self.winch.stored_length is None:
            raise SceneError("winch.stored_length", None, "the cable stored on the drum [m], >= 0 (required with "
                                                          "cable.top.type = 'spool')")
        segments, gear = self.cable.segments, self.winch.gear_segments
        if gear >= len(segments):
            raise SceneError("winch.gear_segments", gear, f"fewer than the {len(segments)} segments (the next one is "
                                                          "fed)")
        fed = segments[gear]
        for i in range(gear):
            name = segments[i].cable_difference(fed)
            if name is not None:
                raise SceneError(f"cable.segments[{i}].{name}", getattr(segments[i], name),
                                 f"{getattr(fed, name)!r}, the fed segment's (cable.segments[{gear}]): the paid-out "
                                 "cable flows through the gear's segments")

    def explicit_step(self) -> float:
        """The largest step [s] the explicit leapfrog takes on this scene's mesh: SAFETY times
        its stability limit (:mod:`towcable_fmu.numerics.explicit_step`), whatever the formulation."""
        segs = [s for s in self.cable.segments for _ in range(s.elements)]
        lumped = self.towbody is not None and self.towbody.model == "lumped"
        end_mass = self.cable.bottom.mass + (self.towbody.mass if lumped else 0.0)
        def col(name: str) -> np.ndarray:
            return np.array([getattr(s, name) for s in segs], dtype=float)

        lengths = np.array([s.length / s.elements for s in segs])
        return SAFETY * step_limit(lengths, col("EA"), col("damping"), col("mass_per_length"), end_mass)

    def _check_explicit(self) -> None:
        """What solver.integrator = 'leapfrog' represents: a nodal-position cable with a lumped
        body, at a step within its stability limit."""
        need = f"{self.explicit_step():.4g} s"
        if self.cable.formulation != "nodal_position":
            raise SceneError("solver.integrator", "leapfrog",
                             f"'genalpha' unless model = 'nodal_position' (the explicit path has no "
                             f"bending, winch, sheave or contact; on this mesh it would need solver.time_step <= "
                             f"{need})")
        if self.towbody is not None and self.towbody.model == "rigid":
            raise SceneError("solver.integrator", "leapfrog", "'genalpha' or 'rk4' with towbody.model = 'rigid' "
                                                              "(the explicit path lumps the body at the last node)")
        if self.solver.time_step > self.explicit_step() * (1.0 + 1e-9):  # (the limit's own round-off)
            raise SceneError("solver.time_step", self.solver.time_step,
                             f"<= {need} with solver.integrator = 'leapfrog': {SAFETY:g} times the stability limit "
                             f"of this mesh ({self.explicit_step() / SAFETY:.4g} s; more elements need shorter "
                             f"steps)")

    def validate(self, key: str) -> None:
        """Cross-section checks."""
        if self.solver.integrator == "rk4" and self.cable.formulation != "nodal_position":
            raise SceneError("solver.integrator", "rk4", "'genalpha' unless model = 'nodal_position'")
        if self.solver.integrator == "leapfrog":
            self._check_explicit()
        if (self.cable.top.type in ("winch", "spool")) != (self.winch is not None):
            raise SceneError("cable.top.type", self.cable.top.type, "'winch' or 'spool' exactly when a [winch] is "
                                                                    "given")
        if self.cable.top.type == "spool":
            self._check_spool()
        elif self.winch is not None and self.winch.gear_segments:
            raise SceneError("winch.gear_segments", self.winch.gear_segments, "0 unless cable.top.type = 'spool'")
        if (self.compensation is not None and self.compensation.get("algorithm", "none") != "none"
                and self.winch is not None and self.winch.program_times):
            raise SceneError("winch.program_times", list(self.winch.program_times),
                             "empty with a [compensation] algorithm (it sets the winch's set-point)")
        if (self.winch is not None and self.winch.stored_length is not None and self.winch.program_payout
                and max(self.winch.program_payout) > self.winch.stored_length):
            raise SceneError("winch.program_payout", list(self.winch.program_payout),
                             f"payouts <= winch.stored_length = {self.winch.stored_length:g} m (the cable stored "
                             "on the drum)")
        if self.compensation is not None and self.winch is None:
            raise SceneError("compensation", self.compensation, "absent without a [winch]")
        if self.load is not None and (self.towbody is not None or self.cable.bottom.type != "free"
                                      or self.cable.bottom.mass > 0.0):
            raise SceneError("load", "[load]", "a free bottom end without [towbody] or bottom mass")
        if self.load is not None and self.load.held and not self.statics.enabled:
            raise SceneError("load.held", True, "false when statics.enabled = false (the load is held in the "
                                                "static equilibrium)")
        if self.free_floating and self.statics.enabled and self.sheave is None:
            raise SceneError("statics.enabled", True, "false when both cable ends are free and nothing holds the "
                                                      "cable (a falling or drifting cable has no equilibrium)")
        if self.towbody is not None and self.cable.bottom.type != "free":
            raise SceneError("cable.bottom.type", self.cable.bottom.type, "'free' when a [towbody] is attached")
        body = self.towbody
        if body is not None and self.water is None and (body.parts or body.lift or body.net_weight is not None):
            raise SceneError("towbody", body.name, "no hydrodynamic properties (parts, lift, net_weight) "
                                                   "without a [water] section")
        if body is not None and body.net_weight is not None and self.water is not None:
            if self.environment.gravity == 0.0:
                raise SceneError("towbody.net_weight", body.net_weight, "absent when gravity is 0 (give 'volume')")
            weight = body.mass * self.environment.gravity
            if not 0.0 <= weight - body.net_weight:
                raise SceneError("towbody.net_weight", body.net_weight, f"<= the weight m_b g = {weight:g} N")
        if self.water is not None and self.water.waves != "off" and self.cable.formulation != "ancf":
            raise SceneError("water.waves", self.water.waves, "'off' unless model = 'ancf' (the other "
                                                              "formulations see still water)")
        motion_type = None if self.motion is None else self.motion.get("type")
        if self.water is not None and self.water.waves == "motion" and motion_type != "irregular":
            raise SceneError("water.waves", "motion", "'off' unless [motion] is an irregular sea (type = "
                                                      f"'irregular'; here: {motion_type or 'no [motion]'})")
        if self.idlers and self.sheave is None:
            raise SceneError("idlers", f"{len(self.idlers)} entries", "none without a [sheave]")
        if self.viv is not None:
            self._validate_viv()

    def _validate_viv(self) -> None:
        """The wake oscillators need a uniform flow across the loaded segments."""
        viv = self.viv
        n = len(self.cable.segments)
        for i, s in enumerate(viv.segments):
            if s >= n:
                raise SceneError(f"viv.segments[{i}]", s, f"an index below {n} (the number of cable segments)")
        if self.cable.formulation != "ancf":
            raise SceneError("viv", "[viv]", "absent unless model = 'ancf'")
        diameters = {self.cable.segments[s].diameter for s in viv.segments}
        if len(diameters) > 1:
            raise SceneError("viv.segments", list(viv.segments), "segments of one diameter (one Strouhal "
                                                                 "frequency for all wake oscillators)")
        if not viv.enabled:
            return
        water = self.water
        if water is None or water.current.type != "uniform" or math.hypot(*water.current.velocity) == 0.0:
            raise SceneError("water.current", None if water is None else water.current.type,
                             "a uniform current of non-zero velocity when [viv] is enabled (the free stream U)")
        u = np.asarray(water.current.velocity, dtype=float)
        u /= np.linalg.norm(u)
        c = np.asarray(viv.cross_flow, dtype=float)
        c /= np.linalg.norm(c)
        if abs(float(u @ c)) > 0.99:
            raise SceneError("viv.cross_flow", list(viv.cross_flow),
                             "a direction not along the current (angle to it > 8 deg)")

    @property
    def free_floating(self) -> bool:
        """True when no end is held: the cable and body move freely (no static equilibrium)."""
        return self.cable.top.type == "free" and self.cable.bottom.type == "free"

    def towbody_volume(self) -> float:
        """Displaced volume of the towed body [m^3] (0 without a body or without water)."""
        body = self.towbody
        if body is None or self.water is None:
            return 0.0
        if body.volume is not None:
            return body.volume
        if body.net_weight is not None:
            g = self.environment.gravity
            return (body.mass * g - body.net_weight) / (self.water.density * g)
        return 0.0
