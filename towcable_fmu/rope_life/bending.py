"""Bending cycles of every material point of the rope as it runs onto and off the drum and
over the sheave, from a run's winch history and the scene's geometry.

A material point is named by its unstretched distance x [m] from the rope's bottom end
(the towed-body end, which never leaves the water). The rope is bent on the drum and on
the sheave and straight elsewhere: every time a material point crosses one of the three
places where that changes (it leaves the drum; it touches the sheave; it leaves the
sheave) it is bent or straightened once: half a bending cycle. A pass over the sheave
is therefore one full cycle (bend and straighten), a wrap onto the drum half of one, and
a point that runs onto the sheave and back off the same side also makes one cycle.

Where those places are in x at each instant:

* winch end (``cable.top.type = "winch"``): the rope's top end is fixed to the drum at
  its rotation phi (output ``winch.phi``, from the top of the drum towards +X, W(120)),
  so x_top = L (the unstretched length) and the rope wrapped between the end and the
  drum's departure point is (r_w + d/2)(phi - alpha_d);
* spool end (``cable.top.type = "spool"``): the spool point on the drum at angle
  alpha_s is x_top = ``winch.deployed``, and (r_w + d/2)(alpha_s - alpha_d) of rope lies
  on the drum between it and the departure point;
* the straight span from the drum to the sheave is the two circles' common tangent
  (fixed in the ship frame), and the rope on the sheave is (r_s + d/2) times the wrap
  angle (output ``contact.wrap_angle``).

The lengths are geometric (stretched) lengths taken as unstretched: the error is the
strain T/EA times the length from the top end (for the full-scale scenes 6e-4 x 10 m =
6 mm). Idlers after the sheave are not counted.
"""

from __future__ import annotations

from typing import Callable, Mapping, NamedTuple

import numpy as np

from ..scene.model import Scene


class RopePath(NamedTuple):
    """The rope's path over drum and sheave in the ship's x-z plane (lengths [m], angles [rad])."""

    drum_radius: float        #: centreline wrap radius on the drum r_w + d/2
    sheave_radius: float      #: centreline radius over the sheave r_s + d/2
    departure_angle: float    #: alpha_d, where the rope leaves the drum (from the top towards +X)
    span: float               #: straight length from the drum to the sheave
    spool_angle: float | None  #: alpha_s of a spool point on the drum (None: a winch end)


def _angle_from_top(vector: np.ndarray) -> float:
    """Angle of an (x, z) vector from +z towards +x [rad], in (-pi, pi]."""
    return float(np.arctan2(vector[0], vector[1]))


def common_tangent(c1: np.ndarray, r1: float, c2: np.ndarray, r2: float) -> tuple[np.ndarray, float]:
    """The straight piece of a rope that turns the same way (clockwise in the x-z plane,
    x right and z up: over the top towards -x) around two circles, from circle 1 to circle 2.

    Parameters
    ----------
    c1, c2
        Centres (x, z) [m].
    r1, r2
        Radii [m].

    Returns
    -------
    normal
        Unit (x, z) vector from each centre to its tangent point [-].
    length
        Length of the straight piece [m].
    """
    d = np.asarray(c2, dtype=float) - np.asarray(c1, dtype=float)
    dist = float(np.hypot(*d))
    if not dist > abs(r1 - r2):
        raise ValueError(f"drum and sheave overlap: centres {dist:g} m apart, radii {r1:g} and {r2:g} m")
    e = d / dist
    perp = np.array([-e[1], e[0]])
    a = (r1 - r2) / dist
    for b in (np.sqrt(1.0 - a * a), -np.sqrt(1.0 - a * a)):
        n = a * e + b * perp
        t = d + (r2 - r1) * n
        # clockwise travel: the normal is the travel direction turned by -90 degrees
        if float(n @ np.array([t[1], -t[0]])) > 0.0:
            return n, float(np.hypot(*t))
    raise AssertionError("no clockwise tangent")  # pragma: no cover (one of the two always is)


def rope_path(scene: Scene) -> RopePath:
    """The path of the scene's rope over its drum and sheave.

    Raises
    ------
    ValueError
        The scene has no winch or no sheave, or a spool point that is not on the drum.
    """
    if scene.winch is None or scene.sheave is None:
        raise ValueError("bending cycles need a [winch] and a [sheave] in the scene")
    d = scene.cable.segments[0].diameter
    drum_c = np.array(scene.winch.position, dtype=float)[[0, 2]]
    sheave_c = np.array(scene.sheave.position, dtype=float)[[0, 2]]
    rw, rs = scene.winch.radius + 0.5 * d, scene.sheave.radius + 0.5 * d
    normal, span = common_tangent(drum_c, rw, sheave_c, rs)
    spool = None
    if scene.cable.top.type == "spool":
        offset = np.array(scene.cable.top.position, dtype=float)[[0, 2]] - drum_c
        if scene.cable.top.frame != "ship" or abs(float(np.hypot(*offset)) - rw) > 1e-3:
            raise ValueError("bending cycles of a spool end need its point on the drum (ship frame, at r_w + d/2)")
        spool = _angle_from_top(offset)
    return RopePath(rw, rs, _angle_from_top(normal), span, spool)


def bend_places(path: RopePath, length: float, series: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Where in x the rope leaves the drum, touches the sheave and leaves it, at each sample.

    Parameters
    ----------
    path
        The scene's rope path.
    length
        Unstretched length of the rope [m].
    series
        The run's outputs: ``winch.phi`` (winch end) or ``winch.deployed`` (spool end)
        [rad, m], and ``contact.wrap_angle`` [rad].

    Returns
    -------
    dict
        ``drum``, ``sheave_on``, ``sheave_off``: x [m] (from the bottom end) per sample.
    """
    if path.spool_angle is None:
        on_drum = path.drum_radius * (np.asarray(series["winch.phi"], dtype=float) - path.departure_angle)
        if np.any(on_drum < 0.0):
            raise ValueError("the rope's end left the drum (winch.phi below the departure angle "
                             f"{path.departure_angle:.4g} rad)")
        drum = length - on_drum
    else:
        wrapped = path.drum_radius * ((path.spool_angle - path.departure_angle) % (2.0 * np.pi))
        drum = np.asarray(series["winch.deployed"], dtype=float) - wrapped
    sheave_on = drum - path.span
    return {"drum": drum, "sheave_on": sheave_on,
            "sheave_off": sheave_on - path.sheave_radius * np.asarray(series["contact.wrap_angle"], dtype=float)}


def half_cycles(grid: np.ndarray, place: np.ndarray, weight: np.ndarray | None = None) -> np.ndarray:
    """How often each material point crosses a moving place (each crossing half a cycle).

    Between samples k and k + 1 the place sweeps [min, max) of its two positions; a point
    in there is crossed once (a point the place only touches and turns back at is not).

    Parameters
    ----------
    grid
        Material points x [m], increasing.
    place
        The place's x [m] at each sample.
    weight
        A weight per step (len(place) - 1), e.g. the tension at the crossing [N]; None: 1.

    Returns
    -------
    numpy.ndarray
        Per material point, the number of crossings (or the sum of the weights of its
        crossings).
    """
    place = np.asarray(place, dtype=float)
    lo, hi = np.minimum(place[:-1], place[1:]), np.maximum(place[:-1], place[1:])
    w = np.ones(lo.size) if weight is None else np.asarray(weight, dtype=float)
    start, stop = np.searchsorted(grid, lo, "left"), np.searchsorted(grid, hi, "left")
    diff = np.zeros(grid.size + 1)
    np.add.at(diff, start, w)
    np.add.at(diff, stop, -w)
    return np.cumsum(diff[:-1])


class BendingCycles(NamedTuple):
    """Bending cycles along the rope over a run."""

    x: np.ndarray                #: material points, unstretched distance from the bottom end [m]
    sheave: np.ndarray           #: bending cycles over the sheave (bend and straighten = 1) [-]
    drum: np.ndarray             #: bending cycles onto and off the drum (a wrap = 0.5) [-]
    sheave_tension: np.ndarray   #: mean tension at the point's sheave crossings (NaN: none) [N]
    max_tension: np.ndarray      #: largest tension at any of the point's crossings (NaN: none) [N]
    damage: np.ndarray | None    #: Miner sum of the point's half cycles, 1/2 / N(S) each (None: no endurance) [-]


def bending_cycles(path: RopePath, length: float, series: Mapping[str, np.ndarray],
                   spacing: float = 0.01,
                   endurance: Callable[[np.ndarray], np.ndarray] | None = None) -> BendingCycles:
    """Bending cycles of every material point over a run, with the tension at its passages.

    Parameters
    ----------
    path
        The scene's rope path (:func:`rope_path`).
    length
        Unstretched rope length [m] (the winch end's top; the most a spool holds plus what is out).
    series
        The run's outputs (see :func:`bend_places`), with ``tension.winch`` (used at the drum and
        where the rope touches the sheave) and ``tension.sheave`` (where it leaves) [N].
    spacing
        Distance between the material points [m].
    endurance
        Bending cycles to discard N(S) at tensions S [N] (None: no damage), e.g. from
        :func:`~towcable_fmu.rope_life.rope_data.bending_cycles_to_discard`.
    """
    places = bend_places(path, length, series)
    x = np.arange(0.0, length + 0.5 * spacing, spacing)
    t_winch = np.asarray(series["tension.winch"], dtype=float)
    t_sheave = np.asarray(series["tension.sheave"], dtype=float)
    step = {"drum": t_winch, "sheave_on": t_winch, "sheave_off": t_sheave}
    count, tension_sum, largest = {}, {}, np.full(x.size, np.nan)
    damage = None if endurance is None else np.zeros(x.size)
    for name, place in places.items():
        at_step = 0.5 * (step[name][:-1] + step[name][1:])
        count[name] = half_cycles(x, place, None)
        tension_sum[name] = half_cycles(x, place, at_step)
        largest = np.fmax(largest, _largest_crossing_tension(x, place, at_step))
        if damage is not None:
            damage += half_cycles(x, place, 0.5 / endurance(at_step))
    sheave_crossings = count["sheave_on"] + count["sheave_off"]
    if damage is not None:  # a point never crossed has none (not the running sum's round-off)
        damage[sheave_crossings + count["drum"] == 0] = 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        mean_sheave = np.where(sheave_crossings > 0, (tension_sum["sheave_on"] + tension_sum["sheave_off"])
                               / sheave_crossings, np.nan)
    return BendingCycles(x, 0.5 * sheave_crossings, 0.5 * count["drum"], mean_sheave, largest, damage)


def _largest_crossing_tension(grid: np.ndarray, place: np.ndarray, tension: np.ndarray) -> np.ndarray:
    """Per material point, the largest tension of the steps whose sweep crosses it (NaN: none)."""
    out = np.full(grid.size, np.nan)
    lo, hi = np.minimum(place[:-1], place[1:]), np.maximum(place[:-1], place[1:])
    start, stop = np.searchsorted(grid, lo, "left"), np.searchsorted(grid, hi, "left")
    for k in np.flatnonzero(stop > start):
        segment = out[start[k]:stop[k]]
        np.fmax(segment, tension[k], out=segment)
    return out
