"""Contacts per step over excitation seeds: which records of the reference case enter the regime
where the cable lies along the wall (~5.5 contacts per step instead of ~2, docs/performance.md).

For seeds 1..N of ``scenario.excitation.casing_random.seed`` (everything else default), a record of
``--duration`` s at dt = 1e-5 s; prints per seed the mean contacts per step in each tenth of the
record, the wall time per step (µs) and HIGH when a tenth exceeds 4 contacts per step; then the share
of such records and the speed read over seeds: the median and quartiles of the wall time per step,
rtf_median_over_seeds (simulated seconds per wall second at the median) and the median of each
regime. With ``--workers 1`` the records run one after another on one core, as bench_time.py's;
with 2 the two processes share the machine and the times are indicative only.
Run: .venv/bin/python benchmarks/contact_regimes.py [--seeds 24] [--duration 1.0] [--workers 2]
"""
import argparse
import time
from multiprocessing import get_context

import numpy as np

import cablecasing_core as cc
from cablecasing_core.engine import Engine
from cablecasing_core.scenario import scenario_motion


def run(job):
    seed, duration = job
    m = cc.load_model().with_overrides({"scenario.excitation.casing_random.seed": seed})
    eng = Engine(m, dt=1e-5, ledger=False, record=True)
    motion = scenario_motion(m, dt=1e-5, duration=duration)
    t0 = time.perf_counter()
    eng.advance(duration, motion)
    wall = time.perf_counter() - t0
    nc = np.count_nonzero(eng.history()["contact_state"], axis=1)
    return seed, [c.mean() for c in np.array_split(nc, 10)], wall / (duration / 1e-5) * 1e6


if __name__ == "__main__":
    p = argparse.ArgumentParser()
    p.add_argument("--seeds", type=int, default=24)
    p.add_argument("--duration", type=float, default=1.0)
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args()
    run((1, 0.01))                       # numba cache
    walls = {False: [], True: []}
    with get_context("spawn").Pool(args.workers) as pool:
        for seed, tenths, us in pool.imap(run, [(s, args.duration) for s in range(1, args.seeds + 1)]):
            flag = max(tenths) > 4.0
            walls[flag].append(us)
            print(f"seed {seed}: contacts by tenth {' '.join(f'{x:.2f}' for x in tenths)}  us_per_step {us:.1f}"
                  + ("  HIGH" if flag else ""))
    print(f"records_with_many_contacts: {len(walls[True])} of {args.seeds}")
    every = walls[False] + walls[True]
    q1, med, q3 = np.percentile(every, [25, 50, 75])
    print(f"us_per_step_median_over_seeds: {med:.2f} (quartiles {q1:.2f} {q3:.2f}; workers {args.workers})")
    print(f"rtf_median_over_seeds: {1e-5 / (med * 1e-6):.3f}")
    for flag, name in ((False, "usual"), (True, "many_contacts")):
        if walls[flag]:
            print(f"us_per_step_median_{name}: {np.median(walls[flag]):.2f} ({len(walls[flag])} records)")
