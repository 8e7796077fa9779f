"""Speed of the FMU: the default scenario through fmpy with a 1e-4 s communication step.

Prints name: value lines: rtf_fmu, core_rtf (the engine on the same inputs and reconstruction),
fmu_overhead (FMU wall time / core wall time), instantiate_s (warm numba cache).
Run: .venv/bin/python benchmarks/bench_fmu.py [--duration 0.2]
"""
import argparse
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

p = argparse.ArgumentParser()
p.add_argument("--duration", type=float, default=0.2)
args = p.parse_args()
if not (ROOT / "dist" / "CableCasing.fmu").exists():
    subprocess.run([sys.executable, str(ROOT / "build_fmu.py")], check=True)

import cablecasing_core as cc  # noqa: E402
from cablecasing_core.engine import Engine  # noqa: E402
from cablecasing_core.kinematics import QuinticStep, taylor_target  # noqa: E402
from fmu_driver import Instance, motion_samples  # noqa: E402

h = 1e-4
samples = motion_samples({}, args.duration, h)
t, (u, v, a) = samples
Instance({}, name="warm")                      # warm the numba cache
t0 = time.perf_counter()
inst = Instance({}, name="bench")
inst.step(u[0], v[0], a[0], h)
instantiate = time.perf_counter() - t0
t0 = time.perf_counter()
for k in range(1, len(t)):
    inst.step(u[k], v[k], a[k], h)
    inst.outputs()
fmu_wall = time.perf_counter() - t0

eng = Engine(cc.load_model(), ledger=False)
support = tuple(np.zeros(12) for _ in range(3))
step = QuinticStep(0.0, h, support, taylor_target(u[0], v[0], a[0], h))
eng.advance(h, step)
support = step.end_state()
t0 = time.perf_counter()
for k in range(1, len(t)):
    step = QuinticStep(eng.time, h, support, taylor_target(u[k], v[k], a[k], h))
    eng.advance(h, step)
    support = step.end_state()
    eng.outputs()
core_wall = time.perf_counter() - t0
sim = (len(t) - 1) * h
print(f"rtf_fmu: {sim / fmu_wall:.4f}")
print(f"core_rtf: {sim / core_wall:.4f}")
print(f"fmu_overhead: {fmu_wall / core_wall:.3f}")
print(f"instantiate_s: {instantiate:.3f}")
