"""What TowCable's ``fmi2DoStep`` costs outside its model, per layer, for source trees in
alternating fresh processes.

The TowCable FMU (full_scale, default sea's ship inputs, the scene's nominal set-point) is
stepped at 0.01 s through fmpy's raw ctypes function ``fmi2DoStep`` (inputs set before each
step, served by the loader layer). Per step (medians over 2000 steps after 500): the
call's wall time, the model wall time it adds (``model_wall_time``: the slave's timer
around the Simulation's step, its Python included) and the difference: the loader layer,
pythonfmu's ``fmi2DoStep`` into Python and the slave's glue around the Simulation; and
the time in the compiled step itself (the Simulation module's compiled entry, ``step_to``
or ``step_on_values``, timed by a wrapper put in its place: the wrapper's own 0.1-0.2 us
count as Python; a step the loader layer makes with the C function of
``towcable_fmu/ancf/native_step.py`` does not pass it, and its compiled time is the model
time the loader timed around that function), so that 'Python around the compiled step'
is the call's wall time minus the compiled step's (with the C function: the loader's own
work, no Python).

Run: ``python benchmarks/cosim_layers.py TREE [TREE ...]`` (each tree's FMUs are built
into a folder of its own on the first run, untimed).
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from cosim_ab import REPEATS, report

H = 0.01


def child(fmu_dir: str) -> None:
    """Measure in this process (the FMUs of ``fmu_dir``); print one JSON line."""
    import time

    import numpy as np

    from towcable_fmu.common import contract
    from towcable_fmu.cosim import FmuInstance
    from towcable_fmu.fmu_build.build import ensure_fmus
    from towcable_fmu.runtime.ship_input import motion_source
    from towcable_fmu.scene import load_scene

    paths = ensure_fmus(fmu_dir)
    fmu = FmuInstance(contract.fmu("TowCable"), paths["TowCable"], echo=False)
    fmu.instantiate(0.0)
    fmu.set_parameters({"scene": "full_scale"})
    f = fmu.fmu
    f.enterInitializationMode()
    scene = load_scene("full_scale")
    motion = motion_source(scene)
    ship_vrs = fmu.vrs([n for n in contract.signals() if n.startswith("ship.")])
    f.setReal(fmu.vrs(["winch.phi_sp", "winch.phi_sp_rate"]), [scene.winch.phi_nom, 0.0])
    f.setReal(ship_vrs, list(motion.evaluate(0.0).ravel()))
    f.exitInitializationMode()
    timer = fmu.vrs(["model_wall_time"])
    compiled = [0.0]
    for name, module in list(sys.modules.items()):  # the FMU's copy of the code may have a private name
        if name.endswith("towcable_fmu.ancf.simulation"):
            for entry in ("step_to", "step_on_values"):
                if hasattr(module, entry):
                    setattr(module, entry, _timed(getattr(module, entry), compiled))
    ships = [list(motion.evaluate(k * H).ravel()) for k in range(2500)]
    do_step, component = f.fmi2DoStep, f.component
    walls, models, kernels = [], [], []
    for k in range(2500):
        f.setReal(ship_vrs, ships[k])
        m0 = f.getReal(timer)[0]
        c0 = compiled[0]
        a = time.perf_counter()
        status = do_step(component, k * H, H, 1)
        b = time.perf_counter()
        if status != 0:
            raise RuntimeError(f"fmi2DoStep at step {k}: status {status}")
        if k >= 500:
            walls.append(b - a)
            models.append(f.getReal(timer)[0] - m0)
            # a step the loader made with the C function (towcable_fmu.ancf.native_step) does not
            # pass the wrapper: its compiled time is the model time the loader timed around it
            kernels.append(compiled[0] - c0 if compiled[0] != c0 else models[-1])
    w, m, c = np.array(walls), np.array(models), np.array(kernels)
    print(json.dumps({"step": 1e6 * statistics.median(w), "model": 1e6 * statistics.median(m),
                      "outside": 1e6 * statistics.median(w - m), "compiled": 1e6 * statistics.median(c),
                      "python": 1e6 * statistics.median(w - c)}))


def _timed(kernel, total: list):
    """``kernel`` with its wall time added to ``total[0]`` [s]."""
    import time

    def timed(*args):
        start = time.perf_counter()
        try:
            return kernel(*args)
        finally:
            total[0] += time.perf_counter() - start

    return timed


def main(trees: list[str]) -> None:

    base = Path(tempfile.mkdtemp(prefix="cosim_layers_"))
    dirs = {tree: base / f"t{k}" for k, tree in enumerate(trees)}
    results: dict[str, list[dict]] = {tree: [] for tree in trees}
    load0 = os.getloadavg()[0]
    for r in range(REPEATS + 1):  # the first round builds the FMUs: not counted
        for tree in (trees if r % 2 == 0 else trees[::-1]):
            dirs[tree].mkdir(exist_ok=True)
            done = subprocess.run([sys.executable, __file__, "--child", str(dirs[tree] / "fmus")], cwd=dirs[tree],
                                  env=dict(os.environ, PYTHONPATH=tree), capture_output=True, text=True)
            if done.returncode:
                raise RuntimeError(f"{tree}: {done.stderr.strip()[-2000:]}")
            if r:
                results[tree].append(json.loads(done.stdout.strip().splitlines()[-1]))
    keys = ("step", "model", "outside", "compiled", "python")
    rows = [[tree, *(f"{statistics.median(x[key] for x in results[tree]):.1f}" for key in keys)] for tree in trees]
    report("TowCable FMU, full_scale, 0.01 s", load0,
           ["tree", "fmi2DoStep [us]", "model_wall_time [us]", "outside the model [us]", "compiled step [us]",
            "Python around the compiled step [us]"], rows)

if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        child(sys.argv[2])
    else:
        main([str(Path(t).resolve()) for t in sys.argv[1:]])
