"""The time step on the installed specimen, one record per step: does the band level converge?

On the installed specimen the drive's response dominates octaves 3-9 and is hardly chaotic there
(a 1e-9 change of the input moves those bands by under 0.3 %; ``benchmarks/bench_time.py --model
installed``), so one record per time step shows the discretisation error of those bands directly,
without an ensemble. Runs the default scenario of a model (default: ``installed``) for
``--duration`` s at each of ``--dts`` and prints, per time step, the nine Table 3 band levels of
casing.B.Fz after ``--skip`` s (N), their relative difference from the finest step, the contacts
per step, the stick share of the closed contacts and the contact Newton iterations per step.

Run: .venv/bin/python benchmarks/installed_time_step.py [--dts 1e-5 5e-6 2.5e-6 1.25e-6] [--seed 1]
[--duration 1.0] [--set contact.damping=0] (about 2 min for the default steps on the shared machine)
"""

import argparse

import numpy as np

import cablecasing_core as cc
from cablecasing_core.model.schema import SUPPORT_OUTPUTS
from cablecasing_core.studies import octave_rms
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

p = argparse.ArgumentParser()
p.add_argument("--model", default="installed")
p.add_argument("--dts", type=float, nargs="+", default=[1e-5, 5e-6, 2.5e-6, 1.25e-6])
p.add_argument("--seed", type=int, default=1)
p.add_argument("--duration", type=float, default=1.0)
p.add_argument("--skip", type=float, default=0.06, help="s left out (0.06: whole periods of the 50 Hz drive)")
p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
args = p.parse_args()
over = {k: float(v) for k, v in (kv.split("=", 1) for kv in args.set)}
model = cc.load_model(args.model).with_overrides({**over, "scenario.excitation.casing_random.seed": args.seed})
col = SUPPORT_OUTPUTS.index("casing.B.Fz")
levels = {}
for dt in sorted(args.dts, reverse=True):
    eng = Engine(model, dt=dt, ledger=False, record=True)
    eng.advance(args.duration, scenario_motion(model, dt=dt))
    h = eng.history(sparse=True)
    F = h["support_forces"][:, col]
    t = dt * np.arange(1, len(F) + 1)
    levels[dt] = octave_rms(F[t > args.skip], 1 / dt).rms
    kept = t[h["contact_step"]] > args.skip  # the sparse contact entries after the skip
    s = h["contact_state"][kept]
    steps = args.duration / dt
    print(f"octave_rms_dt{dt:g}: " + " ".join(f"{x:.5g}" for x in levels[dt]))
    print(f"contacts_per_step_dt{dt:g}: {len(s) / np.count_nonzero(t > args.skip):.3f}")
    print(f"stick_share_dt{dt:g}: {np.count_nonzero(s == 1) / max(np.count_nonzero(s), 1):.3f}")
    print(f"contact_newton_iterations_per_step_dt{dt:g}: {eng.solver_counts[0] / steps:.3f}")
finest = min(levels)
for dt in sorted(levels, reverse=True)[:-1]:
    r = (levels[dt] - levels[finest]) / levels[finest]
    print(f"rel_diff_dt{dt:g}_vs_dt{finest:g}: " + " ".join(f"{x:+.4f}" for x in r))
