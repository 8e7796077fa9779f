"""Cost of the random excitation record (timedomain/random_record.py): its blocks on the run's grid,
the whole support motion of a 1 s run, and its share of a run.

Run: .venv/bin/python benchmarks/bench_record.py [--duration 1.0] [--repeat 3]   (docs/performance.md's command)
Prints ``name: value`` lines:

* record_lines, record_block_samples: lines of the default random excitation (10-1000 Hz at 1/64 Hz)
  and samples per block at dt = 1e-5 s;
* record_block_ms: one block (three chirp-z transforms), best of --repeat;
* motion_ms: the scenario's motion over --duration s at dt = 1e-5, evaluated as the engine asks for
  it (chunks of Engine.CHUNK steps), from a fresh ScenarioMotion (every block computed once);
* motion_off_grid_us_per_time: one time off the grid (the quintic through its two grid neighbours,
  on blocks computed before); direct_sum_us_per_time: the same time as the direct sum over the lines;
* simulate_wall_s and motion_share: cc.simulate of --duration s of the default scenario (contact,
  ledger, recording) and the motion's share of it.
"""

from __future__ import annotations

import time

import numpy as np
from _options import checked, integer, parser

import cablecasing_core as cc
from cablecasing_core.model.validators import number
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.random_record import RandomRecord
from cablecasing_core.timedomain.scenario import scenario_motion

DT = 1e-5
p = parser(__doc__)
p.add_argument("--duration", type=float, default=1.0, help="s simulated by the motion and the simulate run")
p.add_argument("--repeat", type=int, default=3, help="runs of each kind; the fastest counts (shared machine)")
args = p.parse_args()
with checked(p):
    number("--duration", args.duration, ge=DT, unit="s")  # (one step at least)
    integer("--repeat", args.repeat, 1)
model = cc.load_model()
cc.simulate(model, duration=0.01)  # compile or load the kernels


def best(fn):
    out = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


rec = RandomRecord(5.0, [10.0, 1000.0], 1, DT)
print(f"record_lines: {rec.n_lines}")
print(f"record_block_samples: {rec.block}")
print(f"record_block_ms: {1e3 * best(lambda: rec.even(0.0, DT, rec.block)):.2f}")


def motion():
    mo = scenario_motion(model, dt=DT)
    n = int(round(args.duration / DT))
    for j0 in range(0, n, Engine.CHUNK):
        mo(DT * np.arange(j0 + 1, min(n, j0 + Engine.CHUNK) + 1))


m_s = best(motion)
print(f"motion_ms: {1e3 * m_s:.1f}")
print(f"motion_off_grid_us_per_time: {1e6 * best(lambda: rec(np.array([0.123456789]))[0]):.0f}")
print(f"direct_sum_us_per_time: {1e6 * best(lambda: rec.direct(np.array([0.123456789]))):.0f}")
wall = best(lambda: cc.simulate(model, duration=args.duration))
print(f"simulate_wall_s: {wall:.3f}")
print(f"motion_share: {m_s / wall:.3f}")
