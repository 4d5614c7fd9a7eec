"""Rope life: rope data in the scene, tension fatigue (rainflow, Miner), extremes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from towcable_fmu.errors import SceneError
from towcable_fmu.rope_life import extremes, tension_fatigue
from towcable_fmu.rope_life.rope_data import TN_CURVES, cycles_to_failure, intercept_at_mean_load, tn_curve
from towcable_fmu.scene.model import Rope
from towcable_fmu.scene.schema import parse


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
