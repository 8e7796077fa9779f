"""The step kernels run outside the interpreter's lock (numba ``nogil``), which the threads scheduler's
parallel samples and an FMU master's thread pool rely on (docs/performance.md): review AP, NG1, a
``run_steps`` compiled without it gave the same numbers and passed every test.

No speed is asserted. While one call of ``run_steps`` takes 50000 steps (~0.4 s), the main thread
runs a pure-Python loop that keeps a time stamp per ms. A kernel that holds the lock lets no Python
code of another thread run for the whole call (no stamp, strictly: the interpreter never gets to
switch); one that releases it lets the loop run whenever the system gives it a core (here a stamp in
every ms of the call). The middle 80 % of the call is looked at (the call's Python before and after
the kernel is at its ends): any stamp there means the lock was free. On a loaded machine the loop may
get little of a core, but not none over ~0.35 s."""

import threading
import time

import numpy as np

import cablecasing_core as cc
from cablecasing_core.timedomain import kernels as K
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.scenario import zero_motion


def test_the_step_kernels_are_compiled_without_the_interpreters_lock():
    for kernel in (K.run_steps, K.communication_step_in_context):
        assert kernel.targetoptions.get("nogil") is True, kernel


def test_another_thread_runs_python_while_run_steps_steps():
    eng = Engine(cc.load_model())
    eng.advance(eng.dt * 10, zero_motion)  # (compiles or loads the kernel first: not inside the window)
    eng.CHUNK = 50_000  # (one call of run_steps for the whole advance)
    calls, run = [], eng._run

    def timed(*args):
        t0 = time.perf_counter()
        run(*args)
        calls.append((t0, time.perf_counter()))

    eng._run = timed
    done = threading.Event()

    def work():
        try:
            eng.advance(eng.dt * 50_000, zero_motion)
        finally:
            done.set()

    stamps, last = [], 0.0
    worker = threading.Thread(target=work)
    worker.start()
    while not done.is_set():  # (a time stamp per ms the loop runs: a few hundred, not millions)
        t = time.perf_counter()
        if t - last >= 1e-3:
            stamps.append(t)
            last = t
    worker.join()
    assert len(calls) == 1, calls
    t0, t1 = calls[0]
    lo, hi = t0 + 0.1 * (t1 - t0), t1 - 0.1 * (t1 - t0)
    inside = np.count_nonzero((np.asarray(stamps) > lo) & (np.asarray(stamps) < hi))
    assert inside > 0, (t1 - t0, len(stamps))
