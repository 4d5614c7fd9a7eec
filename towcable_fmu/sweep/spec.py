"""Sweep specification: the TOML file of ``towcable sweep``, validated and expanded into cases.

A sweep file has three tables::

    [sweep]
    mode = "scene"            # "scene": the scene's simulation (fast); "cosim": the three FMUs
    scene = "full_scale"      # built-in name or TOML file (relative to the sweep file)
    duration = 120.0          # simulated time per case [s]
    settle = 20.0             # start-up time left out of the statistics [s]
    interval = 0.05           # recording interval [s]
    output = "out/sweep"      # results folder (relative to the current directory)
    table = "results.csv"     # results table in that folder: .csv, or .parquet (needs pyarrow)
    series = false            # also write each case's time series (series/<case_id>.csv)
    statistics = ["tension.sheave.max", "tension.top.p99", ...]   # default: DEFAULT_STATISTICS
    probabilities = [[0.1, 0.2], [0.3, 0.4]]   # optional: the scatter diagram, one probability per case

    [fixed]                   # overrides applied to every case (dotted scene keys or aliases)
    "solver.time_step" = 0.02

    [parameters]              # the swept values; every combination is one case
    hs = [1.0, 2.0, 3.0]
    heading = { start = 0.0, stop = 180.0, step = 45.0 }   # stop included
    tp = { start = 6.0, stop = 12.0, num = 4 }             # num values, ends included
    compensation = ["none", "simplified_sheave"]
    "cable.segments[3].length" = [250.0, 300.0]

A parameter is a dotted scene key (as ``--set``) or one of the :data:`ALIASES`. Each
case's identity is the SHA-256 hash of its full parameter set (mode, scene, run
settings and every override, see :func:`case_id`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import json
import math
import tomllib
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

from ..common.errors import SceneError
from .statistics import DEFAULT_STATISTICS, DERIVED, statistic

#: Short parameter names -> the scene keys they set (``{n}``: every cable segment).
ALIASES: dict[str, tuple[str, ...]] = {
    "hs": ("motion.hs",),
    "tp": ("motion.tp",),
    "heading": ("motion.heading",),
    "seed": ("motion.seed",),
    "speed": ("motion.speed",),
    "compensation": ("compensation.algorithm",),
    "G": ("cable.segments[{n}].drag_amplification",),
}

MODES = ("scene", "cosim")
SWEEP_KEYS = {"mode", "scene", "duration", "settle", "interval", "step", "output", "series", "statistics",
              "fraction", "fmu_dir", "table", "probabilities"}
#: Suffixes of the results table: CSV, or Parquet (needs pyarrow).
TABLE_SUFFIXES = (".csv", ".parquet")
TOP_KEYS = {"sweep", "fixed", "parameters"}


class SpecError(SceneError):
    """An invalid sweep file: the message names the key, the value and what is allowed."""


@dataclasses.dataclass(frozen=True)
class RunSettings:
    """How each case runs (the same for every case).

    Attributes
    ----------
    mode
        ``"scene"`` (the scene's own simulation, :func:`towcable_fmu.models.simulation_from`:
        its own motion and compensation) or ``"cosim"`` (:func:`towcable_fmu.cosim.run_cosim`, three FMUs).
    scene
        Built-in scene name or absolute path of a scene file.
    duration
        Simulated time per case [s].
    settle
        Start-up time left out of the statistics [s], in [0, duration).
    interval
        Recording interval [s].
    step
        Communication step of the co-simulation [s] (cosim mode only).
    fraction
        Share of the towed-body positions inside the ellipsoid [-].
    fmu_dir
        Folder of the FMUs (cosim mode; built there when missing).
    """

    mode: str = "scene"
    scene: str = "full_scale"
    duration: float = 120.0
    settle: float = 20.0
    interval: float = 0.05
    step: float = 0.01
    fraction: float = 0.95
    fmu_dir: str = "fmus"


@dataclasses.dataclass(frozen=True)
class Case:
    """One run of the sweep.

    Attributes
    ----------
    case_id
        Hash of the full parameter set (16 hex digits).
    values
        Swept parameter name (as in the file) -> value.
    overrides
        Dotted scene key -> value: the fixed overrides, then the swept ones expanded.
    settings
        The run settings.
    statistics
        Statistic names to compute.
    keep_series
        Return the time series with the statistics.
    """

    case_id: str
    values: dict[str, Any]
    overrides: tuple[tuple[str, Any], ...]
    settings: RunSettings
    statistics: tuple[str, ...]
    keep_series: bool


@dataclasses.dataclass(frozen=True)
class SweepSpec:
    """A validated sweep file.

    Attributes
    ----------
    settings
        Run settings shared by all cases.
    fixed
        Overrides of every case (name as in the file -> value).
    parameters
        Swept name -> list of values (ranges expanded), in file order.
    statistics
        Statistic names (:func:`~towcable_fmu.sweep.statistics.statistic`).
    units
        Statistic name -> unit of its value.
    output
        Results folder.
    series
        Write per-case time series.
    source
        The sweep file.
    table
        File name of the results table in ``output``; its suffix chooses the format:
        ``.csv`` or ``.parquet``.
    probabilities
        Probability of each case in :meth:`cases` order (a scatter diagram), summing to 1;
        None: not given. Long-term statistics weight the cases by them.
    """

    settings: RunSettings
    fixed: dict[str, Any]
    parameters: dict[str, list[Any]]
    statistics: tuple[str, ...]
    units: dict[str, str]
    output: Path
    series: bool
    source: Path | None = None
    table: str = "results.csv"
    probabilities: tuple[float, ...] | None = None

    def cases(self) -> list[Case]:
        """Every combination of the swept values (the first parameter varies slowest)."""
        segments = _segment_count(self.settings.scene, _named(self.fixed, self.parameters))
        fixed = expand_overrides(self.fixed, segments)
        names = list(self.parameters)
        cases = []
        for combo in itertools.product(*(self.parameters[n] for n in names)):
            values = dict(zip(names, combo))
            overrides = tuple(fixed + expand_overrides(values, segments))
            cases.append(Case(case_id(self.settings, overrides), values, overrides, self.settings,
                              self.statistics, self.series))
        return cases


def case_id(settings: RunSettings, overrides: tuple[tuple[str, Any], ...]) -> str:
    """SHA-256 (first 16 hex digits) of the full parameter set of a case.

    The hash covers the run settings except ``fmu_dir`` and the overrides in order;
    numbers are written as floats so that ``2`` and ``2.0`` are the same case.
    """
    def canonical(value: Any) -> Any:
        if isinstance(value, bool) or isinstance(value, str):
            return value
        if isinstance(value, (int, float)):
            return float(value)
        if isinstance(value, (list, tuple)):
            return [canonical(v) for v in value]
        if isinstance(value, Mapping):
            return {k: canonical(v) for k, v in sorted(value.items())}
        return str(value)

    run = {k: canonical(v) for k, v in dataclasses.asdict(settings).items() if k != "fmu_dir"}
    if settings.mode == "scene":
        run.pop("step")
    text = json.dumps({"run": run, "overrides": [[k, canonical(v)] for k, v in overrides]}, sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def expand_overrides(values: Mapping[str, Any], segments: int) -> list[tuple[str, Any]]:
    """Parameter names (aliases or dotted keys) -> (dotted scene key, value) pairs."""
    out: list[tuple[str, Any]] = []
    for name, value in values.items():
        for key in ALIASES.get(name, (name,)):
            if "{n}" in key:
                out.extend((key.format(n=i), value) for i in range(segments))
            else:
                out.append((key, value))
    return out


def _sets_every_segment(names: Iterable[str]) -> bool:
    """Whether one of the parameter names is an alias of a key of every cable segment (``{n}``)."""
    return any("{n}" in key for name in names for key in ALIASES.get(name, ()))


def _named(fixed: Mapping[str, Any], parameters: Mapping[str, Any] | None = None) -> list[tuple[str, str]]:
    """(table, name) of every parameter of a spec."""
    return [("fixed", n) for n in fixed] + [("parameters", n) for n in parameters or ()]


def _segment_count(scene: str, named: Iterable[tuple[str, str]]) -> int:
    """The scene's number of cable segments if one of the (table, name) parameters is an
    alias of a key of every segment, else 0.

    Raises
    ------
    SpecError
        Such an alias on a scene whose cable has no segments (a rigid-link scene).
    """
    from ..scene import load_scene

    for table, name in named:
        if _sets_every_segment([name]):
            cable = load_scene(scene).cable
            if not hasattr(cable, "segments"):
                raise SpecError(f"{table}.{name}", name, "a parameter of this scene: its cable has no segments "
                                                         f"(the alias sets {ALIASES[name][0]})")
            return len(cable.segments)
    return 0


def scene_signals(settings: RunSettings, fixed: Mapping[str, Any]) -> tuple[tuple[str, ...], Callable[[str], str]]:
    """The output signals a case's series will have, and their units.

    Scene mode: the outputs of the scene's simulation (with the fixed overrides, or
    without them if the scene refuses them: that case fails on its own). Cosim mode: every
    output of the three FMUs.
    """
    from ..common import contract

    if settings.mode == "cosim":
        names = ["time"] + [v.name for f in contract.fmus().values() for v in f.outputs if not v.diagnostic]
        return tuple(dict.fromkeys(names)), contract.unit_of
    from ..models import simulation_from

    segments = _segment_count(settings.scene, _named(fixed))
    try:
        sim = simulation_from(settings.scene, expand_overrides(fixed, segments))
    except SceneError:
        sim = simulation_from(settings.scene)
    return tuple(sim.output_names), sim.unit_of


def _checked_statistics(names: Any, settings: RunSettings, signals: tuple[str, ...]) -> tuple[str, ...]:
    """The spec's statistic names, each of a signal the scene has (default: those of
    :data:`~towcable_fmu.sweep.statistics.DEFAULT_STATISTICS` it has signals for)."""
    if names is None:
        return tuple(n for n in DEFAULT_STATISTICS if all(s in signals for s in statistic(n).signals))
    if not isinstance(names, list) or not names:
        raise SpecError("sweep.statistics", names, "a non-empty list of statistic names")
    allowed = ("SIGNAL.max, .min, .mean, .std or .pNN (e.g. tension.sheave.max, tension.top.p99), SIGNAL.damage "
               "or .mpm (rope life, e.g. tension.sheave.damage), or one of "
               + ", ".join(DERIVED) + f", of the signals {settings.scene} has in {settings.mode} mode: "
               + ", ".join(s for s in signals if s != "time"))
    for i, name in enumerate(names):
        try:
            stat = statistic(name) if isinstance(name, str) else None
        except ValueError:
            stat = None
        if stat is None:
            raise SpecError(f"sweep.statistics[{i}]", name, allowed)
        missing = [s for s in stat.signals if s not in signals]
        if missing:
            raise SpecError(f"sweep.statistics[{i}]", name, f"(no signal {', '.join(missing)}) " + allowed)
    if len(set(names)) != len(names):
        raise SpecError("sweep.statistics", names, "distinct names")
    return tuple(names)


# ---------------------------------------------------------------------------- loading
def load_spec(path: str | Path) -> SweepSpec:
    """Read and validate a sweep file.

    Raises
    ------
    SpecError
        Unknown tables or keys, a value of the wrong type or out of range, a malformed
        range, an unknown statistic; the message names the key, the value and what is
        allowed. (A value the scene refuses is not checked here: that case fails and is
        recorded when it runs.)
    """
    path = Path(path)
    try:
        doc = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise SpecError("SPEC", str(path), "an existing sweep TOML file") from None
    except tomllib.TOMLDecodeError as exc:
        raise SpecError("SPEC", str(path), f"valid TOML ({exc})") from None
    return spec_from_table(doc, base_dir=path.parent, source=path)


def spec_from_table(doc: Mapping[str, Any], base_dir: Path = Path("."), source: Path | None = None) -> SweepSpec:
    """Validate a parsed sweep document (see :func:`load_spec`)."""
    for key in doc:
        if key not in TOP_KEYS:
            raise SpecError(key, doc[key], "one of the tables " + ", ".join(f"[{k}]" for k in sorted(TOP_KEYS)))
    sweep = _table(doc, "sweep")
    for key in sweep:
        if key not in SWEEP_KEYS:
            raise SpecError(f"sweep.{key}", sweep[key], "one of " + ", ".join(sorted(SWEEP_KEYS)))
    mode = sweep.get("mode", "scene")
    if mode not in MODES:
        raise SpecError("sweep.mode", mode, " or ".join(f"'{m}'" for m in MODES))
    scene = sweep.get("scene", "full_scale")
    if not isinstance(scene, str) or not scene:
        raise SpecError("sweep.scene", scene, "a built-in scene name or a scene TOML file")
    scene = _resolve_scene(scene, base_dir)
    duration = _number(sweep, "duration", 120.0, lambda v: v > 0, "a time > 0 s")
    settle = _number(sweep, "settle", min(20.0, 0.5 * duration), lambda v: 0 <= v < duration,
                     f"a time in [0, duration = {duration:g}) s")
    interval = _number(sweep, "interval", 0.05, lambda v: 0 < v <= duration, "an interval in (0, duration] s")
    step = _number(sweep, "step", 0.01, lambda v: 0 < v <= interval, "a step in (0, interval] s")
    fraction = _number(sweep, "fraction", 0.95, lambda v: 0 < v <= 1, "a share in (0, 1]")
    output = sweep.get("output", "out/sweep")
    if not isinstance(output, str) or not output:
        raise SpecError("sweep.output", output, "a folder name")
    table_name = sweep.get("table", "results.csv")
    if (not isinstance(table_name, str) or Path(table_name).name != table_name
            or Path(table_name).suffix not in TABLE_SUFFIXES or not Path(table_name).stem):
        raise SpecError("sweep.table", table_name, "a file name ending in " + " or ".join(TABLE_SUFFIXES)
                        + " (the table's format), without a folder")
    series = sweep.get("series", False)
    if not isinstance(series, bool):
        raise SpecError("sweep.series", series, "true or false")
    fmu_dir = sweep.get("fmu_dir", "fmus")
    if not isinstance(fmu_dir, str):
        raise SpecError("sweep.fmu_dir", fmu_dir, "a folder name")

    fixed = dict(_table(doc, "fixed"))
    for key, value in fixed.items():
        _check_name(f"fixed.{key}", key, value)
        _check_value(f"fixed.{key}", value)
    parameters: dict[str, list[Any]] = {}
    for key, raw in _table(doc, "parameters").items():
        _check_name(f"parameters.{key}", key, raw)
        if key in fixed:
            raise SpecError(f"parameters.{key}", raw, "a parameter not also in [fixed]")
        parameters[key] = _values(f"parameters.{key}", raw)
    settings = RunSettings(mode=mode, scene=scene, duration=duration, settle=settle, interval=interval, step=step,
                           fraction=fraction, fmu_dir=fmu_dir)
    _segment_count(scene, _named(fixed, parameters))  # a segment alias needs segments
    signals, unit_of = scene_signals(settings, fixed)
    stats = _checked_statistics(sweep.get("statistics"), settings, signals)
    _check_rope(stats, scene, fixed, {k: v[0] for k, v in parameters.items()})
    units = {n: statistic(n).unit or unit_of(statistic(n).signals[0]) for n in stats}
    probabilities = None
    if "probabilities" in sweep:
        probabilities = checked_probabilities(sweep["probabilities"], [len(v) for v in parameters.values()])
    return SweepSpec(settings=settings, fixed=fixed, parameters=parameters, statistics=stats, units=units,
                     output=Path(output), series=series, source=source, table=table_name,
                     probabilities=probabilities)


def _check_rope(stats: tuple[str, ...], scene: str, fixed: Mapping[str, Any], first: Mapping[str, Any]) -> None:
    """A rope-life statistic needs rope data in the scene (``cable.segments[].rope``), as the
    first case (``first``: its swept values) sets it."""
    from ..rope_life.assessment import scene_rope
    from ..scene import load_scene

    for i, name in enumerate(stats):
        if statistic(name).needs_rope:
            segments = _segment_count(scene, _named(fixed, first))
            try:
                scene_rope(load_scene(scene, expand_overrides(fixed, segments) + expand_overrides(first, segments)))
            except SceneError as exc:
                raise SpecError(f"sweep.statistics[{i}]", name, f"a statistic of a scene with rope data ({exc})") from None


def checked_probabilities(raw: Any, shape: list[int]) -> tuple[float, ...]:
    """The probabilities of a sweep's cases from ``[sweep] probabilities``.

    Parameters
    ----------
    raw
        Nested lists, one level per swept parameter in file order (the first the outermost),
        e.g. a scatter diagram over hs (rows) and tp (columns); a flat list with one swept
        parameter.
    shape
        Number of values of each swept parameter.

    Raises
    ------
    SpecError
        Not of that shape, a negative or non-finite entry, or a sum other than 1 (within 1e-6).
    """
    key = "sweep.probabilities"
    where = " x ".join(str(n) for n in shape) or "1"

    def flat(value: Any, level: int, at: str) -> list[float]:
        if level == len(shape):
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
                raise SpecError(f"{key}{at}", value, "a probability >= 0")
            return [float(value)]
        if not isinstance(value, list) or len(value) != shape[level]:
            raise SpecError(f"{key}{at}", value, f"nested lists of shape {where} (one probability per case, the "
                                                 "parameters in file order)")
        return [p for i, v in enumerate(value) for p in flat(v, level + 1, f"{at}[{i}]")]

    values = flat(raw, 0, "")
    total = math.fsum(values)
    if abs(total - 1.0) > 1e-6:
        raise SpecError(key, raw, f"probabilities summing to 1 (they sum to {total:.9g})")
    return tuple(values)


def _table(doc: Mapping[str, Any], name: str) -> Mapping[str, Any]:
    table = doc.get(name, {})
    if not isinstance(table, Mapping):
        raise SpecError(name, table, f"a table [{name}]")
    return table


def _resolve_scene(scene: str, base_dir: Path) -> str:
    from ..scene import builtin_scene_names

    if scene in builtin_scene_names():
        return scene
    path = Path(scene) if Path(scene).is_absolute() else base_dir / scene
    if not path.is_file():
        raise SpecError("sweep.scene", scene, "a built-in scene (" + ", ".join(builtin_scene_names())
                        + ") or an existing scene TOML file (relative to the sweep file)")
    return str(path.resolve())


def _number(table: Mapping[str, Any], key: str, default: float, ok, allowed: str) -> float:
    value = table.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or not ok(value):
        raise SpecError(f"sweep.{key}", value, allowed)
    return float(value)


def _check_name(where: str, name: str, value: Any) -> None:
    if name in ALIASES:
        return
    if "." not in name or any(not part for part in name.split(".")):
        raise SpecError(where, value, "a dotted scene key (e.g. solver.time_step, cable.segments[3].length) or "
                                      "one of the aliases " + ", ".join(ALIASES))


def _check_value(where: str, value: Any) -> None:
    """TOML gives numbers, strings, Booleans, arrays and tables only; numbers must be finite."""
    if isinstance(value, float) and not math.isfinite(value):
        raise SpecError(where, value, "a finite number")


def _values(where: str, raw: Any) -> list[Any]:
    """A list of values, or a range table ``{start, stop, step}`` / ``{start, stop, num}``."""
    if isinstance(raw, list):
        if not raw:
            raise SpecError(where, raw, "a non-empty list of values or a range table {start, stop, step|num}")
        for i, v in enumerate(raw):
            _check_value(f"{where}[{i}]", v)
        if len({json.dumps(v, sort_keys=True) for v in raw}) != len(raw):
            raise SpecError(where, raw, "distinct values")
        return list(raw)
    if not isinstance(raw, Mapping):
        raise SpecError(where, raw, "a list of values or a range table {start, stop, step} or {start, stop, num}")
    keys = set(raw)
    if keys not in ({"start", "stop", "step"}, {"start", "stop", "num"}):
        raise SpecError(where, dict(raw), "a range table with exactly the keys start, stop and step, or start, "
                                          "stop and num")
    for key in ("start", "stop"):
        value = raw[key]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise SpecError(f"{where}.{key}", value, "a finite number")
    start, stop = raw["start"], raw["stop"]
    integer = isinstance(start, int) and isinstance(stop, int)
    if "num" in raw:
        num = raw["num"]
        if isinstance(num, bool) or not isinstance(num, int) or num < 1 or (num == 1 and start != stop):
            raise SpecError(f"{where}.num", num, "an integer >= 2 (or 1 when start = stop)")
        values = [start + (stop - start) * k / (num - 1) for k in range(num)] if num > 1 else [start]
        return [float(v) for v in values]
    step = raw["step"]
    if isinstance(step, bool) or not isinstance(step, (int, float)) or not math.isfinite(step) or step == 0 \
            or (stop - start) * step < 0:
        raise SpecError(f"{where}.step", step, f"a non-zero number with the sign of stop - start = {stop - start:g}")
    count = int(math.floor((stop - start) / step + 1e-9)) + 1
    if count > 100000:
        raise SpecError(f"{where}.step", step, "a step giving at most 100000 values")
    values = [start + k * step for k in range(count)]
    return [int(v) for v in values] if integer and isinstance(step, int) else [float(v) for v in values]
