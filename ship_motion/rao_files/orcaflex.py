"""OrcaFlex vessel-type displacement RAOs from an OrcaFlex text (YAML) data file.

Layout read (OrcaFlex's text data file, section ``VesselTypes``): a list of vessel
types, each with ``Name``, its RAO conventions and ``Draughts``; each draught has
``CentreOfMass`` [m] and ``DisplacementRAOs`` with ``RAOOrigin`` [m], ``PhaseOrigin``
(a ``~`` coordinate: the RAO origin's) and ``RAOs``, a list of ``RAODirection`` [deg] and the table
``RAOPeriodOrFrequency, RAOSurgeAmp, RAOSurgePhase, ..., RAOYawPhase`` (13 numbers a
row). All points are in the vessel's axes (x forward, y port, z up) relative to its
origin; ``General.UnitsSystem`` must be SI (metres).

Conventions, all read from the vessel type (a missing one is an error naming it):

- ``WavesReferredToBy``: ``period (s)``, ``frequency (rad/s)`` or ``frequency (Hz)``;
  rows at period or frequency 0 (the limits) are skipped.
- ``RAODirection``: the direction the waves travel relative to the vessel's x axis,
  counter-clockwise [deg] (180 = head seas), as ours.
- ``RAOResponseUnits``: the rotational amplitudes in ``degrees`` or ``radians`` per
  unit wave amplitude (``RAOWaveUnit: amplitude``; per unit slope is not read).
- ``RAOPhaseConvention``: ``leads`` or ``lags``; ``RAOPhaseUnitsConvention``: ``degrees``
  or ``radians``; ``RAOPhaseRelativeToConvention``: the wave event at phase 0 at the
  phase origin: ``crest`` (ours), ``trough``, ``zero up-crossing`` or ``zero down-crossing``
  (an elevation ``cos(omega t)`` has them at omega t = 0, pi, -pi/2, pi/2).
- ``Symmetry``: ``none`` or ``xz plane`` (port-starboard: the headings given are mirrored).

The RAOs are moved from the RAO origin and the phase origin to ``CentreOfMass``
(:mod:`ship_motion.rao_files.conventions`). Needs PyYAML (``pip install ".[orcaflex]"``).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from towcable_fmu.common.errors import SceneError

from ..rao import RaoTable
from .conventions import SourceFrame, from_modulus_phase, mirror_half_range, move_to_cg

TABLE_KEY = ("RAOPeriodOrFrequency, RAOSurgeAmp, RAOSurgePhase, RAOSwayAmp, RAOSwayPhase, RAOHeaveAmp, "
             "RAOHeavePhase, RAORollAmp, RAORollPhase, RAOPitchAmp, RAOPitchPhase, RAOYawAmp, RAOYawPhase")

#: Allowed values of the conventions read (compared in lower case).
CONVENTIONS: dict[str, tuple[str, ...]] = {
    "WavesReferredToBy": ("period (s)", "frequency (rad/s)", "frequency (hz)"),
    "RAOResponseUnits": ("degrees", "radians"),
    "RAOWaveUnit": ("amplitude",),
    "RAOPhaseConvention": ("leads", "lags"),
    "RAOPhaseUnitsConvention": ("degrees", "radians"),
    "RAOPhaseRelativeToConvention": ("crest", "trough", "zero up-crossing", "zero down-crossing"),
    "Symmetry": ("none", "xz plane"),
}
#: omega t of the wave event at phase 0, for an elevation cos(omega t).
_EVENT = {"crest": 0.0, "trough": math.pi, "zero up-crossing": -0.5 * math.pi, "zero down-crossing": 0.5 * math.pi}


def _load(path: Path, key: str) -> dict:
    try:
        import yaml
    except ImportError:
        raise SceneError(key, str(path), "PyYAML installed to read OrcaFlex files (pip install "
                         "\".[orcaflex]\")") from None
    if not path.is_file():
        raise SceneError(key, str(path), "an existing OrcaFlex text data file (.yml)")
    try:
        doc = yaml.safe_load(path.read_text(encoding="utf-8-sig"))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1})" if mark is not None else ""
        raise SceneError(key, str(path), f"an OrcaFlex text data file in YAML{where}: {exc}") from None
    if not isinstance(doc, dict):
        raise SceneError(key, str(path), "an OrcaFlex text data file with a VesselTypes section")
    return doc


def _named(items: Any, name: str | None, what: str, where: str, key: str, path: Path) -> dict:
    if not isinstance(items, list) or not items or not all(isinstance(i, dict) for i in items):
        raise SceneError(key, str(path), f"an OrcaFlex text data file with a list {where}")
    names = [str(i.get("Name")) for i in items]
    if name is None:
        if len(items) > 1:
            raise SceneError(key, str(path), f"one {what} in {where}, or the key {what} naming one of "
                             + ", ".join(names))
        return items[0]
    if name not in names:
        raise SceneError(key, str(path), f"a {what} named {name!r} in {where} (found: {', '.join(names)})")
    return items[names.index(name)]


def _get(table: dict, name: str, where: str, key: str, path: Path) -> Any:
    if name not in table:
        raise SceneError(key, str(path), f"an OrcaFlex file whose {where} declares {name}"
                         + (" (one of " + ", ".join(CONVENTIONS[name]) + ")" if name in CONVENTIONS else ""))
    value = table[name]
    if name in CONVENTIONS:
        text = str(value).strip().lower()
        if text not in CONVENTIONS[name]:
            raise SceneError(key, str(path), f"{where}.{name} one of " + ", ".join(CONVENTIONS[name])
                             + f" (found {value!r})")
        return text
    return value


def _point(value: Any, fallback: Any, where: str, key: str, path: Path) -> tuple[float, ...]:
    if isinstance(value, list) and fallback is not None and len(value) == 3:
        value = [f if v is None else v for v, f in zip(value, fallback)]   # ~: the RAO origin's coordinate
    try:
        point = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        point = ()
    if len(point) != 3 or not all(map(math.isfinite, point)):
        raise SceneError(key, str(path), f"{where} a list of 3 numbers [m] (found {value!r})")
    return point


def read_orcaflex(path: str | Path, *, vessel_type: str | None = None, draught: str | None = None,
                  key: str = "file") -> RaoTable:
    """Read the displacement RAOs of one vessel type's draught into our RAOs at its CG.

    Parameters
    ----------
    path
        The OrcaFlex text data file.
    vessel_type, draught
        Their names; None: the only one in the file.
    key
        Configuration key naming the file (error messages).

    Raises
    ------
    SceneError
        Naming the file, the YAML key and what is allowed.
    """
    path = Path(path)
    doc = _load(path, key)
    units = (doc.get("General") or {}).get("UnitsSystem", "SI")
    if str(units).upper() != "SI":
        raise SceneError(key, str(path), f"General.UnitsSystem SI (found {units!r})")
    vt = _named(doc.get("VesselTypes"), vessel_type, "vessel_type", "VesselTypes", key, path)
    where = f"VesselTypes[{vt.get('Name')}]"
    conv = {name: _get(vt, name, where, key, path) for name in CONVENTIONS if name != "Symmetry"}
    symmetry = _get(vt, "Symmetry", where, key, path) if "Symmetry" in vt else "none"
    dr = _named(vt.get("Draughts"), draught, "draught", f"{where}.Draughts", key, path)
    where = f"{where}.Draughts[{dr.get('Name')}]"
    cg = _point(_get(dr, "CentreOfMass", where, key, path), None, f"{where}.CentreOfMass", key, path)
    disp = _get(dr, "DisplacementRAOs", where, key, path)
    origin = _point(_get(disp, "RAOOrigin", f"{where}.DisplacementRAOs", key, path), None,
                    f"{where}.DisplacementRAOs.RAOOrigin", key, path)
    phase_origin = _point(disp.get("PhaseOrigin", [None] * 3), origin, f"{where}.DisplacementRAOs.PhaseOrigin",
                          key, path)
    raos = _get(disp, "RAOs", f"{where}.DisplacementRAOs", key, path)
    if not isinstance(raos, list) or not raos:
        raise SceneError(key, str(path), f"{where}.DisplacementRAOs.RAOs a list of RAODirection and tables")
    angle = math.pi / 180.0 if conv["RAOResponseUnits"] == "degrees" else 1.0
    phase_unit = 1.0 if conv["RAOPhaseUnitsConvention"] == "degrees" else 180.0 / math.pi
    lag = conv["RAOPhaseConvention"] == "lags"
    event = _EVENT[conv["RAOPhaseRelativeToConvention"]]
    headings, tables, abscissa = [], [], None
    for n, entry in enumerate(raos):
        here = f"{where}.DisplacementRAOs.RAOs[{n}]"
        try:
            direction = float(_get(entry, "RAODirection", here, key, path))
            rows = np.array(_get(entry, TABLE_KEY, here, key, path), dtype=float)
        except (TypeError, ValueError):
            direction, rows = math.nan, np.empty(0)
        if not math.isfinite(direction) or rows.ndim != 2 or rows.shape[1] != 13 or not np.all(np.isfinite(rows)):
            raise SceneError(key, str(path), f"{here}: RAODirection a number [deg] and rows of 13 finite numbers "
                             "(period or frequency, then amplitude and phase of surge, sway, heave, roll, pitch, yaw)")
        rows = rows[rows[:, 0] > 0.0]
        if abscissa is None:
            abscissa = rows[:, 0]
        elif rows.shape[0] != abscissa.size or np.any(rows[:, 0] != abscissa):
            raise SceneError(key, str(path), f"{here}: the same periods or frequencies for every direction")
        h = from_modulus_phase(rows[:, 1::2], rows[:, 2::2] * phase_unit, lag=lag) * np.exp(-1j * event)
        h[:, 3:] *= angle
        headings.append(math.radians(direction) % (2.0 * math.pi))
        tables.append(h)
    reference = conv["WavesReferredToBy"]
    omega = (2.0 * math.pi / abscissa if reference == "period (s)"
             else abscissa * (2.0 * math.pi if reference == "frequency (hz)" else 1.0))
    order_f, order_h = np.argsort(omega), np.argsort(headings)
    if np.unique(omega).size != omega.size or np.unique(np.round(headings, 12)).size != len(headings):
        raise SceneError(key, str(path), f"{where}.DisplacementRAOs: each direction and period once")
    freqs, heads = omega[order_f], np.array(headings)[order_h]
    values = np.stack(tables, axis=1)[order_f][:, order_h]
    if symmetry == "xz plane":
        heads, values = mirror_half_range(heads, values)
    frame = SourceFrame(rao_origin=origin, phase_origin=phase_origin[:2], centre_of_gravity=cg)
    return RaoTable(freqs, heads, move_to_cg(freqs, heads, values, frame), label=path.name)
