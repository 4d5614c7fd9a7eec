"""Where the time goes, scene by scene.

For every built-in scene: a run of a few seconds with the scene's own settings gives the
counts (time steps, residual evaluations, Jacobian factorisations) and the wall time;
the per-call cost of each kernel, measured on the state the run ends in, times its
count gives its share:

* elastic: the residual with the water and the contact switched off (inertia, internal
  damping, bending, axial force, gravity);
* hydrodynamics and contact: what switching each on adds to the residual;
* Jacobian: assembling the banded iteration matrix; LU: its factorisation; back-solves;
* the rest: the integrator's own arithmetic (predictor, error estimate, drive
  polynomials), the outputs and Python.

Kernel calls from Python pay for unboxing the model (measured with an empty compiled
function and subtracted); inside the compiled loop they do not. Writes
``results/profile.md`` and ``results/profile.png``. Run: ``python benchmarks/profile_scenes.py``.
"""

from __future__ import annotations

import time

import numpy as np
from numba import njit

from common import RESULTS, machine_header, markdown_table, per_call_us

SCENES = {"hanging_cable": 20.0, "snapping_cable": 5.0, "flume_pinned": 10.0, "flume": 10.0,
          "full_scale_pinned": 20.0, "full_scale": 20.0, "pulley_static": 2.0, "pulley_moving": 2.0}
PARTS = ("elastic", "hydrodynamics", "contact", "Jacobian", "LU", "back-solve", "rest")


@njit(cache=True)
def _unbox(model) -> int:
    return model.kl


def profile(name: str, duration: float) -> dict:
    """Counts, wall time and the time per part [s] of a run of ``duration`` seconds."""
    from towcable_fmu.ancf.system import iteration_matrix, residual
    from towcable_fmu.numerics.banded import band_lu, band_solve
    from towcable_fmu.ancf.simulation import Simulation

    warm = Simulation.from_scene(name)  # loads the compiled kernels (numba cache) outside the timing
    warm.initialize()
    warm.run(0.05)
    sim = Simulation.from_scene(name)
    sim.initialize()
    start = time.perf_counter()
    sim.run(duration)
    wall = time.perf_counter() - start
    stats = sim.statistics()
    m, st, ws = sim.model, sim.state, sim.workspace
    t = sim.time
    r = np.zeros_like(st.q)
    unbox = per_call_us(lambda: _unbox(m))
    no_contact = m.terms._replace(contact=m.terms.contact._replace(enabled=False))
    dry = m._replace(water=m.water._replace(enabled=False), terms=no_contact)
    wet = m._replace(terms=no_contact)
    touching = m._replace(water=m.water._replace(enabled=False))

    def cost(model) -> float:
        return per_call_us(lambda: residual(model, st.q, st.v, st.a, t, ws.ship, r)) - unbox

    elastic = cost(dry)
    hydro = cost(wet) - elastic if m.water.enabled else 0.0
    contact = cost(touching) - elastic if m.terms.contact.enabled else 0.0
    n = m.free_dofs.size
    ab = ws.ab.copy()
    jac = per_call_us(lambda: iteration_matrix(m, st.q, st.v, t, ws.ship, 1.0, 1e-3, 1e-6, ab)) - unbox
    factors = ab.copy()
    band_lu(factors, n, m.kl, m.ku, ws.ipiv)
    copy = per_call_us(lambda: ab.copy())
    lu = per_call_us(lambda: band_lu(ab.copy(), n, m.kl, m.ku, ws.ipiv)) - copy
    x = np.ones(n)
    solve = per_call_us(lambda: band_solve(factors, n, m.kl, m.ku, ws.ipiv, x))
    residuals = stats["solver.residual_evaluations"]
    jacobians = stats["solver.jacobian_factorisations"]
    parts = {"elastic": residuals * elastic, "hydrodynamics": residuals * hydro, "contact": residuals * contact,
             "Jacobian": jacobians * jac, "LU": jacobians * lu, "back-solve": residuals * solve}
    parts = {k: 1e-6 * v for k, v in parts.items()}
    parts["rest"] = max(wall - sum(parts.values()), 0.0)
    return {"scene": name, "duration": duration, "wall": wall, "steps": stats["solver.steps"],
            "residuals": residuals, "jacobians": jacobians, "unknowns": n, "elements": sim.mesh.n_elements,
            "us_residual": elastic + hydro + contact, "us_jacobian": jac, "us_lu": lu, "parts": parts}


def main() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    results = [profile(name, duration) for name, duration in SCENES.items()]
    rows = []
    for p in results:
        share = {k: 100.0 * v / p["wall"] for k, v in p["parts"].items()}
        rows.append([p["scene"], p["elements"], f"{p['duration']:g}", f"{p['duration'] / p['wall']:.1f}",
                     p["steps"], f"{p['residuals'] / p['steps']:.2f}", f"{p['jacobians'] / p['steps']:.3f}",
                     f"{p['us_residual']:.1f}", f"{p['us_jacobian']:.1f}", f"{p['us_lu']:.1f}"]
                    + [f"{share[k]:.0f}" for k in PARTS])
    text = ["# Where the time goes, scene by scene\n", machine_header(),
            "\nEach scene runs with its own settings for the simulated time given; per-call costs are measured "
            "on its final state (see the module docstring of `profile_scenes.py`). The shares are of the run's "
            "wall time; 'rest' is the integrator's own arithmetic, the outputs and Python. A scene pays only "
            "for what it contains: dry scenes show no hydrodynamics, scenes without winch or sheave no "
            "contact.\n\n",
            markdown_table(["scene", "elements", "sim [s]", "x real time", "steps", "residuals/step",
                            "Jacobians/step", "residual [us]", "Jacobian [us]", "LU [us]"]
                           + [f"{k} [%]" for k in PARTS], rows)]
    (RESULTS / "profile.md").write_text("".join(text), encoding="utf-8")

    fig, ax = plt.subplots(figsize=(10, 4.5))
    left = np.zeros(len(results))
    for part in PARTS:
        widths = np.array([100.0 * p["parts"][part] / p["wall"] for p in results])
        ax.barh([p["scene"] for p in results], widths, left=left, label=part)
        left += widths
    ax.set_xlabel("share of the wall time [%]")
    ax.set_title("where the time goes (built-in scenes, their own settings)")
    ax.legend(ncol=4, fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(RESULTS / "profile.png", dpi=120)
    print("".join(text))


if __name__ == "__main__":
    main()
