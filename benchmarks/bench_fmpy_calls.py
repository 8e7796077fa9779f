"""What fmpy itself costs per communication step of the FMU, apart from the FMU's work.

Loads ``dist/CableCasing.fmu`` with fmpy's ``FMU2Slave`` in this process and times, over the same
steps of the default scenario's inputs (36 inputs, 27 Real outputs, communication step 1e-4 s):

* ``fmpy_list_set_get_us``: ``setReal(vrs, list)`` + ``getReal(vrs)``, fmpy's convenience calls,
  which convert the values to new ctypes arrays at every call;
* ``fmpy_ctypes_set_get_us``: ``fmi2SetReal`` + ``fmi2GetReal`` on ctypes arrays made once, as
  fmpy's own ``simulate_fmu`` sets its inputs (``simulation.Input.apply``) and as
  ``tests/fmu/fmu_driver.py`` and ``bench_fmu.py`` do;
* ``fmpy_do_step_us``: ``fmi2DoStep`` alone (the FMU's work: ten Newmark steps with contact);
* ``list_api_share_of_step``: fmpy_list_set_get_us / fmpy_do_step_us (measured in one run).

The package is imported from this checkout (the FMU then uses it, and says so in a warning).

Run: .venv/bin/python benchmarks/bench_fmpy_calls.py [--steps 2000]
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "fmu"))

import fmu_driver  # noqa: E402
from fmpy import extract, read_model_description  # noqa: E402
from fmpy.fmi2 import FMU2Slave, fmi2Real, fmi2True, fmi2ValueReference  # noqa: E402

import cablecasing_core as cc  # noqa: E402
from cablecasing_core.timedomain.scenario import scenario_motion  # noqa: E402

FMU = ROOT / "dist" / "CableCasing.fmu"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--steps", type=int, default=2000, help="communication steps of each kind")
    args = p.parse_args()
    h, n = 1e-4, args.steps
    md = read_model_description(str(FMU))
    var = {v.name: v for v in md.modelVariables}
    in_vr = [var[name].valueReference for name in fmu_driver.INPUTS]
    out_vr = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    s = FMU2Slave(
        guid=md.guid, unzipDirectory=extract(str(FMU)), modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="bench",
    )  # fmt: skip
    s.instantiate(loggingOn=False)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    table = np.hstack(scenario_motion(cc.load_model())(h * np.arange(3 * n + 200)))
    vin, vout = (fmi2ValueReference * len(in_vr))(*in_vr), (fmi2ValueReference * len(out_vr))(*out_vr)
    xin, xout = (fmi2Real * len(in_vr))(), (fmi2Real * len(out_vr))()
    view = np.ctypeslib.as_array(xin)
    t = 0.0
    for row in table[:200]:  # loads the kernels, factorises
        view[:] = row
        s.fmi2SetReal(s.component, vin, len(in_vr), xin)
        s.fmi2DoStep(s.component, t, h, fmi2True)
        t += h
    t0 = time.perf_counter()
    for row in table[200 : 200 + n]:
        s.setReal(in_vr, list(row))
        s.getReal(out_vr)
    t1 = time.perf_counter()
    for row in table[200 : 200 + n]:
        view[:] = row
        s.fmi2SetReal(s.component, vin, len(in_vr), xin)
        s.fmi2GetReal(s.component, vout, len(out_vr), xout)
    t2 = time.perf_counter()
    for _ in range(n):
        s.fmi2DoStep(s.component, t, h, fmi2True)
        t += h
    t3 = time.perf_counter()
    s.terminate()
    s.freeInstance()
    lists, ctypes_, step = ((b - a) / n * 1e6 for a, b in ((t0, t1), (t1, t2), (t2, t3)))
    print(f"fmpy_list_set_get_us: {lists:.1f}")
    print(f"fmpy_ctypes_set_get_us: {ctypes_:.1f}")
    print(f"fmpy_do_step_us: {step:.1f}")
    print(f"list_api_share_of_step: {lists / step:.3f}")


if __name__ == "__main__":
    main()
