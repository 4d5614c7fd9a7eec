"""The explicit path of the nodal-position cable (solver.integrator = "leapfrog",
towcable_fmu/nodal/explicit.py): closed forms of lumped chains, its energy, its stability
limit against the measured cliff, a slack-taut bounce, the implicit path's answer and the
TowCable FMU."""

from __future__ import annotations

import math

import numpy as np
import pytest

from towcable_fmu.common.errors import SceneError, SolverError
from towcable_fmu.nodal.explicit import node_masses
from towcable_fmu.nodal.simulation import NodalSimulation
from towcable_fmu.numerics.explicit_step import SAFETY, step_limit
from towcable_fmu.scene import load_scene

G = 9.81


def _chain(tmp_path, *, elements: int, length: float, mu: float, ea: float, mass: float, step: float,
           damping: float = 0.0, gravity: float = G, compression: bool = True,
           direction: tuple = (0.0, 0.0, -1.0)) -> NodalSimulation:
    """A chain in air from a fixed top at the origin, the body lumped at its last node, laid
    out unstretched along ``direction`` (no statics): leapfrog with ``step`` [s]."""
    path = tmp_path / "chain.toml"
    path.write_text(f"""
[environment]
gravity = {gravity}
[cable]
formulation = "nodal_position"
[[cable.segments]]
length = {length}
elements = {elements}
diameter = 0.01
mass_per_length = {mu}
EA = {ea}
EI = 0.0
damping = {damping}
compression = {"true" if compression else "false"}
[cable.top]
type = "pinned"
position = [0.0, 0.0, 0.0]
[cable.bottom]
type = "free"
[cable.initial]
shape = "straight"
direction = [{direction[0]}, {direction[1]}, {direction[2]}]
[towbody]
mass = {mass}
[solver]
integrator = "leapfrog"
time_step = {step}
[statics]
enabled = false
""")
    return NodalSimulation.from_scene(path)


def _lumped_chain_solution(m: np.ndarray, k: float, g: float, t: np.ndarray) -> np.ndarray:
    """Displacements u(t) [m] (down positive, from the unstretched layout) of the free nodes of
    a linear spring chain with lumped masses ``m`` [kg] (free nodes, from the top), springs
    ``k`` [N/m], released from rest unstretched under gravity ``g``: the modes of M^-1 K."""
    n = m.size
    stiffness = np.zeros((n, n))
    for i in range(n):  # spring i joins node i - 1 (the fixed top for i = 0) and node i
        stiffness[i, i] += k
        if i > 0:
            stiffness[i - 1, i - 1] += k
            stiffness[i, i - 1] -= k
            stiffness[i - 1, i] -= k
    root = 1.0 / np.sqrt(m)
    omega2, phi = np.linalg.eigh(root[:, None] * stiffness * root[None, :])
    static = np.linalg.solve(stiffness, m * g)
    modal = phi.T @ (np.sqrt(m) * static)  # u_s in mass-normalised modal coordinates
    return static[None, :] - root[None, :] * ((np.cos(np.sqrt(omega2)[None, :] * t[:, None]) * modal[None, :]) @ phi.T)


def test_order_of_accuracy_on_a_linear_chain(tmp_path):
    """A stiff chain (strain 2e-7: the element law's O(eps^2), 1e-11 m, is below the errors
    compared) against the modes of its lumped equations, released unstretched under gravity
    (all modes excited): the error falls as h^2 (leapfrog is second order)."""
    mu, length, n, mass, ea = 1.0, 10.0, 5, 10.0, 1e9
    errors = []
    limit = step_limit(np.full(n, length / n), np.full(n, ea), np.zeros(n), np.full(n, mu), mass)
    steps = [0.4 * limit, 0.2 * limit, 0.1 * limit]  # omega_max h = 0.8 and below
    duration = 50 * steps[0]
    for h in steps:
        sim = _chain(tmp_path, elements=n, length=length, mu=mu, ea=ea, mass=mass, step=h)
        sim.initialize()
        out = sim.run(duration, interval=duration / 20)
        m = node_masses(sim.model)[1:]
        exact = _lumped_chain_solution(m, ea * n / length, G, out["time"])[:, -1]
        errors.append(np.max(np.abs(-(out["towbody.z"] + length) - exact)))
    amplitude = float(np.max(np.abs(_lumped_chain_solution(m, ea * n / length, G, out["time"])[:, -1])))
    assert errors[0] < 0.05 * amplitude  # resolved: the test compares converging runs
    for coarse, fine in zip(errors[:-1], errors[1:]):
        assert coarse / fine == pytest.approx(4.0, rel=0.15)


def _energy(sim: NodalSimulation, masses: np.ndarray, ea: float, g: float) -> float:
    """Kinetic, strain (of the element law N = EA lambda (lambda - 1), lambda = L/L0) and
    gravity energy [J] of a chain from its state."""
    m = sim.model
    q = sim.state.q.reshape(-1, 3)
    v = sim.state.v.reshape(-1, 3)
    lam = np.linalg.norm(np.diff(q, axis=0), axis=1) / m.L0
    strain = np.sum(ea * m.L0 * (lam ** 3 / 3.0 - lam ** 2 / 2.0 + 1.0 / 6.0))
    return float(0.5 * np.sum(masses[:, None] * v ** 2) + strain + g * np.sum(masses * q[:, 2]))


def test_energy_of_an_undamped_chain_stays_bounded_over_a_million_steps(tmp_path):
    """A chain released unstretched (strain up to 0.4 %: the element law's nonlinearity acts)
    at the largest step the scene allows: leapfrog keeps a nearby energy, so the energy error
    oscillates at a fixed bound and does not drift."""
    mu, length, n, mass, ea = 0.5, 10.0, 8, 2.0, 2e4
    limit = step_limit(np.full(n, length / n), np.full(n, ea), np.zeros(n), np.full(n, mu), mass)
    h = SAFETY * limit
    sim = _chain(tmp_path, elements=n, length=length, mu=mu, ea=ea, mass=mass, step=h)
    sim.initialize()
    masses = node_masses(sim.model)
    e0 = _energy(sim, masses, ea, G)
    static = np.linalg.solve(np.diag(np.full(n, 2.0)) - np.eye(n, k=1) - np.eye(n, k=-1)
                             - np.diag(np.r_[np.zeros(n - 1), 1.0]), masses[1:] * G) / (ea * n / length)
    motion = 0.5 * np.dot(masses[1:] * G, static)  # the energy of the oscillation about equilibrium [J]
    still = np.zeros((3, 6))
    error = []
    for _ in range(100):
        sim.step(10_000 * h, still)
        error.append(abs(_energy(sim, masses, ea, G) - e0))
    assert sim.statistics()["solver.steps"] >= 1_000_000
    error = np.array(error)
    assert np.max(error) < 1e-2 * motion
    assert np.max(error[-10:]) < 1.5 * np.max(error[:10])  # no drift


def _bounded(sim: NodalSimulation, h: float, steps: int) -> bool:
    """Whether ``steps`` leapfrog steps of ``h`` [s] (forced past the scene's check) stay finite."""
    sim.options = sim.options._replace(h_max=h)
    sim.initialize()
    try:
        out = sim.run(steps * h, interval=steps * h / 10)
    except SolverError:
        return False
    return bool(np.all(np.isfinite(out["towbody.z"])) and np.max(np.abs(out["towbody.z"])) < 100.0)


@pytest.mark.parametrize("damping", [0.0, 40.0])
def test_stability_limit_from_the_formula_is_the_measured_cliff(tmp_path, damping):
    """A uniform damped chain: its leapfrog is stable just below the formula's step
    (omega = 2 c/l, zeta = BA/(l sqrt(EA mu))) and blows up 3 % above it; the scene refuses a
    step 10 % above the allowed one (naming it), and runs at the allowed step."""
    mu, length, n, mass, ea = 0.0112, 18.9, 20, 12.2, 134.2e3
    l = length / n
    c = math.sqrt(ea / mu)
    omega, zeta = 2.0 * c / l, damping / (l * math.sqrt(ea * mu))
    formula = 2.0 / omega * (math.sqrt(1.0 + zeta ** 2) - zeta)
    assert step_limit(np.full(n, l), np.full(n, ea), np.full(n, damping), np.full(n, mu), mass) == \
        pytest.approx(formula, rel=1e-12)
    allowed = SAFETY * formula
    sim = _chain(tmp_path, elements=n, length=length, mu=mu, ea=ea, mass=mass, step=allowed, damping=damping)
    assert _bounded(sim, 0.99 * formula, 20_000)
    assert not _bounded(sim, 1.03 * formula, 20_000)
    with pytest.raises(SceneError) as err:
        _chain(tmp_path, elements=n, length=length, mu=mu, ea=ea, mass=mass, step=1.1 * allowed, damping=damping)
    assert "solver.time_step" in str(err.value) and f"{allowed:.4g} s" in str(err.value)
    assert _bounded(sim, allowed, 20_000)


def test_snapping_scene_runs_bounded_at_its_allowed_step():
    """The snapping cable (slack and taut, drag, added mass, the sphere) at the largest step
    the scene allows: bounded through its snaps."""
    sim = NodalSimulation.from_scene("snapping_cable_nodal", {
        "solver.integrator": "leapfrog", "solver.time_step": load_scene("snapping_cable_nodal").explicit_step()})
    sim.initialize()
    out = sim.run(3.0, interval=5e-4)
    assert np.all(np.isfinite(out["tension.top"]))
    assert out["tension.top"].max() > 4.0 * out["tension.top"][0]  # it snaps
    assert out["tension.top"].max() < 10.0 * out["tension.top"][0]


def test_slack_taut_bounce_of_a_mass_on_a_tension_only_spring(tmp_path):
    """A mass thrown up from the taut length of a tension-only spring: free flight for
    2 v0/g, then the spring catches it, peak force m g + sqrt((m g)^2 + k m v0^2)."""
    mass, length, ea, v0 = 1.0, 1.0, 2.0e4, 1.0
    k = ea / length
    sim = _chain(tmp_path, elements=1, length=length, mu=1e-6, ea=ea, mass=mass, step=1e-4, compression=False)
    sim.initialize()
    data = sim.get_state()
    data["fields"]["v"][-1] = v0  # up
    data["fields"]["x"][-1] = -G  # the spring is unstretched: gravity alone
    sim.set_state(data)
    out = sim.run(0.4, interval=1e-5)
    tension, t = out["tension.max"], out["time"]  # the element force: exactly 0 while slack
    impact = t[np.argmax((t > 0.01) & (tension > 0.0))]
    assert impact == pytest.approx(2.0 * v0 / G, rel=1e-2)
    m = mass + 0.5e-6 * length  # the node's lumped mass
    peak = m * G + math.sqrt((m * G) ** 2 + k * m * v0 ** 2)
    assert tension.max() == pytest.approx(peak, rel=1e-2)


def _tension(integrator: str, elements: int, step: float, duration: float) -> np.ndarray:
    sim = NodalSimulation.from_scene("snapping_cable_nodal", {
        "solver.integrator": integrator, "solver.time_step": step, "cable.segments[0].elements": elements})
    sim.initialize()
    return sim.run(duration, interval=5e-4)["tension.top"]


def test_explicit_and_implicit_runs_converge_to_the_same_answer():
    """The snapping cable through its first snaps: lumped against consistent masses, half-step
    against exact velocities in the damping; their difference shrinks as the mesh and the
    steps are refined."""
    duration = 1.0
    diffs = []
    for n in (10, 20, 40):
        explicit = _tension("leapfrog", n, load_scene("snapping_cable_nodal", {
            "solver.integrator": "genalpha", "cable.segments[0].elements": n}).explicit_step(), duration)
        implicit = _tension("genalpha", n, 5e-5, duration)
        diffs.append(np.sqrt(np.mean((explicit - implicit) ** 2)) / implicit[0])
    assert diffs[2] < 0.6 * diffs[1] < 0.36 * diffs[0]
    assert diffs[2] < 5e-3


def test_leapfrog_is_refused_where_it_cannot_represent_the_scene():
    with pytest.raises(SceneError) as err:
        load_scene("full_scale", {"solver.integrator": "leapfrog"})
    text = str(err.value)
    assert "nodal_position" in text and "solver.time_step <=" in text
    with pytest.raises(SceneError, match="towbody.model = 'rigid'"):
        load_scene("sea_trial_turn_rigid", {"solver.integrator": "leapfrog"})


# ------------------------------------------------------------------ the TowCable FMU
def _fmu_run(fmu, motion, t: float, n: int, dt: float) -> tuple[float, list[dict[str, float]]]:
    """n communication steps of dt [s] with the scene's ship motion as inputs."""
    from fmu_util import outputs, set_inputs, ship_inputs

    rows = []
    for _ in range(n):
        set_inputs(fmu, ship_inputs(motion.evaluate(t)))
        fmu.fmu.doStep(t, dt)
        t = round(t + dt, 12)
        rows.append(outputs(fmu))
    return t, rows


def test_explicit_scene_in_the_fmu_is_bit_identical_to_the_standalone_run_and_rolls_back_across_a_snap(fmu_paths):
    """snapping_cable_nodal (leapfrog by default) in the TowCable FMU against the simulation
    stepped to the same communication points with the same inputs: the same outputs to the
    last bit. A state saved before the first snaps, restored after them, repeats them exactly."""
    from fmu_util import open_fmu, set_inputs, ship_inputs
    from towcable_fmu.runtime.ship_input import motion_source

    scene = load_scene("snapping_cable_nodal")
    assert scene.solver.integrator == "leapfrog"
    motion = motion_source(scene)
    fmu = open_fmu(fmu_paths, "TowCable", {"scene": "snapping_cable_nodal"})
    set_inputs(fmu, ship_inputs(motion.evaluate(0.0)))
    fmu.exit_initialization()
    dt = 0.01
    t, rows = _fmu_run(fmu, motion, 0.0, 10, dt)
    sim = NodalSimulation(scene)
    sim.initialize(0.0, motion.evaluate(0.0))
    ts = 0.0
    for row in rows:
        got = sim.step((ts + dt) - sim.time, motion.evaluate(ts))  # as the FMU steps (towcable_fmu/fmu.py)
        ts = round(ts + dt, 12)
        for name in ("tension.top", "tension.max", "tension.min", "towbody.z", "towbody.vz"):
            assert row[name] == got[name], name
    state = fmu.fmu.getFMUstate()
    _, first = _fmu_run(fmu, motion, t, 90, dt)
    top = np.array([r["tension.top"] for r in first])
    assert top.max() > 3.0 * rows[0]["tension.top"] and top.min() < 0.2 * rows[0]["tension.top"]  # slack, then snaps
    fmu.fmu.setFMUstate(state)
    _, second = _fmu_run(fmu, motion, t, 90, dt)
    assert second == first
    fmu.fmu.freeFMUstate(state)
    fmu.free()


def test_top_motion_from_the_kept_drive_piece_is_the_drives():
    """The top node from the drive piece's quintics (the step's fast path) against the drive's
    Hermite evaluation, across pieces, before and after the table, with the ship rotating in
    some pieces (then the general evaluation itself)."""
    from towcable_fmu.nodal.explicit import new_top_piece, prescribe_top_fast
    from towcable_fmu.nodal.integrators import prescribe_top_with

    rng = np.random.default_rng(5)
    drive_t = np.array([0.0, 0.1, 0.25, 0.3, 0.5])
    drive_x = rng.normal(0.0, 1.0, (5, 3, 7))
    drive_x[:3, :, 3:6] = 0.0  # no rotation in the first two pieces; rotation from knot 3 on
    top_point = np.array([0.4, -0.2, -1.0])
    piece = new_top_piece()
    ship, basis = np.empty((3, 6)), np.empty((6, 3))
    times = np.sort(np.concatenate([rng.uniform(-0.05, 0.6, 300), drive_t]))
    fast, ref = np.zeros((times.size, 3, 3)), np.zeros((times.size, 3, 3))
    for i, t in enumerate(times):
        prescribe_top_fast(True, top_point, drive_t, drive_x, t, fast[i, 0], fast[i, 1], fast[i, 2], ship, basis, piece)
        prescribe_top_with(True, top_point, drive_t, drive_x, t, ref[i, 0], ref[i, 1], ref[i, 2], ship, basis)
    plain = int(np.sum(times <= 0.25))
    for row in range(3):  # position, velocity, acceleration: to round-off of their size over the run
        assert np.allclose(fast[:, row], ref[:, row], rtol=0.0, atol=1e-12 * np.max(np.abs(ref[:, row])))
    assert plain > 50


def _reference_step(sim: NodalSimulation, drive: tuple, t: float, h: float, q: np.ndarray, v: np.ndarray,
                    a: np.ndarray) -> None:
    """One leapfrog step from time ``t`` [s] written out in numpy on the implicit path's
    residual, in place: forces minus cable_residual at zero acceleration, each free node's
    3x3 mass the row sums of the residual's mass matrices (its change when every node
    accelerates alike by e_k), the top node from the drive (prescribe_top)."""
    from towcable_fmu.nodal.assembly import cable_residual
    from towcable_fmu.nodal.integrators import prescribe_top

    m = sim.model
    n = q.size
    r0, r1 = np.empty(n), np.empty(n)
    v[3:] += 0.5 * h * a[3:]
    q[3:] += h * v[3:]
    prescribe_top(m, drive[0], drive[1], t + h, q, v, a)
    cable_residual(m, q, v, np.zeros(n), t + h, r0)
    masses = np.empty((m.n_nodes, 3, 3))
    for k in range(3):
        cable_residual(m, q, v, np.tile(np.eye(3)[k], m.n_nodes), t + h, r1)
        masses[:, :, k] = (r1 - r0).reshape(-1, 3)
    a[3:] = np.linalg.solve(masses[1:], -r0.reshape(-1, 3)[1:, :, None])[:, :, 0].ravel()
    v[3:] += 0.5 * h * a[3:]


@pytest.mark.parametrize("elements", [2, 13, 40, 140])  # the compiled stride (the element loop padded
# to a multiple of its vector width: 2 -> 4, 13 -> 16; 40 exactly) and the node count
def test_the_compiled_step_is_a_leapfrog_on_cable_residual(elements):
    """The compiled step (structure-of-arrays rows, vectorised, fused multiply-adds, the top
    from the kept drive piece) against :func:`_reference_step`, an independent computation,
    step by step from the reference's states: the snapping cable released straight from a
    top 0.3 m above the surface (it falls, goes slack and taut, its Gauss points cross the
    surface), with a current, lift and a body of height: equal to round-off at every step."""
    from towcable_fmu.nodal.explicit import leapfrog_recording

    overrides = {"cable.segments[0].elements": elements, "cable.top.position": [0.0, 0.0, 0.3],
                 "statics.enabled": False, "towbody.height": 0.3,
                 "water.current": {"type": "linear", "velocity": [0.3, -0.1, 0.0], "gradient": [0.05, 0.0, 0.0]},
                 "towbody.lift": {"area": 0.05, "coefficient": 0.4, "direction": [0.0, 0.6, -0.8],
                                  "axis": [1.0, 0.0, 0.0]}}
    h = load_scene("snapping_cable_nodal", {**overrides, "solver.integrator": "genalpha"}).explicit_step()
    sim = NodalSimulation.from_scene("snapping_cable_nodal", {**overrides, "solver.time_step": h})
    sim.initialize()
    steps = 200 if elements < 100 else 40
    drive = sim._drive(np.array([0.0, (steps + 2) * h]), 10 * h)
    q, v, a = sim.state.q.copy(), sim.state.v.copy(), sim.state.x.copy()
    crossing, slack = False, False
    values = np.zeros((1, 14))
    for step in range(steps):
        t = step * h
        sim.state.q[:], sim.state.v[:], sim.state.x[:] = q, v, a
        sim.state.clock[0] = t
        assert leapfrog_recording(sim.model, sim._lumped, sim.options, sim.state, np.array([t + h]), *drive, values,
                                  sim._interpolant, False, t + h) == 1
        _reference_step(sim, drive, t, h, q, v, a)
        # (the accelerations carry the strain's round-off times EA/m, the stiff axial law: up to
        # 3e-10 of their largest here, and the velocities h/2 times that)
        for mine, ref, tol in ((sim.state.q, q, 1e-12), (sim.state.v, v, 1e-10), (sim.state.x, a, 1e-8)):
            assert np.allclose(mine, ref, rtol=0.0, atol=tol * np.max(np.abs(ref))), step
        wet = q[2::3] < 0.0
        crossing |= wet.any() and not wet.all()
        slack |= bool(np.any(np.linalg.norm(np.diff(q.reshape(-1, 3), axis=0), axis=1) < sim.model.L0))
    assert crossing and slack


def test_the_compiled_step_with_a_rotating_ship_is_a_leapfrog_on_cable_residual():
    """The step loop compiled for any drive (the ship pitches and rolls from the third knot on,
    so the top node comes from the drive's general evaluation there and from the kept piece's
    quintics before; the other step test's ship only heaves) against :func:`_reference_step`, step by step from the reference's
    states: equal to round-off, across the change from plain to rotating pieces."""
    from towcable_fmu.nodal.explicit import leapfrog_recording

    overrides = {"cable.segments[0].elements": 12, "statics.enabled": False,
                 "cable.top.position": [0.5, 0.2, 0.3]}
    h = load_scene("snapping_cable_nodal", {**overrides, "solver.integrator": "genalpha"}).explicit_step()
    sim = NodalSimulation.from_scene("snapping_cable_nodal", {**overrides, "solver.time_step": h})
    sim.initialize()
    steps = 120
    drive_t, drive_x = sim._drive(np.array([0.0, (steps + 2) * h]), 10 * h)
    assert not drive_x[:, :, 3:6].any()  # heave only
    drive_x = drive_x.copy()
    w = 2.0 * math.pi * 3.0
    for channel, amplitude in ((3, 0.05), (4, 0.08)):  # roll, pitch [rad] from the third knot on
        s = np.where(drive_t >= drive_t[2], np.sin(w * drive_t), 0.0)
        c = np.where(drive_t >= drive_t[2], np.cos(w * drive_t), 0.0)
        drive_x[:, 0, channel], drive_x[:, 1, channel], drive_x[:, 2, channel] = (
            amplitude * s, amplitude * w * c, -amplitude * w * w * s)
    assert steps * h > drive_t[4]  # through plain and rotating pieces
    q, v, a = sim.state.q.copy(), sim.state.v.copy(), sim.state.x.copy()
    values = np.zeros((1, 14))
    for step in range(steps):
        t = step * h
        sim.state.q[:], sim.state.v[:], sim.state.x[:] = q, v, a
        sim.state.clock[0] = t
        assert leapfrog_recording(sim.model, sim._lumped, sim.options, sim.state, np.array([t + h]), drive_t, drive_x,
                                  values, sim._interpolant, False, t + h) == 1
        _reference_step(sim, (drive_t, drive_x), t, h, q, v, a)
        for mine, ref, tol in ((sim.state.q, q, 1e-12), (sim.state.v, v, 1e-10), (sim.state.x, a, 1e-8)):
            assert np.allclose(mine, ref, rtol=0.0, atol=tol * np.max(np.abs(ref))), step
