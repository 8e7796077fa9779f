"""Drive dist/CableCasing.fmu through fmpy in this (fresh) process; used by test_fmu.py.

python tests/fmu_driver.py SCENARIO OUT.npz '{"json": "args"}'
"""
import json
import sys
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "fmu_src"))

from cablecasing_core.config import CHANNELS  # noqa: E402
from cablecasing_core.engine import OUTPUTS  # noqa: E402
from CableCasing import input_name  # noqa: E402

FMU = str(ROOT / "dist" / "CableCasing.fmu")


class Instance:
    def __init__(self, params=None, name="inst", log=None, unzip=None):
        self.md = read_model_description(FMU)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.unzip = unzip or extract(FMU)
        self.log = log if log is not None else []

        def logger(env, instance, status, category, message):
            self.log.append((status, message.decode() if isinstance(message, bytes) else message))
        self.fmu = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzip,
                             modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(loggingOn=True, callbacks=None)
        from fmpy.fmi2 import fmi2CallbackLoggerTYPE
        self._cb = fmi2CallbackLoggerTYPE(logger)
        self.fmu.callbacks.logger = self._cb
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        for k, v in (params or {}).items():
            if isinstance(v, bool):
                self.fmu.setBoolean([self.vr[k]], [v])
            elif isinstance(v, str):
                self.fmu.setString([self.vr[k]], [v])
            else:
                self.fmu.setReal([self.vr[k]], [float(v)])
        self.fmu.exitInitializationMode()
        self.in_vr = [self.vr[input_name(ch, p)] for p in ("", "v", "a") for ch in CHANNELS]
        self.out_vr = [self.vr[n] for n in OUTPUTS if n != "contact.active"]
        self.t = 0.0

    def step(self, u, v, a, h):
        self.fmu.setReal(self.in_vr, list(np.concatenate([u, v, a])))
        from fmpy.fmi1 import FMICallException
        try:
            status = self.fmu.fmi2DoStep(self.fmu.component, self.t, h, 1)
        except FMICallException as exc:  # fmpy raises on any status but OK
            status = exc.status
        if status == 0:
            self.t += h
        return status

    def outputs(self):
        r = self.fmu.getReal(self.out_vr)
        return np.array(r + [self.fmu.getInteger([self.vr["contact.active"]])[0]])


def motion_samples(model_over, duration, h):
    import cablecasing_core as cc
    from cablecasing_core.scenario import scenario_motion
    m = cc.load_model().with_overrides(model_over)
    t = h * np.arange(0, int(round(duration / h)))
    return t, scenario_motion(m)(t)     # the scenario's own record (periodic over scenario.duration)


def run(inst, samples, h):
    t, (u, v, a) = samples
    outs = []
    for k in range(len(t)):
        st = inst.step(u[k], v[k], a[k], h)
        if st != 0:
            raise RuntimeError(f"doStep status {st} at t={t[k]}: {inst.log[-3:]}")
        outs.append(inst.outputs())
    return np.array(outs)


def main():
    scen, out = sys.argv[1], sys.argv[2]
    args = json.loads(sys.argv[3]) if len(sys.argv) > 3 else {}
    h = args.get("h", 1e-4)
    res = {}
    if scen == "contact":
        samples = motion_samples(args["model"], args["duration"], h)
        res["out"] = run(Instance(args.get("params")), samples, h)
    elif scen == "state":
        samples = motion_samples(args["model"], args["duration"], h)
        t, (u, v, a) = samples
        inst = Instance(args.get("params"))
        n = len(t) // 2
        for k in range(n):
            inst.step(u[k], v[k], a[k], h)
        s = inst.fmu.getFMUstate()
        blob = inst.fmu.serializeFMUstate(s)
        t_mid = inst.t
        first = []
        for k in range(n, len(t)):
            inst.step(u[k], v[k], a[k], h)
            first.append(inst.outputs())
        inst.fmu.setFMUstate(s)
        inst.t = t_mid
        second = []
        for k in range(n, len(t)):
            inst.step(u[k], v[k], a[k], h)
            second.append(inst.outputs())
        other = Instance(args.get("params"), name="other")
        other.fmu.setFMUstate(other.fmu.deSerializeFMUstate(blob))
        other.t = t_mid
        third = []
        for k in range(n, len(t)):
            other.step(u[k], v[k], a[k], h)
            third.append(other.outputs())
        res.update(first=np.array(first), second=np.array(second), third=np.array(third))
    elif scen == "two":
        samples = motion_samples(args["model"], args["duration"], h)
        t, (u, v, a) = samples
        i1, i2 = Instance(args["p1"], "one"), Instance(args["p2"], "two")
        o1, o2 = [], []
        for k in range(len(t)):
            i1.step(u[k], v[k], a[k], h)
            i2.step(u[k], v[k], a[k], h)
            o1.append(i1.outputs())
            o2.append(i2.outputs())
        res.update(o1=np.array(o1), o2=np.array(o2))
    elif scen == "errors":
        log = []
        inst = Instance({}, log=log)
        z = np.zeros(12)
        bad = z.copy()
        bad[2] = np.nan
        res["nan_status"] = inst.step(bad, z, z, 1e-4)
        res["after_nan_status"] = inst.step(z, z, z, 1e-4)
        log2 = []
        inst2 = Instance({"casing.E": -1.0}, log=log2, name="bad")
        res["badparam_status"] = inst2.step(z, z, z, 1e-4)
        res["log"] = np.array([m for _, m in log + log2])
    np.savez(out, **res)


if __name__ == "__main__":
    main()
