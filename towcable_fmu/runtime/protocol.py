"""What every simulation offers, whatever its model (ANCF, nodal-position or rigid-link
cable): the command line, the TowCable FMU, sweeps and studies use only this.

:func:`towcable_fmu.models.simulation_for` picks the class; tests/test_models.py checks
each against :class:`CableSimulation`.
"""

from __future__ import annotations

from typing import Any, Callable, Iterable, Mapping, Protocol, runtime_checkable

import numpy as np

#: Solver counters every simulation reports in :meth:`CableSimulation.statistics`, by one
#: name whatever the model: accepted steps, residual (right-hand-side) evaluations and
#: factorisations of the iteration matrix. The generalised-alpha models also report
#: ``solver.rejected_steps`` and ``solver.newton_iterations``; the statics add
#: ``solver.statics_*``.
SOLVER_STATISTICS = ("solver.steps", "solver.residual_evaluations", "solver.jacobian_factorisations")


@runtime_checkable
class CableSimulation(Protocol):
    """One towed-cable system in time (SI units throughout)."""

    #: Current simulation time [s].
    time: float
    #: The loaded scene the simulation was built from (read for its name and title; the
    #: model itself reads it once, when it is built).
    scene: Any
    #: The outputs without ``time``, in the order of :meth:`step_row`.
    names: tuple[str, ...]

    @property
    def n_elements(self) -> int:
        """Number of elements of the cable (links of the rigid-link model)."""

    def initialize(self, t0: float = 0.0, ship: np.ndarray | None = None,
                   setpoint: tuple[float, float] | None = None, statics: bool | None = None) -> dict[str, float]:
        """The initial state at ``t0`` [s] (static equilibrium if ``statics``; None: the
        scene's choice); the outputs there."""

    def step(self, dt: float, ship: np.ndarray, setpoint: tuple[float, float] | None = None) -> dict[str, float]:
        """Advance by ``dt`` [s] with the ship state (3, 6) and winch set-point at the step's
        start; the outputs at the new time."""

    def step_row(self, dt: float, ship: np.ndarray | None = None,
                 setpoint: tuple[float, float] | None = None) -> np.ndarray:
        """:meth:`step` with the outputs as an array in the order of :attr:`names`."""

    def run(self, duration: float, interval: float | None = None,
            progress: Callable[[float, float], None] | None = None) -> dict[str, np.ndarray]:
        """Record the outputs every ``interval`` [s] for ``duration`` [s] (the scene's own
        motion); columns :attr:`output_names`."""

    @property
    def output_names(self) -> tuple[str, ...]:
        """The outputs, ``time`` first."""

    def outputs(self) -> dict[str, float]:
        """The outputs at the current state."""

    def only_outputs(self, wanted: Iterable[str]) -> None:
        """The caller reads only the outputs in ``wanted`` from now on: the model may leave
        the others out of :attr:`names` (and not compute them)."""

    def unit_of(self, name: str) -> str:
        """Unit of an output or statistic name."""

    def statistics(self) -> dict[str, float]:
        """Solver counters (:data:`SOLVER_STATISTICS` and the model's own ``solver.*``)."""

    def get_state(self) -> dict[str, Any]:
        """The complete state as JSON-able data."""

    def set_state(self, data: Mapping[str, Any]) -> None:
        """Restore a state from :meth:`get_state`."""
