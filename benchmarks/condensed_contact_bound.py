"""What condensing the installed specimen's contacts into the bodies' banded step would cost, against
the step the engine takes now, in one process.

The design (docs/performance.md, "What bounds `rtf_installed` at 1e-5 s"): instead of the Delassus
matrix of the contacts (the bodies' compliance at the contact points), add each contact's
linearised law to the effective stiffness of both bodies and solve the coupled system by Newton.
With the two bodies' nodes interleaved station by station (casing node i, then cable node i: 12 DOFs
a station), a cable node touches the casing element (i - 1, i) or (i, i + 1), so the coupled matrix
is banded with a half-bandwidth of 23 DOFs (cable node i's last DOF to casing node i - 1's first),
432 DOFs at 35 elements. Its law's tangent changes every Newton iteration (the contacts slide), so
each iteration factors that band anew: its cost is a floor of the design's step, before the search,
the law and the response are counted.

Printed as ``name: value`` lines: us_per_step_installed (the engine's installed step at 1e-5 s over
``--duration`` s of its scenario, the fastest of ``--repeat`` runs), us_band_factorization (the package's band LU,
``_band_lu_factor`` of the contact Newton, on that band: the fastest of ``--repeat`` rounds of 200,
alternating with the runs, less the copy of the matrix that each takes), newton_iterations_per_step (the engine's), and
condensed_floor_over_step: the factorizations of one step (one per Newton iteration) over the whole
present step.
Run: .venv/bin/python benchmarks/condensed_contact_bound.py [--duration 0.05] [--repeat 5]
(about 10 s on one core).
"""

import time

import numpy as np
from _options import checked, integer, parser

import cablecasing_core as cc
from cablecasing_core.model.validators import number
from cablecasing_core.timedomain.engine import Engine
from cablecasing_core.timedomain.kernels._contact_newton_for_fixed_modes import _band_lu_factor
from cablecasing_core.timedomain.scenario import scenario_motion

DT = 1e-5
p = parser(__doc__)
p.add_argument("--duration", type=float, default=0.05, help="s of the installed scenario per timed run")
p.add_argument("--repeat", type=int, default=5, help="timed runs (and rounds of factorizations); the fastest counts")
args = p.parse_args()
with checked(p):
    number("--duration", args.duration, ge=DT, unit="s")  # (one step at least)
    integer("--repeat", args.repeat, 1)
model = cc.load_model("installed")
n_nodes = model.geometry["n_elements"] + 1
m, band = 12 * n_nodes, 23  # (12 DOFs a station; cable node i to casing node i - 1: 12 + 11)
rng = np.random.default_rng(1)
A0 = np.zeros((m, m))
for i in range(m):  # a diagonally dominant band (no pivoting: the least work the LU does)
    lo, hi = max(0, i - band), min(m, i + band + 1)
    A0[i, lo:hi] = 0.01 * rng.standard_normal(hi - lo)
    A0[i, i] = 10.0
A, piv = A0.copy(), np.zeros(m, np.int64)
_band_lu_factor(A, m, band, piv)  # (compiles or loads it)
Engine(model, dt=DT, ledger=False).advance(2 * DT, scenario_motion(model))  # (compiles or loads the step)

steps, factor = [], []
for _ in range(args.repeat):
    eng = Engine(model, dt=DT, ledger=False)
    motion = scenario_motion(model, dt=DT)
    t0 = time.perf_counter()
    eng.advance(args.duration, motion)
    steps.append((time.perf_counter() - t0) / (args.duration / DT))
    its = eng.solver_counts[0] / (args.duration / DT)
    t0 = time.perf_counter()
    for _ in range(200):
        A[:] = A0
        _band_lu_factor(A, m, band, piv)
    t1 = time.perf_counter()
    for _ in range(200):  # (the copy alone, left out: the band LU works on a dense array)
        A[:] = A0
    factor.append((2 * t1 - t0 - time.perf_counter()) / 200)
step_us, factor_us = min(steps) * 1e6, min(factor) * 1e6
print(f"us_per_step_installed: {step_us:.2f}")
print(f"us_band_factorization: {factor_us:.2f} ({m} DOFs, half-bandwidth {band})")
print(f"newton_iterations_per_step: {its:.2f}")
print(f"condensed_floor_over_step: {its * factor_us / step_us:.2f}")
