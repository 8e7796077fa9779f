"""A Python host of CableCasing FMUs that a test talks to, one request at a time, in a process of its
own (fmpy's FMU2Slave): so a crash of the FMU is a dead host the test sees (its exit status, a
signal), not the end of the test run, and many cases share one process.

    python tests/fmu/fmu_probe.py [FOLDER] # requests on stdin, one JSON object a line; answers on stdout

FOLDER: where fmpy unpacks the FMUs (its extract() makes a new temporary folder it never removes,
~12 MB: under the test's tmp_path, which pytest prunes, a test run leaks none, as fmu_driver.py).

Requests (``op`` and its arguments); every answer is one JSON line, ``{"ok": true, ...}``, or
``{"ok": false, "error": ...}`` for a request the host itself could not serve:

* ``instantiate`` name, fmu, logging (default true): fmi2Instantiate, the instance kept by name;
* ``initialize`` name, params {variable: value}, start (s), stop (s or null), kinds {variable:
  type}: fmi2SetupExperiment, EnterInitializationMode, one fmi2Set<type> per parameter (its own
  type, or the one ``kinds`` gives), ExitInitializationMode; answers the status of each set
  (``set``, in order) and of the exit (``init``);
* ``step`` name, inputs {variable: value} (set once before the first step), h (s), n: n doSteps
  from the instance's time; answers their statuses and the outputs named in ``outputs`` after them;
* ``free`` name: fmi2Terminate and fmi2FreeInstance;
* ``compile``: numba compiles a kernel of the FMU's model code (cablecasing_core's, as imported by
  the FMU) for argument types it has not seen, then a function of the host's own: what a model
  that needs machine code the cache lacks makes numba do;
* ``case`` fmu, params, inputs, h, n, start, stop, kinds: instantiate, initialize, step, free in one
  request (a fuzz case): answers the statuses ``set``, ``init``, ``steps``;
* ``log``: the messages logged since the last ``log`` as [instance, status, message], and clears them.

FMI status codes: 0 OK, 1 warning, 2 discard, 3 error, 4 fatal. This module does not import
cablecasing_core: the FMU loads its own copy.
"""

from __future__ import annotations

import json
import sys
from ctypes import byref

import numpy as np

LOG = []
DTYPES = iter([np.float32, np.int32, np.int16, np.uint32, np.uint16])  # (argument types numba has not seen)


def _callbacks():
    from fmpy import calloc, free
    from fmpy.fmi2 import (
        fmi2CallbackAllocateMemoryTYPE,
        fmi2CallbackFreeMemoryTYPE,
        fmi2CallbackFunctions,
        fmi2CallbackLoggerTYPE,
    )
    from fmpy.logging import addLoggerProxy

    def logger(env, instance, status, category, message):
        LOG.append(
            [instance.decode("utf-8", "replace") if instance else "", int(status), message.decode("utf-8", "replace")]
        )

    cb = fmi2CallbackFunctions()
    cb.logger = fmi2CallbackLoggerTYPE(logger)
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    addLoggerProxy(byref(cb))  # (formats the message as printf would: the FMU escapes its '%' signs)
    return cb


CALLBACKS = None
FMUS = {}  # path -> (model description, unzip folder, {name: variable})
INSTANCES = {}  # name -> [FMU2Slave, variables, time]


def status_of(f, *args):
    """The status of an FMI call (fmpy raises for anything worse than fmi2Warning)."""
    from fmpy.fmi1 import FMICallException

    try:
        f(*args)
        return 0
    except FMICallException as exc:
        return int(str(exc).split("status ")[1].split()[0])


def _fmu(path):
    if path not in FMUS:
        from fmpy import extract, read_model_description

        md = read_model_description(path)
        FMUS[path] = (md, extract(path), {v.name: v for v in md.modelVariables})
    return FMUS[path]


def instantiate(name, fmu, logging=True):
    global CALLBACKS
    from fmpy.fmi2 import FMU2Slave

    md, unzip, var = _fmu(fmu)
    CALLBACKS = CALLBACKS or _callbacks()
    slave = FMU2Slave(
        guid=md.guid, unzipDirectory=unzip, modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name
    )
    slave.instantiate(callbacks=CALLBACKS, loggingOn=logging)
    INSTANCES[name] = [slave, var, 0.0]
    return {}


def _set(slave, var, name, value, kind=None):
    """fmi2Set<kind> (default: the variable's type) of one variable; a Boolean is passed as the int
    given (fmi2Boolean is an int: 2 is no fmi2True), a String as UTF-8."""
    from fmpy.fmi2 import fmi2Boolean, fmi2Integer, fmi2Real, fmi2String, fmi2ValueReference

    kind = kind or var[name].type
    ctype, setter = {
        "Real": (fmi2Real, slave.fmi2SetReal),
        "Integer": (fmi2Integer, slave.fmi2SetInteger),
        "Boolean": (fmi2Boolean, slave.fmi2SetBoolean),
        "String": (fmi2String, slave.fmi2SetString),
    }[kind]
    value = value.encode("utf-8") if kind == "String" else float(value) if kind == "Real" else int(value)
    vr = (fmi2ValueReference * 1)(var[name].valueReference)
    return status_of(setter, slave.component, vr, 1, (ctype * 1)(value))


def initialize(name, params=None, start=0.0, stop=None, kinds=None):
    """... and ``kinds`` {variable: type}: set those through another fmi2Set<type> than theirs."""
    slave, var, _ = INSTANCES[name]
    slave.setupExperiment(startTime=start, stopTime=stop)
    slave.enterInitializationMode()
    sets = [_set(slave, var, k, v, (kinds or {}).get(k)) for k, v in (params or {}).items()]
    INSTANCES[name][2] = start
    return {"set": sets, "init": status_of(slave.exitInitializationMode)}


def step(name, inputs=None, h=1e-4, n=1, outputs=()):
    slave, var, t = INSTANCES[name]
    for k, v in (inputs or {}).items():
        slave.setReal([var[k].valueReference], [float(v)])
    statuses = []
    for _ in range(n):
        s = status_of(slave.doStep, t, h)
        statuses.append(s)
        if s > 1:  # (a refused step: the master does not go on with it)
            break
        t += h
    INSTANCES[name][2] = t
    out = slave.getReal([var[o].valueReference for o in outputs]) if outputs and statuses[-1] <= 1 else []
    return {"steps": statuses, "outputs": list(out)}


def free(name):
    slave, _, _ = INSTANCES.pop(name)
    status_of(slave.terminate)
    slave.freeInstance()
    return {}


def compile_kernels():
    """numba compiles the model's accept_rows for a dtype it has not seen, then a host function."""
    import numba

    kernel = sys.modules["cablecasing_core.timedomain.kernels._quintic_support_motion"].accept_rows
    dtype = next(DTYPES)
    kernel(np.zeros((5, 2), dtype), np.zeros((6, 2), dtype), np.zeros(2, dtype), 0.0)

    @numba.njit
    def hosts_own(x):
        return x + 1

    hosts_own(1)
    return {"dtype": np.dtype(dtype).name}


def case(fmu, params=None, inputs=None, h=1e-4, n=2, start=0.0, stop=None, kinds=None):
    instantiate("case", fmu, logging=False)
    res = initialize("case", params, start, stop, kinds)
    res.update(step("case", inputs, h, n) if res["init"] <= 1 else {"steps": []})
    free("case")
    return res


def take_log():
    out = list(LOG)
    LOG.clear()
    return {"log": out}


OPS = {
    "instantiate": instantiate,
    "initialize": initialize,
    "step": step,
    "free": free,
    "compile": compile_kernels,
    "case": case,
    "log": take_log,
}


def main():
    if len(sys.argv) > 1:
        import tempfile

        tempfile.tempdir = sys.argv[1]
    for line in sys.stdin:
        request = json.loads(line)
        op = request.pop("op")
        try:
            answer = {"ok": True, **OPS[op](**request)}
        except Exception as exc:  # noqa: BLE001  (the host's own failure: said to the test, the host goes on)
            answer = {"ok": False, "error": f"{type(exc).__name__}: {exc}"}
        sys.stdout.write(json.dumps(answer) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
