"""Where a communication step of the main job goes, model by model and part by part.

The three slaves of ``towcable cosim`` (full_scale, default sea, simplified-sheave
set-point) are run in this process as Python objects, wired as the master wires them
(the values copied in Python: no FMI C layer, no master), at a 0.01 s communication
step for 60 s after a 20 s settle. Reported per communication step (medians over
blocks of 100 steps):

* each slave's own model time (its ``model_wall_time``) and all the calls the master
  makes on it (``set_real`` of its inputs, ``do_step``, ``get_real`` of its outputs:
  the model plus the slave's Python glue);
* TowCable: Newton iterations, residual evaluations and factorisations per step, and
  the per-call costs of a residual, a factorisation (iteration matrix and banded LU),
  a back-solve and the outputs (each a compiled loop over the same call at the last
  state), with the time left for the rest of the step (Python around the compiled
  step, the integrator's own loops); the residual's contact and hydrodynamic terms, the
  iteration matrix (its contact and hydrodynamic tangents) and the banded LU apart
  (with a copy of the matrix, 417 x 417 with 11 sub- and super-diagonals on full_scale),
  and the outputs' contact summary;
* the standalone ``Simulation.step`` of the same scene at the same step, and
  ``towcable run full_scale --set solver.time_step=0.01`` (``Simulation.run``).

Run: ``python benchmarks/cosim_step.py`` (prints a Markdown table; figures are medians,
on a shared machine compare only figures of one run).
"""

from __future__ import annotations

import statistics
import time

import numpy as np
from numba import njit

from common import machine_header, markdown_table, per_call_us
from towcable_fmu.ancf.forces import contact_quadrature, hydro_quadrature
from towcable_fmu.ancf.forces.contact import elements
from towcable_fmu.ancf.output_kernel import output_values
from towcable_fmu.ancf.system import iteration_matrix, residual
from towcable_fmu.numerics.banded import band_lu, band_solve

STEP = 0.01
SETTLE = 20.0
DURATION = 60.0
BLOCK = 100
CALLS = 200


@njit(cache=True)
def _residuals(model, q, v, a, t, ship, r, n):
    for _ in range(n):
        residual(model, q, v, a, t, ship, r)


@njit(cache=True)
def _factorisations(model, q, v, t, ship, ab, ipiv, n):
    for _ in range(n):
        iteration_matrix(model, q, v, t, ship, 1.0, 1e-3, 1e-5, ab)
        band_lu(ab, model.free_dofs.shape[0], model.kl, model.ku, ipiv)


@njit(cache=True)
def _matrices(model, q, v, t, ship, ab, n):
    for _ in range(n):
        iteration_matrix(model, q, v, t, ship, 1.0, 1e-3, 1e-5, ab)


@njit(cache=True)
def _lus(model, ab0, ab, ipiv, n):
    for _ in range(n):
        ab[:, :] = ab0
        band_lu(ab, model.free_dofs.shape[0], model.kl, model.ku, ipiv)


@njit(cache=True)
def _contact_residuals(model, q, v, ship, r, n):
    for _ in range(n):
        contact_quadrature.add_residual(model.terms.contact, elements(model), q, v, ship, 0, model.el_len.shape[0], r)


@njit(cache=True)
def _hydro_residuals(model, q, v, a, t, r, n):
    for _ in range(n):
        hydro_quadrature.add_residual(model.water, model.terms.hydrodynamics, model.el_len, q, v, a, t, 0,
                                      model.el_len.shape[0], r)


@njit(cache=True)
def _contact_tangents(model, q, v, ship, n):
    ne = model.el_len.shape[0]
    blocks = np.empty((ne, 12, 12))
    touched = np.empty(ne, dtype=np.bool_)
    for _ in range(n):
        contact_quadrature.add_jacobian(model.terms.contact, elements(model), q, v, ship, 1e-3, 1e-5, blocks, touched)


@njit(cache=True)
def _hydro_tangents(model, q, v, t, n):
    ne = model.el_len.shape[0]
    blocks = np.empty((ne, 12, 12))
    wet = np.empty(ne, dtype=np.bool_)
    for _ in range(n):
        hydro_quadrature.add_jacobians(model.water, model.terms.hydrodynamics, model.el_len, q, v, t, 1.0, 1e-3,
                                       1e-5, blocks, wet)


@njit(cache=True)
def _contact_summaries(model, q, v, ship, n):
    for _ in range(n):
        contact_quadrature.surface_summary(model.terms.contact, elements(model), q, v, ship,
                                           contact_quadrature.new_summary(0))


@njit(cache=True)
def _solves(model, ab, ipiv, rhs, n):
    for _ in range(n):
        rhs[:] = 1.0
        band_solve(ab, model.free_dofs.shape[0], model.kl, model.ku, ipiv, rhs)


@njit(cache=True)
def _outputs(model, q, v, a, phi, t, ship, scene, r, n):
    for _ in range(n):
        output_values(model, q, v, a, phi, t, ship, scene, r)


def _slaves():
    """The three slaves with the master's parameters, initialised as the master does."""
    from ship_motion.fmu import ShipMotion
    from controllers.fmu import HeaveCompensation
    from towcable_fmu.fmu import TowCable
    from towcable_fmu.cosim import CosimConfig
    from towcable_fmu.cosim.config import compensation_geometry
    from towcable_fmu.scene import load_scene

    config = CosimConfig(duration=DURATION, step=STEP, compensation="simplified_sheave")
    geometry = compensation_geometry(load_scene("full_scale"), config)
    ship, ctrl, cable = (cls(instance_name=cls.__name__, resources=None)
                         for cls in (ShipMotion, HeaveCompensation, TowCable))
    cable.values["scene"] = "full_scale"
    ctrl.values.update({"algorithm": geometry["algorithm"], "winch_radius": geometry["winch_radius"],
                        "phi_nom": geometry["phi_nom"],
                        **{f"reference_point.{c}": v for c, v in zip("xyz", geometry["reference_point"])}})
    for key, value in geometry["extra"].items():
        ctrl.values[key] = 0.0 if value is None else float(value)
    for s in (ship, ctrl, cable):
        s.setup_experiment(0.0)
        s.enter_initialization_mode()
    ship.exit_initialization_mode()
    names = [n for n in ship.values if n.startswith("ship.")]
    for n in names:
        cable.values[n] = ship.values[n]
    cable.values["winch.phi_sp"] = geometry["phi_nom"]
    cable.values["winch.phi_sp_rate"] = 0.0
    cable.exit_initialization_mode()
    ctrl.values["theta_nom"] = min(max(cable.values["sheave_angle"], 0.0), 0.5 * np.pi - 1e-6)
    return ship, ctrl, cable, names


def _exchange(slaves: dict) -> tuple[dict, dict]:
    """Per slave: the value references of its connected Real inputs with where each comes
    from (source slave, its output's value reference), and of its Real outputs."""
    from towcable_fmu.common import contract

    vr = {name: {var.name: ref for ref, var in slave.vars.items()} for name, slave in slaves.items()}
    inputs = {name: ([], []) for name in slaves}
    for c in contract.connections():
        inputs[c.target][0].append(vr[c.target][c.signal])
        inputs[c.target][1].append((c.source, vr[c.source][c.signal]))
    outputs = {name: [vr[name][v.name] for v in slave.spec.outputs if v.type == "Real"]
               for name, slave in slaves.items()}
    return inputs, outputs


def profile() -> dict[str, float]:
    """Per-step medians of the in-process system (module docstring): the master's calls
    (set inputs, step, get outputs) made on the slaves' Python methods."""
    ship, ctrl, cable, _ = _slaves()
    slaves = {"ShipMotion": ship, "HeaveCompensation": ctrl, "TowCable": cable}
    inputs, outputs = _exchange(slaves)
    last = {name: dict(zip(outputs[name], slave.get_real(outputs[name]))) for name, slave in slaves.items()}
    ctrl.exit_initialization_mode()
    sim = cable.sim
    stats = sim.state.stats
    keys = [f"{n}.{part}" for n in slaves for part in ("model", "calls")] + ["iterations", "residuals",
                                                                           "factorisations"]
    rows = {k: [] for k in keys}
    n_steps = int(round((SETTLE + DURATION) / STEP))
    acc = dict.fromkeys(keys, 0.0)
    counts = stats.copy()

    def feed(name):
        refs, sources = inputs[name]
        if refs:
            slaves[name].set_real(refs, [last[src][ref] for src, ref in sources])

    def read(name):
        last[name] = dict(zip(outputs[name], slaves[name].get_real(outputs[name])))

    for k in range(n_steps):
        t = k * STEP
        model = {name: slave._model_time for name, slave in slaves.items()}
        calls = dict.fromkeys(slaves, 0.0)
        a = time.perf_counter()
        feed("HeaveCompensation")  # the master's order (towcable_fmu.cosim.master)
        read("HeaveCompensation")
        b = time.perf_counter()
        calls["HeaveCompensation"] += b - a
        for name in ("ShipMotion", "TowCable"):
            a = time.perf_counter()
            feed(name)
            calls[name] += time.perf_counter() - a
        for name, slave in slaves.items():
            a = time.perf_counter()
            if not slave.do_step(t, STEP):
                raise RuntimeError(f"{name} refused the step at t = {t}")
            calls[name] += time.perf_counter() - a
        for name in ("ShipMotion", "TowCable"):
            a = time.perf_counter()
            read(name)
            calls[name] += time.perf_counter() - a
        if t >= SETTLE:
            for name, slave in slaves.items():
                acc[f"{name}.model"] += slave._model_time - model[name]
                acc[f"{name}.calls"] += calls[name]
        if k % BLOCK == BLOCK - 1:
            if t >= SETTLE:
                d = stats - counts
                acc["iterations"], acc["residuals"], acc["factorisations"] = d[2], d[3], d[4]
                for key, value in acc.items():
                    rows[key].append(value / BLOCK)
            acc = dict.fromkeys(keys, 0.0)
            counts = stats.copy()
    out = {key: statistics.median(v) for key, v in rows.items()}
    for key in ("iterations", "residuals", "factorisations"):
        out[key] = float(np.mean(rows[key]))
    out.update(_part_costs(sim))
    return out


def _part_costs(sim) -> dict[str, float]:
    """Per-call costs [s] at the current state of ``sim`` (compiled loops of ``CALLS`` calls:
    a call from Python would add the unboxing of the model)."""
    m, st, ws = sim.model, sim.state, sim.workspace
    rhs = np.ones(m.free_dofs.size)
    ab = ws.ab.copy()
    ipiv = ws.ipiv.copy()
    r = np.empty_like(ws.r)
    q, v, a, t, ship = st.q, st.v, st.a, sim.time, ws.ship
    iteration_matrix(m, q, v, t, ship, 1.0, 1e-3, 1e-5, ab)
    ab0 = ab.copy()
    loops = {
        "residual": lambda: _residuals(m, q, v, a, t, ship, r, CALLS),
        "residual.contact": lambda: _contact_residuals(m, q, v, ship, r, CALLS),
        "residual.hydro": lambda: _hydro_residuals(m, q, v, a, t, r, CALLS),
        "factorisation": lambda: _factorisations(m, q, v, t, ship, ab, ipiv, CALLS),
        "factorisation.matrix": lambda: _matrices(m, q, v, t, ship, ab, CALLS),
        "factorisation.contact": lambda: _contact_tangents(m, q, v, ship, CALLS),
        "factorisation.hydro": lambda: _hydro_tangents(m, q, v, t, CALLS),
        "factorisation.lu": lambda: _lus(m, ab0, ab, ipiv, CALLS),
        "solve": lambda: _solves(m, ws.ab, ws.ipiv, rhs, CALLS),
        "outputs": lambda: _outputs(m, q, v, a, st.phi, t, ship, sim.output_scene, r, CALLS),
        "outputs.contact": lambda: _contact_summaries(m, q, v, ship, CALLS),
    }
    return {name: per_call_us(loop) / CALLS * 1e-6 for name, loop in loops.items()}


def standalone() -> dict[str, float]:
    """Simulation.run of full_scale at 0.01 s (recording every 0.1 s): model time per 0.01 s [s]."""
    from towcable_fmu.ancf.simulation import Simulation

    sim = Simulation.from_scene("full_scale", {"solver": {"time_step": STEP},
                                               "compensation": {"algorithm": "simplified_sheave"}})
    sim.initialize()
    sim.run(5.0, interval=0.1)
    start = time.perf_counter()
    sim.run(30.0, interval=0.1)
    return {"run_per_step": (time.perf_counter() - start) / (30.0 / STEP)}


def main() -> None:
    p = profile()
    p.update(standalone())
    us = {k: 1e6 * v for k, v in p.items()}
    parts = (us["residual"] * p["residuals"] + us["factorisation"] * p["factorisations"]
             + us["solve"] * p["iterations"] + us["outputs"])
    rows = [[f"{name} model / all its calls (model + slave glue) [us]",
             f"{us[name + '.model']:.1f} / {us[name + '.calls']:.1f}"]
            for name in ("ShipMotion", "HeaveCompensation", "TowCable")]
    rows += [
        ["TowCable: Newton iterations, residuals, factorisations per step",
         f"{p['iterations']:.2f}, {p['residuals']:.2f}, {p['factorisations']:.3f}"],
        ["TowCable per call: residual, factorisation, back-solve, outputs [us]",
         f"{us['residual']:.1f}, {us['factorisation']:.1f}, {us['solve']:.1f}, {us['outputs']:.1f}"],
        ["TowCable residual by term: contact, hydrodynamics, the rest (cable structure, body) [us]",
         f"{us['residual.contact']:.1f}, {us['residual.hydro']:.1f}, "
         f"{us['residual'] - us['residual.contact'] - us['residual.hydro']:.1f}"],
        ["TowCable factorisation: iteration matrix (of which contact, hydrodynamic tangents), banded LU [us]",
         f"{us['factorisation.matrix']:.1f} ({us['factorisation.contact']:.1f}, {us['factorisation.hydro']:.1f}), "
         f"{us['factorisation.lu']:.1f}"],
        ["TowCable outputs: contact summary (with its angular span), the rest [us]",
         f"{us['outputs.contact']:.1f}, {us['outputs'] - us['outputs.contact']:.1f}"],
        ["TowCable parts: residuals + factorisations + back-solves + outputs [us]", f"{parts:.1f}"],
        ["TowCable rest of its model time (Python, integrator loops) [us]", f"{us['TowCable.model'] - parts:.1f}"],
        ["standalone `Simulation.run` at 0.01 s, per step [us]", f"{us['run_per_step']:.1f}"],
    ]
    print(machine_header())
    print(markdown_table(["per 0.01 s communication step", "value"], rows))


if __name__ == "__main__":
    main()
