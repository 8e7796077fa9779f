"""What a review of the FMU by a C++ integrator found (docs/fmu.md, "Variables", "Behaviour",
"Statuses for careless masters"): position inputs not zero at the start time warn, naming them,
since the model starts from rest at its reference position; a master's last step clamped to
stopTime, down to 1e-3 solver.dt, is taken, and a shorter one is refused naming solver.dt and the
value that takes it, with nothing computed; a step within a clock's rounding clears the memory of a
discarded step; fmi2SetupExperiment's tolerance is checked and said unused; stopTime belongs to the
instance, not to its FMU state; the messages' wording. The FMU runs in a fresh process
(tests/fmu/fmu_driver.py's Instance, fmpy's FMU2Slave with the log captured)."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cablecasing_core.model.schema import value_range

pytestmark = pytest.mark.slow  # the FMU in a fresh process

HERE = Path(__file__).resolve().parent
H = 1e-4

# The host: one process, each case its own instance; prints {case: ...} as JSON.
HOST = r"""
import json, math, sys
import numpy as np
sys.path.insert(0, sys.argv[3])
from fmu_driver import INPUTS, Instance

fmu, table = sys.argv[1], np.load(sys.argv[2])
FORCES = ["casing.A.Fz", "casing.B.Fy", "casing.B.Fz", "cable.B.Fx"]
TERMINATED = 3  # fmi2Terminated
res = {}

def log(inst):
    out = [[s, m] for s, m in inst.log]
    inst.log.clear()
    return out

# D1: every support 1 mm up in z from the start, and the same run at rest
offset = np.zeros(len(INPUTS))
for c in ("casing.A.z", "casing.B.z", "cable.A.z", "cable.B.z"):
    offset[INPUTS.index(c)] = 1e-3
for name, row in (("offset", offset), ("rest", np.zeros(len(INPUTS)))):
    inst = Instance(fmu, name=name)
    log(inst)
    res[name] = []
    for _ in range(3):
        status = inst.step(row, 1e-4)
        res[name].append([status, inst.get(["casing.A.Fz"]).tolist()[0], log(inst)])
    inst.free()

# D2: a last step clamped to stopTime = 0.001 + 5e-8 s (5e-3 solver.dt), against the full step
inst = Instance(fmu, name="clamped", initialize=False)
inst.fmu.setupExperiment(startTime=0.0, stopTime=0.001 + 5e-8)
inst.fmu.enterInitializationMode()
inst.fmu.exitInitializationMode()
for row in table[:10]:
    inst.step(row, 1e-4)
res["clamped_before"] = inst.get(FORCES).tolist()
log(inst)
res["clamped_status"] = inst.step(table[10], (0.001 + 5e-8) - inst.t)
res["clamped"] = inst.get(FORCES).tolist()
res["clamped_log"] = log(inst)
inst.free()
inst = Instance(fmu, name="full")
for row in table[:11]:
    inst.step(row, 1e-4)
res["full"] = inst.get(FORCES).tolist()
inst.free()
# a master whose every step is 1e-7 s (1e-2 solver.dt)
inst = Instance(fmu, name="fixed_short")
res["fixed_short"] = [inst.step(table[0], 1e-7) for _ in range(20)]
res["fixed_short_t"] = inst.fmu.getRealStatus(2)  # fmi2LastSuccessfulTime
inst.free()
# a step of 5e-9 s (5e-4 solver.dt): refused; with the solver.dt the message names, taken
inst = Instance(fmu, name="tiny")
log(inst)
res["tiny"] = inst.step(table[0], 5e-9)
res["tiny_log"] = log(inst)
res["tiny_t"] = inst.fmu.getRealStatus(2)
inst.free()
inst = Instance(fmu, name="tiny_fixed", params={"solver.dt": 5e-6})
res["tiny_fixed"] = [inst.step(table[0], 5e-9) for _ in range(3)]
inst.free()

# D3: a discarded step, a step within a clock's rounding (taken), the first step asked for again
inst = Instance(fmu, name="clock")
log(inst)
res["clock"] = [Instance.call(inst.fmu.doStep, 0.0, 5e-9), Instance.call(inst.fmu.doStep, 0.0, 1e-11)]
res["clock"].append(Instance.call(inst.fmu.doStep, 0.0, 5e-9))
res["clock_terminated"] = bool(inst.fmu.getBooleanStatus(TERMINATED))
res["clock_log"] = log(inst)
inst.free()

# D4: fmi2SetupExperiment's tolerance
inst = Instance(fmu, name="tol", initialize=False)
log(inst)
res["tol_bad"] = [Instance.call(inst.fmu.setupExperiment, tol, 0.0) for tol in (math.nan, -1.0, 0.0, math.inf)]
res["tol_bad_log"] = log(inst)
res["tol_good"] = [Instance.call(inst.fmu.setupExperiment, 1e-6, 0.0) for _ in range(2)]
res["tol_good_log"] = log(inst)
inst.fmu.enterInitializationMode()
inst.fmu.exitInitializationMode()
res["tol_steps"] = [inst.step(table[0], 1e-4) for _ in range(2)]
inst.free()

# D5: a state saved under stopTime = 0.003 s, restored into instances with other stopTimes
a = Instance(fmu, name="saved", initialize=False)
a.fmu.setupExperiment(startTime=0.0, stopTime=0.003)
a.fmu.enterInitializationMode()
a.fmu.exitInitializationMode()
for row in table[:10]:
    a.step(row, 1e-4)
data = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
a.free()
for name, stop in (("no_stop", None), ("stop_002", 0.002)):
    b = Instance(fmu, name=name, initialize=False)
    b.fmu.setupExperiment(startTime=0.0, stopTime=stop)
    b.fmu.enterInitializationMode()
    b.fmu.exitInitializationMode()
    b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(data))
    b.t = b.fmu.getRealStatus(2)
    log(b)
    res[name] = [b.step(table[0], 1e-4) for _ in range(30)]
    res[name + "_log"] = [m for s, m in log(b) if s >= 2]
    b.free()

# D6: the wording of two refusals
inst = Instance(fmu, name="words")
log(inst)
res["get_integer"] = Instance.call(inst.fmu.getInteger, [inst.var["casing.A.Fz"].valueReference])
res["deserialise"] = Instance.call(inst.fmu.deSerializeFMUstate, b"not a state")
res["words_log"] = log(inst)
inst.free()
print(json.dumps(res))
"""


@pytest.fixture(scope="module")
def host(fmu, tmp_path_factory, drive_casing_b_120hz):
    path = tmp_path_factory.mktemp("review_g") / "inputs.npy"
    np.save(path, drive_casing_b_120hz(12, H))
    proc = subprocess.run(
        [sys.executable, "-c", HOST, str(fmu), str(path), str(HERE)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_position_inputs_not_zero_at_the_start_warn_naming_them(host):
    """All four supports 1 mm up from the start: the model starts from rest at its reference position,
    so the first step moves them there, and the bodies feel it (casing.A.Fz hundreds of N, where a
    rigid shift would give none); the first step warns once, naming the inputs and their values, what
    happens and what to give instead, and still returns fmi2OK. The same run at rest says nothing."""
    (s0, f0, log0), *later = host["offset"]
    assert s0 == 0 and abs(f0) > 100.0, (s0, f0)  # (the jump the warning names: 437 N in the review)
    warnings = [m for s, m in log0 if s == 1]
    assert len(warnings) == 1, log0
    text = warnings[0]
    for name in ("casing.A.z", "casing.B.z", "cable.A.z", "cable.B.z"):
        assert f"{name} = 0.001 m" in text, text
    assert "casing.A.x" not in text and "starts from rest at its reference position" in text, text
    assert "within the first step" in text and "relative to their values at the start time" in text, text
    assert all(s == 0 and not log for s, _, log in later), later
    assert all(s == 0 and not [m for st, m in log if st >= 1] for s, _, log in host["rest"]), host["rest"]


def test_a_last_step_clamped_to_the_stop_time_is_taken(host):
    """A last step of 5e-8 s (5e-3 solver.dt) to land on stopTime is one Newmark step of it: OK, and
    the forces move (a step not computed leaves them as they were to the bit) by less than 1 % of the
    next full step's change. The move is not resolved beyond that: linear interpolation would move
    them by 5e-4 of that change, and the digits such a short step loses (within 1e-3 of a force's
    RMS, tests/timedomain/test_engine.py) are larger; measured, 0.1-0.4 % of the change."""
    assert host["clamped_status"] == 0, host["clamped_log"]
    before, after, full = (np.array(host[k]) for k in ("clamped_before", "clamped", "full"))
    moving = full != before  # (cable.B.Fx stays 0: the cable's end B is clamped and not driven)
    assert moving.sum() == 3 and np.all(after[~moving] == before[~moving]), (before, full)
    assert np.all(after[moving] != before[moving]), (after, before)
    assert np.all(np.abs(after - before)[moving] <= 0.01 * np.abs(full - before)[moving]), (after, before, full)
    assert host["fixed_short"] == [0] * 20
    assert host["fixed_short_t"] == pytest.approx(20 * 1e-7, rel=1e-9)


def test_a_step_too_short_names_solver_dt_and_the_value_that_takes_it(host):
    """A step of 5e-9 s (5e-4 solver.dt) is refused before anything is computed (the FMU stays at
    t = 0; not "rolled back"), naming solver.dt, the least step and the solver.dt that takes it
    (5e-6 s), with which it is taken."""
    assert host["tiny"] == 2 and host["tiny_t"] == 0.0
    text = " ".join(m for s, m in host["tiny_log"])
    assert "nothing computed" in text and "rolled back" not in text, text
    assert "solver.dt = 1e-05 s" in text and "at least 0.001 solver.dt (1e-08 s;" in text, text
    assert "set solver.dt to at most 5e-06 s (h / 0.001) before fmi2ExitInitializationMode" in text, text
    assert "stopTime" in text, text
    assert host["tiny_fixed"] == [0, 0, 0]


def test_a_clock_rounding_step_clears_the_memory_of_a_discarded_step(host):
    """A step discarded (5e-9 s), a step within a clock's rounding (1e-11 s: taken, fmi2OK), then the
    first step asked for again from t = 0: discarded for its time alone (the FMU is at 1e-11 s), not
    blamed as a repeat, and fmi2Terminated stays false (docs/fmu.md: the memory holds until a step
    is taken)."""
    assert host["clock"] == [2, 0, 2], host["clock_log"]
    assert not host["clock_terminated"]
    text = " ".join(m for s, m in host["clock_log"])
    assert "but the FMU is at t = 1e-11 s" in text and "asked for again" not in text, text


def test_the_tolerance_is_checked_and_said_unused(host):
    """fmi2SetupExperiment with toleranceDefined: a NaN, negative, zero or infinite tolerance is
    fmi2Error naming it (as a NaN start time is); a valid one is accepted and said once (info) not
    to be used, naming solver.dt and contact.event_tolerance."""
    assert host["tol_bad"] == [3, 3, 3, 3], host["tol_bad_log"]
    errors = [m for s, m in host["tol_bad_log"] if s == 3]
    assert len(errors) == 4, host["tol_bad_log"]
    for value, text in zip(("nan", "-1.0", "0.0", "inf"), errors):
        assert f"tolerance = {value} (toleranceDefined): must be a finite number > 0" in text, text
    assert host["tol_good"] == [0, 0]
    said = [m for s, m in host["tol_good_log"] if "tolerance = 1e-06 is not used" in m]
    assert len(said) == 1 and "solver.dt" in said[0] and "contact.event_tolerance" in said[0], host["tol_good_log"]
    assert host["tol_steps"] == [0, 0]


def test_stop_time_belongs_to_the_instance_not_to_its_state(host):
    """A state saved at 1 ms under stopTime = 3 ms: restored into an instance without stopTime it steps
    on past 3 ms; into one with stopTime = 2 ms its steps past 2 ms are fmi2Error naming that
    stopTime (docs/fmu.md, "State": a continuation with a later stopTime, fmusim's
    --initial-fmu-state-file, is not held to the saved one)."""
    assert host["no_stop"] == [0] * 30, host["no_stop_log"]
    assert host["stop_002"] == [0] * 10 + [3] * 20
    assert "past stopTime = 0.002 s" in host["stop_002_log"][0], host["stop_002_log"]


def test_refusals_are_worded_right(host):
    assert host["get_integer"] == 3 and host["deserialise"] == 3
    text = " ".join(m for s, m in host["words_log"])
    assert "cannot get an Integer through value reference" in text, text
    assert "the FMU state cannot be deserialised (11 bytes are not a serialised CableCasing FMU state" in text, text
    assert "not an npz archive" in text and "allow_pickle" not in text, text  # (numpy's advice is not ours)


def test_every_bounded_number_parameter_has_its_bounds_in_the_model_description(fmu):
    """min and max on every number parameter the schema bounds (solver.dt as scenario.dt); a key the
    schema leaves unbounded (a harmonic excitation's phase, rad) has neither (docs/fmu.md, Build)."""
    from fmpy import read_model_description

    seen = set()
    for v in read_model_description(str(fmu)).modelVariables:
        if v.causality != "parameter" or v.type not in ("Real", "Integer"):
            continue
        lo, hi = value_range("scenario.dt" if v.name == "solver.dt" else v.name)
        if v.type == "Real":
            assert (v.min is None, v.max is None) == (lo is None, hi is None), (v.name, v.min, v.max, lo, hi)
        else:  # (an Integer is also bounded by FMI's 32 bits)
            assert v.min is not None and v.max is not None, v.name
        if v.min is None:
            seen.add(v.name)
    assert seen == {"scenario.excitation.cable_axial.phase"}
