"""Run dist/CableCasing.fmu in a fresh Python process (all FMUs of a process share its interpreter
and module cache, so each test scenario gets its own process).

This module does not import cablecasing_core: the FMU must load its own bundled copy. The test
process prepares the input table (n, 36) - displacement, velocity, acceleration of the 12 support
channels at each communication point - and reads back the outputs.

    python tests/fmu/fmu_driver.py SCENARIO job.json      # writes job["out"] (npz)

From a test: ``result = fmu_driver.run(tmp_path, "run", fmu=..., inputs=table, params={...})``.

This module is over 400 lines because it is the one driver script of every scenario the FMU tests
run in fresh processes.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from ctypes import byref
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CHANNELS = [f"{b}.{s}.{d}" for b in ("casing", "cable") for s in "AB" for d in "xyz"]
INPUTS = [f"{b}.{s}.{k}{d}" for k in ("", "v", "a") for b, s, d in (c.split(".") for c in CHANNELS)]
STATUS = {0: "ok", 1: "warning", 2: "discard", 3: "error", 4: "fatal"}


# ------------------------------------------------------------------------------ called by the tests
def run(tmp_path, scenario, fmu, inputs=None, timeout=600, cwd=None, env=None, prefix=(), **args):
    """Run ``scenario`` of this driver in a fresh process; returns the npz content as a dict.

    ``inputs``: array (n, 36) in the order of :data:`INPUTS` (m, m/s, m/s2) at t = k h, or in the
    order of ``input_names`` (a job argument: an FMU built for a model file has more inputs).
    ``prefix``: the command that starts the process (the ``unprivileged`` fixture's)."""
    tmp_path = Path(tmp_path)
    n = len(list(tmp_path.glob("job*.json")))
    job = dict(args, fmu=str(fmu), out=str(tmp_path / f"out{n}.npz"))
    if inputs is not None:
        np.save(tmp_path / f"inputs{n}.npy", np.asarray(inputs, dtype=float))
        job["inputs"] = str(tmp_path / f"inputs{n}.npy")
    path = tmp_path / f"job{n}.json"
    path.write_text(json.dumps(job))
    proc = subprocess.run(
        [*prefix, sys.executable, str(Path(__file__)), scenario, str(path)],
        capture_output=True,
        text=True,
        timeout=timeout,
        cwd=cwd,
        env=env,
    )
    if proc.returncode != 0:
        raise RuntimeError(f"fmu_driver {scenario} failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
    with np.load(job["out"], allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


# ------------------------------------------------------------------------------ fmpy instance


def pool_host_command(fmu, folder, n, h, reps, values, parameter="contact.friction"):
    """The command that runs tests/fmu/pool_host.c on ``fmu``: one instance per value of ``values`` of
    the real ``parameter``, ``n`` steps of ``h`` (s) each, ``reps`` times (compiled and unpacked into
    ``folder``); None without a C compiler on Linux."""
    import shutil

    import fmpy
    from fmpy import extract, read_model_description

    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None or not sys.platform.startswith("linux"):
        return None
    exe = folder / "pool_host"
    source = Path(__file__).with_name("pool_host.c")
    inc = Path(fmpy.__file__).parent / "c-code"
    cmd = [compiler, "-O1", f"-I{inc}", "-o", str(exe), str(source), "-ldl", "-lpthread", "-lm"]
    subprocess.run(cmd, check=True, capture_output=True)
    unzip = Path(extract(str(fmu), unzipdir=folder / "unzip"))
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    ports = ["casing.A.z", "casing.A.vz", "casing.A.az", "casing.B.Fz", parameter]
    return (
        [str(exe), str(unzip / "binaries" / "linux64" / "CableCasing.so"), md.guid, (unzip / "resources").as_uri()]
        + [str(n), repr(h), str(reps)]
        + [str(vr[p]) for p in ports]
        + [repr(float(x)) for x in values]
    )


class Instance:
    """One FMU instance through fmpy's FMU2Slave, with the log captured."""

    unzip_dirs = {}

    def __init__(
        self, fmu, name="cc", params=None, start_time=0.0, logging=True, unzip=None, initialize=True, inputs=None
    ):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave, fmi2Real, fmi2ValueReference

        self.md = read_model_description(fmu)
        self.var = {v.name: v for v in self.md.modelVariables}
        if unzip is None:
            unzip = Instance.unzip_dirs.setdefault(fmu, extract(fmu))
        self.log = []
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=unzip,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(callbacks=self._callbacks(), loggingOn=logging)
        self.t = start_time
        inputs = list(inputs or INPUTS)  # the input table's columns
        self.in_vr = [self.var[n].valueReference for n in inputs]
        # the inputs go in as fmpy's own simulate_fmu sets them (simulation.Input.apply): one
        # fmi2SetReal on ctypes arrays made once, not fmpy's setReal(list), whose conversion of 36
        # values to new ctypes arrays costs ~15 µs per step by itself (docs/performance.md, FMU)
        self._in_vr = (fmi2ValueReference * len(inputs))(*self.in_vr)
        self._in_values = (fmi2Real * len(inputs))()
        self._in_view = np.ctypeslib.as_array(self._in_values)
        self._plans = {}
        if not initialize:
            return
        self.fmu.setupExperiment(startTime=start_time)
        self.fmu.enterInitializationMode()
        self.status_init = self.set(params or {})
        self.status_init = max(self.status_init, self.call(self.fmu.exitInitializationMode))

    def _callbacks(self):
        from fmpy import calloc, free
        from fmpy.fmi2 import (
            fmi2CallbackAllocateMemoryTYPE,
            fmi2CallbackFreeMemoryTYPE,
            fmi2CallbackFunctions,
            fmi2CallbackLoggerTYPE,
        )
        from fmpy.logging import addLoggerProxy

        def logger(env, instance, status, category, message):
            self.log.append((int(status), message.decode("utf-8", "replace") if message else ""))

        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(logger)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(cb))
        self._cb = cb  # keep the C callbacks alive
        return cb

    @staticmethod
    def call(f, *a):
        """Status of an FMI call (fmpy raises on anything worse than fmi2Warning)."""
        from fmpy.fmi1 import FMICallException

        try:
            f(*a)
            return 0
        except FMICallException as exc:
            return int(str(exc).split("status ")[1].split()[0])

    def set(self, values):
        status = 0
        for name, value in values.items():
            v = self.var[name]
            vr = [v.valueReference]
            setter = {
                "Real": self.fmu.setReal,
                "Integer": self.fmu.setInteger,
                "Boolean": self.fmu.setBoolean,
                "String": self.fmu.setString,
            }[v.type]
            status = max(status, self.call(setter, vr, [value]))
        return status

    def step(self, row, h):
        from fmpy.fmi2 import fmi2True

        self._in_view[:] = row
        self.fmu.fmi2SetReal(self.fmu.component, self._in_vr, len(self.in_vr), self._in_values)
        status = self.call(self.fmu.fmi2DoStep, self.fmu.component, self.t, h, fmi2True)
        if status == 0:
            self.t += h
        return status

    def get(self, names):
        """Outputs by name: one fmi2GetReal and one fmi2GetInteger call, as a master would."""
        key = tuple(names)
        if key not in self._plans:  # ctypes arrays made once per list of names (as fmpy's Recorder)
            from fmpy.fmi2 import fmi2Integer, fmi2Real, fmi2ValueReference

            reals = [i for i, n in enumerate(names) if self.var[n].type == "Real"]
            ints = [i for i, n in enumerate(names) if self.var[n].type == "Integer"]
            self._plans[key] = plan = []
            for idx, ctype, getter in (
                (reals, fmi2Real, self.fmu.fmi2GetReal),
                (ints, fmi2Integer, self.fmu.fmi2GetInteger),
            ):
                if idx:
                    vr = (fmi2ValueReference * len(idx))(*(self.var[names[i]].valueReference for i in idx))
                    values = (ctype * len(idx))()
                    plan.append((idx, getter, vr, values, np.ctypeslib.as_array(values)))
        out = np.empty(len(names))
        for idx, getter, vr, values, view in self._plans[key]:
            getter(self.fmu.component, vr, len(idx), values)
            out[idx] = view
        return out

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def simulate(inst, table, h, outputs):
    """Step through the input table; outputs after each step and the status of each step."""
    out = np.zeros((len(table), len(outputs)))
    status = np.zeros(len(table), int)
    for k, row in enumerate(table):
        status[k] = inst.step(row, h)
        out[k] = inst.get(outputs)
    return out, status


# ------------------------------------------------------------------------------ scenarios
def scenario_run(job, table):
    """Instantiate (parameters ``params``), step through the table; outputs after each step.
    Also times instantiation up to the end of the first step (unzip excluded) and the rest."""
    from fmpy import extract

    Instance.unzip_dirs.setdefault(job["fmu"], extract(job["fmu"]))
    t0 = time.perf_counter()
    inst = Instance(job["fmu"], params=job.get("params"), inputs=job.get("input_names"))
    out = np.zeros((len(table), len(job["outputs"])))
    status = np.zeros(len(table), int)
    if len(table):
        status[0] = inst.step(table[0], job["h"])
        out[0] = inst.get(job["outputs"])
    t1 = time.perf_counter()
    out[1:], status[1:] = simulate(inst, table[1:], job["h"], job["outputs"])
    t2 = time.perf_counter()
    inst.free()
    return dict(
        out=out, status=status, init_status=inst.status_init, log=_log(inst.log), first_step_s=t1 - t0, run_s=t2 - t1
    )


def scenario_steps(job, table):
    """Varying communication steps job["steps"] (s), one input row per step."""
    inst = Instance(job["fmu"], params=job.get("params"), inputs=job.get("input_names"))
    out = np.zeros((len(table), len(job["outputs"])))
    status = np.zeros(len(table), int)
    for k, (row, h) in enumerate(zip(table, job["steps"])):
        status[k] = inst.step(row, h)
        out[k] = inst.get(job["outputs"])
    return dict(out=out, status=status, log=_log(inst.log))


def scenario_clock(job, table):
    """A master's own clock: doStep from times[k] over times[k+1] - times[k] (s, as the master
    computes them, rounding and all), from the start time times[0], row k of the table before each."""
    times = job["times"]
    inst = Instance(job["fmu"], params=job.get("params"), inputs=job.get("input_names"), start_time=times[0])
    out = np.zeros((len(table), len(job["outputs"])))
    status = np.zeros(len(table), int)
    for k, row in enumerate(table):
        inst.t = times[k]
        status[k] = inst.step(row, times[k + 1] - times[k])
        out[k] = inst.get(job["outputs"])
    return dict(out=out, status=status, log=_log(inst.log))


def scenario_state(job, table):
    """Get the state half way; continue (A); set the state and continue again (B); serialise it and
    continue in a new instance (C) and in one created with other parameters (E); reset the first
    instance and run everything again (D)."""
    h, names = job["h"], job["outputs"]
    inst = Instance(job["fmu"], name="first", params=job.get("params"))
    n = len(table) // 2
    first, _ = simulate(inst, table[:n], h, names)
    state = inst.fmu.getFMUstate()
    blob = inst.fmu.serializeFMUstate(state)
    t_mid = inst.t
    a, sa = simulate(inst, table[n:], h, names)
    inst.fmu.setFMUstate(state)
    inst.t = t_mid
    b, sb = simulate(inst, table[n:], h, names)
    inst.fmu.freeFMUstate(state)
    other = Instance(job["fmu"], name="second", params=job.get("params"))
    restored = other.fmu.deSerializeFMUstate(blob)
    other.fmu.setFMUstate(restored)
    other.t = t_mid
    c, sc = simulate(other, table[n:], h, names)
    # an instance built with other parameters (other mesh, too) takes the state's parameters along
    third = Instance(job["fmu"], name="third", params={"contact.friction": 0.5, "geometry.n_elements": 30})
    third.fmu.setFMUstate(third.fmu.deSerializeFMUstate(blob))
    third.t = t_mid
    e, se = simulate(third, table[n:], h, names)
    inst.fmu.reset()
    inst.t = 0.0
    inst.fmu.setupExperiment(startTime=0.0)
    inst.fmu.enterInitializationMode()
    inst.set(job.get("params") or {})
    inst.fmu.exitInitializationMode()
    d, sd = simulate(inst, table, h, names)
    return dict(
        first=first,
        a=a,
        b=b,
        c=c,
        d=d,
        e=e,
        status=np.concatenate([sa, sb, sc, sd, se]),
        blob_bytes=len(blob),
        log=_log(inst.log + other.log),
    )


def scenario_foreign_state(job, table):
    """A state of one FMU set into an instance of another (``fmu2``, built for another model with the
    same variables): its status and log, and the second instance's outputs over the table's second
    half after it, against those of an instance of fmu2 that never saw the state."""
    h, names = job["h"], job["outputs"]
    n = len(table) // 2
    one = Instance(job["fmu"], name="one")
    simulate(one, table[:n], h, names)
    blob = one.fmu.serializeFMUstate(one.fmu.getFMUstate())
    res = {}
    for key in ("two", "alone"):
        inst = Instance(job["fmu2"], name=key)
        simulate(inst, table[:n], h, names)
        if key == "two":
            state = inst.fmu.deSerializeFMUstate(blob)
            res["set_status"] = np.array(Instance.call(inst.fmu.setFMUstate, state))
            res["log"] = np.array(_log(inst.log) or [""])
            inst.fmu.freeFMUstate(state)
        res[key], res[f"{key}_status"] = simulate(inst, table[n:], h, names)
    return res


def scenario_two(job, table):
    """Two instances with different parameters, stepped alternately in this process; the second
    of another FMU when the job names one (``fmu2``, with its ``input_names2``, ``outputs2`` and
    its input table ``inputs2``, a .npy path, as long as ``table``)."""
    h, names = job["h"], job["outputs"]
    names2 = job.get("outputs2", names)
    table2 = np.load(job["inputs2"]) if "inputs2" in job else table
    one = Instance(job["fmu"], name="one", params=job.get("p1"))
    two = Instance(job.get("fmu2", job["fmu"]), name="two", params=job.get("p2"), inputs=job.get("input_names2"))
    o1, o2 = np.zeros((len(table), len(names))), np.zeros((len(table), len(names2)))
    for k, (row, row2) in enumerate(zip(table, table2)):
        assert one.step(row, h) == 0 and two.step(row2, h) == 0
        o1[k], o2[k] = one.get(names), two.get(names2)
    return dict(o1=o1, o2=o2)


def scenario_errors(job, table):
    """Misuse, one after the other in this process: each must give a status and a log message, and
    the process (and where sensible the instance) must go on."""
    h, names = job["h"], job["outputs"]
    res = {}
    zero = np.zeros(len(INPUTS))

    def record(key, inst, status):
        res[f"{key}_status"] = np.array(status)
        res[f"{key}_log"] = np.array(_log(inst.log))
        inst.log.clear()

    inst = Instance(job["fmu"], name="nan")
    bad = zero.copy()
    bad[INPUTS.index("casing.A.z")] = np.nan
    record("nan", inst, inst.step(bad, h))
    bad = zero.copy()
    bad[INPUTS.index("cable.B.vy")] = np.inf
    record("inf", inst, inst.step(bad, h))
    record("after_nan", inst, [inst.step(row, h) for row in table[:5]])
    res["after_nan_out"] = inst.get(names)
    record("wrong_time", inst, Instance.call(inst.fmu.doStep, inst.t + 1.0, h))
    inst.free()

    inst = Instance(job["fmu"], name="badparam", params={"casing.E": -1.0})
    record("badparam_init", inst, inst.status_init)
    record("badparam", inst, inst.step(zero, h))
    inst = Instance(job["fmu"], name="badgap", params={"cable.d": 0.005})
    record("badgap", inst, [inst.status_init, inst.step(zero, h)])
    inst = Instance(job["fmu"], name="badfile", params={"model_file": "/nonexistent/model.toml"})
    record("badfile", inst, [inst.status_init, inst.step(zero, h)])
    inst = Instance(job["fmu"], name="baddt", params={"solver.dt": -1e-5})
    record("baddt", inst, [inst.status_init, inst.step(zero, h)])
    inst = Instance(job["fmu"], name="tinydt", params={"solver.dt": 1e-12})
    record("tinydt", inst, [inst.status_init])
    inst = Instance(job["fmu"], name="coarsedrive", params={"scenario.drive": True, "solver.dt": 1e-3})
    record("coarsedrive", inst, [inst.status_init])

    inst = Instance(job["fmu"], name="blowup")
    jump = zero.copy()
    jump[INPUTS.index("cable.A.y")] = 0.05  # 50 mm in one step: far through the casing wall
    record("blowup", inst, inst.step(jump, h))
    record("after_blowup", inst, [inst.step(row, h) for row in table[:5]])
    res["after_blowup_out"] = inst.get(names)
    # the same blow-up later (inside one compiled call), asked for twice, then a step with the inputs
    # of the table: fmi2Terminated (kind 3) after each
    terminated = []
    for k, row in enumerate([jump, jump, table[-1]]):
        record(f"late_blowup{k}", inst, inst.step(row, h))
        terminated.append(inst.fmu.getBooleanStatus(3))
    res["late_blowup_terminated"] = np.array(terminated)
    res["late_blowup_t"] = np.array(inst.t)

    inst = Instance(job["fmu"], name="badstate")
    record("badstate", inst, [Instance.call(inst.fmu.deSerializeFMUstate, b"not a state at all"), inst.step(zero, h)])

    inst = Instance(job["fmu"], name="fresh", start_time=0.25)  # the process goes on
    out, status = simulate(inst, table[:5], h, names)
    record("fresh", inst, status)
    res["fresh_out"] = out
    return res


def scenario_libcosim(job, table):
    """The same run under libcosimpy (Open Simulation Platform), outputs after each step."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    h, names = job["h"], job["outputs"]
    step_ns = int(round(h * 1e9))
    ex = CosimExecution.from_step_size(step_size=step_ns)
    slave = ex.add_local_slave(CosimLocalSlave(fmu_path=job["fmu"], instance_name="cc"))
    ref = {v.name.decode(): (v.reference, v.type) for v in ex.slave_variables(slave)}
    for name, value in (job.get("params") or {}).items():
        setter = {bool: ex.boolean_initial_value, str: ex.string_initial_value, int: ex.integer_initial_value}.get(
            type(value), ex.real_initial_value
        )
        setter(slave, ref[name][0], value)
    manipulator = CosimManipulator.create_override()
    ex.add_manipulator(manipulator)
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer)
    in_refs = [ref[n][0] for n in INPUTS]
    ints = [n for n in names if n == "contact.active"]
    reals = [n for n in names if n not in ints]
    out = np.zeros((len(table), len(names)))
    ok = np.zeros(len(table), bool)
    for k, row in enumerate(table):
        manipulator.slave_real_values(slave, in_refs, [float(x) for x in row])
        ok[k] = ex.step(1)
        vals = dict(zip(reals, observer.last_real_values(slave, [ref[n][0] for n in reals])))
        vals.update(zip(ints, observer.last_integer_values(slave, [ref[n][0] for n in ints])))
        out[k] = [vals[n] for n in names]
    return dict(out=out, ok=ok)


def scenario_cache(job, table):
    """Load the FMU from a fresh unpack folder, take one step, and report what numba did: cache
    hits and misses (compilations) of every kernel of the FMU's own package, where the cache and
    the package live, and the FMU's log. With an input table (and ``params``, ``outputs``), the
    first step is the table's first row and the outputs after each of its rows are returned too
    (``out``), computed by the kernels as this process got them (compiled or loaded). With
    ``read_only_unpack``, the unpack folder is made read-only before the FMU is loaded; with
    ``tempdir``, the process's temporary folder is that one from then on."""
    import os
    import tempfile

    from fmpy import extract
    from numba.core.registry import CPUDispatcher

    unzip = extract(job["fmu"])
    if job.get("read_only_unpack"):
        for root, _, files in os.walk(unzip, topdown=False):
            for path in [os.path.join(root, name) for name in files] + [root]:
                os.chmod(path, os.stat(path).st_mode & ~0o222)
    if job.get("tempdir"):
        tempfile.tempdir = job["tempdir"]
    inst = Instance(job["fmu"], unzip=unzip, params=job.get("params"))
    rows = table if len(table) else np.zeros((1, len(INPUTS)))
    status = inst.step(rows[0], job["h"])
    out = np.zeros((0, 0))
    if job.get("outputs"):
        out = np.zeros((len(rows), len(job["outputs"])))
        out[0] = inst.get(job["outputs"])
        out[1:], steps = simulate(inst, rows[1:], job["h"], job["outputs"])
        status = max(status, int(steps.max(initial=0)))
    disp = [
        v
        for name, mod in list(sys.modules.items())
        if name.split(".")[0] == "cablecasing_core" and mod
        for v in vars(mod).values()
        if isinstance(v, CPUDispatcher)
    ]
    run_steps = next(d for d in disp if d.__name__ == "run_steps")
    return dict(
        status=status,
        hits=sum(sum(d.stats.cache_hits.values()) for d in disp),
        misses=sum(sum(d.stats.cache_misses.values()) for d in disp),
        run_steps_hits=sum(run_steps.stats.cache_hits.values()),
        cache_path=run_steps.stats.cache_path,
        package_file=sys.modules["cablecasing_core"].__file__,
        unzip=str(unzip),
        log=_log(inst.log),
        out=out,
    )


def scenario_careless(job, table):
    """What careless masters do (docs/fmu.md, "Careless masters"), each case's status and log."""
    from fmpy.fmi2 import fmi2String, fmi2ValueReference

    h, names = job["h"], job["outputs"]
    res = {}

    def record(key, inst, status):
        res[f"{key}_status"] = np.array(status)
        res[f"{key}_log"] = np.array(_log(inst.log) or [""])
        inst.log.clear()

    def set_raw_string(inst, name, raw):
        vr = (fmi2ValueReference * 1)(inst.var[name].valueReference)
        return Instance.call(inst.fmu.fmi2SetString, inst.fmu.component, vr, 1, (fmi2String * 1)(raw))

    # strings: not UTF-8, NULL; the instance goes on and initialises with the built-in model
    inst = Instance(job["fmu"], name="strings", initialize=False)
    inst.fmu.setupExperiment(startTime=0.0)
    inst.fmu.enterInitializationMode()
    record("non_utf8", inst, set_raw_string(inst, "model_file", b"/tmp/\xff\xfe-model.toml"))
    record("null_string", inst, set_raw_string(inst, "model_file", None))
    res["model_file_after"] = np.array(inst.fmu.getString([inst.var["model_file"].valueReference])[0].decode())
    record("strings_init", inst, Instance.call(inst.fmu.exitInitializationMode))
    record("strings_step", inst, inst.step(table[0], h))
    # times and steps
    record("nan_time", inst, Instance.call(inst.fmu.doStep, float("nan"), h))
    record("nan_step", inst, Instance.call(inst.fmu.doStep, inst.t, float("nan")))
    record("huge_step", inst, Instance.call(inst.fmu.doStep, inst.t, 1e12))
    record("after_refusals", inst, [inst.step(row, h) for row in table[1:4]])
    res["after_refusals_out"] = inst.get(names)
    # a failed state restore leaves the instance as it was: getters and steps work
    good = inst.fmu.getFMUstate()
    before = inst.get(names)
    import io

    z = dict(np.load(io.BytesIO(bytes(inst.fmu.serializeFMUstate(good))), allow_pickle=False))
    z["engine.casing.U"] = z["engine.casing.U"][:-1]  # a state of the wrong shape
    buf = io.BytesIO()
    np.savez(buf, **z)
    wrong = inst.fmu.deSerializeFMUstate(buf.getvalue())
    record("bad_restore", inst, Instance.call(inst.fmu.setFMUstate, wrong))
    res["after_bad_restore_out"] = inst.get(names)
    res["before_bad_restore_out"] = before
    record("after_bad_restore_step", inst, inst.step(table[4], h))
    z["engine.casing.U"] = np.load(io.BytesIO(bytes(inst.fmu.serializeFMUstate(good))))["engine.casing.U"]
    z["fmu.start_time"] = np.array(np.nan)  # a clock every later step would be checked against
    buf = io.BytesIO()
    np.savez(buf, **z)
    record("nan_clock_restore", inst, Instance.call(inst.fmu.setFMUstate, inst.fmu.deSerializeFMUstate(buf.getvalue())))
    record("after_nan_clock_step", inst, inst.step(table[5], h))
    # a step too short for Newmark to take alone (5e-4 solver.dt), then one as long as a clock's rounding
    record("short_step", inst, Instance.call(inst.fmu.doStep, inst.t, 5e-9))
    record("rounding_step", inst, Instance.call(inst.fmu.doStep, inst.t, 1e-13))
    # parameters are fixed after initialisation
    record("late_parameter", inst, inst.set({"contact.friction": 0.3}))
    record("same_parameter", inst, inst.set({"contact.friction": 0.15}))
    # calls after terminate
    inst.fmu.terminate()
    record("step_after_terminate", inst, Instance.call(inst.fmu.doStep, inst.t, h))
    record("set_after_terminate", inst, inst.set({"casing.A.z": 1e-3}))
    inst.fmu.freeInstance()

    # NaN start time; getters before initialisation (FMI 2.0, 4.2.4: not allowed, there is no value yet)
    inst = Instance(job["fmu"], name="nanstart", initialize=False)
    record("get_instantiated", inst, Instance.call(inst.fmu.getReal, [inst.var["casing.A.Fz"].valueReference]))
    record(
        "get_bool_instantiated", inst, Instance.call(inst.fmu.getBoolean, [inst.var["contact.enabled"].valueReference])
    )
    record("nan_start", inst, Instance.call(inst.fmu.setupExperiment, None, float("nan"), None))
    # a component pointer that is no instance: unmapped memory, then a freed instance (fmi2Error, no
    # crash), through the library this instance keeps loaded (fmpy unloads it with the last instance)
    import ctypes

    do_step = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_int)(
        ctypes.cast(inst.fmu.dll.fmi2DoStep, ctypes.c_void_p).value
    )
    res["bogus_component_status"] = np.array(do_step(0xDEADBEEF, 0.0, h, 1))
    other = Instance(job["fmu"], name="freed", initialize=False)
    freed = other.fmu.component
    other.fmu.freeInstance()
    res["freed_component_status"] = np.array(do_step(freed, 0.0, h, 1))
    # a freed instance's pointer after a new instance was made, which the allocator may have put at
    # the freed one's address (it did in 2 of 3 processes within 50 tries): refused, every time
    stale = []
    for _ in range(20):
        other = Instance(job["fmu"], name="freed", initialize=False)
        freed = other.fmu.component
        other.fmu.freeInstance()
        newer = Instance(job["fmu"], name="newer", initialize=False)
        newer.fmu.setupExperiment(startTime=0.0)
        newer.fmu.enterInitializationMode()
        newer.fmu.exitInitializationMode()  # a step on it would be taken
        stale.append([do_step(freed, 0.0, h, 1), newer.fmu.component == freed])
        newer.fmu.freeInstance()
    res["stale_component"] = np.array(stale)
    inst.fmu.freeInstance()
    # the state of an instance whose initialisation failed (FMI 2.0: only reset or free after that),
    # set into a good instance (made last: fmpy's logger proxy is the newest instance's)
    failed = Instance(job["fmu"], name="failed", initialize=False)
    failed.set({"contact.event_substeps": 0})
    failed.fmu.setupExperiment(startTime=0.0)
    failed.fmu.enterInitializationMode()
    res["failed_init_status"] = np.array(Instance.call(failed.fmu.exitInitializationMode))
    failed_state = failed.fmu.getFMUstate()
    good = Instance(job["fmu"], name="good")
    record("failed_state_restore", good, Instance.call(good.fmu.setFMUstate, failed_state))
    record("after_failed_state_step", good, good.step(table[0], h))
    failed.fmu.freeFMUstate(failed_state)
    # fmusim's convention for fmi2FreeFMUstate (the state where its address belongs), twice: the second
    # time it is a freed handle, refused without being read through (it crashed the host)
    state = good.fmu.getFMUstate()
    free_state = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p)(
        ctypes.cast(good.fmu.dll.fmi2FreeFMUstate, ctypes.c_void_p).value
    )
    res["quirk_free"] = np.array([free_state(good.fmu.component, state.value) for _ in range(2)])
    # two more copies of the binary (as two FMUs, or one unpacked twice), each with its first instance:
    # the two instances' handles differ, and each copy refuses the other's
    import shutil
    import tempfile

    from fmpy import extract

    folders = [tempfile.mkdtemp() for _ in range(2)]
    try:
        twins = [
            Instance(job["fmu"], name=f"twin{k}", unzip=extract(job["fmu"], unzipdir=f)) for k, f in enumerate(folders)
        ]
        setup = ctypes.CFUNCTYPE(
            ctypes.c_int, ctypes.c_void_p, ctypes.c_int, ctypes.c_double, ctypes.c_double, ctypes.c_int, ctypes.c_double
        )
        one, two = (setup(ctypes.cast(t.fmu.dll.fmi2SetupExperiment, ctypes.c_void_p).value) for t in twins)
        res["twin_handles_differ"] = np.array(twins[0].fmu.component != twins[1].fmu.component)
        res["other_copy_status"] = np.array([two(twins[0].fmu.component, 0, 0.0, 0.0, 0, 0.0),
                                             one(twins[1].fmu.component, 0, 0.0, 0.0, 0, 0.0)])  # fmt: skip
        for t in twins:
            t.fmu.freeInstance()
    finally:
        for f in folders:
            shutil.rmtree(f, ignore_errors=True)
    good.fmu.freeInstance()
    failed.fmu.freeInstance()
    return res


def scenario_phases(job, table):
    """FMU states saved before initialisation restore the phase they were saved in (FMI 2.0,
    2.1.8), and a step shorter than the engine's resolution of time moves the FMU's clock."""
    h, names, res = job["h"], job["outputs"], {}
    # saved while instantiated (the experiment set up), restored after a step: the instance is
    # instantiated again, so it sets up, initialises and steps as a new one, to the same outputs
    inst = Instance(job["fmu"], name="phases", initialize=False)
    inst.fmu.setupExperiment(startTime=0.0)
    early = inst.fmu.getFMUstate()
    inst.fmu.enterInitializationMode()
    inst.fmu.exitInitializationMode()
    res["first_step"] = np.array(inst.step(table[0], h))
    res["first_out"] = inst.get(names)
    res["restore_instantiated"] = np.array(Instance.call(inst.fmu.setFMUstate, early))
    inst.t = 0.0
    res["again"] = np.array(
        [
            Instance.call(inst.fmu.setupExperiment, None, 0.0, None),
            Instance.call(inst.fmu.enterInitializationMode),
            Instance.call(inst.fmu.exitInitializationMode),
            inst.step(table[0], h),
        ]
    )
    res["again_out"] = inst.get(names)
    # saved in initialisation mode with a parameter set: restored after a step, it exits
    # initialisation mode again (with that parameter) and steps
    inst.fmu.reset()
    inst.t = 0.0
    inst.fmu.setupExperiment(startTime=0.0)
    inst.fmu.enterInitializationMode()
    inst.set({"contact.friction": 0.3})
    in_init = inst.fmu.getFMUstate()
    inst.fmu.exitInitializationMode()
    inst.step(table[0], h)
    res["restore_initialization"] = np.array(Instance.call(inst.fmu.setFMUstate, in_init))
    inst.t = 0.0
    res["init_again"] = np.array([Instance.call(inst.fmu.exitInitializationMode), inst.step(table[0], h)])
    res["friction_after"] = np.array(inst.fmu.getReal([inst.var["contact.friction"].valueReference])[0])
    # a step of 1e-15 s (below 1e-6 solver.dt): OK, the clock moves by it, the next step follows
    from fmpy.fmi2 import fmi2LastSuccessfulTime

    res["tiny"] = np.array(inst.step(table[1], 1e-15))
    res["tiny_time"] = np.array(inst.fmu.getRealStatus(fmi2LastSuccessfulTime))
    res["tiny_master"] = np.array(inst.t)
    res["after_tiny"] = np.array(inst.step(table[1], h))
    res["log"] = np.array(_log(inst.log) or [""])
    inst.fmu.terminate()
    inst.fmu.freeInstance()
    return res


def scenario_initial_outputs(job, table):
    """Outputs read in Initialization Mode, after each of ``params`` (a list of {name: value}) is
    set, then after fmi2ExitInitializationMode; the status of every call (set up, enter, then a set
    and a read per item, exit)."""
    names = job["outputs"]
    inst = Instance(job["fmu"], name="initial", initialize=False)
    status = [Instance.call(inst.fmu.setupExperiment, None, 0.0, None), Instance.call(inst.fmu.enterInitializationMode)]
    during = []
    for values in job["params"]:
        status.append(inst.set(values))
        got = []
        status.append(Instance.call(lambda: got.append(inst.get(names))))  # noqa: B023
        during.append(got[0] if got else np.full(len(names), np.nan))
    status.append(Instance.call(inst.fmu.exitInitializationMode))
    after = inst.get(names)
    inst.free()
    return {
        "during": np.array(during),
        "after": after,
        "status": np.array(status),
        "log": np.array(_log(inst.log) or [""]),
    }


def scenario_threads(job, table):
    """Two instances started at once on two threads in a process that never loaded the FMU (the
    per-user cache empty: the test sets XDG_CACHE_HOME), then a third after fmpy deleted their
    unpack folders; and the process's own warnings still shown afterwards."""
    import contextlib
    import io
    import threading
    import warnings

    from fmpy import simulate_fmu

    results, errors = {}, {}
    gate = threading.Barrier(2)

    def one(name):
        try:
            gate.wait()
            r = simulate_fmu(job["fmu"], stop_time=0.002, output_interval=1e-4, output=job["outputs"])
            results[name] = np.column_stack([r[n] for n in job["outputs"]])
        except Exception as exc:  # noqa: BLE001  (reported to the test)
            errors[name] = repr(exc)

    threads = [threading.Thread(target=one, args=(f"t{i}",)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    one_more = simulate_fmu(job["fmu"], stop_time=0.002, output_interval=1e-4, output=job["outputs"])
    shown = io.StringIO()
    with contextlib.redirect_stderr(shown):
        warnings.warn("the host's own warning", UserWarning, stacklevel=1)
    return dict(
        errors=np.array(sorted(f"{k}: {v}" for k, v in errors.items()) or [""]),
        t0=results.get("t0", np.zeros(0)),
        t1=results.get("t1", np.zeros(0)),
        after=np.column_stack([one_more[n] for n in job["outputs"]]),
        host_warning=np.array(shown.getvalue()),
    )


def scenario_memory(job, table):
    """Resident memory over many steps of ever-changing size (a variable-step master)."""
    inst = Instance(job["fmu"], params={"contact.enabled": False})
    rng = np.random.default_rng(1)
    rss = []
    zero = np.zeros(len(INPUTS))
    for k in range(job["steps"]):
        assert inst.step(zero, float(rng.uniform(0.5e-4, 1.5e-4))) == 0
        if k % 100 == 0:
            with open("/proc/self/statm") as f:
                rss.append(int(f.read().split()[1]) * 4096)
    inst.free()
    return dict(rss=np.array(rss))


def scenario_model_file(job, table):
    """Getters with a model file set, and a parameter set to its built-in value."""
    res = {}
    inst = Instance(job["fmu"], name="model-file", initialize=False)
    fmu, var = inst.fmu, inst.var
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    vr = lambda n: [var[n].valueReference]  # noqa: E731
    res["E_builtin"] = fmu.getReal(vr("casing.E"))[0]
    fmu.setString(vr("model_file"), [job["model_file"]])
    res["model_file"] = np.array(fmu.getString(vr("model_file"))[0].decode())
    res["E_file"] = fmu.getReal(vr("casing.E"))[0]
    res["friction_file"] = fmu.getReal(vr("contact.friction"))[0]
    fmu.setReal(vr("contact.friction"), [job["friction"]])
    res["friction_set"] = fmu.getReal(vr("contact.friction"))[0]
    fmu.exitInitializationMode()
    in_vr = [var[n].valueReference for n in INPUTS]
    out_vr = [var[n].valueReference for n in job["outputs"]]
    out = np.zeros((len(table), len(out_vr)))
    t = 0.0
    for k, row in enumerate(table):
        fmu.setReal(in_vr, list(row))
        fmu.doStep(t, job["h"])
        t += job["h"]
        out[k] = fmu.getReal(out_vr)
    fmu.terminate()
    fmu.freeInstance()
    res["out"] = out
    return res


def _log(entries):
    return [f"{STATUS.get(s, s)}: {m}" for s, m in entries]


def scenario_preimported(job, table):
    """The host imports cablecasing_core from ``job["package_parent"]`` before it loads the FMU."""
    sys.path.insert(0, job["package_parent"])
    import cablecasing_core  # noqa: F401

    inst = Instance(job["fmu"], name="preimported")
    status = inst.step(np.zeros(len(INPUTS)), 1e-4)
    inst.free()
    return dict(status=status, log=_log(inst.log))


def scenario_references(job, table):
    """fmi2GetReal and fmi2SetReal of each list of value references in job["references"] (after
    initialisation): their statuses, the values read and the log of each call."""
    from fmpy.fmi2 import fmi2Real, fmi2ValueReference

    inst = Instance(job["fmu"], name="references", inputs=job.get("input_names"))
    res = {"get_status": [], "set_status": []}
    for k, vrs in enumerate(job["references"]):
        vr, val = (fmi2ValueReference * len(vrs))(*vrs), (fmi2Real * len(vrs))()
        res["get_status"].append(Instance.call(inst.fmu.fmi2GetReal, inst.fmu.component, vr, len(vrs), val))
        res["set_status"].append(Instance.call(inst.fmu.fmi2SetReal, inst.fmu.component, vr, len(vrs), val))
        res[f"log{k}"] = _log(inst.log) or [""]
        inst.log.clear()
    inst.free()
    return res


SCENARIOS = {
    "run": scenario_run,
    "references": scenario_references,
    "preimported": scenario_preimported,
    "steps": scenario_steps,
    "clock": scenario_clock,
    "state": scenario_state,
    "two": scenario_two,
    "foreign_state": scenario_foreign_state,
    "errors": scenario_errors,
    "libcosim": scenario_libcosim,
    "cache": scenario_cache,
    "careless": scenario_careless,
    "phases": scenario_phases,
    "threads": scenario_threads,
    "initial_outputs": scenario_initial_outputs,
    "memory": scenario_memory,
    "model_file": scenario_model_file,
}


def main():
    import tempfile

    scenario, path = sys.argv[1], sys.argv[2]
    # fmpy's extract() unpacks each FMU into a new temporary folder that it never removes (~12 MB):
    # under the job's own folder (the test's tmp_path, which pytest prunes) a test run leaks none
    tempfile.tempdir = str(Path(path).resolve().parent)
    job = json.loads(Path(path).read_text())
    table = np.load(job["inputs"]) if "inputs" in job else np.zeros((0, len(INPUTS)))
    res = SCENARIOS[scenario](job, table)
    np.savez(job["out"], **{k: np.asarray(v) for k, v in res.items()})


if __name__ == "__main__":
    main()
