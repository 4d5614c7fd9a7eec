"""Peer 2: Exudyn (C++ multibody code, ANCF cable elements, implicit generalized-alpha)
on the ``snapping_cable`` case (see snapping_case.py and README.md).

Set-up
------
* 2D model (x horizontal, y up): ``ObjectANCFCable2D`` elements on
  ``NodePoint2DSlope1`` nodes (position + slope, cubic Hermite), length L/n each. The
  motion is planar (vertical), and only the 2D cable has an axial-force user function,
  which we need for the tension-only law; the 3D ``ObjectANCFCable`` has none.
* Axial law, as in MoorDyn: N = EA*max(eps, 0) + BA*eps_t, as a *symbolic* user
  function (``exudyn.symbolic`` via ``CreateSymbolicUserFunction``: an expression tree
  evaluated in C++, no Python call per evaluation). Exudyn 1.13.6 only evaluates the
  axial-force user function when a bending-moment user function is set as well
  (CObjectANCFCable2D.cpp tests ``HasTorqueUserFunction()`` in the axial branch), so a
  symbolic bending function with the default law EI*(K - K0) + bendingDamping*K_t is
  attached too. With user functions, the element Jacobian is built numerically.
* Gravity + buoyancy of the cable: ``LoadMassProportional`` on each element with the
  reduced acceleration g (1 - rho A / mu) (buoyancy is proportional to mass here).
* Sphere: ``ObjectMassPoint2D`` on the last cable node with mass m + Ca rho V (added
  mass, isotropic as for a sphere), a ``LoadForceVector`` with its wet weight, and the
  quadratic drag as an ``ObjectConnectorCartesianSpringDamper`` to ground whose
  symbolic ``springForceUserFunction`` returns 0.5 rho Cd A |v| v (the connector
  hands the relative velocity to the function).
* Cable drag (option ``cable_drag``): the same kind of connector on every node, with
  the drag of the node's share of cable length (lumped like MoorDyn), normal and
  tangential parts split with the *vertical* as tangent: the connector user function
  does not see the cable slope. Exact here, because the cable stays vertical.
  Exudyn has no built-in hydrodynamic loads.
* Cable added mass (normal, Ca = 1) is NOT modelled: Exudyn's cable has one isotropic
  mass per length, and the normal velocity stays zero in this case, so it does no work.
* Top end: x fixed and y prescribed by ``CoordinateConstraint`` with symbolic
  ``offsetUserFunction`` A sin(wt) (and ``offsetUserFunction_t``). The top tension is
  the constraint's reaction force (its Lagrange multiplier; sign flipped), i.e. the
  force on the support, like MoorDyn's coupled point force.
* Start: ``SolveStatic`` with the offset functions not yet attached (top at rest), the
  result becomes the initial state, then the offset functions are attached.
* Time integration: generalized-alpha (index 3), fixed step ``time_step_s``, spectral
  radius 0.8 (1.0 = trapezoidal blows up: the index-3 constraint force oscillates
  without numerical damping; 0.6 and 0.9 change Tmax/T0 by < 0.3 %), modified Newton
  with relative tolerance 1e-6 (1e-8 gives the same numbers 10 % slower), reduced
  Gauss integration of the cable (order 7 axial / 3 bending: 18 % faster, Tmax/T0
  changes by 0.02 %), sparse LU (Eigen; dense LU costs the same at these sizes),
  one thread.
"""

from __future__ import annotations

import math
import os
import sys
import time as _time
import warnings

import numpy as np

try:  # imported as benchmarks.peers.exudyn_snapping
    from . import snapping_case as case
    from . import study
except ImportError:  # run as a script from this directory
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import snapping_case as case  # type: ignore[no-redef]
    import study  # type: ignore[no-redef]


def build(frequency_hz: float, n_segments: int, *, amplitude_m: float | None = None,
          cable_drag: bool = True, symbolic: bool = True,
          cable_axial_damping: float | None = None, reduced_integration: int = 0):
    """Create the Exudyn system. Returns (SC, mbs, handles) where handles holds the
    object indices, the symbolic functions (must stay alive) and the offset functions
    to attach after the static solve."""
    import exudyn as exu
    from exudyn.advancedUtilities import CreateSymbolicUserFunction
    from exudyn.itemInterface import (CartesianSpringDamper, CoordinateConstraint,
                                      LoadForceVector, LoadMassProportional,
                                      MarkerBodyMass, MarkerBodyPosition,
                                      MarkerNodeCoordinate, MarkerNodePosition,
                                      MassPoint2D, NodePoint2DSlope1, NodePointGround,
                                      ObjectANCFCable2D, ObjectGround)

    esym = exu.symbolic
    A = case.AMPLITUDE if amplitude_m is None else amplitude_m
    om = 2.0 * math.pi * frequency_hz
    EA, EI = case.CABLE_EA, case.CABLE_EI
    BA = case.CABLE_AXIAL_DAMPING if cable_axial_damping is None else cable_axial_damping
    mu, L, n = case.CABLE_MASS_PER_LENGTH, case.CABLE_LENGTH, int(n_segments)
    le = L / n
    rho, g = case.RHO_WATER, case.G

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    keep = []  # symbolic user functions must outlive the simulation

    def attach(index, name, fn):
        if symbolic:
            uf = CreateSymbolicUserFunction(mbs, fn, name, index)
            keep.append(uf)
            mbs.SetObjectParameter(index, name, uf)
        else:
            mbs.SetObjectParameter(index, name, fn)

    M = esym if symbolic else math
    smax = esym.max if symbolic else max
    sabs = esym.abs if symbolic else abs

    oGround = mbs.AddObject(ObjectGround())
    nGround = mbs.AddNode(NodePointGround())
    mGroundCoord = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nGround, coordinate=0))
    mGroundPos = mbs.AddMarker(MarkerBodyPosition(bodyNumber=oGround, localPosition=[0, 0, 0]))

    # nodes: reference = unstretched straight cable hanging from the top; initial
    # coordinates = analytic static stretch (the static solve then makes it exact
    # for the discretisation)
    nodes = []
    for i in range(n + 1):
        s = i * le
        eps = case.static_tension(L - s) / EA
        drop = float(case.static_stretch_from_top(s))
        nodes.append(mbs.AddNode(NodePoint2DSlope1(
            referenceCoordinates=[0.0, case.TOP_Z0 - s, 0.0, -1.0],
            initialCoordinates=[0.0, -(drop - s), 0.0, -eps])))

    def axial_force(mbs, t, itemNumber, axialPositionNormalized, axialStrain, axialStrain_t,
                    axialStrainRef, axialStiffness, axialDamping, curvature, curvature_t,
                    curvatureRef):
        return axialStiffness * smax(axialStrain, 0.0) + axialDamping * axialStrain_t

    def bending_moment(mbs, t, itemNumber, axialPositionNormalized, curvature, curvature_t,
                       curvatureRef, bendingStiffness, bendingDamping, axialStrain,
                       axialStrain_t, axialStrainRef):
        return bendingStiffness * (curvature - curvatureRef) + bendingDamping * curvature_t

    g_eff = g * (1.0 - rho * case.cable_area() / mu)
    elements = []
    for i in range(n):
        oe = mbs.AddObject(ObjectANCFCable2D(
            nodeNumbers=[nodes[i], nodes[i + 1]], length=le, massPerLength=mu,
            bendingStiffness=EI, axialStiffness=EA, axialDamping=BA,
            useReducedOrderIntegration=reduced_integration))
        attach(oe, "axialForceUserFunction", axial_force)
        attach(oe, "bendingMomentUserFunction", bending_moment)
        mMass = mbs.AddMarker(MarkerBodyMass(bodyNumber=oe))
        mbs.AddLoad(LoadMassProportional(markerNumber=mMass, loadVector=[0.0, -g_eff, 0.0]))
        elements.append(oe)

    # top end: x fixed, y prescribed (offset functions attached after the static solve)
    mTopX = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[0], coordinate=0))
    mTopY = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[0], coordinate=1))
    mbs.AddObject(CoordinateConstraint(markerNumbers=[mGroundCoord, mTopX]))
    oTopY = mbs.AddObject(CoordinateConstraint(markerNumbers=[mGroundCoord, mTopY]))

    def offset(mbs, t, itemNumber, lOffset):
        return A * M.sin(om * t)

    def offset_t(mbs, t, itemNumber, lOffset):
        return A * om * M.cos(om * t)

    # sphere
    mSphere = mbs.AddMarker(MarkerNodePosition(nodeNumber=nodes[-1]))
    mbs.AddObject(MassPoint2D(nodeNumber=nodes[-1],
                              mass=case.SPHERE_MASS + case.sphere_added_mass()))
    mbs.AddLoad(LoadForceVector(markerNumber=mSphere, loadVector=[0.0, -case.sphere_wet_weight(), 0.0]))

    def quadratic_drag(mbs, t, itemNumber, displacement, velocity, stiffness, damping, offset):
        # isotropic quadratic drag; coefficient 0.5 rho Cd A passed in stiffness[0]
        vx, vy = velocity[0], velocity[1]
        vabs = M.sqrt(vx * vx + vy * vy)
        return [stiffness[0] * vabs * vx, stiffness[0] * vabs * vy, 0.0]

    cS = 0.5 * rho * case.SPHERE_CD * case.sphere_frontal_area()
    oDrag = mbs.AddObject(CartesianSpringDamper(markerNumbers=[mGroundPos, mSphere],
                                                stiffness=[cS, cS, cS], damping=[0, 0, 0]))
    attach(oDrag, "springForceUserFunction", quadratic_drag)

    if cable_drag:
        def cable_node_drag(mbs, t, itemNumber, displacement, velocity, stiffness, damping, offset):
            # tangent = vertical (y); stiffness = [cn, ct, 0]: 0.5 rho Cdn D l, 0.5 rho Cdt pi D l
            vx, vy = velocity[0], velocity[1]
            return [stiffness[0] * sabs(vx) * vx, stiffness[1] * sabs(vy) * vy, 0.0]
        for i, nd in enumerate(nodes[1:], start=1):  # node 0 is prescribed
            l_node = le if i < n else 0.5 * le
            cn = 0.5 * rho * case.CABLE_CD_NORMAL * case.CABLE_DIAMETER * l_node
            ct = 0.5 * rho * case.CABLE_CD_TANGENTIAL * math.pi * case.CABLE_DIAMETER * l_node
            mNode = mSphere if i == n else mbs.AddMarker(MarkerNodePosition(nodeNumber=nd))
            oc = mbs.AddObject(CartesianSpringDamper(markerNumbers=[mGroundPos, mNode],
                                                     stiffness=[cn, ct, 0.0], damping=[0, 0, 0]))
            attach(oc, "springForceUserFunction", cable_node_drag)

    handles = {"oTopY": oTopY, "nodes": nodes, "elements": elements, "keep": keep,
               "offset": offset, "offset_t": offset_t, "attach": attach}
    return SC, mbs, handles


def run(frequency_hz: float, duration_s: float, n_segments: int, time_step_s: float,
        *, amplitude_m: float | None = None, spectral_radius: float = 0.8,
        cable_drag: bool = True, symbolic: bool = True, sample_target_s: float = 5e-4,
        cable_axial_damping: float | None = None, sparse: bool = True,
        newton_rel_tol: float = 1e-6, reduced_integration: int = 1) -> dict:
    """Simulate the case with Exudyn and return the top-tension results.

    Returns a dict with T0 [N] (static reaction at the top), Tmax_over_T0 and
    Tmin_over_T0 over the whole run (case.WINDOW_FULL, clipped to duration_s), the
    same over the late window (keys *_late; NaN if the run ends before 5 s),
    wall_time_s and cpu_time_s (SolveDynamic only; model build and static solve are
    init_time_s), sim_time_s, newton_iterations / jacobians, time [s] and
    tension_top [N] (every k-th step, k*h ~ sample_target_s). The other keywords are
    the solver settings tuned in README.md and switches for the cost study.
    """
    import exudyn as exu
    from exudyn.itemInterface import SensorObject

    t_init = _time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        SC, mbs, h = build(frequency_hz, n_segments, amplitude_m=amplitude_m,
                           cable_drag=cable_drag, symbolic=symbolic,
                           cable_axial_damping=cable_axial_damping,
                           reduced_integration=reduced_integration)
    _, dt_out = case.sample_interval(time_step_s, sample_target_s)
    sT = mbs.AddSensor(SensorObject(objectNumber=h["oTopY"],
                                    outputVariableType=exu.OutputVariableType.Force,
                                    storeInternal=True, writeToFile=False))
    mbs.Assemble()

    ss = exu.SimulationSettings()
    ss.solution.file.write = False
    ss.solution.sensors.writePeriod = dt_out * (1.0 - 1e-9)
    ss.show.statistics = False
    ss.show.computationTime = False
    ss.linearSolver.solverType = (exu.LinearSolverType.EigenSparse if sparse
                                  else exu.LinearSolverType.EXUdense)
    ss.parallel.numberOfThreads = 1
    ss.staticSolver.verboseMode = 0
    ss.timeIntegration.verboseMode = 0
    ss.timeIntegration.numberOfSteps = int(round(duration_s / time_step_s))
    ss.timeIntegration.endTime = duration_s
    ss.timeIntegration.generalizedAlpha.spectralRadius = spectral_radius
    ss.timeIntegration.newton.useModifiedNewton = True
    ss.timeIntegration.newton.relativeTolerance = newton_rel_tol
    ss.timeIntegration.newton.absoluteTolerance = 1e-10

    # static equilibrium with the top at rest
    mbs.SolveStatic(ss)
    # NOTE: after SolveStatic the constraint force has the opposite sign to the one the
    # dynamic solver reports (observed in Exudyn 1.13.6); the magnitude is T0
    T0 = abs(float(mbs.GetObjectOutput(h["oTopY"], exu.OutputVariableType.Force)))
    state = mbs.systemData.GetSystemState()
    mbs.systemData.SetSystemState(state, configuration=exu.ConfigurationType.Initial)
    h["attach"](h["oTopY"], "offsetUserFunction", h["offset"])
    h["attach"](h["oTopY"], "offsetUserFunction_t", h["offset_t"])
    mbs.Assemble()
    init_time = _time.perf_counter() - t_init

    wall0 = _time.perf_counter()
    cpu0 = _time.process_time()
    ok = mbs.SolveDynamic(ss, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    wall = _time.perf_counter() - wall0
    cpu = _time.process_time() - cpu0
    if not ok:
        raise RuntimeError("Exudyn SolveDynamic did not finish")
    stats = {}
    try:
        it = mbs.sys["dynamicSolver"].it
        stats = {"newton_iterations": int(it.newtonStepsCount),
                 "jacobians": int(it.newtonJacobiCount)}
    except Exception:  # solver statistics are optional
        pass

    data = mbs.GetSensorStoredData(sT)
    time = np.asarray(data[:, 0])
    tension = -np.asarray(data[:, 1])
    if abs(tension[0] / T0 - 1.0) > 1e-6:
        raise RuntimeError(f"initial top force {tension[0]} N differs from static T0 {T0} N")
    w_full = (case.WINDOW_FULL[0], min(case.WINDOW_FULL[1], duration_s))
    w_late = (case.WINDOW_LATE[0], min(case.WINDOW_LATE[1], duration_s))
    tmax, tmin = case.tension_metrics(time, tension, T0, w_full)
    tmax_l, tmin_l = case.tension_metrics(time, tension, T0, w_late)
    out = {
        "peer": "exudyn",
        "frequency_hz": frequency_hz,
        "n_segments": int(n_segments),
        "time_step_s": time_step_s,
        "spectral_radius": spectral_radius,
        "cable_drag": cable_drag,
        "T0": T0,
        "T0_hand": case.static_top_tension(),
        "Tmax_over_T0": tmax,
        "Tmin_over_T0": tmin,
        "Tmax_over_T0_late": tmax_l,
        "Tmin_over_T0_late": tmin_l,
        "window": w_full,
        "window_late": w_late,
        "wall_time_s": wall,
        "cpu_time_s": cpu,
        "init_time_s": init_time,
        "sim_time_s": duration_s,
        "time": time,
        "tension_top": tension,
    }
    out.update(stats)
    del SC, mbs
    return out


def main(argv: list[str] | None = None) -> None:
    import argparse

    import exudyn  # noqa: F401

    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--duration", type=float, default=case.DURATION)
    p.add_argument("--frequencies", type=float, nargs="*", default=list(case.FREQUENCIES_HZ))
    p.add_argument("--spectral-radius", type=float, default=0.8)
    p.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                 "results", "exudyn_snapping.json"))
    args = p.parse_args(argv)

    print(case.summary())
    print(f"exudyn {study.package_version('exudyn')}, generalized-alpha rho_inf="
          f"{args.spectral_radius}, symbolic user functions, sparse LU")
    # ladder 1: refine segments and time step together
    seg_ladder = [(2, 4e-3), (5, 2e-3), (10, 1e-3), (20, 5e-4), (40, 2.5e-4)]
    # ladder 2: time step alone at 10 segments
    dt_ladder = [(10, dt) for dt in (1e-2, 5e-3, 2.5e-3, 1e-3, 5e-4)]
    # ladder 3: segments alone at 1 ms
    n_ladder = [(n, 1e-3) for n in (2, 5, 10, 20)]
    kw = {"spectral_radius": args.spectral_radius}
    results = study.run_study(run, args.frequencies, args.duration,
                              {"segments+dt": seg_ladder, "dt@10seg": dt_ladder,
                               "seg@1ms": n_ladder},
                              peer="exudyn", run_kwargs=kw)
    study.sanity_checks(run, results, small_setting=(10, 1e-3), peer="exudyn", run_kwargs=kw)
    results["cost_breakdown"] = cost_breakdown(kw)
    study.save(results, args.out)


def cost_breakdown(kw: dict, f: float = 1.27, n: int = 10, dt: float = 1e-3) -> list:
    """CPU time of the user-function variants at one setting (symbolic vs Python)."""
    print(f"\ncost of the user functions (f={f} Hz, {n} elements, h={dt} s, 15 s simulated):")
    rows = []
    for label, extra in (("symbolic UFs, with cable drag", {}),
                         ("symbolic UFs, no cable drag", {"cable_drag": False}),
                         ("Python UFs, with cable drag", {"symbolic": False})):
        r = run(f, case.DURATION, n, dt, **kw, **extra)
        rows.append({"variant": label, "cpu_time_s": r["cpu_time_s"], "wall_time_s": r["wall_time_s"],
                     "Tmax_over_T0": r["Tmax_over_T0"]})
        print(f"  {label:<32} cpu {r['cpu_time_s']:7.3f} s  wall {r['wall_time_s']:7.3f} s  "
              f"Tmax/T0 {r['Tmax_over_T0']:.4f}")
    return rows


if __name__ == "__main__":
    main()
