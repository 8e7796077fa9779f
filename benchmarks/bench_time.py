"""Speed of the time domain: the reference case of issue 3.

Default model (35 + 35 elements), contact with friction, random excitation 10-1000 Hz at 5 m/s2 RMS at
casing end A plus the cable's 50 Hz axial excitation, dt = 1e-5 s, on one core.
Run: .venv/bin/python benchmarks/bench_time.py [--duration 1.0]   (prints name: value lines)
"""
import argparse
import time

import numpy as np

import cablecasing_core as cc
from cablecasing_core.engine import Engine
from cablecasing_core.scenario import scenario_motion

p = argparse.ArgumentParser()
p.add_argument("--duration", type=float, default=1.0)
args = p.parse_args()
model = cc.load_model()
t0 = time.perf_counter()
eng = Engine(model, dt=1e-5, ledger=False)
eng.advance(1e-5, scenario_motion(model))
compile_s = time.perf_counter() - t0
for contact, label in ((True, "coupled"), (False, "linear")):
    eng = Engine(model, dt=1e-5, contact=contact, ledger=False, record=contact)
    mo = scenario_motion(model, dt=1e-5, duration=args.duration)
    t0 = time.perf_counter()
    eng.advance(args.duration, mo)
    wall = time.perf_counter() - t0
    print(f"rtf_{label}: {args.duration / wall:.4f}")
    print(f"us_per_step_{label}: {wall / (args.duration / 1e-5) * 1e6:.2f}")
    if contact:
        h = eng.history()
        print(f"mean_active_contacts: {np.mean(np.count_nonzero(h['contact_state'], axis=1)):.3f}")
print(f"numba_compile_or_cache_load_s: {compile_s:.2f}")

# accuracy under time-step refinement: octave-band RMS of casing.B.Fz (Table 3) at dt and dt / 4
from cablecasing_core.studies import octave_rms  # noqa: E402

levels = {}
for dt in (1e-5, 2.5e-6):
    res = cc.simulate(model, duration=args.duration, dt=dt)
    keep = res.time > 0.05
    levels[dt] = octave_rms(res.support_force("casing.B.Fz")[keep], 1 / dt).rms
rel = np.abs(levels[1e-5] - levels[2.5e-6]) / levels[2.5e-6]
print(f"octave_rms_max_rel_diff: {rel.max():.4f}")
print("octave_rms_rel_diff_per_band: " + " ".join(f"{r:.3f}" for r in rel))
