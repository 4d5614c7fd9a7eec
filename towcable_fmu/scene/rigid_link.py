"""Scene tables of the rigid-link model (``model = "rigid_link"`` in a scene file).

Frame: ``x`` horizontal along the tow (the tug ahead, at larger ``x``; ``x = 0`` at the
towed vessel's initial fairlead), ``z`` up from the mean waterline (both fairleads start
at ``layout.height``). Each class is one TOML table; every field declares its unit,
default and allowed range through :func:`~towcable_fmu.common.schema.spec`.
"""

from __future__ import annotations

import dataclasses

from ..common.errors import SceneError
from ..common.schema import spec
from .model import Environment
from ..builtin_scenes import BASED_ON_DOC


@dataclasses.dataclass(frozen=True)
class LinkCable:
    """The cable, discretised into equal rigid links joined by elastic, damped hinges."""

    links: int = spec(unit="-", ge=2, le=500, doc="number n of rigid links")
    mass_per_length: float = spec(unit="kg/m", gt=0.0, doc="mass per unit length (lumped at each link's centre)")
    EI: float = spec(0.0, unit="N m^2", ge=0.0,
                     doc="bending stiffness; each interior joint gets the rotational stiffness k = EI / l")
    bending_damping: float = spec(0.0, unit="N m^2 s", ge=0.0,
                                  doc="bending damping; each interior joint gets the rotational damping c = value / l")
    EA: float = spec(0.0, unit="N", ge=0.0,
                     doc="axial stiffness of the real cable: not used by the rigid links (inextensible), "
                         "kept to compare with the elastic catenary and the ANCF scene")


@dataclasses.dataclass(frozen=True)
class Vessel:
    """A vessel at one end of the cable: mass, heave PD force, quadratic resistance."""

    mass: float = spec(unit="kg", gt=0.0, doc="mass M (lumped at the fairlead)")
    heave_kp: float = spec(unit="N/m", ge=0.0, doc="proportional gain of the vertical force (heave stiffness)")
    heave_kd: float = spec(unit="N s/m", ge=0.0, doc="derivative gain of the vertical force (heave damping)")
    resistance: float = spec(0.0, unit="N s^2/m^2", ge=0.0,
                             doc="quadratic hull resistance coefficient: F_x = -value |u| u")
    wave_amplitude: float = spec(0.0, unit="m", ge=0.0, doc="amplitude of the heave reference z_ref")
    wave_period: float = spec(8.0, unit="s", gt=0.0, doc="period of the heave reference")
    wave_phase: float = spec(0.0, unit="rad", doc="phase of the heave reference z_ref = z0 + A sin(2 pi t / T + phase)")


@dataclasses.dataclass(frozen=True)
class Thrust:
    """Motor thrust on the tug, brought to ``maximum`` with a trapezoidal rate profile."""

    maximum: float = spec(320e3, unit="N", ge=0.0, doc="thrust after the ramp")
    ramp_time: float = spec(80.0, unit="s", gt=0.0, doc="time to reach the maximum")
    rise_fraction: float = spec(0.25, unit="-", gt=0.0, le=0.5,
                                doc="share of the ramp time spent raising (and again lowering) the thrust rate")


@dataclasses.dataclass(frozen=True)
class Layout:
    """Initial configuration: the cable hangs as a parabola between the two fairleads."""

    span: float = spec(30.0, unit="m", gt=0.0, doc="horizontal distance D between the fairleads")
    sag: float = spec(2.0, unit="m", ge=0.0, doc="sag d of the initial parabola z = -4 d (x/D)(1 - x/D)")
    height: float = spec(0.0, unit="m", doc="height z0 of both fairleads (and of the heave references)")


@dataclasses.dataclass(frozen=True)
class RigidLinkSolver:
    """Time integration with one of scipy's ODE solvers (scipy.integrate)."""

    method: str = spec("LSODA", choices=("LSODA", "Radau", "BDF", "DOP853", "RK45"),
                       doc="scipy.integrate solver class")
    rtol: float = spec(1e-7, unit="-", gt=0.0, lt=1.0, doc="relative tolerance")
    atol: float = spec(1e-8, unit="-", gt=0.0, doc="absolute tolerance (m, rad, m/s, rad/s)")
    max_step: float = spec(0.05, unit="s", gt=0.0, doc="largest step")
    taut_tolerance: float = spec(1e-3, unit="-", gt=0.0, lt=1.0,
                                 doc="the cable is taut when span >= (1 - value) x length")


@dataclasses.dataclass(frozen=True)
class RigidLinkOutput:
    """Recording."""

    interval: float = spec(0.1, unit="s", gt=0.0, doc="time between recorded output samples")


@dataclasses.dataclass(frozen=True)
class RigidLinkScene:
    """A tug and a towed vessel joined by a chain of rigid links (Gomes & Gomes 2021)."""

    cable: LinkCable = spec(doc="the cable")
    tug: Vessel = spec(doc="the tug (cable end at the first link)")
    towed: Vessel = spec(doc="the towed vessel (cable end at the last link)")
    model: str = spec("rigid_link", choices=("rigid_link",), doc="model kind (see the top-level 'model' key)")
    title: str = spec("", doc="one-line title")
    description: str = spec("", doc="what the scene is and where its numbers come from")
    environment: Environment = spec(Environment(), doc="gravity")
    thrust: Thrust = spec(Thrust(), doc="motor thrust on the tug")
    layout: Layout = spec(Layout(), doc="initial configuration")
    solver: RigidLinkSolver = spec(RigidLinkSolver(), doc="time integration")
    output: RigidLinkOutput = spec(RigidLinkOutput(), doc="recording")
    base_dir: str = spec("", doc="folder of the scene file (unused; accepted for the loader)")
    based_on: str = spec("", doc=BASED_ON_DOC)

    def validate(self, key: str) -> None:
        """Cross-field checks."""
        if self.layout.sag >= 0.5 * self.layout.span:
            raise SceneError("layout.sag", self.layout.sag, f"< span / 2 = {0.5 * self.layout.span:g} m")
