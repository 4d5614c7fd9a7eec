"""How fast could it go? Upper bounds on the speed of two targets of issue 18.

A second-order implicit step of our cable cannot cost less than one residual evaluation
and one back-solve with a matrix already factorised (a step that converges in one Newton
iteration, a factorisation that is never refreshed), plus the outputs it records. This
benchmark measures those three per-call costs on states of real runs (compiled loops, the
median over the states) and turns them into the best speed any such step could reach at
the step size the accuracy allows:

* ``snapping_cable`` (abrupt 1.27 Hz): h = 0.5 ms is the largest step within 1 % RMS
  series error (1 ms gives 3.6 %, ``results/snapping.md``), with outputs every 0.5 ms; at
  20 elements (the scene's mesh) and at 12 (the coarsest within 1 %). MoorDyn's matched
  set-up (20 segments, RK4, 0.2 ms) is run here, median of 3, for the ratio; the target
  is 2x MoorDyn.
* the main job (``towcable cosim``, 0.01 s communication steps): the two other FMUs and
  the master's glue per step (``cosim.py``'s runs, medians) plus TowCable's
  lowest cost per 0.01 s step of ``full_scale``; the target is 50x real time.

Writes ``results/bounds.md``. Run: ``python benchmarks/bounds.py`` (about 2 min).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from towcable_fmu.ancf.system import residual
from towcable_fmu.numerics.banded import band_solve
from towcable_fmu.ancf.output_kernel import output_values

import cosim
import snapping
from common import RESULTS, machine_header, markdown_table, per_call_us

SNAP_FREQUENCY = 1.27
SNAP_STEP = 5e-4
SNAP_POINTS = 2
COSIM_STEP = 0.01
#: states the per-call costs are measured on: every `spacing` seconds of a run, `count` of them
SNAP_STATES = (0.5, 8)
COSIM_STATES = (10.0, 6)
CALLS = 2000


@njit(cache=True)
def _residuals(model, q, v, a, t, ship, r, n):
    for _ in range(n):
        residual(model, q, v, a, t, ship, r)


@njit(cache=True)
def _solves(ab, size, kl, ku, ipiv, rhs, x, n):
    for _ in range(n):
        x[:] = rhs
        band_solve(ab, size, kl, ku, ipiv, x)


@njit(cache=True)
def _outputs(model, q, v, a, phi, t, ship, scene, r, n):
    for _ in range(n):
        output_values(model, q, v, a, phi, t, ship, scene, r)


def _per_call_us(loop, *args) -> float:
    """Cost of one call [us] of the kernel a compiled ``loop`` calls CALLS times
    (:func:`common.per_call_us` over whole loops: no Python between the calls)."""
    return per_call_us(lambda: loop(*args, CALLS)) / CALLS


def step_costs(scene: str, overrides: dict, states: tuple[float, int]) -> dict[str, float]:
    """Median per-call costs [us] of a residual, a back-solve and the outputs over states
    of a run of ``scene`` (``states``: spacing [s], count), and the run's counters."""
    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene(scene, overrides)
    sim.initialize()
    spacing, count = states
    rows = []
    for _ in range(count):
        sim.run(spacing, spacing)
        m, st, ws = sim.model, sim.state, sim.workspace
        n = m.free_dofs.shape[0]
        rhs = np.linspace(-1.0, 1.0, n)
        rows.append([_per_call_us(_residuals, m, st.q, st.v, st.a, sim.time, ws.ship, ws.r),
                     _per_call_us(_solves, ws.ab, n, m.kl, m.ku, ws.ipiv, rhs, np.empty(n)),
                     _per_call_us(_outputs, m, st.q, st.v, st.a, st.phi, sim.time, ws.ship, sim.output_scene,
                                  ws.r)])
    residual_us, solve_us, output_us = np.median(np.array(rows), axis=0)
    stats = sim.statistics()
    return {"residual": float(residual_us), "solve": float(solve_us), "outputs": float(output_us),
            "iterations": stats["solver.newton_iterations"] / stats["solver.steps"],
            "factorisations": stats["solver.jacobian_factorisations"] / stats["solver.steps"]}


def cosim_others() -> dict[str, float]:
    """Per communication step [us]: ShipMotion, HeaveCompensation and the glue outside the
    three models, and TowCable; and the x real time (``cosim.cosim``: medians of its runs)."""
    cosim.cosim(COSIM_STEP)  # builds the FMUs if needed, loads the kernels
    t = cosim.cosim(COSIM_STEP)
    steps = t["steps"]
    return {"ShipMotion": 1e6 * t["model.ShipMotion"] / steps,
            "HeaveCompensation": 1e6 * t["model.HeaveCompensation"] / steps,
            "glue": 1e6 * (t["wall"] - t["model"]) / steps, "TowCable": 1e6 * t["model.TowCable"] / steps,
            "speed": t["realtime_factor"]}


def main() -> None:
    moordyn = None
    if snapping.peers_available()["MoorDyn"]:
        matched = snapping.peer("MoorDyn", SNAP_FREQUENCY, *snapping.MATCHED, repeats=snapping.REPEATS)
        moordyn = snapping.DURATION / matched["wall_time_s"]
    snap_rows = []
    for elements in (20, 12):
        c = step_costs("snapping_cable", {"cable.segments[0].elements": elements, "solver.time_step": SNAP_STEP},
                       SNAP_STATES)
        floor = c["residual"] + c["solve"] + c["outputs"]  # one step, one sample per step
        bound = SNAP_STEP / (1e-6 * floor)
        ours = snapping.ours(SNAP_FREQUENCY, elements, SNAP_STEP, SNAP_POINTS, repeats=snapping.REPEATS)
        speed = snapping.DURATION / ours["wall_time_s"]
        ratio = (lambda x: f"{x / moordyn:.2f}") if moordyn else (lambda x: "-")
        unrecorded = SNAP_STEP / (1e-6 * (c["residual"] + c["solve"]))  # the same with outputs free
        snap_rows.append([elements, f"{c['residual']:.1f}", f"{c['solve']:.1f}", f"{c['outputs']:.1f}",
                          f"{floor:.1f}", f"{bound:.1f}", ratio(bound), ratio(unrecorded), f"{speed:.1f}", ratio(speed),
                          f"{c['iterations']:.2f}", f"{c['factorisations']:.2f}"])
        print(snap_rows[-1], flush=True)
    others = cosim_others()
    c = step_costs("full_scale", {"compensation": {"algorithm": "simplified_sheave"}, "solver.time_step": COSIM_STEP},
                   COSIM_STATES)
    tow_floor = c["residual"] + c["solve"] + c["outputs"]
    outside = others["ShipMotion"] + others["HeaveCompensation"] + others["glue"]
    cosim_rows = [
        ["ShipMotion, HeaveCompensation, glue (measured)", f"{outside:.0f}", f"{COSIM_STEP / (1e-6 * outside):.0f}"],
        ["+ TowCable's floor: residual, back-solve, outputs "
         f"({c['residual']:.0f} + {c['solve']:.0f} + {c['outputs']:.0f})", f"{outside + tow_floor:.0f}",
         f"{COSIM_STEP / (1e-6 * (outside + tow_floor)):.1f}"],
        [f"as run: TowCable {others['TowCable']:.0f} us per step ({c['iterations']:.2f} iterations, "
         f"{c['factorisations']:.2f} factorisations)", f"{outside + others['TowCable']:.0f}", f"{others['speed']:.1f}"],
    ]
    text = ["# Upper bounds: how fast one Newton iteration per step would go\n", machine_header(), "\n",
            __doc__.split("\n\n")[1].replace("\n", " ") + "\n",
            f"\n## snapping_cable, {SNAP_FREQUENCY:g} Hz, h = {SNAP_STEP * 1e3:g} ms, {snapping.DURATION:g} s, outputs "
            "every 0.5 ms\n\n",
            f"Per-call costs: medians over {SNAP_STATES[1]} states {SNAP_STATES[0]:g} s apart. "
            f"MoorDyn ({snapping.MATCHED[0]} segments, RK4, {snapping.MATCHED[1] * 1e3:g} ms, median of "
            f"{snapping.REPEATS}): "
            + (f"{moordyn:.1f} x real time.\n\n" if moordyn else "not installed.\n\n"),
            markdown_table(["elements", "residual [us]", "back-solve [us]", "outputs [us]", "floor per step [us]",
                            "bound [x real time]", "bound / MoorDyn",
                            "bound, outputs free / MoorDyn", "as run [x real time]", "as run / MoorDyn",
                            "iterations per step", "factorisations per step"], snap_rows),
            f"\n## Main job: `towcable cosim`, {COSIM_STEP:g} s communication step, {cosim.DURATION:g} s (medians of "
            f"{cosim.REPEATS} runs)\n\n",
            f"TowCable's per-call costs on full_scale at h = {COSIM_STEP:g} s: medians over {COSIM_STATES[1]} states "
            f"{COSIM_STATES[0]:g} s apart.\n\n",
            markdown_table(["per communication step", "cost [us]", "x real time"], cosim_rows)]
    (RESULTS / "bounds.md").write_text("".join(text))
    print("".join(text))


if __name__ == "__main__":
    main()
