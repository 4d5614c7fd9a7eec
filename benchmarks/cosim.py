"""Co-simulation of the three FMUs: speed and FMU overhead.

The full-scale system (ShipMotion in the default sea -> HeaveCompensation with the
simplified-sheave set-point -> TowCable ``full_scale``) run by the fmpy master
(``towcable_fmu.cosim.run_cosim``) for 120 s at communication steps of 0.01 s (the
issue's figure) and 0.02 s (the scene's own time step), three repeats each (medians).
Per communication step: the time in each model, in the slaves' Python glue (measured
in-process, ``cosim_step.py``) and in the FMI calls and the master (the rest of the
loop's wall time). Overhead = the share of the loop's wall time spent outside the three
models' own computations.
The standalone ``Simulation`` on the same scene and sea is given for comparison.

The loader layer's shared values (the light FMUs stepped by their compiled functions,
gets and sets without Python) against every call through Python
(``TOWCABLE_FMU_PASS_THROUGH=1``, as before them): the two runs interleaved in this
process, medians of three, per communication step the time outside TowCable's model
(the two light FMUs, every FMI call, the master) and the speed.

The same system under a third-party host, libcosim (OSP's, through libcosimpy, from the
SSP file of the master's parameters): per communication step each model's time and
the rest (the FMI calls and the host), beside fmpy's master (issue 40, item 5).

Run: ``python benchmarks/cosim.py``; writes ``results/cosim.md``
(``--shared-values``: only the comparison, printed; ``--hosts``: only the two hosts,
printed).
"""

from __future__ import annotations

import os
import statistics
import sys
import time

from common import RESULTS, machine_header, markdown_table

DURATION = 120.0
STEPS = (0.01, 0.02)
REPEATS = 3
FMUS = ("TowCable", "ShipMotion", "HeaveCompensation")


def cosim(step: float) -> dict:
    """Median timing of REPEATS co-simulations at communication step ``step`` [s]."""
    from towcable_fmu.cosim import CosimConfig, run_cosim

    runs = [run_cosim(CosimConfig(duration=DURATION, step=step, compensation="simplified_sheave",
                                  fmu_dir="fmus"), echo=False).timing for _ in range(REPEATS)]
    return {key: statistics.median(r[key] for r in runs) for key in runs[0]}


def shared_values(step: float, duration: float = DURATION) -> dict[str, list[float]]:
    """Medians of REPEATS interleaved runs with the shared values (``shared``) and with
    every call through Python (``python``): [x real time, outside TowCable's model
    [us/step], TowCable's model [us/step]]."""
    from towcable_fmu.cosim import CosimConfig, run_cosim

    runs: dict[str, list] = {"python": [], "shared": []}
    for _ in range(REPEATS):
        for mode in runs:
            os.environ["TOWCABLE_FMU_PASS_THROUGH"] = "1" if mode == "python" else "0"
            t = run_cosim(CosimConfig(duration=duration, step=step, compensation="simplified_sheave",
                                      fmu_dir="fmus"), echo=False).timing
            n = t["steps"]
            runs[mode].append((t["realtime_factor"], 1e6 * (t["wall"] - t["model.TowCable"]) / n,
                               1e6 * t["model.TowCable"] / n))
    os.environ.pop("TOWCABLE_FMU_PASS_THROUGH")
    return {mode: [statistics.median(column) for column in zip(*rows)] for mode, rows in runs.items()}


def shared_values_table() -> str:
    """The comparison of :func:`shared_values` at both steps (Markdown)."""
    rows = []
    for step in STEPS:
        m = shared_values(step)
        rows.append([f"{step:g}", f"{m['python'][0]:.1f}", f"{m['shared'][0]:.1f}", f"{m['python'][1]:.1f}",
                     f"{m['shared'][1]:.1f}", f"{m['python'][2]:.1f}", f"{m['shared'][2]:.1f}"])
    return ("\nShared values (the loader serves gets and sets and steps the light FMUs compiled) against every "
            "call through Python (`TOWCABLE_FMU_PASS_THROUGH=1`), interleaved in one process, medians of "
            f"{REPEATS}; 'outside' is the loop's wall time outside TowCable's model (the light FMUs, every FMI "
            "call, the master):\n\n"
            + markdown_table(["communication step [s]", "x real time, Python", "x real time, shared",
                              "outside [us/step], Python", "outside [us/step], shared",
                              "TowCable model [us/step], Python", "TowCable model [us/step], shared"], rows))


def libcosim_host(step: float, duration: float = DURATION) -> dict[str, float]:
    """The same system run by a third-party host, libcosim (OSP, through libcosimpy) from
    the SSP file of the master's parameters: medians of REPEATS runs of the wall time of
    its steps and of each FMU's ``model_wall_time`` per communication step [us], and the
    rest ('FMI calls + host': the loaders, libcosim's exchange and its own loop)."""
    import tempfile
    from pathlib import Path

    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    from towcable_fmu.cosim import CosimConfig, run_cosim
    from towcable_fmu.fmu_build.build import ensure_fmus
    from towcable_fmu.fmu_build.ssp import write_ssp

    config = CosimConfig(duration=step, step=step, compensation="simplified_sheave", fmu_dir="fmus")
    parameters = run_cosim(config, echo=False).parameters  # (the master's geometry: theta_nom, reference point)
    ssp = write_ssp(Path(tempfile.mkdtemp()) / "system.ssp", ensure_fmus("fmus"), parameters,
                    stop_time=duration + step)
    log_output_level(CosimLogLevel.ERROR)
    n = int(round(duration / step))
    runs = []
    for _ in range(REPEATS):
        execution = CosimExecution.from_ssp_file(str(ssp), step_size=int(round(step * 1e9)))
        observer = CosimObserver.create_last_value()
        execution.add_observer(observer)
        index = {info.name.decode(): info.index for info in execution.slave_infos()}
        timer = {name: next(v.reference for v in execution.slave_variables(i) if v.name.decode() == "model_wall_time")
                 for name, i in index.items()}
        execution.step(1)  # initialisation and the first step: not timed

        def models() -> dict[str, float]:
            return {name: observer.last_real_values(i, [timer[name]])[0] for name, i in index.items()}

        before = models()
        start = time.perf_counter()
        execution.step(n)
        wall = time.perf_counter() - start
        after = models()
        run = {f"model.{name}": 1e6 * (after[name] - before[name]) / n for name in FMUS}
        run["wall"] = 1e6 * wall / n
        run["outside"] = run["wall"] - sum(run[f"model.{name}"] for name in FMUS)
        run["realtime_factor"] = duration / wall
        runs.append(run)
    return {key: statistics.median(r[key] for r in runs) for key in runs[0]}


def hosts_table() -> str:
    """Per communication step, fmpy's master (`run_cosim`) and libcosim side by side (Markdown)."""
    rows = []
    for step in STEPS:
        t = cosim(step)
        n = t["steps"]
        fmpy = [1e6 * t[f"model.{name}"] / n for name in FMUS]
        lib = libcosim_host(step)
        rows.append([f"{step:g}", "fmpy master (`run_cosim`)", f"{t['realtime_factor']:.1f}", *(f"{m:.1f}" for m in fmpy),
                     f"{1e6 * t['wall'] / n - sum(fmpy):.1f}"])
        rows.append([f"{step:g}", "libcosim (SSP)", f"{lib['realtime_factor']:.1f}",
                     *(f"{lib[f'model.{name}']:.1f}" for name in FMUS), f"{lib['outside']:.1f}"])
    return ("\nPer communication step, two hosts of the same FMUs: fmpy's master and a third-party host, "
            f"libcosim (libcosimpy, from the SSP file of the master's parameters), {DURATION:g} s, medians of "
            f"{REPEATS}. Each model's time is its `model_wall_time`; 'FMI calls + host' is the rest of the wall "
            "time of the steps (the loader layer, pythonfmu, the host's exchange and loop).\n\n"
            + markdown_table(["communication step [s]", "host", "x real time", "TowCable [us/step]",
                              "ShipMotion [us/step]", "HeaveCompensation [us/step]", "FMI calls + host [us/step]"],
                             rows))


def standalone() -> float:
    """Median simulated seconds per wall second of the Simulation alone (same scene and sea)."""
    from towcable_fmu.ancf.simulation import Simulation

    speeds = []
    for _ in range(REPEATS):
        sim = Simulation.from_scene("full_scale", {"compensation": {"algorithm": "simplified_sheave"}})
        sim.initialize()
        start = time.perf_counter()
        sim.run(DURATION, interval=0.1)
        speeds.append(DURATION / (time.perf_counter() - start))
    return statistics.median(speeds)


def main() -> None:
    from cosim_step import profile

    cosim(0.01)  # build the FMUs if needed and load the compiled kernels
    glue = profile()  # the slaves' calls made in-process: model and Python glue per step
    glue_us = 1e6 * sum(glue[f"{name}.calls"] - glue[f"{name}.model"] for name in FMUS)
    rows = []
    for step in STEPS:
        t = cosim(step)
        n = t["steps"]
        models = [1e6 * t[f"model.{name}"] / n for name in FMUS]
        outside = 1e6 * (t["wall"] - t["model"]) / n
        rows.append([f"{step:g}", f"{t['realtime_factor']:.1f}", f"{t['wall']:.2f}", *(f"{m:.1f}" for m in models),
                     f"{outside:.1f}", f"{glue_us:.1f}", f"{outside - glue_us:.1f}", f"{100 * t['overhead_share']:.1f}"])
    alone = standalone()
    text = ["# Co-simulation: speed and FMU overhead\n", machine_header(),
            f"\nfull_scale in the default sea with the simplified-sheave set-point, {DURATION:g} s, fmpy master "
            f"(`run_cosim`, compiled stepping loop), medians of {REPEATS} runs. Per communication step: each FMU's "
            "own model time; 'outside' the loop's wall time outside the three models, split into the slaves' "
            "Python glue (their set/get/step methods around the models, measured in-process by "
            "`cosim_step.py` at 0.01 s) and the rest: pythonfmu's and our C layer, ctypes and the master's "
            "compiled loop. 'overhead' is 1 - (time in the three models) / (loop wall time).\n\n",
            markdown_table(["communication step [s]", "x real time", "wall [s]", "TowCable [us/step]",
                            "ShipMotion [us/step]", "HeaveCompensation [us/step]", "outside [us/step]",
                            "slaves' glue [us/step]", "FMI calls + master [us/step]", "overhead [%]"],
                           rows),
            f"\nThe `Simulation` alone on the same scene, sea and set-point (recording every 0.1 s): "
            f"{alone:.1f} x real time.\n", hosts_table(), shared_values_table(), "\n"]
    (RESULTS / "cosim.md").write_text("".join(text), encoding="utf-8")
    print("".join(text))


if __name__ == "__main__":
    if "--hosts" in sys.argv:
        cosim(0.01)  # build the FMUs if needed and load the compiled kernels
        print(machine_header() + hosts_table())
    elif "--shared-values" in sys.argv:
        cosim(0.01)  # build the FMUs if needed and load the compiled kernels
        print(machine_header() + shared_values_table())
    else:
        main()
