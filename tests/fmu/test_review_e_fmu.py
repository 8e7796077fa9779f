"""What an integrator's review of the FMU found (docs/fmu.md): paths with non-ASCII characters in
C hosts (the unpack folder, model_file), a model_file that gives no model named as model_file,
the random excitation kept across fmi2SetFMUstate, a freed instance freed at once, a model too
large for the machine's memory refused, an overflowing velocity or acceleration input named, the
model's warnings once when outputs are read in Initialization Mode, fmi2SetDebugLogging's
categories and the hints of the word parameters' NULL and non-UTF-8 values.

The fmpy cases run in one fresh process (tests/fmu/fmu_driver.py's Instance, the log captured);
the C hosts (fmusim, the FMU Compliance Checker) in the plain environment (test_hosts.py)."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.slow  # the FMU in fresh processes

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]


def read_csv(path):
    with open(path, encoding="utf-8") as f:
        names = [c.strip('"') for c in f.readline().strip().split(",")]
    return names, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


# The host: one process, each case its own instance; prints {case: ...} as JSON.
HOST = r"""
import gc, json, sys, weakref
import numpy as np
sys.path.insert(0, sys.argv[2])
from fmu_driver import INPUTS, Instance
from fmpy.fmi2 import fmi2String, fmi2ValueReference

fmu, folder = sys.argv[1], sys.argv[3]
res = {}
zero = np.zeros(len(INPUTS))

def log(inst, least=0):
    out = [m for s, m in inst.log if s >= least]
    inst.log.clear()
    return out

def fresh(name, params, before_exit=None, logging=True):
    inst = Instance(fmu, name=name, initialize=False, logging=logging)
    inst.fmu.setupExperiment(startTime=0.0)
    inst.fmu.enterInitializationMode()
    status = inst.set(params)
    if before_exit:
        status = max(status, before_exit(inst))
    return inst, max(status, Instance.call(inst.fmu.exitInitializationMode))

def set_raw_string(inst, name, raw):
    vr = (fmi2ValueReference * 1)(inst.var[name].valueReference)
    return Instance.call(inst.fmu.fmi2SetString, inst.fmu.component, vr, 1, (fmi2String * 1)(raw))

# --- scenario.drive across fmi2SetFMUstate: the random record's blocks (RandomRecord.even, ~30 ms
# each) are computed at initialisation and not again after a restore; the restored run equals the
# uninterrupted one to the bit
inst, res["drive_init"] = fresh("drive", {"scenario.drive": True})
ref, _ = fresh("drive-ref", {"scenario.drive": True})
records = sys.modules["cablecasing_core.timedomain.random_record"].RandomRecord
computed, even = [0], records.even
def counted(self, *args, **kwargs):
    computed[0] += 1
    return even(self, *args, **kwargs)
records.even = counted
fz = ["casing.B.Fz"]
for k in range(3):
    inst.step(zero, 1e-4), ref.step(zero, 1e-4)
got, want = [], []
for k in range(5):  # a master that rolls back and retries each step
    state = inst.fmu.getFMUstate()
    inst.step(zero, 1e-4)
    inst.t -= 1e-4
    inst.fmu.setFMUstate(state)
    inst.fmu.freeFMUstate(state)
    inst.step(zero, 1e-4), ref.step(zero, 1e-4)
    got.append(float(inst.get(fz)[0])), want.append(float(ref.get(fz)[0]))
res["drive_blocks_computed"] = computed[0]
res["drive_got"], res["drive_want"] = got, want
records.even = even
inst.free(), ref.free()

# --- fmi2FreeInstance frees the slave and its engine at once (the cyclic collector off)
gc.disable()
inst = Instance(fmu, name="free", params={"scenario.drive": True})
inst.step(zero, 1e-4)
slaves = [o for o in gc.get_objects() if type(o).__name__ == "CableCasing" and getattr(o, "_engine", None)]
res["free_slaves"] = len(slaves)
slave, engine = weakref.ref(slaves[0]), weakref.ref(slaves[0]._engine)
del slaves
inst.free()
res["free_slave_alive"], res["free_engine_alive"] = slave() is not None, engine() is not None
gc.enable()

# --- a model larger than the memory available (the FMU's own copy of the core told it has 100 MB)
files = sys.modules["cablecasing_core.files"]
available = files.memory_available
files.memory_available = lambda: 10**8
inst, res["memory"] = fresh("memory", {"geometry.n_elements": 300})
res["memory_log"] = log(inst, 3)
res["memory_step"] = inst.step(zero, 1e-4)
inst.fmu.freeInstance()
files.memory_available = available

# --- overflowing velocity and acceleration inputs: discarded, the input named
inst, _ = fresh("overflow", {})
for name in ("casing.A.vz", "casing.A.az"):
    for value in (1e300, 1e160):
        row = zero.copy()
        row[INPUTS.index(name)] = value
        log(inst)
        res[f"overflow {name} {value!r}"] = [inst.step(row, 1e-4)] + log(inst)
inst.fmu.freeInstance()

# --- model_file without [geometry] in a folder with non-ASCII characters; a file whose reading
# fails unexpectedly (as a path the file system's encoding cannot take did in a C host)
empty = folder + "/d\u00fcn \u00ef/empty.toml"
inst, res["empty"] = fresh("empty", {"model_file": empty})
res["empty_log"], res["empty_path"] = log(inst, 3), empty
inst.fmu.freeInstance()
core = sys.modules["cablecasing_core"]
load = core.load_model
def failing(path=None, *args, **kwargs):
    if path and str(path).endswith("odd.toml"):
        raise UnicodeEncodeError("ascii", str(path), 0, 1, "ordinal not in range(128)")
    return load(path, *args, **kwargs)
core.load_model = failing
odd = folder + "/odd.toml"
res["odd_get"] = []
def read_e(inst):
    got = []
    status = Instance.call(lambda: got.append(inst.fmu.getReal([inst.var["casing.E"].valueReference])))
    res["odd_get"] = [status] + [float(x) for x in got[0]] if got else [status]
    return status
inst, res["odd"] = fresh("odd", {"model_file": odd}, before_exit=read_e)
res["odd_log"], res["odd_path"] = log(inst, 3), odd
inst.fmu.freeInstance()
core.load_model = load

# --- the model's warnings once when the master reads outputs in Initialization Mode
inst, res["warned"] = fresh("warned", {"loads.gravity.z": -10000.0}, before_exit=lambda i: (i.get(fz), 0)[1])
res["warned_log"] = log(inst, 1)
inst.free()

# --- fmi2SetDebugLogging's categories
inst = Instance(fmu, name="logging", logging=False, initialize=False)
def debug(on, names):
    arr = (fmi2String * len(names))(*[n.encode() for n in names])
    return Instance.call(inst.fmu.fmi2SetDebugLogging, inst.fmu.component, on, len(names), arr)
res["debug_unknown"] = [debug(1, ["noSuchCategory"])] + log(inst)
res["debug_error_only"] = debug(1, ["logStatusError"])
inst.fmu.setupExperiment(startTime=0.0)
inst.fmu.enterInitializationMode()
inst.set({"scenario.drive": True})
inst.fmu.exitInitializationMode()
res["debug_error_only_log"] = log(inst)
res["debug_all"] = debug(1, ["logAll"])
inst.step(zero, 1e-4)
inst.fmu.terminate()
res["debug_all_log"] = log(inst)
inst.fmu.freeInstance()

# --- NULL and non-UTF-8 values of a word parameter
inst = Instance(fmu, name="words", initialize=False)
inst.fmu.setupExperiment(startTime=0.0)
inst.fmu.enterInitializationMode()
log(inst)
res["word_null"] = [set_raw_string(inst, "casing.supports.A", None)] + log(inst)
res["word_bytes"] = [set_raw_string(inst, "casing.supports.A", b"\xff\xfe")] + log(inst)
inst.fmu.freeInstance()
print(json.dumps(res))
"""


@pytest.fixture(scope="module")
def host(fmu, tmp_path_factory):
    folder = tmp_path_factory.mktemp("review_e")
    (folder / "d\u00fcn \u00ef").mkdir()
    (folder / "d\u00fcn \u00ef" / "empty.toml").write_text("")
    (folder / "odd.toml").write_text((ROOT / "examples" / "installation.toml").read_text())
    proc = subprocess.run(
        [sys.executable, "-c", HOST, str(fmu), str(HERE), str(folder)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_a_restored_state_keeps_the_random_excitation_computed_ahead(host):
    """Five get/step/set/step cycles with scenario.drive compute no block of the random record (each
    restore computed them all again, ~30 ms per block: the next doStep took 28 ms, not 0.13 ms), and
    the retried steps equal an uninterrupted run to the bit."""
    assert host["drive_init"] == 0
    assert host["drive_blocks_computed"] == 0
    assert host["drive_got"] == host["drive_want"] and any(host["drive_want"])


def test_a_freed_instance_is_freed_at_once(host):
    """After fmi2FreeInstance the slave and its engine are gone without the cyclic garbage
    collector (they stayed in a reference cycle: 237 MB -> 590 MB over 200 instances)."""
    assert host["free_slaves"] == 1
    assert not host["free_slave_alive"] and not host["free_engine_alive"]


def test_a_model_larger_than_the_memory_is_an_error_naming_the_elements(host):
    """The core's memory check (model/limits.py) before the engine is built: fmi2Error naming
    geometry.n_elements and the figures, and steps refused (n_elements = 2000 took 50 s and 12.3 GB
    in fmi2ExitInitializationMode)."""
    assert host["memory"] == 3 and host["memory_step"] == 3
    (msg,) = host["memory_log"]
    assert msg.startswith("invalid parameter geometry.n_elements = 300: is too many for this machine"), msg
    assert "0.313 GB for its matrices, more than the 0.08 GB of memory it may use" in msg, msg


@pytest.mark.parametrize("name", ["casing.A.vz", "casing.A.az"])
@pytest.mark.parametrize("value", [1e300, 1e160])
def test_an_overflowing_velocity_or_acceleration_input_is_named(host, name, value):
    """fmi2Discard naming the input and its value, in whole sentences (the message stopped at "the
    step is unstable or the input is")."""
    status, *log = host[f"overflow {name} {value!r}"]
    assert status == 2
    (msg,) = log
    unit = "m/s" if name.endswith("vz") else "m/s2"
    assert msg.startswith(f"input {name} = {value!r} {unit} at t = 0 s"), msg
    assert "too large for double precision" in msg and msg.endswith("step discarded (state rolled back)"), msg
    assert "the input is)" not in msg


def test_a_model_file_without_geometry_names_model_file_and_the_path(host):
    assert host["empty"] == 3
    (msg,) = host["empty_log"]
    assert msg == (
        f"invalid parameter model_file = {host['empty_path']!r}: its [geometry] table is required; the file has none"
    )


def test_a_model_file_that_fails_unexpectedly_is_an_error_naming_it(host):
    """A failure of reading the file that is not the core's (here a UnicodeEncodeError, as a path
    under an ASCII file-system encoding raised): fmi2Error naming model_file and the path, no internal
    error or traceback; a getter in Initialization Mode still answers (the base model's value)."""
    assert host["odd"] == 3
    assert host["odd_get"][0] == 0 and host["odd_get"][1] > 0
    (msg,) = host["odd_log"]
    assert msg.startswith(f"invalid parameter model_file = {host['odd_path']!r}: cannot be read: UnicodeEncodeError")
    assert "Traceback" not in msg and "internal error" not in msg


def test_model_warnings_once_when_outputs_are_read_in_initialization_mode(host):
    assert host["warned"] == 0
    warned = [m for m in host["warned_log"] if "static state moves it" in m or "1.02e+03 g" in m]
    assert len(warned) == 3 and len(set(warned)) == 3, host["warned_log"]


def test_set_debug_logging_takes_its_categories(host):
    """An unknown category is fmi2Error naming it; logStatusError alone does not switch the
    informational messages on (logAll does)."""
    status, msg = host["debug_unknown"]
    assert status == 3 and "'noSuchCategory' is not one of this FMU's" in msg
    assert host["debug_error_only"] == 0 and host["debug_error_only_log"] == []
    assert host["debug_all"] == 0 and any("real time: the longest doStep call" in m for m in host["debug_all_log"])


def test_null_and_non_utf8_word_parameters_give_the_word_hints(host):
    for key in ("word_null", "word_bytes"):
        status, msg = host[key]
        assert status == 3 and msg.startswith("casing.supports.A = "), msg
        assert "'clamped'" in msg and "empty string" not in msg and "path" not in msg, msg


# ---------------------------------------------------------------------------------- C hosts
def test_fmusim_runs_a_model_file_under_a_non_ascii_path(c_hosts, fmu, tmp_path, plain_env):
    """fmusim in the plain environment (the "C" locale) with model_file "ünï/mödel file.toml" (a copy
    of examples/installation.toml, driven by its scenario), relative to its working folder: it runs
    and exits with 0, and the log names the file (it was an internal error, 'ascii' codec, with a traceback, exit 3)."""
    folder = tmp_path / "\u00fcn\u00ef"
    folder.mkdir()
    model = folder / "m\u00f6del file.toml"
    shutil.copy(ROOT / "examples" / "installation.toml", model)
    log, out = tmp_path / "fs.log", tmp_path / "out.csv"
    proc = subprocess.run(
        [str(c_hosts / "fmusim"), "--interface-type", "cs", "--stop-time", "0.002", "--output-interval", "1e-4",
         "--start-value", "model_file", "\u00fcn\u00ef/m\u00f6del file.toml",
         "--start-value", "scenario.drive", "true", "--logging-on",
         "--log-file", str(log), "--output-file", str(out), str(fmu)],
        env=plain_env, cwd=tmp_path, capture_output=True, timeout=300,
    )  # fmt: skip
    text = log.read_bytes().decode("utf-8", "replace")
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stderr[-2000:]}\n{text[-3000:]}"
    assert f"model_file: {model}" in text, text[-3000:]
    assert "internal error" not in text and "Traceback" not in text
    names, data = read_csv(out)
    assert len(data) == 21 and abs(data[-1, names.index("casing.B.Fz")]) > 0


def test_the_compliance_checker_unpacks_into_a_non_ascii_folder(c_hosts, fmu, tmp_path, plain_env):
    """fmuCheck -t with an unpack folder "tmp ünï" in the plain environment: the FMU instantiates
    and simulates, 0 errors (fmi2Instantiate returned NULL: 'ascii' codec can't encode '\\xfc')."""
    unpack = tmp_path / "tmp \u00fcn\u00ef"
    unpack.mkdir()
    log = tmp_path / "chk.log"
    proc = subprocess.run(
        [str(c_hosts / "fmuCheck.linux64"), "-h", "1e-4", "-s", "0.002", "-l", "3", "-t", str(unpack),
         "-o", str(tmp_path / "chk.csv"), "-e", str(log), str(fmu)],
        env=plain_env, capture_output=True, timeout=300,
    )  # fmt: skip
    text = log.read_bytes().decode("utf-8", "replace")
    assert proc.returncode == 0, f"exit {proc.returncode}\n{text[-3000:]}"
    assert "0 Error(s)" in text and "cannot load its bridge" not in text, text[-3000:]
