"""Speed of the frequency domain: full 3x3 TRFAM of the default model at 2000 lines.

Prints ``name: value`` lines: trfam_3x3_2000_lines_s (``cc.trfam_matrix`` of the casing, A to B,
2000 frequencies from 10 to 1000 Hz, viscous damping, the mean of 5 calls after a warm-up),
assembly_s (the casing's matrices), modal_basis_s (its modal basis, ``FrequencyResponse``) and dofs.

Run: .venv/bin/python benchmarks/bench_frequency.py   (no options; a few seconds)

BLAS runs on one thread (OPENBLAS_NUM_THREADS, OMP_NUM_THREADS, MKL_NUM_THREADS = 1, set before numpy
is imported unless the environment sets them): on the shared 2-core machine OpenBLAS's default of one
thread per core contends with the other jobs and made the 216-DOF eigenproblem 35-110 times slower.
"""

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")  # (before numpy: BLAS reads it when it loads)

import time  # noqa: E402

import numpy as np  # noqa: E402
from _options import parser  # noqa: E402

import cablecasing_core as cc  # noqa: E402
from cablecasing_core.frequency.trfam import FrequencyResponse  # noqa: E402
from cablecasing_core.structure.assembly import assemble_body  # noqa: E402

parser(__doc__).parse_args()  # (no options: --help shows the above, a typo is refused)
model = cc.load_model()
f = np.linspace(10.0, 1000.0, 2000)
cc.trfam_matrix(model, "casing", "A", "B", f[:10])  # warm-up (imports, BLAS)
reps = 5
t0 = time.perf_counter()
for _ in range(reps):
    for damping in ("viscous",):
        H = cc.trfam_matrix(model, "casing", "A", "B", f, damping)
t_total = (time.perf_counter() - t0) / reps
t0 = time.perf_counter()
sysm = assemble_body(model, "casing")
t_asm = time.perf_counter() - t0
t0 = time.perf_counter()
fr = FrequencyResponse(sysm)
t_modal = time.perf_counter() - t0
print(f"trfam_3x3_2000_lines_s: {t_total:.4f}")
print(f"assembly_s: {t_asm:.4f}")
print(f"modal_basis_s: {t_modal:.4f}")
print(f"dofs: {sysm.ndof}")
