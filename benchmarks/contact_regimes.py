"""Contacts per step over excitation seeds: which records of the reference case enter the regime
where the cable lies along the wall (~5.5 contacts per step instead of ~2, docs/performance.md).

For seeds 1..N of ``scenario.excitation.casing_random.seed`` (everything else default), a record of
``--duration`` s at dt = 1e-5 s; prints (as ``name: value`` lines) per seed and RMS the mean
contacts per step in each tenth of the record (``rms<R>_seed<S>_contacts_by_tenth``), the wall
time per step (``rms<R>_seed<S>_us_per_step``, µs) and its regime (``rms<R>_seed<S>_regime``:
``many_contacts`` when a tenth exceeds 4 contacts per step, else ``usual``); then the share of
such records and the speed read over seeds: the median and quartiles of the wall time per step, rtf_median_over_seeds
(simulated seconds per wall second at the median) and the median of each regime. With
``--workers 1`` the records run one after another on one core, as bench_time.py's; with 2 the two
processes share the machine and the times are indicative only.

Cost per contact: every record is also timed chunk by chunk (the engine evaluates the support
motion once per ``Engine.CHUNK`` steps; the wall time between the end of one evaluation and the
start of the next is the step loop's time for that chunk). ``cost_model`` is the least-squares line
through all chunks of all records but their first (which pays the first touch of memory): wall time
per step (µs) = a + b x (contacts per step in that chunk), so an FMU user can budget a step by its
contacts. ``--rms`` repeats the seeds at other RMS accelerations of the casing's random excitation
(m/s2), which spreads the contact counts the fit is read over.
Run: .venv/bin/python benchmarks/contact_regimes.py [--seeds 24] [--duration 1.0] [--workers 2]
     [--rms 5 10 20]   (docs/performance.md: ``--seeds 8 --duration 1.0 --workers 1 --rms 5 20``)
"""

import time
from multiprocessing import get_context

import numpy as np
from _options import checked, integer, parser

import cablecasing_core as cc
from cablecasing_core.model.schema import lookup
from cablecasing_core.model.validators import number
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import scenario_motion


def run(job):
    """One record: (seed, rms, mean contacts per step by tenth, wall µs per step, and per chunk of
    Engine.CHUNK steps its wall µs per step and mean contacts per step)."""
    seed, rms, duration = job
    m = cc.load_model().with_overrides(
        {"scenario.excitation.casing_random.seed": seed, "scenario.excitation.casing_random.rms": rms}
    )
    eng = Engine(m, dt=1e-5, ledger=False, record=True)
    motion = scenario_motion(m, dt=1e-5)
    marks = []  # (start, end) of each evaluation of the motion, s

    def timed(t):
        if t.shape == (1,) and t[0] == 0.0:
            return motion(t)  # the supports' state at the start, read once before the first chunk
        t_in = time.perf_counter()
        out = motion(t)
        marks.append((t_in, time.perf_counter()))
        return out

    t0 = time.perf_counter()
    eng.advance(duration, timed)
    wall = time.perf_counter() - t0
    ends = [b for _, b in marks]
    starts = [a for a, _ in marks[1:]] + [t0 + wall]
    chunk_s = np.subtract(starts, ends)
    nc = np.count_nonzero(eng.history()["contact_state"], axis=1)
    edges = np.arange(0, len(nc), Engine.CHUNK)
    steps = np.diff(np.append(edges, len(nc)))  # steps per chunk (the last may be short)
    chunk_nc = np.add.reduceat(nc, edges) / steps
    chunk_us = chunk_s / steps * 1e6
    return (seed, rms, [c.mean() for c in np.array_split(nc, 10)], wall / (duration / 1e-5) * 1e6, chunk_us, chunk_nc)


if __name__ == "__main__":
    p = parser(__doc__)
    p.add_argument("--seeds", type=int, default=24, help="seeds 1..N of the casing's random excitation")
    p.add_argument("--duration", type=float, default=1.0, help="s simulated per record")
    p.add_argument("--workers", type=int, default=2, help="processes")
    p.add_argument(
        "--rms",
        type=float,
        nargs="+",
        default=[5.0],
        help="RMS accelerations (m/s2) of the casing's random excitation; 5 is the reference case",
    )
    args = p.parse_args()
    with checked(p):
        integer("--seeds", args.seeds, 1)
        # (the cost model leaves out each record's first chunk: two chunks at least)
        number("--duration", args.duration, ge=2 * Engine.CHUNK * 1e-5, unit="s")
        integer("--workers", args.workers, 1)
        for rms in args.rms:
            lookup("scenario.excitation.casing_random.rms").check(rms, "--rms")
    run((1, args.rms[0], 0.01))  # numba cache
    walls = {False: [], True: []}
    chunks = []
    jobs = [(s, rms, args.duration) for rms in args.rms for s in range(1, args.seeds + 1)]
    with get_context("spawn").Pool(args.workers) as pool:
        for seed, rms, tenths, us, chunk_us, chunk_nc in pool.imap(run, jobs):
            flag = max(tenths) > 4.0
            if rms == 5.0:  # the reference case's figures
                walls[flag].append(us)
            chunks.append(np.column_stack([chunk_nc, chunk_us])[1:])  # (the first chunk pays the first touch)
            print(f"rms{rms:g}_seed{seed}_contacts_by_tenth: {' '.join(f'{x:.2f}' for x in tenths)}")
            print(f"rms{rms:g}_seed{seed}_us_per_step: {us:.1f}")
            print(f"rms{rms:g}_seed{seed}_regime: {'many_contacts' if flag else 'usual'}")
    chunks = np.concatenate(chunks)
    (b, a), *_ = np.linalg.lstsq(np.column_stack([chunks[:, 0], np.ones(len(chunks))]), chunks[:, 1], rcond=None)
    resid = chunks[:, 1] - (a + b * chunks[:, 0])
    print(
        f"cost_model: us_per_step = {a:.2f} + {b:.2f} x contacts_per_step ({len(chunks)} chunks of "
        f"{Engine.CHUNK} steps, contacts {chunks[:, 0].min():.2f}-{chunks[:, 0].max():.2f} per step, "
        f"residual RMS {np.sqrt(np.mean(resid**2)):.2f} us)"
    )
    if 5.0 not in args.rms:
        raise SystemExit(0)
    print(f"records_with_many_contacts: {len(walls[True])} of {args.seeds}")
    every = walls[False] + walls[True]
    q1, med, q3 = np.percentile(every, [25, 50, 75])
    print(f"us_per_step_median_over_seeds: {med:.2f} (quartiles {q1:.2f} {q3:.2f}; workers {args.workers})")
    print(f"rtf_median_over_seeds: {1e-5 / (med * 1e-6):.3f}")
    for flag, name in ((False, "usual"), (True, "many_contacts")):
        if walls[flag]:
            print(f"us_per_step_median_{name}: {np.median(walls[flag]):.2f} ({len(walls[flag])} records)")
