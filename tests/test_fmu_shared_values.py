"""FMI calls served by the loader layer from the values it shares with the slave.

Once a slave is initialised the loader answers fmi2GetReal/Integer/Boolean and keeps
sets of Real inputs in a buffer shared with it, and steps ShipMotion (irregular sea)
and HeaveCompensation (motion algorithms) with compiled functions
(``towcable_fmu/fmu_build/csrc/shared_values.h``). The reference is the same FMU with
``TOWCABLE_FMU_PASS_THROUGH=1``, where every call enters Python as before: both run the
same calls and must give the same values bit for bit.
"""

from __future__ import annotations

import ctypes
import gc
import math

import pytest

from fmu_util import SMALL_SCENE, open_fmu, ship_inputs

PARAMS = {"TowCable": {"scene": str(SMALL_SCENE)},
          "HeaveCompensation": {"algorithm": "simplified_sheave", "phi_nom": 3.5},
          "ShipMotion": {}}  # the default sea: irregular
H = 0.01


def instance(paths, name, monkeypatch, shared: bool, tag: str = "", amplitude: float = 0.8):
    """An instance in initialisation mode, shared or all through Python, with a regular
    sea of this heave amplitude to feed its ship inputs."""
    from ship_motion import motion_from_config

    monkeypatch.setenv("TOWCABLE_FMU_PASS_THROUGH", "0" if shared else "1")
    fmu = open_fmu(paths, name, PARAMS[name], instance=f"{name}_{'shared' if shared else 'python'}{tag}")
    monkeypatch.delenv("TOWCABLE_FMU_PASS_THROUGH")
    fmu.motion = motion_from_config({"type": "regular", "ramp": 0.0, "heave": {"amplitude": amplitude, "period": 6.0},
                                     "pitch": {"amplitude": 2.0, "period": 7.0}})
    return fmu


def slave_of(fmu):
    """The Python slave behind an instance (the FMUs run in this process)."""
    # by class name: the FMU may run our slaves under their private package name; no
    # attribute of other objects is looked up (a ctypes library unloaded since would crash)
    found = [o for o in gc.get_objects()
             if any(cls.__name__ == "ContractSlave" for cls in type(o).__mro__) and o.instance_name == fmu.name]
    assert len(found) == 1
    return found[0]


def inputs_at(fmu, k: int, **changed) -> tuple[list[int], list[float]]:
    """The Real inputs of communication point k (value references, values)."""
    names = [v.name for v in fmu.spec.inputs if v.type == "Real"]
    values = {**ship_inputs(fmu.motion.evaluate(k * H)), "sheave_angle": 0.4 + 0.01 * k, "tension.winch": 1.0e4,
              "winch.phi_sp": 0.0, "winch.phi_sp_rate": 0.0, **changed}
    return fmu.vrs(names), [values[n] for n in names]


def snapshot(fmu) -> tuple:
    """Every Real, Boolean and String value but the diagnostics (wall times)."""
    reals = [v.name for v in fmu.spec.variables if v.type == "Real" and not v.diagnostic]
    bools = [v.name for v in fmu.spec.variables if v.type == "Boolean"]
    strings = [v.name for v in fmu.spec.variables if v.type == "String"]
    got = tuple(fmu.fmu.getReal(fmu.vrs(reals)))
    got += tuple(fmu.fmu.getBoolean(fmu.vrs(bools))) if bools else ()
    return got + tuple(fmu.fmu.getString(fmu.vrs(strings))) if strings else got


def script(fmu, steps: int = 6) -> list:
    """Initialise; step with gets after each set and each step; take a state at step 2
    and restore it at the end; step again; reset and enter initialisation again: every
    value read on the way, and fmi2LastSuccessfulTime."""
    seen = []
    if fmu.spec.inputs:
        fmu.fmu.setReal(*inputs_at(fmu, 0))
    fmu.exit_initialization()
    seen.append(snapshot(fmu))
    state = taken = None
    for k in range(steps):
        if fmu.spec.inputs:
            vrs, values = inputs_at(fmu, k)
            fmu.fmu.setReal(vrs, values)
            assert list(fmu.fmu.getReal(vrs)) == values  # a get right after a set: the value set
            seen.append(snapshot(fmu))
        fmu.fmu.doStep(k * H, H)
        seen.append(snapshot(fmu))
        if k == 2:
            state, taken = fmu.fmu.getFMUstate(), snapshot(fmu)
    seen.append(("last successful time", fmu.fmu.getRealStatus(2)))  # fmi2LastSuccessfulTime
    fmu.fmu.setFMUstate(state)
    seen.append(("restored", snapshot(fmu)))
    assert seen[-1][1] == taken  # the gets after a restore: the values of the state
    fmu.fmu.doStep(3 * H, H)
    seen.append(snapshot(fmu))
    fmu.fmu.freeFMUstate(state)
    fmu.fmu.reset()
    fmu.fmu.setupExperiment(startTime=0.0)
    fmu.fmu.enterInitializationMode()
    seen.append(("reset", snapshot(fmu)))
    return seen


@pytest.mark.parametrize("name", ["TowCable", "HeaveCompensation", "ShipMotion"])
def test_shared_values_give_what_python_gives(fmu_paths, monkeypatch, name):
    """The same calls, shared and through Python: the same values, bit for bit, at every
    get (after sets, steps, a state restored, a reset: the start values again)."""
    fmu = instance(fmu_paths, name, monkeypatch, shared=True)
    ref = instance(fmu_paths, name, monkeypatch, shared=False)
    assert slave_of(fmu)._shared is not None and slave_of(ref)._shared is None
    got, expected = script(fmu), script(ref)
    assert got == expected
    assert got[-4] == ("last successful time", pytest.approx(6 * H, abs=1e-12))  # the end of the 6th step
    assert got[-1][1] != got[-2]  # the reset changed the values back (the test sees something)
    fmu.free()
    ref.free()


@pytest.mark.parametrize("name", ["HeaveCompensation", "ShipMotion", "TowCable"])
def test_steps_do_not_enter_the_python_step(fmu_paths, monkeypatch, name):
    """Stepping as a master does (set, get, step, get): the light FMUs step with their
    compiled functions, TowCable with its Simulation's (towcable_fmu.ancf.native_step):
    the slave's Python step is never taken."""
    fmu = instance(fmu_paths, name, monkeypatch, shared=True)
    if fmu.spec.inputs:
        fmu.fmu.setReal(*inputs_at(fmu, 0))
    fmu.exit_initialization()
    slave = slave_of(fmu)
    python_steps = []
    step = slave._do_step
    monkeypatch.setattr(slave, "_do_step", lambda *args: python_steps.append(args) or step(*args))
    for k in range(5):
        if fmu.spec.inputs:
            fmu.fmu.setReal(*inputs_at(fmu, k))
        fmu.get_outputs()
        fmu.fmu.doStep(k * H, H)
        fmu.get_outputs()
    assert python_steps == []
    assert slave._shared.header.compiled_steps == 5
    fmu.free()


@pytest.mark.parametrize("name", ["HeaveCompensation", "ShipMotion", "TowCable"])
def test_a_host_that_reads_every_variable_at_every_step_does_not_enter_python(fmu_paths, monkeypatch, name):
    """libcosim's observers read every variable, Strings too, after every step: the
    String parameters the slave gave once are answered by the loader, so the steps stay
    in compiled code (the slave is entered for the first get only); and what the gets
    return is what the slave holds."""
    fmu = instance(fmu_paths, name, monkeypatch, shared=True)
    if fmu.spec.inputs:
        fmu.fmu.setReal(*inputs_at(fmu, 0))
    fmu.exit_initialization()
    slave = slave_of(fmu)
    strings = [v.name for v in fmu.spec.variables if v.type == "String"]
    assert strings  # (the test sees something)
    entries = []
    get_string = slave.get_string
    monkeypatch.setattr(slave, "get_string", lambda vrs: entries.append(list(vrs)) or get_string(vrs))
    for k in range(5):
        if fmu.spec.inputs:
            fmu.fmu.setReal(*inputs_at(fmu, k))
        fmu.fmu.doStep(k * H, H)
        snapshot(fmu)
        assert [s.decode() for s in fmu.fmu.getString(fmu.vrs(strings))] == [slave.values[n] for n in strings]
    assert len(entries) == 1
    assert slave._shared.header.compiled_steps == 5
    fmu.free()


@pytest.mark.parametrize("name", ["HeaveCompensation", "TowCable"])
def test_a_nan_input_is_refused_at_the_step(fmu_paths, monkeypatch, name):
    """A NaN input set in step mode is accepted by the set and refused by the step
    (fmi2Discard, a message naming it); the next step with finite inputs is made and
    gives what an instance that never saw the NaN gives."""
    from fmpy.fmi1 import FMICallException

    fmu = instance(fmu_paths, name, monkeypatch, shared=True)
    ref = instance(fmu_paths, name, monkeypatch, shared=False, tag="ref")
    for f in (fmu, ref):
        f.fmu.setReal(*inputs_at(f, 0))
        f.exit_initialization()
        f.fmu.setReal(*inputs_at(f, 0))
        f.fmu.doStep(0.0, H)
    fmu.fmu.setReal(*inputs_at(fmu, 1, **{"ship.z": math.nan}))
    mark = len(fmu.messages)
    with pytest.raises(FMICallException, match=r"status 2 \(discard\)"):
        fmu.fmu.doStep(H, H)
    assert "ship.z" in fmu.log_text(mark, least=2)
    for f in (fmu, ref):
        f.fmu.setReal(*inputs_at(f, 1))
        f.fmu.doStep(H, H)
    assert snapshot(fmu) == snapshot(ref)
    fmu.free()
    ref.free()


def test_two_instances_do_not_share_their_values(fmu_paths, monkeypatch):
    """Two shared instances stepped in turn with different inputs: each as it is alone."""
    name = "HeaveCompensation"
    a = instance(fmu_paths, name, monkeypatch, shared=True, tag="a", amplitude=0.8)
    b = instance(fmu_paths, name, monkeypatch, shared=True, tag="b", amplitude=2.0)
    alone = instance(fmu_paths, name, monkeypatch, shared=False, tag="alone", amplitude=2.0)
    for fmu in (a, b, alone):
        fmu.fmu.setReal(*inputs_at(fmu, 0))
        fmu.exit_initialization()
    for k in range(4):
        for fmu in (a, b, alone):
            fmu.fmu.setReal(*inputs_at(fmu, k))
            fmu.fmu.doStep(k * H, H)
        assert snapshot(b) == snapshot(alone) != snapshot(a)
    for fmu in (a, b, alone):
        fmu.free()


def test_no_host_reaches_the_shared_values(fmu_paths, monkeypatch):
    """The loader's function that hands the buffer to the slave answers nothing to a
    caller outside fmi2Instantiate and fmi2Reset (a host calling it directly)."""
    fmu = instance(fmu_paths, "TowCable", monkeypatch, shared=True)
    function = fmu.fmu.dll.towcable_shared_values
    function.restype = ctypes.c_void_p
    assert function() is None
    assert slave_of(fmu)._shared is not None  # the slave got it, inside fmi2Instantiate
    fmu.free()
