"""Peer 1: MoorDyn v2 (lumped-mass cable, C++ library with a Python wrapper) on the
``snapping_cable`` case (see snapping_case.py and README.md).

Set-up
------
* The input file is written programmatically into a temporary directory:
  one line type with the cable properties, a ``Coupled`` point at the top (no mass,
  no volume) whose motion we drive, a ``Free`` point for the sphere (mass, volume,
  CdA = Cd*pi*D^2/4, Ca), and one line from the sphere (end A) to the top (end B).
* ``moordyn.Init`` finds the static equilibrium (MoorDyn's stationary solver; the
  sphere starts at the analytically stretched position), then each coupling step
  calls ``moordyn.Step(system, x, xd, t, dt)`` with the top position at the start of
  the step and the *average* velocity over the step, (z(t+dt) - z(t))/dt: MoorDyn moves
  a coupled point linearly, r = x + xd*(t - t_step) (Point::updateFairlead), so the
  top follows the exact sinusoid at every coupling instant without position jumps.
* The top tension is the vertical force that ``Step`` returns for the coupled point
  (sign flipped): the force of the cable on the support, i.e. the top segment's
  tension plus the wet weight/drag lumped on the top node (Point::doRHS adds
  Line::getEndStuff). It is evaluated at the integrator's last stage: for RK4 at the
  end of the step, for RK2 at its midpoint; the samples are time-stamped accordingly.

``time_step_s`` is MoorDyn's internal step dtM (explicit RK4; see _time_step_for for
the two stability limits, axial waves and slack-cable damping). The coupling (and output) interval is
an integer multiple of dtM close to 0.5 ms.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import tempfile
import time as _time

import numpy as np

try:  # imported as benchmarks.peers.moordyn_snapping
    from . import snapping_case as case
    from . import study
except ImportError:  # run as a script from this directory
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import snapping_case as case  # type: ignore[no-redef]
    import study  # type: ignore[no-redef]


@contextlib.contextmanager
def silenced(fd: int = 1, enabled: bool = True):
    """Send the C++ code's output on file descriptor ``fd`` to /dev/null for a while:
    MoorDyn prints a banner and IC progress on stdout (1) and every node of a diverging
    run on stderr (2)."""
    if not enabled:
        yield
        return
    stream = sys.stdout if fd == 1 else sys.stderr
    stream.flush()
    saved = os.dup(fd)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
        yield
    finally:
        stream.flush()
        os.dup2(saved, fd)
        os.close(saved)
        os.close(devnull)


def build_input(n_segments: int, time_step_s: float, scheme: str = "RK4",
                cable_axial_damping: float | None = None,
                cable_cd_tangential: float | None = None) -> str:
    """MoorDyn v2 input file text for the case."""
    BA = case.CABLE_AXIAL_DAMPING if cable_axial_damping is None else cable_axial_damping
    cdt = case.CABLE_CD_TANGENTIAL if cable_cd_tangential is None else cable_cd_tangential
    z0 = case.TOP_Z0
    z_sphere = z0 - case.static_stretched_length()
    cda = case.SPHERE_CD * case.sphere_frontal_area()
    # MoorDyn: Cd uses d per unit length, CdAx uses pi*d per unit length (Line.cpp),
    # Ca/CaAx multiply rho*pi*d^2/4 per unit length; EI = 0 (no bending).
    return f"""--------------------- MoorDyn Input File ------------------------------------
towcable benchmark snapping_cable (written by benchmarks/peers/moordyn_snapping.py)
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
wire  {case.CABLE_DIAMETER:.10g}  {case.CABLE_MASS_PER_LENGTH:.10g}  {case.CABLE_EA:.10g}  {BA:.10g}  0.0  {case.CABLE_CD_NORMAL:.10g}  {case.CABLE_CA_NORMAL:.10g}  {cdt:.10g}  {case.CABLE_CA_TANGENTIAL:.10g}
---------------------- POINT PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Coupled   0.0     0.0     {z0:.10g}     0.0     0.0     0.0    0.0
2     Free      0.0     0.0     {z_sphere:.10g}  {case.SPHERE_MASS:.10g}  {case.sphere_volume():.10g}  {cda:.10g}  {case.SPHERE_CA:.10g}
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     wire       2        1         {case.CABLE_LENGTH:.10g}   {int(n_segments)}   -
---------------------- OPTIONS -----------------------------------------
0             writeLog      no log file
{time_step_s:.10g}   dtM           internal time step (s)
{scheme}      tScheme       time integration scheme
{case.RHO_WATER:.10g}   WtrDnsty      water density (kg/m^3)
{case.G:.10g}   g             gravity (m/s^2)
{case.WATER_DEPTH:.10g}   WtrDpth       water depth (m)
0.5           dtIC          IC convergence check interval (s)
60            TmaxIC        max time for IC generation (s)
1e-7          threshIC      IC convergence threshold (-)
0             WaveKin       no waves
0             Currents      no currents
1             disableOutput no console output while stepping
1             disableOutTime
------------------------- need this line --------------------------------------
"""


def run(frequency_hz: float, duration_s: float, n_segments: int, time_step_s: float,
        *, scheme: str = "RK4", amplitude_m: float | None = None,
        coupling_target_s: float = 5e-4, cable_axial_damping: float | None = None,
        cable_cd_tangential: float | None = None, quiet: bool = True) -> dict:
    """Simulate the case with MoorDyn and return the top-tension results.

    Returns a dict with T0 [N] (MoorDyn's static top force), Tmax_over_T0 and
    Tmin_over_T0 over the whole run (case.WINDOW_FULL, clipped to duration_s), the
    same over the late window (keys *_late; NaN if the run ends before 5 s),
    wall_time_s and cpu_time_s (stepping loop only, without input writing and the
    static initialisation, which is init_time_s), sim_time_s, and the time series
    time [s] / tension_top [N]. ``coupling_target_s`` sets the coupling/output
    interval (a multiple of time_step_s); the other keywords override case values
    for sensitivity runs.
    """
    import moordyn

    A = case.AMPLITUDE if amplitude_m is None else amplitude_m
    _, dt_c = case.sample_interval(time_step_s, coupling_target_s)
    n_out = int(round(duration_s / dt_c))
    tt = np.arange(n_out + 1) * dt_c
    z = case.top_position(tt, frequency_hz, A)
    # stamp of the force returned by Step (last stage of the last internal step)
    stamp = -0.5 * time_step_s if scheme.upper() == "RK2" else 0.0

    with tempfile.TemporaryDirectory(prefix="moordyn_snap_") as tmp:
        path = os.path.join(tmp, "snapping.txt")
        with open(path, "w") as fh:
            fh.write(build_input(n_segments, time_step_s, scheme, cable_axial_damping,
                                 cable_cd_tangential))
        t_init = _time.perf_counter()
        with silenced(1, quiet):
            system = moordyn.Create(path)
            moordyn.Init(system, [0.0, 0.0, z[0]], [0.0, 0.0, 0.0])
        init_time = _time.perf_counter() - t_init
        f0 = moordyn.Step(system, [0.0, 0.0, z[0]], [0.0, 0.0, 0.0], 0.0, 0.0)
        T0 = -f0[2]

        tension = np.empty(n_out)
        step = moordyn.Step
        t = 0.0
        wall0 = _time.perf_counter()
        cpu0 = _time.process_time()
        try:
            for i in range(n_out):
                vz = (z[i + 1] - z[i]) / dt_c
                f = step(system, [0.0, 0.0, z[i]], [0.0, 0.0, vz], t, dt_c)
                t = tt[i + 1]
                tension[i] = -f[2]
        finally:
            wall = _time.perf_counter() - wall0
            cpu = _time.process_time() - cpu0
            with silenced(1, quiet):
                moordyn.Close(system)

    time = np.concatenate(([0.0], tt[1:] + stamp))
    tension = np.concatenate(([T0], tension))
    w_full = (case.WINDOW_FULL[0], min(case.WINDOW_FULL[1], duration_s))
    w_late = (case.WINDOW_LATE[0], min(case.WINDOW_LATE[1], duration_s))
    tmax, tmin = case.tension_metrics(time, tension, T0, w_full)
    tmax_l, tmin_l = case.tension_metrics(time, tension, T0, w_late)
    return {
        "peer": "moordyn",
        "frequency_hz": frequency_hz,
        "n_segments": int(n_segments),
        "time_step_s": time_step_s,
        "scheme": scheme,
        "coupling_dt_s": dt_c,
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


# ----------------------------------------------------------------------------- study
def _time_step_for(n_segments: int) -> float:
    """Internal step for RK4: about half of the explicit stability limit.

    Two limits: the axial waves, dt < 1.4 l/c (c = sqrt(EA/mu), l = L/n), and, while
    the cable is slack (no stiffness, only the BA damping), the real eigenvalue
    -4 BA/(mu l^2) of the damping, dt < 2.78 mu l^2/(4 BA) (RK4 stability on the real
    axis). The second one wins beyond ~50 segments (it scales with l^2).
    """
    l = case.CABLE_LENGTH / n_segments
    c = math.sqrt(case.CABLE_EA / case.CABLE_MASS_PER_LENGTH)
    wave = 1.4 * l / c
    damping = 2.78 * case.CABLE_MASS_PER_LENGTH * l * l / (4.0 * case.CABLE_AXIAL_DAMPING)
    return float(f"{0.5 * min(wave, damping):.1g}")


def main(argv: list[str] | None = None) -> None:
    import argparse

    import moordyn  # noqa: F401  (fail early if missing)

    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--duration", type=float, default=case.DURATION)
    p.add_argument("--frequencies", type=float, nargs="*", default=list(case.FREQUENCIES_HZ))
    p.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                 "results", "moordyn_snapping.json"))
    args = p.parse_args(argv)

    print(case.summary())
    print(f"moordyn {study.package_version('moordyn')}, scheme RK4, coupling/output every ~0.5 ms")
    # ladder 1: refine segments and time step together (dt ~ 0.5 x explicit limit)
    seg_ladder = [(n, _time_step_for(n)) for n in (2, 5, 10, 20, 40, 80)]
    # ladder 2: time step alone at 20 segments
    dt_ladder = [(20, dt) for dt in (2e-4, 1e-4, 5e-5, 2.5e-5)]
    results = study.run_study(run, args.frequencies, args.duration,
                              {"segments+dt": seg_ladder, "dt@20seg": dt_ladder},
                              peer="moordyn")
    study.sanity_checks(run, results, small_setting=(20, 2e-4), peer="moordyn")
    study.save(results, args.out)


if __name__ == "__main__":
    main()
