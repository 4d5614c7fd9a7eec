"""The rope-life report: a markdown table of tension damage, extremes and bending, with
the methods and sources stated, and its two figures."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .assessment import Assessment, life_years
from .plots import plot_bending_along_rope, plot_rainflow_histogram


def _g(value: float | None, digits: int = 4) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return f"{value:.{digits}g}"


def report_markdown(a: Assessment, title: str) -> str:
    """The report's text (markdown)."""
    rope, curve = a.rope, a.curve
    lines = [f"# Rope life: {title}", "",
             f"Rope: minimum breaking strength {rope.breaking_strength:g} N, construction `{rope.construction}`: "
             f"T-N curve N R^M = K with M = {curve.M:g}, K = {curve.K:g} ({curve.source}; R = tension range / "
             "breaking strength).", "",
             f"## Tension fatigue of `{a.signal}`", "",
             "Rainflow counting (ASTM E1049-85, 5.4.4; residue as half cycles) and Palmgren-Miner damage; per "
             "hour and per year of the same sea all year round.", "",
             "| run | duration [s] | cycles | damage [-] | per hour [1/h] | per year [1/year] | life [years] | "
             f"max [N] | MPM {a.storm / 3600:g} h (peaks) [N] | Weibull shape [-] |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in a.runs:
        t = r.tension
        lines.append(f"| {r.label} | {t.duration:.6g} | {_g(float(np.sum(t.cycles.counts)))} | {_g(t.damage)} | "
                     f"{_g(t.per_hour)} | {_g(t.per_year)} | {_g(life_years(t.per_year))} | {_g(r.maximum)} | "
                     f"{_g(r.peaks.mpm if r.peaks else None)} | {_g(r.peaks.shape if r.peaks else None, 3)} |")
    lines += ["", f"Mean damage per year over the runs: {_g(a.damage_per_year())}; life "
                  f"{_g(life_years(a.damage_per_year()))} years.", "",
              "## Extremes", "",
              f"Most probable maximum (MPM) of `{a.signal}` in a storm of {a.storm:g} s:", "",
              "* per run, a Weibull fit of the peaks above the mean (one per mean up-crossing period), by maximum "
              "likelihood: MPM = mean + alpha (ln n)^(1/gamma), n the peaks in the storm (table above);",
              "* over the runs (seeds), a Gumbel fit of their maxima by maximum likelihood, moved to the storm's "
              "duration (mu + beta ln(T_storm / T_run)): "
              + (f"**{_g(a.gumbel_mpm)} N**." if a.gumbel_mpm is not None else "needs at least 3 runs."), ""]
    along = a.bending_per_hour()
    if along is None:
        lines += ["## Bending", "", "The scene has no winch and sheave: no bending cycles counted.", ""]
    else:
        x, sheave, drum = along
        worst = int(np.argmax(sheave + drum))
        lines += ["## Bending over the sheave and the drum", "",
                  "Every crossing of a place where the rope's bending changes (leaves the drum, touches the sheave, "
                  "leaves it) is half a bending cycle: a pass over the sheave is one, a wrap onto the drum half "
                  "of one. Material points by their unstretched distance from the bottom end; mean over the runs.",
                  "",
                  "| quantity | value |", "|---|---|",
                  f"| worst point [m from the bottom end] | {x[worst]:.2f} |",
                  f"| its sheave bending cycles per hour [1/h] | {_g(sheave[worst])} |",
                  f"| its drum bending cycles per hour [1/h] | {_g(drum[worst])} |",
                  f"| its bending cycles per year [1/year] | {_g((sheave[worst] + drum[worst]) * 24 * 365.25)} |",
                  f"| rope that bends [m] | {np.count_nonzero(sheave + drum) * (x[1] - x[0]):.2f} |"]
        damage = a.bending_damage_per_year()
        if damage is None:
            lines += ["", "No bending damage: the rope gives no bending endurance (rope.bending_cycles, "
                          "bending_tension, bending_exponent); the counts and the tension at the passages are its "
                          "input.", ""]
        else:
            xd, per_year = damage
            k = int(np.argmax(per_year))
            lines += [f"| worst bending damage: point [m from the bottom end] | {xd[k]:.2f} |",
                      f"| its bending damage per year [1/year] | {_g(per_year[k])} |",
                      f"| its bending life [years] | {_g(life_years(float(per_year[k])))} |", "",
                      f"Bending damage: each half cycle counts 1/(2 N(S)) at the tension S of its passage, "
                      f"N = {a.rope.bending_cycles:g} ({a.rope.bending_tension:g} N / S)^{a.rope.bending_exponent:g} "
                      "(the rope's endurance; Feyrer's collective method, eq. 3.93); the same endurance on the drum.",
                      ""]
        lines += ["![bending cycles along the rope](bending.png)", ""]
    lines += ["![rainflow histogram](rainflow.png)", ""]
    return "\n".join(lines)


def write_report(a: Assessment, folder: Path, title: str) -> list[Path]:
    """Write ``report.md``, ``bending.png`` and ``rainflow.png`` into ``folder``.

    Returns
    -------
    list of Path
        The files written.
    """
    folder.mkdir(parents=True, exist_ok=True)
    written = [folder / "report.md"]
    written[0].write_text(report_markdown(a, title), encoding="utf-8")
    along = a.bending_per_hour()
    if along is not None:
        damage = a.bending_damage_per_year()
        written.append(plot_bending_along_rope(*along, folder / "bending.png", f"{title}: bending cycles",
                                               None if damage is None else damage[1]))
    first = a.runs[0]
    written.append(plot_rainflow_histogram(first.tension.cycles, a.rope.breaking_strength, folder / "rainflow.png",
                                           f"{title}: rainflow of {a.signal} ({first.label})"))
    return written
