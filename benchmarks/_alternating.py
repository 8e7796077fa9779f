"""Timing several runs against each other in one process: each advanced by one chunk in turn, the
order reversed every other round, so the machine's drift within the run (it moves by up to 2 x from
hour to hour) falls on every run alike (docs/performance.md, "Comparing two trees")."""

import time

import numpy as np


def alternate(chunk_calls, rounds):
    """Call each of ``chunk_calls`` (callables that advance one run by one chunk) once per round,
    in turn, for ``rounds`` rounds; returns the wall times (s), an array (rounds, runs)."""
    walls = np.empty((rounds, len(chunk_calls)))
    for k in range(rounds):
        order = range(len(chunk_calls)) if k % 2 == 0 else reversed(range(len(chunk_calls)))
        for j in order:
            t0 = time.perf_counter()
            chunk_calls[j]()
            walls[k, j] = time.perf_counter() - t0
    return walls


def ratio_quartiles(numerator, denominator, skip=0):
    """The quartiles (25, 50 and 75 %) of the chunk-by-chunk ratio of two runs' wall times from the
    same rounds of :func:`alternate` (what one costs over the other, robust to the machine's drift),
    leaving out the first ``skip`` rounds (at most half of them: a run's start, while its contacts
    build up)."""
    r = np.asarray(numerator, float) / np.asarray(denominator, float)
    return np.percentile(r[min(skip, len(r) // 2) :], [25, 50, 75])
