"""VIV of the wire rope over two sheaves, the four cases of Westin 2018 appendix A (Table A2).

For each case (built-in scenes viv_sheave, viv_sheave_case2..4):

* pluck: no wind, no damping, a first-mode velocity on the span; the frequency of the
  mid-span vertical motion (largest spectral peak over 8 s) against A24;
* lock-in: the scene as it is (wind at the Table A2 speed, wake oscillators), mid-span
  vertical amplitude and frequency (zero crossings) over the last 5 s of a 15 s (2 m
  span) or 30 s (5 m spans) run, and the amplitude of the 5 s before (steadiness).

Writes ``results.json`` and the table ``results.md`` next to this file.
Run: ``python docs/studies/viv_sheave/run.py`` (about a minute).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from towcable_fmu.ancf.simulation import Simulation

HERE = Path(__file__).resolve().parent
D, MU, EI, XI = 0.020, 1.38, 0.73, 0.10
CASES = {1: ("viv_sheave", 2.0, 200.0, 12, 19.9, 0.302), 2: ("viv_sheave_case2", 5.0, 200.0, 16, 7.57, 0.121),
         3: ("viv_sheave_case3", 5.0, 500.0, 16, 12.0, 0.190), 4: ("viv_sheave_case4", 5.0, 1000.0, 16, 16.9, 0.269)}
H = 0.002


def omega_a24(span: float, tension: float) -> float:
    """Eq. A24 [rad/s]."""
    return (math.pi / span) ** 2 * math.sqrt(EI / MU * (1.0 + tension / EI * (span / math.pi) ** 2))


def amplitude_frequency(x: np.ndarray, h: float) -> tuple[float, float]:
    """Half peak-to-peak and angular frequency from upward zero crossings."""
    x = x - 0.5 * (x.max() + x.min())
    i = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    t = (i + x[i] / (x[i] - x[i + 1])) * h
    return 0.5 * (x.max() - x.min()), 2.0 * math.pi * (t.size - 1) / (t[-1] - t[0])


def spectral_peak(x: np.ndarray, h: float, low: float, high: float) -> float:
    """Angular frequency of the largest peak of the Hann-windowed, 16x zero-padded spectrum in (low, high)."""
    n = x.size
    spectrum = np.abs(np.fft.rfft((x - x.mean()) * np.hanning(n), 16 * n))
    omega = 2.0 * math.pi * np.fft.rfftfreq(16 * n, h)
    band = np.flatnonzero((omega > low) & (omega < high))
    return float(omega[band[np.argmax(spectrum[band])]])


def record(sim: Simulation, node: int, duration: float) -> np.ndarray:
    t0 = sim.time
    z = np.empty(int(round(duration / H)))
    for k in range(z.size):
        sim.advance(t0 + (k + 1) * H)
        z[k] = sim.node_positions()[node, 2]
    return z


def pluck(scene: str, span_nodes: range, span: float, tension: float) -> float:
    overrides = {"viv.enabled": False, "water.current.type": "none", "water.current.velocity": [0.0, 0.0, 0.0]}
    overrides.update({f"cable.segments[{i}].damping": 0.0 for i in range(5)})
    sim = Simulation.from_scene(scene, overrides)
    sim.initialize()
    x = sim.node_positions()[list(span_nodes)]
    s = (x[:, 0] - x[0, 0]) / (x[-1, 0] - x[0, 0])
    q = sim.state.q.copy()
    v = np.zeros_like(q)
    for k, node in enumerate(span_nodes):
        v[6 * node + 2] = 0.01 * math.sin(math.pi * s[k])
        v[6 * node + 5] = 0.01 * math.pi / span * math.cos(math.pi * s[k])
    sim.set_coordinates(q, v)
    mid = span_nodes[len(span_nodes) // 2]
    omega = omega_a24(span, tension)
    return spectral_peak(record(sim, mid, 8.0), H, 0.7 * omega, 1.2 * omega)


def main() -> None:
    rows = []
    for case, (scene, span, tension, n_span, table_omega, table_speed) in CASES.items():
        sim = Simulation.from_scene(scene)
        first = sum(s.elements for s in sim.scene.cable.segments[:2])  # the span's first node (after the free end and sheave 1)
        nodes = range(first, first + n_span + 1)
        mid = first + n_span // 2
        omega_pluck = pluck(scene, nodes, span, tension)
        sim.initialize()
        duration = 15.0 if span < 3.0 else 30.0  # the 5 m spans settle more slowly (xi omega smaller)
        z = record(sim, mid, duration)
        amp, omega = amplitude_frequency(z[-int(5.0 / H):], H)
        amp_early, _ = amplitude_frequency(z[-int(10.0 / H):-int(5.0 / H)], H)
        wake = next(h for h in sim.hooks if h.name == "wake").coupling  # the wake oscillators
        row = {"case": case, "scene": scene, "span": span, "tension": tension, "omega_a24": omega_a24(span, tension),
               "omega_table": table_omega, "speed_table": table_speed, "speed": wake.speed,
               "omega_st": wake.omega, "omega_pluck": omega_pluck, "omega_response": omega,
               "amplitude": amp, "amplitude_over_d": amp / D, "amplitude_previous_5s": amp_early}
        rows.append(row)
        print(json.dumps(row))
    (HERE / "results.json").write_text(json.dumps(rows, indent=1) + "\n", encoding="utf-8")
    lines = ["| case | span [m] | T [N] | omega_n A24 [rad/s] | Table A2 | U [m/s] | model first mode (pluck) "
             "[rad/s] | response frequency [rad/s] | amplitude A [m] | A/d | A (5 s earlier) / A |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['span']:g} | {r['tension']:g} | {r['omega_a24']:.2f} | {r['omega_table']} | "
                     f"{r['speed']:.4f} | {r['omega_pluck']:.2f} ({r['omega_pluck'] / r['omega_a24'] - 1:+.1%}) | "
                     f"{r['omega_response']:.2f} ({r['omega_response'] / r['omega_st'] - 1:+.1%} of w_st) | "
                     f"{r['amplitude']:.2e} | {r['amplitude_over_d']:.1e} | "
                     f"{r['amplitude_previous_5s'] / r['amplitude']:.3f} |")
    (HERE / "results.md").write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
