"""The rope life of one or more runs of a scene: tension damage, bending cycles along the
rope and extremes, gathered for the report (:mod:`.report`) and the command line."""

from __future__ import annotations

import dataclasses
from typing import Mapping, NamedTuple, Sequence

import numpy as np

from ..common.errors import SceneError
from ..scene.model import Rope, Scene
from . import bending, extremes
from .extremes import STORM
from .rope_data import TNCurve, bending_cycles_to_discard, tn_curve
from .tension_fatigue import YEAR, TensionDamage, tension_damage


def scene_rope(scene: Scene) -> Rope:
    """The rope data of a scene's cable: the one ``rope`` table its segments give.

    Raises
    ------
    SceneError
        No segment gives rope data, or two give different data (naming them).
    """
    given = [(i, s.rope) for i, s in enumerate(scene.cable.segments) if s.rope is not None]
    if not given:
        raise SceneError("cable.segments[].rope", None, "a table in at least one segment: the rope's "
                         "breaking_strength [N] and construction, e.g. rope = { breaking_strength = 69800.0, "
                         "construction = \"six_strand\" }")
    first, rope = given[0]
    for i, other in given[1:]:
        if other != rope:
            raise SceneError(f"cable.segments[{i}].rope", dataclasses.asdict(other), f"the same as cable.segments[{first}].rope (one rope per "
                             "cable for its life)")
    return rope


class RunLife(NamedTuple):
    """The rope life of one run."""

    label: str                                #: the run's name (its file)
    tension: TensionDamage                    #: rainflow and Miner damage of the signal
    peaks: extremes.PeakFit | None            #: Weibull fit of the signal's peaks (None: too few)
    maximum: float                            #: largest value of the signal in the window [N]
    bending: bending.BendingCycles | None     #: bending cycles along the rope (None: no winch or sheave)


class Assessment(NamedTuple):
    """The rope life of a scene from one or more runs (seeds) of the same sea."""

    signal: str                  #: the tension output assessed
    rope: Rope                   #: the rope data
    curve: TNCurve               #: its T-N curve
    storm: float                 #: storm duration of the most probable maxima [s]
    runs: list[RunLife]          #: per run
    gumbel_mpm: float | None     #: MPM from the Gumbel fit of the runs' maxima (None: fewer than 3 runs) [N]

    def damage_per_year(self) -> float:
        """Mean tension damage per year over the runs [1/year]."""
        return float(np.mean([r.tension.per_year for r in self.runs]))

    def bending_per_hour(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """Material points x [m] and the mean sheave and drum bending cycles per hour there
        over the runs (None: no bending counted)."""
        found = [(r.bending, r.tension.duration) for r in self.runs if r.bending is not None]
        if not found:
            return None
        size = min(b.x.size for b, _ in found)
        sheave = np.mean([b.sheave[:size] * 3600.0 / d for b, d in found], axis=0)
        drum = np.mean([b.drum[:size] * 3600.0 / d for b, d in found], axis=0)
        return found[0][0].x[:size], sheave, drum

    def bending_damage_per_year(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Material points x [m] and the mean bending damage per year there over the runs
        [1/year] (None: no endurance given or no bending counted)."""
        found = [(r.bending, r.tension.duration) for r in self.runs
                 if r.bending is not None and r.bending.damage is not None]
        if not found:
            return None
        size = min(b.x.size for b, _ in found)
        return found[0][0].x[:size], np.mean([b.damage[:size] * YEAR / d for b, d in found], axis=0)


def _endurance(rope: Rope):
    """The rope's bending cycles to discard N(S) [-] of tension S [N] (None: not given)."""
    if rope.bending_cycles is None:
        return None
    return lambda tension: bending_cycles_to_discard(tension, rope.bending_cycles, rope.bending_tension,
                                                     rope.bending_exponent)


def _window(series: Mapping[str, np.ndarray], settle: float) -> dict[str, np.ndarray]:
    keep = np.asarray(series["time"]) >= settle
    if np.count_nonzero(keep) < 2:
        raise ValueError(f"settle = {settle:g} s leaves fewer than 2 samples of the run")
    return {k: np.asarray(v)[keep] for k, v in series.items()}


def _rope_length(scene: Scene, series: Mapping[str, np.ndarray]) -> float:
    """Unstretched rope that can reach the drum's departure point [m]."""
    if scene.cable.top.type == "spool":
        return float(np.max(series["winch.deployed"]))
    return scene.cable.length


def assess_run(scene: Scene, series: Mapping[str, np.ndarray], label: str, signal: str, rope: Rope,
               storm: float, settle: float = 0.0) -> RunLife:
    """The rope life of one run.

    Parameters
    ----------
    scene
        The scene the run was made of.
    series
        The run's outputs (contract names) with ``time`` [s].
    label
        Name of the run.
    signal
        Tension output to assess, e.g. ``tension.sheave`` [N].
    rope
        The rope data.
    storm
        Storm duration of the most probable maximum [s].
    settle
        Samples before this time are left out [s].

    Raises
    ------
    ValueError
        The run lacks the signal (or the outputs the bending count needs).
    """
    if signal not in series:
        raise ValueError(f"{label}: no output '{signal}' (the run has: {', '.join(sorted(series))})")
    s = _window(series, settle)
    damage = tension_damage(s["time"], s[signal], rope.breaking_strength, tn_curve(rope.construction))
    try:
        peaks = extremes.mpm_from_peaks(s["time"], s[signal], storm)
    except ValueError:
        peaks = None
    counted = None
    if scene.winch is not None and scene.sheave is not None:
        need = ["contact.wrap_angle", "tension.winch", "tension.sheave",
                "winch.deployed" if scene.cable.top.type == "spool" else "winch.phi"]
        missing = [n for n in need if n not in s]
        if missing:
            raise ValueError(f"{label}: the bending count needs the outputs {', '.join(missing)}")
        counted = bending.bending_cycles(bending.rope_path(scene), _rope_length(scene, s), s,
                                         endurance=_endurance(rope))
    return RunLife(label, damage, peaks, float(np.max(s[signal])), counted)


def assess(scene: Scene, runs: Sequence[tuple[str, Mapping[str, np.ndarray]]], signal: str = "tension.sheave",
           storm: float = STORM, settle: float = 0.0) -> Assessment:
    """The rope life of a scene from runs of the same sea (seeds).

    Parameters
    ----------
    scene
        The scene.
    runs
        (label, series) per run.
    signal, storm, settle
        See :func:`assess_run`.
    """
    rope = scene_rope(scene)
    lives = [assess_run(scene, series, label, signal, rope, storm, settle) for label, series in runs]
    gumbel = None
    if len(lives) >= 3:
        durations = {round(r.tension.duration, 6) for r in lives}
        if len(durations) > 1:
            raise ValueError(f"runs of different durations {sorted(durations)} s: a Gumbel fit of their maxima needs "
                             "equally long runs")
        gumbel = extremes.mpm_from_maxima(np.array([r.maximum for r in lives]), lives[0].tension.duration, storm)
    return Assessment(signal, rope, tn_curve(rope.construction), storm, lives, gumbel)


def life_years(per_year: float) -> float:
    """Years to a Miner sum of 1 at a damage rate [1/year] (inf at no damage)."""
    return float("inf") if per_year <= 0.0 else 1.0 / per_year

