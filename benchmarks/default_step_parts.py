"""The default specimen's step in three parts, in one process: what the contact costs when no node is
near the wall, and what the contacts themselves cost.

Three engines of the built-in model (its scenario, records on, ledger off, Δt = ``--dt``), advanced
in turn by 0.01 s chunks (``_alternating.alternate``) after a 2 ms warm-up:
* contact_free: ``contact=False``, the bodies' Newmark step alone;
* all_far: contact on with ``Engine.gap`` = 1 m, so every cable node passes the far-from-wall test
  and no contact closes: the step plus the contact's bookkeeping (the far test, the zeroed
  forces, the ledger's contact work, the copies of the contact memory);
* full: the default step.
Printed as ``name: value`` lines (medians over the chunks, µs per step): us_per_step_contact_free,
us_per_step_all_far, us_per_step_full, contacts_per_step (closed contacts per step of the full
engine, warm-up included),
contact_bookkeeping_us_per_step (all_far - contact_free), contact_work_us_per_contact
((full - all_far) / contacts_per_step; left out, with a ``#`` line, when no contact closed), and
rtf_coupled_from_full_median.
What the parts are, and what was tried on each: docs/performance.md, "What bounds `rtf_coupled` at
1e-5 s".
Run: .venv/bin/python benchmarks/default_step_parts.py [--rounds 100] [--dt 1e-5]
(about 10 s on one core at the defaults).
"""

import numpy as np
from _alternating import alternate
from _options import checked, divides, integer, parser, time_step

import cablecasing_core as cc
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion

CHUNK = 0.01
p = parser(__doc__)
p.add_argument("--rounds", type=int, default=100, help="0.01 s chunks per engine")
p.add_argument("--dt", type=float, default=1e-5, help="time step (s); it divides the 0.01 s chunk")
args = p.parse_args()
with checked(p):
    integer("--rounds", args.rounds, 1)
    time_step("--dt", args.dt)
    divides("--dt", args.dt, "the chunk", CHUNK)
model = cc.load_model()
motion = scenario_motion(model, dt=args.dt)
engines = {
    "contact_free": Engine(model, dt=args.dt, contact=False, ledger=False, record=True),
    "all_far": Engine(model, dt=args.dt, ledger=False, record=True),
    "full": Engine(model, dt=args.dt, ledger=False, record=True),
}
engines["all_far"].gap = 1.0  # m: wider than any displacement, so no node is near the wall
for eng in engines.values():
    eng.advance(0.002, motion)
walls = alternate([lambda e=eng: e.advance(CHUNK, motion) for eng in engines.values()], args.rounds)
us = {name: np.median(w) / (CHUNK / args.dt) * 1e6 for name, w in zip(engines, walls.T)}
closed = np.count_nonzero(engines["full"].history()["contact_state"], axis=1).mean()
far_closed = np.count_nonzero(engines["all_far"].history()["contact_state"])
if far_closed:
    raise SystemExit(f"all_far closed {far_closed} contacts: Engine.gap = 1 m did not keep every node off the wall")
for name, value in us.items():
    print(f"us_per_step_{name}: {value:.3f}")
print(f"contacts_per_step: {closed:.3f}")
print(f"contact_bookkeeping_us_per_step: {us['all_far'] - us['contact_free']:.3f}")
if closed:
    print(f"contact_work_us_per_contact: {(us['full'] - us['all_far']) / closed:.3f}")
else:  # (a short run: no contact closed yet, so no cost per contact)
    print("# no contact closed in the full engine's run: no contact_work_us_per_contact")
print(f"rtf_coupled_from_full_median: {args.dt / (us['full'] * 1e-6):.4f}")
