"""Speed and accuracy of the time domain: the reference case of issue 3.

Default model (35 + 35 elements), contact with friction, random excitation 10-1000 Hz at 5 m/s2 RMS at
casing end A plus the cable's 50 Hz axial excitation, dt = 1e-5 s, on one core.
Run: .venv/bin/python benchmarks/bench_time.py [--duration 1.0] [--repeat 3]   (prints name: value lines)

Speed: wall time of Engine.advance over the whole duration (support motion evaluated inside), the
fastest of ``--repeat`` runs (the machine is shared; the spread is printed too).

Accuracy (octave-band RMS of casing.B.Fz, Table 3, samples after 0.05 s):
* octave_rms_max_rel_diff: dt = 1e-5 against dt = 2.5e-6, one record each (the issue's figure);
* the same with contact off (the linear discretisation error alone);
* perturbation_max_rel_diff: dt = 1e-5 against dt = 1e-5 with the casing RMS scaled by 1 + 1e-9. The
  contact response is chaotic: two records that differ by 1e-9 in the input differ by as much as
  two time steps do, so the single-record comparison measures the scatter of a 1 s record;
* early_force_err_*: max |F(dt) - F(2.5e-6)| / RMS(F) over t < 0.05 s, before the trajectories
  separate: the discretisation error proper, which shrinks with dt.
"""
import argparse
import time

import numpy as np

import cablecasing_core as cc
from cablecasing_core.engine import Engine
from cablecasing_core.scenario import scenario_motion
from cablecasing_core.studies import octave_rms

p = argparse.ArgumentParser()
p.add_argument("--duration", type=float, default=1.0)
p.add_argument("--repeat", type=int, default=3)
args = p.parse_args()
model = cc.load_model()
DT = 1e-5
t0 = time.perf_counter()
Engine(model, dt=DT, ledger=False).advance(DT, scenario_motion(model))
print(f"numba_compile_or_cache_load_s: {time.perf_counter() - t0:.2f}")

for contact, label in ((True, "coupled"), (False, "linear")):
    walls = []
    for _ in range(args.repeat):
        eng = Engine(model, dt=DT, contact=contact, ledger=False, record=contact)
        mo = scenario_motion(model, dt=DT, duration=args.duration)
        t0 = time.perf_counter()
        eng.advance(args.duration, mo)
        walls.append(time.perf_counter() - t0)
    wall = min(walls)
    steps = args.duration / DT
    print(f"rtf_{label}: {args.duration / wall:.4f}")
    print(f"us_per_step_{label}: {wall / steps * 1e6:.2f}")
    print(f"us_per_step_{label}_slowest_run: {max(walls) / steps * 1e6:.2f}")
    if contact:
        h = eng.history()
        print(f"mean_active_contacts: {np.mean(np.count_nonzero(h['contact_state'], axis=1)):.3f}")
        its, passes, failed = eng.solver_counts
        print(f"contact_newton_iterations_per_step: {its / steps:.3f}")
        print(f"contact_stick_slip_passes_per_step: {passes / steps:.3f}")
        print(f"contact_unconverged_steps: {int(failed)}")


def force(m, dt, duration, contact=None, motion=None):
    res = cc.simulate(m, duration=duration, dt=dt, contact=contact, motion=motion)
    return res.time, res.support_force("casing.B.Fz")


def bands(t, F, dt):
    return octave_rms(F[t > 0.05], 1 / dt).rms


def rel(a, b):
    return np.abs(a - b) / b


runs = {dt: force(model, dt, args.duration) for dt in (1e-5, 2.5e-6)}
lv = {dt: bands(*runs[dt], dt) for dt in runs}
r = rel(lv[1e-5], lv[2.5e-6])
print(f"octave_rms_max_rel_diff: {r.max():.4f}")
print("octave_rms_rel_diff_per_band: " + " ".join(f"{x:.3f}" for x in r))

perturbed = model.with_overrides({"scenario.excitation.casing_random.rms": 5.0 * (1 + 1e-9)})
r = rel(bands(*force(perturbed, 1e-5, args.duration), 1e-5), lv[1e-5])
print(f"perturbation_max_rel_diff: {r.max():.4f}")
print("perturbation_rel_diff_per_band: " + " ".join(f"{x:.3f}" for x in r))

lin = {dt: bands(*force(model, dt, args.duration, contact=False), dt) for dt in (1e-5, 2.5e-6)}
r = rel(lin[1e-5], lin[2.5e-6])
print(f"octave_rms_max_rel_diff_contact_off: {r.max():.4f}")
print("octave_rms_rel_diff_per_band_contact_off: " + " ".join(f"{x:.3f}" for x in r))

# the trajectories before chaos separates them (t < 0.05 s): error against dt = 2.5e-6
tr, Fr = runs[2.5e-6]
rms = np.sqrt(np.mean(Fr[tr > 0.05] ** 2))
for dt in (1e-5, 5e-6):
    # the same excitation record (its length sets its frequency lines), only 0.05 s of it
    t, F = runs[dt] if dt in runs else force(model, dt, 0.05, motion=scenario_motion(model, dt=dt, duration=args.duration))
    e = t < 0.05
    Fref = np.interp(t[e], tr, Fr)          # the reference at the coarse times (common grid points)
    print(f"early_force_err_dt{dt:g}: {np.max(np.abs(F[e] - Fref)) / rms:.2e}")
