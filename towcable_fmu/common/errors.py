"""Exceptions shared by every part of towcable.

Every error raised for bad user input names the offending key, its value and what
is allowed, so that the message alone tells the user what to change.
"""

from __future__ import annotations


class TowcableError(Exception):
    """Base class of all towcable errors."""


class SceneError(TowcableError, ValueError):
    """A scene file, an override or a parameter is invalid.

    Parameters
    ----------
    key
        Dotted path of the offending entry (for example ``cable.segments[0].length``).
    value
        The value that was given.
    allowed
        Human-readable description of what is allowed (for example ``"> 0 m"``).
    """

    def __init__(self, key: str, value: object, allowed: str) -> None:
        self.key = key
        self.value = value
        self.allowed = allowed
        super().__init__(f"{key} = {value!r} is invalid: allowed {allowed}")


class SolverError(TowcableError, RuntimeError):
    """The solver could not complete a step (Newton failed at the minimum step size,
    or a non-finite value appeared). The simulation state is left as it was before
    the failed call."""
