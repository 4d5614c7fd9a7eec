"""Rope life: rope data in the scene, tension fatigue (rainflow, Miner), extremes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from towcable_fmu.cli import main
from towcable_fmu.common.errors import SceneError
from towcable_fmu.models import simulation_from
from towcable_fmu.rope_life import bending, extremes, tension_fatigue
from towcable_fmu.rope_life.assessment import assess, scene_rope
from towcable_fmu.rope_life.rope_data import TN_CURVES, cycles_to_failure, intercept_at_mean_load, tn_curve
from towcable_fmu.rope_life.rope_data import bending_cycles_to_discard as rope_data_bending
from towcable_fmu.common.run_io import read_csv, write_csv
from towcable_fmu.scene import load_scene
from towcable_fmu.scene.model import Rope
from towcable_fmu.common.schema import parse
from towcable_fmu.sweep.case import _rope, run_case, simulate
from towcable_fmu.sweep.long_term import long_term_damage
from towcable_fmu.sweep.spec import SpecError, load_spec, spec_from_table
from towcable_fmu.sweep.statistics import compute_statistics

ROOT = Path(__file__).resolve().parents[1]


# ---------------------------------------------------------------- rope data
def test_rope_table_parses_and_rejects_bad_values():
    rope = parse(Rope, {"breaking_strength": 6.98e4, "construction": "spiral_strand"}, "cable.segments[0].rope")
    assert rope.construction == "spiral_strand"
    with pytest.raises(SceneError) as neg:
        parse(Rope, {"breaking_strength": -1.0}, "cable.segments[0].rope")
    assert "cable.segments[0].rope.breaking_strength" in str(neg.value) and "-1" in str(neg.value) and "> 0" in str(neg.value)
    with pytest.raises(SceneError) as unknown:
        parse(Rope, {"breaking_strength": 1e5, "construction": "chain"}, "cable.segments[0].rope")
    text = str(unknown.value)
    assert "construction" in text and "chain" in text and "'six_strand'" in text and "'spiral_strand'" in text


def test_scene_constructions_are_the_curves():
    import dataclasses
    field = {f.name: f for f in dataclasses.fields(Rope)}["construction"]
    assert set(field.metadata["spec"].choices) == set(TN_CURVES)
    with pytest.raises(ValueError, match="six_strand"):
        tn_curve("chain")


def test_api_2sk_third_edition_intercepts_are_the_second_editions_at_mean_load_0_3():
    # two published tables of the same curves: API RP 2SK 3rd ed. K (231, 166) and the 2nd
    # ed. fits 10^(3.20 - 2.79 Lm), 10^(3.25 - 3.43 Lm) at the reference Lm = 0.3, rounded to
    # the 3rd edition's three digits
    for name in TN_CURVES:
        curve = tn_curve(name)
        assert round(intercept_at_mean_load(curve, 0.3)) == curve.K


def test_cycles_to_failure_of_the_curve():
    curve = tn_curve("six_strand")
    # N R^M = K at R = 1 and scaling by M
    assert cycles_to_failure(1e5, 1e5, curve) == pytest.approx(231.0)
    assert cycles_to_failure(1e4, 1e5, curve) / cycles_to_failure(2e4, 1e5, curve) == pytest.approx(2.0 ** 4.09)
    assert math.isinf(float(cycles_to_failure(0.0, 1e5, curve)))


# ---------------------------------------------------------------- rainflow and Miner
def test_rainflow_counts_the_astm_e1049_example():
    # ASTM E1049-85 (2017), 5.4.4 and its Fig. 6 / Table 4: the history -2 1 -3 5 -1 3 -4 4 -2
    # has ranges 3 (0.5), 4 (1.5), 6 (0.5), 8 (1.0), 9 (0.5)
    cycles = tension_fatigue.rainflow_cycles(np.array([-2, 1, -3, 5, -1, 3, -4, 4, -2], dtype=float))
    table = {}
    for r, c in zip(cycles.ranges, cycles.counts):
        table[r] = table.get(r, 0.0) + c
    assert table == {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def test_miner_damage_of_a_constant_amplitude_sine_is_n_over_N():
    mbs, curve = 7.0e4, tn_curve("six_strand")
    n, amplitude = 200, 3.0e3
    t = np.linspace(0.0, n * 8.0, n * 400 + 1)            # 8 s period, 400 samples a period
    tension = 2.0e4 - amplitude * np.cos(2.0 * np.pi * t / 8.0)  # starts and ends at a trough
    result = tension_fatigue.tension_damage(t, tension, mbs, curve)
    closed = n * (2.0 * amplitude / mbs) ** curve.M / curve.K
    assert result.damage == pytest.approx(closed, rel=1e-6)
    assert result.per_hour == pytest.approx(closed * 3600.0 / t[-1], rel=1e-6)
    assert result.per_year == pytest.approx(closed * 365.25 * 24 * 3600 / t[-1], rel=1e-6)


def test_miner_damage_of_a_two_level_block_is_the_hand_sum():
    mbs, curve = 1.0e5, tn_curve("spiral_strand")
    n1, r1, n2, r2 = 30, 1.0e4, 7, 2.5e4
    history = [0.0, r1] * n1 + [0.0, r2] * n2 + [0.0]
    cycles = tension_fatigue.rainflow_cycles(np.array(history) + 3.0e4)
    hand = n1 / (curve.K * (r1 / mbs) ** -curve.M) + n2 / (curve.K * (r2 / mbs) ** -curve.M)
    assert tension_fatigue.miner_damage(cycles, mbs, curve) == pytest.approx(hand, rel=1e-12)


# ---------------------------------------------------------------- extremes
def test_gumbel_fit_recovers_the_parameters_of_gumbel_samples():
    rng = np.random.default_rng(7)
    mu, beta, n = 5.0e4, 2.0e3, 4000
    fit = extremes.fit_gumbel(rng.gumbel(mu, beta, n))
    # standard errors of the ML estimates: 1.05 beta / sqrt(n) and 0.78 beta / sqrt(n)
    assert abs(fit.location - mu) < 4 * 1.05 * beta / math.sqrt(n)
    assert abs(fit.scale - beta) < 4 * 0.78 * beta / math.sqrt(n)


def test_mpm_from_maxima_scales_with_storm_duration():
    rng = np.random.default_rng(3)
    mu, beta = 100.0, 5.0
    maxima = rng.gumbel(mu, beta, 2000)
    # the maximum of 10 runs: Gumbel with location mu + beta ln 10
    assert extremes.mpm_from_maxima(maxima, 600.0, 6000.0) == pytest.approx(mu + beta * math.log(10.0), abs=0.6)


def test_mpm_of_a_narrow_band_gaussian_process_is_the_rayleigh_value():
    rng = np.random.default_rng(11)
    f0, width, waves = 0.1, 0.004, 400                    # narrow band around 0.1 Hz
    freqs = rng.uniform(f0 - width / 2, f0 + width / 2, waves)
    phases = rng.uniform(0.0, 2 * np.pi, waves)
    sigma, dt, duration = 1.5e3, 0.25, 10.0 * 3600.0
    t = np.arange(0.0, duration, dt)
    x = np.zeros_like(t)
    for f, p in zip(freqs, phases):
        x += np.cos(2 * np.pi * f * t + p)
    x *= sigma * math.sqrt(2.0 / waves)
    storm = 3.0 * 3600.0
    fit = extremes.mpm_from_peaks(t, 4.0e4 + x, storm)
    rayleigh = 4.0e4 + sigma * math.sqrt(2.0 * math.log(f0 * storm))
    assert fit.shape == pytest.approx(2.0, rel=0.05)
    assert fit.mpm == pytest.approx(rayleigh, rel=0.01)


# ---------------------------------------------------------------- bending over sheave and drum


def test_common_tangent_touches_both_circles():
    c1, r1, c2, r2 = np.array([-28.8, 3.1]), 0.305, np.array([-36.8, 3.7]), 0.255
    n, length = bending.common_tangent(c1, r1, c2, r2)
    p1, p2 = c1 + r1 * n, c2 + r2 * n
    assert np.hypot(*n) == pytest.approx(1.0)
    assert float(n @ (p2 - p1)) == pytest.approx(0.0, abs=1e-12)         # tangent at both points
    assert length == pytest.approx(np.hypot(*(p2 - p1)))
    assert length == pytest.approx(math.sqrt(float((c2 - c1) @ (c2 - c1)) - (r1 - r2) ** 2))
    assert n[1] > 0.99                                                    # over the tops, towards -x
    # equal radii side by side: the top line, as long as the centres are apart
    n, length = bending.common_tangent(np.array([0.0, 0.0]), 1.0, np.array([-5.0, 0.0]), 1.0)
    assert n == pytest.approx([0.0, 1.0]) and length == pytest.approx(5.0)


def _sine_payout(amplitude: float, period: float, periods: int, per_period: int = 400):
    t = np.linspace(0.0, periods * period, periods * per_period + 1)
    return t, amplitude * np.sin(2.0 * np.pi * t / period)


def _expected(x, centre, amplitude, periods):
    """Closed form: a point within the amplitude of a place it oscillates about is crossed
    twice a period (half a cycle each); nothing else is."""
    return np.where(np.abs(x - centre) < amplitude, 2.0 * periods, 0.0)


@pytest.mark.parametrize("name", ["full_scale", "full_scale_deploy"])
def test_sinusoidal_payout_bends_the_points_within_its_amplitude(name):
    scene = load_scene(name)
    path = bending.rope_path(scene)
    amplitude, period, periods, wrap = 0.8, 10.0, 5, 1.9
    t, payout = _sine_payout(amplitude, period, periods)
    series = {"contact.wrap_angle": np.full(t.size, wrap),
              "tension.winch": np.full(t.size, 4.0e3), "tension.sheave": np.full(t.size, 4.1e3)}
    if scene.cable.top.type == "winch":
        length = scene.cable.length
        series["winch.phi"] = scene.winch.phi_nom - payout / path.drum_radius
        drum0 = length - path.drum_radius * (scene.winch.phi_nom - path.departure_angle)
    else:
        length, deployed0 = 200.0, 150.0
        series["winch.deployed"] = deployed0 + payout
        drum0 = deployed0 - path.drum_radius * ((path.spool_angle - path.departure_angle) % (2 * np.pi))
    on0 = drum0 - path.span
    off0 = on0 - path.sheave_radius * wrap
    result = bending.bending_cycles(path, length, series, spacing=0.01)
    x = result.x
    clear = np.ones(x.size, bool)          # leave out points within round-off of an edge
    for centre in (drum0, on0, off0):
        clear &= np.abs(np.abs(x - centre) - amplitude) > 1e-6
    np.testing.assert_array_equal(result.drum[clear], 0.5 * _expected(x, drum0, amplitude, periods)[clear])
    sheave = 0.5 * (_expected(x, on0, amplitude, periods) + _expected(x, off0, amplitude, periods))
    np.testing.assert_array_equal(result.sheave[clear], sheave[clear])
    # the amplitude exceeds half the sheave arc (0.26 m x 1.9): some points pass over it both ways
    assert result.sheave.max() == 2 * periods and np.count_nonzero(result.sheave) > 100
    assert np.nanmax(result.max_tension) == pytest.approx(4.1e3)


def test_a_point_paid_out_past_the_sheave_and_hauled_back_makes_exactly_those_passes():
    scene = load_scene("full_scale_deploy")
    path = bending.rope_path(scene)
    # the scene's own payout program: veer 300 m, hold, haul the 300 m back
    t = np.arange(0.0, 700.0, 0.05)
    payout = np.interp(t, scene.winch.program_times, scene.winch.program_payout)
    deployed0 = 150.0
    series = {"winch.deployed": deployed0 + payout, "contact.wrap_angle": np.full(t.size, 1.9),
              "tension.winch": np.full(t.size, 4.0e3), "tension.sheave": np.full(t.size, 4.0e3)}
    result = bending.bending_cycles(path, deployed0 + 300.0, series, spacing=0.05)
    drum0 = deployed0 - path.drum_radius * ((path.spool_angle - path.departure_angle) % (2 * np.pi))
    off0 = drum0 - path.span - path.sheave_radius * 1.9
    x = result.x
    # points between the sheave's far side at the start and the drum at the end: out over the
    # sheave and off the drum once, back over the sheave and onto the drum once
    middle = (x > drum0 + 0.01) & (x < off0 + 300.0 - 0.01)
    assert np.all(result.sheave[middle] == 2.0) and np.all(result.drum[middle] == 1.0)
    # points that were in the water at the start never reach the sheave; points still on the
    # drum at the end of the veer never leave it
    assert np.all(result.sheave[x < off0 - 0.01] == 0.0) and np.all(result.drum[x < drum0 - 0.01] == 0.0)
    assert np.all(result.sheave[x > drum0 + 300.0 + 0.01] == 0.0)


def test_bending_needs_a_winch_and_a_sheave():
    with pytest.raises(ValueError, match="winch"):
        bending.rope_path(load_scene("full_scale_pinned"))


# ---------------------------------------------------------------- assessment, report and command line


def _winch_run(seed: int, duration: float = 600.0, dt: float = 0.1) -> dict:
    """A synthetic run of full_scale: sheave tension a sine of 8 s (range 2 kN) plus a seeded
    random sea-like part, the winch rotating by a sine of 0.5 m payout amplitude."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration + 0.5 * dt, dt)
    noise = sum(a * np.sin(2 * np.pi * f * t + p) for a, f, p in
                zip(rng.rayleigh(50.0, 20), rng.uniform(0.08, 0.12, 20), rng.uniform(0, 6.3, 20)))
    tension = 4.0e3 - 1.0e3 * np.cos(2 * np.pi * t / 8.0)
    scene = load_scene("full_scale")
    return {"time": t, "tension.sheave": tension + noise, "tension.winch": tension, "contact.wrap_angle": 0.33 + 0 * t,
            "winch.phi": scene.winch.phi_nom - 0.5 / 0.305 * np.sin(2 * np.pi * t / 20.0)}


def test_fatigue_command_writes_the_report(tmp_path):
    run = _winch_run(0)
    run["tension.sheave"] = run["tension.winch"]                   # the pure sine: n / N in closed form
    write_csv(tmp_path / "run.csv", run)
    assert main(["fatigue", str(tmp_path / "run.csv"), "--scene", "full_scale", "--output", str(tmp_path / "out")]) == 0
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == ["bending.png", "rainflow.png", "report.md"]
    text = (tmp_path / "out" / "report.md").read_text(encoding="utf-8")
    closed = 75 * (2.0e3 / 69800.0) ** 4.09 / 231.0                 # 75 periods of 8 s in 600 s
    assert f"{closed:.4g}" in text and "API RP 2SK" in text and "ASTM E1049" in text
    # the payout's 0.5 m amplitude moves the rope 1 m over each bending place: 1 m bends on
    # the drum, a bit more than 1 m (plus the arc, 0.255 m x 0.33) over the sheave
    result = assess(load_scene("full_scale"), [("run", read_csv(tmp_path / "run.csv"))])
    bent = result.runs[0].bending
    assert np.count_nonzero(bent.drum) * 0.01 == pytest.approx(1.0, abs=0.02)
    assert np.count_nonzero(bent.sheave) * 0.01 == pytest.approx(1.0 + 0.255 * 0.33, abs=0.02)
    assert bent.drum.max() == 30 * 0.5 * 2  # 30 periods of 20 s, two crossings a period


def test_fatigue_of_several_seeds_fits_their_maxima(tmp_path):
    runs = [(f"seed{s}", _winch_run(s)) for s in range(4)]
    result = assess(load_scene("full_scale"), runs, storm=3600.0)
    maxima = np.array([r.maximum for r in result.runs])
    assert result.gumbel_mpm is not None and result.gumbel_mpm > maxima.mean()
    with pytest.raises(ValueError, match="different durations"):
        assess(load_scene("full_scale"), runs[:2] + [("short", _winch_run(9, duration=300.0))])


def test_rope_data_missing_or_mixed_is_an_error():
    with pytest.raises(SceneError, match=r"cable\.segments\[\]\.rope"):
        scene_rope(load_scene("hanging_cable"))
    mixed = load_scene("full_scale", [("cable.segments[1].rope.breaking_strength", 5.0e4)])
    with pytest.raises(SceneError, match=r"cable\.segments\[1\]\.rope.*cable\.segments\[0\]\.rope"):
        scene_rope(mixed)


def test_fatigue_command_names_a_missing_signal(tmp_path, capsys):
    run = _winch_run(0)
    del run["tension.sheave"]
    write_csv(tmp_path / "run.csv", run)
    assert main(["fatigue", str(tmp_path / "run.csv"), "--scene", "full_scale", "--output", str(tmp_path)]) == 2
    assert "tension.sheave" in capsys.readouterr().err


# ---------------------------------------------------------------- sweep statistics and the scatter diagram


def test_damage_and_mpm_statistics_of_a_case():
    run = _winch_run(5)
    rope = scene_rope(load_scene("full_scale"))
    stats = compute_statistics(run, ["tension.sheave.damage", "tension.sheave.mpm"], settle=100.0, rope=rope)
    keep = run["time"] >= 100.0
    direct = tension_fatigue.tension_damage(run["time"][keep], run["tension.sheave"][keep], 69800.0,
                                            tn_curve("six_strand"))
    assert stats["tension.sheave.damage"] == pytest.approx(direct.per_year, rel=1e-12)
    assert stats["tension.sheave.mpm"] == pytest.approx(
        extremes.mpm_from_peaks(run["time"][keep], run["tension.sheave"][keep], 3 * 3600.0).mpm)
    assert math.isnan(compute_statistics(run, ["tension.sheave.damage"], settle=0.0)["tension.sheave.damage"])


SCATTER = {"sweep": {"scene": "full_scale", "statistics": ["tension.sheave.damage", "tension.sheave.max"],
                     "probabilities": [[0.1, 0.2, 0.05], [0.3, 0.25, 0.1]]},
           "parameters": {"hs": [1.5, 3.0], "tp": [6.0, 8.0, 10.0]}}


def test_scatter_diagram_probabilities_weight_the_cases():
    spec = spec_from_table(SCATTER)
    assert spec.probabilities == (0.1, 0.2, 0.05, 0.3, 0.25, 0.1)
    cases = spec.cases()
    assert [c.values for c in cases][1] == {"hs": 1.5, "tp": 8.0}      # first parameter slowest, as the rows
    damage = [1e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3]
    rows = [{"case_id": c.case_id, "tension.sheave.damage [1/year]": f"{d:.10g}"} for c, d in zip(cases, damage)]
    hand = 0.1e-3 + 0.4e-3 + 0.15e-3 + 1.2e-3 + 1.25e-3 + 0.6e-3
    assert long_term_damage(spec, rows) == {"tension.sheave.damage": pytest.approx(hand, rel=1e-12)}
    rows[4]["tension.sheave.damage [1/year]"] = ""                      # a failed case
    assert math.isnan(long_term_damage(spec, rows)["tension.sheave.damage"])


@pytest.mark.parametrize("probabilities, message", [
    ([[0.1, 0.2, 0.05], [0.3, 0.25, 0.2]], "summing to 1 (they sum to 1.1)"),
    ([[0.1, 0.2], [0.3, 0.4]], "shape 2 x 3"),
    ([[0.1, 0.2, -0.05], [0.3, 0.25, 0.2]], ">= 0"),
])
def test_bad_probabilities_are_errors_naming_key_and_value(probabilities, message):
    doc = {**SCATTER, "sweep": {**SCATTER["sweep"], "probabilities": probabilities}}
    with pytest.raises(SpecError) as info:
        spec_from_table(doc)
    assert str(info.value).startswith("sweep.probabilities") and message in str(info.value)


def test_a_damage_statistic_needs_rope_data_and_a_case_uses_its_own():
    with pytest.raises(SpecError) as info:
        spec_from_table({"sweep": {"scene": "pulley_static", "statistics": ["tension.sheave.damage"]}})
    assert "sweep.statistics[0]" in str(info.value) and "cable.segments[].rope" in str(info.value)
    spec = spec_from_table({"sweep": {"scene": "full_scale", "statistics": ["tension.sheave.damage"]},
                            "parameters": {"cable.segments[2].rope.breaking_strength": [5.0e4]},
                            "fixed": {f"cable.segments[{i}].rope.breaking_strength": 5.0e4 for i in (0, 1, 3, 4)}})
    assert _rope(spec.cases()[0]).breaking_strength == 5.0e4           # the case's, not the scene's 69.8 kN


def test_the_rope_life_sweep_example_is_valid():
    spec = load_spec(ROOT / "towcable_fmu" / "example_sweeps" / "rope_life.toml")
    assert len(spec.cases()) == 9 and math.fsum(spec.probabilities) == pytest.approx(1.0)
    assert spec.units["tension.sheave.damage"] == "1/year"


def test_a_sweep_case_computes_its_damage_from_its_own_run():
    spec = spec_from_table({"sweep": {"scene": "full_scale", "duration": 12.0, "settle": 2.0,
                                      "statistics": ["tension.sheave.damage"]}})
    case = spec.cases()[0]
    result = run_case(case)
    assert result.status == "ok", result.error
    series = simulate(case)
    keep = series["time"] >= 2.0
    direct = tension_fatigue.tension_damage(series["time"][keep], series["tension.sheave"][keep], 69800.0,
                                            tn_curve("six_strand")).per_year
    assert result.statistics["tension.sheave.damage"] == pytest.approx(direct, rel=1e-9) and direct > 0.0


def test_a_rope_end_run_off_the_drum_and_a_bad_csv_are_errors(tmp_path):
    path = bending.rope_path(load_scene("full_scale"))
    series = {"winch.phi": np.array([3.8, 0.0]), "contact.wrap_angle": np.array([0.3, 0.3])}
    with pytest.raises(ValueError, match="left the drum"):
        bending.bend_places(path, 460.0, series)
    (tmp_path / "bad.csv").write_text("time,tension.sheave\n0,1\n0.05,abc\n", encoding="utf-8")
    with pytest.raises(ValueError, match=r"row 3, column 'tension.sheave': 'abc'"):
        read_csv(tmp_path / "bad.csv")


# ---------------------------------------------------------------- bending damage
def test_bending_endurance_goes_together():
    with pytest.raises(SceneError) as info:
        parse(Rope, {"breaking_strength": 7e4, "bending_cycles": 1e6}, "cable.segments[0].rope")
    assert "cable.segments[0].rope.bending_tension" in str(info.value) and "go together" in str(info.value)


def test_bending_damage_along_the_rope_is_the_miner_sum_of_its_passes():
    scene = load_scene("full_scale")
    path = bending.rope_path(scene)
    n0, s0, p = 2.0e5, 4.0e3, 3.5
    # 10 periods of a 0.8 m sinusoidal payout: 5 at 4 kN, then 5 at 6 kN
    t, payout = _sine_payout(0.8, 10.0, 10)
    tension = np.where(t <= 50.0, 4.0e3, 6.0e3)
    series = {"winch.phi": scene.winch.phi_nom - payout / path.drum_radius, "contact.wrap_angle": 0 * t + 0.33,
              "tension.winch": tension, "tension.sheave": tension}
    endurance = lambda s: rope_data_bending(s, n0, s0, p)  # noqa: E731
    result = bending.bending_cycles(path, scene.cable.length, series, endurance=endurance)
    # leave out the points the places cross in the one step in which the tension changes (at
    # t = 50 s the payout passes zero: within 0.8 m x sin(2 pi 0.025 / 10) = 1.3 cm of the
    # places' mid positions); their crossing counts at the step's mean tension
    places = bending.bend_places(path, scene.cable.length, series)
    away = np.all([np.abs(result.x - p0[0]) > 0.02 for p0 in places.values()], axis=0)
    cycles = np.where(away, result.sheave + result.drum, -1.0)
    full = cycles == 20.0                                 # points crossing two places: 10 cycles at each
    # Feyrer's collective (eq. 3.93a): Z cycles with shares u_i at k_i = S_i / S_0 are worth
    # Z sum u_i k_i^p cycles at S_0: here 10 cycles, half at k = 1, half at k = 1.5
    collective = 10 * (0.5 * 1.0 + 0.5 * 1.5 ** p) / n0
    one_place = away & ((result.sheave == 10.0) & (result.drum == 0.0) | (result.sheave == 0.0) & (result.drum == 10.0))
    assert np.count_nonzero(one_place) > 50
    np.testing.assert_allclose(result.damage[one_place], collective, rtol=1e-12)
    np.testing.assert_allclose(result.damage[full], 2 * collective, rtol=1e-12)
    assert np.all(result.damage[cycles == 0] == 0.0)


def test_report_gives_bending_damage_with_an_endurance(tmp_path):
    run = _winch_run(0)
    write_csv(tmp_path / "run.csv", run)
    sets = []
    for i in range(5):
        sets += ["--set", f"cable.segments[{i}].rope={{ breaking_strength = 69800.0, bending_cycles = 1e6, "
                          f"bending_tension = 4000.0, bending_exponent = 3.0 }}"]
    assert main(["fatigue", str(tmp_path / "run.csv"), "--scene", "full_scale", "--output", str(tmp_path / "o")]
                + sets) == 0
    text = (tmp_path / "o" / "report.md").read_text(encoding="utf-8")
    assert "its bending damage per year" in text and "Feyrer" in text


@pytest.mark.parametrize("name", ["full_scale", "full_scale_deploy"])
def test_a_run_with_a_sinusoidal_payout_program_bends_the_closed_form_points(name):
    """The simulation itself (ship still, no compensation) with the winch's payout program
    A (1 - cos 2 pi t / P): each bending place moves over 2 A of rope and back every period,
    so the points within its stroke are crossed twice a period (the winch's PD drive follows
    the program to 0.3 mm)."""
    amplitude, period, periods = 0.4, 10.0, 3
    times = np.arange(0.0, periods * period + 1e-9, 0.1)
    program = amplitude * (1.0 - np.cos(2 * np.pi * times / period))
    overrides = {"motion.type": "none", "compensation.algorithm": "none",
                 "winch.program_times": [float(v) + 1.0 for v in times],
                 "winch.program_payout": [float(v) for v in program]}
    scene = load_scene(name, overrides)
    series = simulation_from(name, overrides).run(periods * period + 6.0, interval=0.05)
    path = bending.rope_path(scene)
    result = assess(scene, [("run", series)]).runs[0].bending
    # the places at zero payout, from the scene alone
    if scene.cable.top.type == "winch":
        drum0 = scene.cable.length - path.drum_radius * (scene.winch.phi_nom - path.departure_angle)
    else:
        drum0 = scene.cable.length - path.drum_radius * ((path.spool_angle - path.departure_angle) % (2 * np.pi))
    on0 = drum0 - path.span
    off0 = on0 - path.sheave_radius * float(np.mean(series["contact.wrap_angle"]))
    x, stroke, margin = result.x, 2.0 * amplitude, 0.01
    inside = {c: ((x > c) & (x < c + stroke)).astype(int) for c in (drum0, on0, off0)}
    clear = np.all([np.abs(x - c) > margin for c in (drum0, on0, off0)]
                   + [np.abs(x - c - stroke) > margin for c in (drum0, on0, off0)], axis=0)
    np.testing.assert_array_equal(result.drum[clear], periods * inside[drum0][clear])
    np.testing.assert_array_equal(result.sheave[clear], periods * (inside[on0] + inside[off0])[clear])
    assert np.count_nonzero(result.sheave[clear] == 2 * periods) > 50   # the stroke is longer than the arc


def test_a_deploy_run_gives_every_point_paid_past_the_sheave_and_back_exactly_those_passes():
    """full_scale_deploy's own program (ship still): veer 300 m from the spool, hold, haul the
    300 m back. A point that went from the drum past the sheave and came back made two passes
    over the sheave and left and rejoined the drum once: 2 sheave cycles, 1 drum cycle; a
    point that stayed in the water none."""
    overrides = {"motion.type": "none", "compensation.algorithm": "none"}
    scene = load_scene("full_scale_deploy", overrides)
    series = simulation_from("full_scale_deploy", overrides).run(700.0, interval=0.1)
    assert series["winch.deployed"].max() - series["winch.deployed"][0] == pytest.approx(300.0, abs=0.01)
    bent = assess(scene, [("deploy", series)]).runs[0].bending
    path = bending.rope_path(scene)
    drum0 = scene.cable.length - path.drum_radius * ((path.spool_angle - path.departure_angle) % (2 * np.pi))
    off0 = drum0 - path.span - path.sheave_radius * float(np.max(series["contact.wrap_angle"]))
    x, margin = bent.x, 0.05
    middle = (x > drum0 + margin) & (x < off0 + 300.0 - margin)
    assert np.count_nonzero(middle) > 28000
    assert np.all(bent.sheave[middle] == 2.0) and np.all(bent.drum[middle] == 1.0)
    water = x < off0 - margin
    assert np.all(bent.sheave[water] == 0.0) and np.all(bent.drum[water] == 0.0)
