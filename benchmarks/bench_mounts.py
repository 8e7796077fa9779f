"""What isolators and clips cost: the time domain's step and the TRFAM, with and without mounts.

The built-in specimen's scenario (contact on) on its own routing with the ends clamped, against
the same with both casing ends on isolators and two clips (examples/installation.toml's mounts),
alternated in one process so that the shared machine's load affects both alike; and the casing's
TRFAM casing.A.z -> casing.B.z on 1981 frequencies (10-1000 Hz) by the modal sum (clamped) and by
the banded direct solve (mounts). Prints ``name: value`` lines: us_per_step_clamped,
us_per_step_mounted (µs per step, the fastest of the runs), step_cost_ratio_mounted_over_clamped,
trfam_1981_frequencies_s_clamped and trfam_1981_frequencies_s_mounted (s).
Run: .venv/bin/python benchmarks/bench_mounts.py [--duration 0.2] [--repeat 3]   (docs/performance.md's command)

BLAS runs on one thread (OPENBLAS_NUM_THREADS, OMP_NUM_THREADS, MKL_NUM_THREADS = 1, set before numpy
is imported unless the environment sets them), as benchmarks/bench_frequency.py: with OpenBLAS's
default of a thread per core the TRFAM's timing on the shared machine varied tenfold (0.073 / 0.73 s).
"""

from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")  # (before numpy: BLAS reads it when it loads)

import copy  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from _options import checked, integer, parser, seconds  # noqa: E402

import cablecasing_core as cc  # noqa: E402
from cablecasing_core.timedomain.engine import Engine  # noqa: E402
from cablecasing_core.timedomain.scenario import scenario_motion  # noqa: E402

ISO = {"stiffness": [4e5, 1e5, 1e5], "rotational_stiffness": [5.0, 20.0, 20.0], "damping": [60.0, 25.0, 25.0]}
CLIPS = [{"at": 0.40, "stiffness": [2e4, 5e4, 5e4], "damping": 8.0}, {"at": 0.60, "stiffness": [2e4, 5e4, 5e4]}]


def mounted():
    d = copy.deepcopy(cc.load_model().data)
    d["casing"]["supports"] = {"A": "isolator", "B": "isolator"}
    d["casing"]["isolator"] = {"A": ISO, "B": ISO}
    d["casing"]["clip"] = CLIPS
    return cc.model_from_dict(d)


def main():
    p = parser(__doc__)
    p.add_argument("--duration", type=float, default=0.2, help="model time per timed run, s")
    p.add_argument("--repeat", type=int, default=3, help="alternations of the two models, fastest kept")
    args = p.parse_args()
    with checked(p):
        seconds("--duration", args.duration)
        integer("--repeat", args.repeat, 1)
    models = {"clamped": cc.load_model(), "mounted": mounted()}
    best = {}
    for _ in range(args.repeat):
        for name, m in models.items():
            eng = Engine(m, ledger=False)
            motion = scenario_motion(m)
            eng.advance(1e-3, motion)  # compiled, factors built
            t = time.perf_counter()
            eng.advance(args.duration, motion)
            us = (time.perf_counter() - t) / (args.duration / eng.dt) * 1e6
            best[name] = min(best.get(name, np.inf), us)
    for name, us in best.items():
        print(f"us_per_step_{name}: {us:.3g}")
    print(f"step_cost_ratio_mounted_over_clamped: {best['mounted'] / best['clamped']:.3f}")
    f = np.arange(10.0, 1000.0 + 0.25, 0.5)
    for name, m in models.items():
        t = time.perf_counter()
        cc.trfam(m, "casing.A.z", "casing.B.z", f)
        print(f"trfam_1981_frequencies_s_{name}: {time.perf_counter() - t:.3g}")


if __name__ == "__main__":
    main()
