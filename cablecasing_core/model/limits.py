"""Limits that protect the machine: the memory and time a run would need, estimated from its sizes
before any work, and refused with a :class:`~cablecasing_core.errors.ModelError` that names the key
and the figures (docs/model_file.md, "Limits").

* **Frequency domain** (modes, TRFAM, a time-domain run with a frequency-dependent modulus): the
  dense eigenproblem of a body's free DOFs, 6 (n_elements + 1) of them. LAPACK's dense solver takes
  time growing as DOFs^3 (2.6 s for one body of 400 elements on one core of the 2-core reference
  machine, :data:`DENSE_SECONDS_AT_400`, ``benchmarks/limits.py``; about 40 s at 1000) and
  :data:`DENSE_COPIES` matrices of DOFs^2 doubles; :data:`MAX_DENSE_ELEMENTS` is 14 times the paper's
  mesh of 35 elements.
* **Time domain**: each body holds :data:`TIME_DOMAIN_COPIES` dense matrices of its DOFs (stiffness,
  mass, factors, compliance, and the work arrays of their set-up; 3.3 GB peak for two bodies of 1000
  elements), and the record keeps :data:`BYTES_PER_STEP` bytes per time step (support forces,
  driven inputs, contact summary, and their copies when written). The sum must fit in
  :data:`MEMORY_SHARE` of the memory available.
"""

from __future__ import annotations

import math

from ..errors import ModelError

#: The most elements of a body in the frequency domain's dense eigenproblem (3006 DOFs: 0.5 GB peak
#: and 4.9 s per body on one core of the 2-core machine, 2.8 s on both; 14 times the paper's mesh).
MAX_DENSE_ELEMENTS = 500
#: Seconds the dense eigenproblem of one body of 400 elements (2406 free DOFs) takes on one core of
#: the 2-core reference machine (benchmarks/limits.py, 2026-12-05): the base of the estimate in the
#: refusal's message, which grows as DOFs^3.
DENSE_SECONDS_AT_400 = 2.6
#: Dense DOFs x DOFs matrices alive in the dense eigenproblem (K, M, modes, workspace; measured:
#: 1.8 GB for 6006 DOFs).
DENSE_COPIES = 6
#: Dense DOFs x DOFs matrices a body holds at the time domain's peak (measured: 3.3 GB, two bodies
#: of 6006 DOFs, 3.1 GB above the process's own 0.24 GB: 5.35 matrices per body, 2026-12-05).
TIME_DOMAIN_COPIES = 6
#: Bytes a recorded time step takes: 24 support outputs, up to 36 driven inputs and the contact
#: summary as doubles, twice (the run's arrays and the record being written).
BYTES_PER_STEP = 2 * 8 * (24 + 36 + 8)
#: The share of the available memory a run may plan to use.
MEMORY_SHARE = 0.8


#: The most runs of a study (its design, CSV and statistics stay below 1 GB; a million runs of the
#: default evaluation would take years on one machine).
MAX_STUDY_SAMPLES = 1_000_000
#: The most seeds of an ensemble (its runs are held in memory until it is saved).
MAX_SEEDS = 100_000
#: The largest seed of an ensemble: its CSV holds the seeds among the levels as doubles, exact to 2**53.
MAX_ENSEMBLE_SEED = 2**53
#: The most frequencies of a TRFAM (its (frequencies x modes x supports) complex arrays: about 3 GB
#: for the specimen at this size).
MAX_FREQUENCIES = 200_000


def _gb(x):
    return f"{x / 1e9:.3g} GB"


def _available():
    from ..files import memory_available

    return memory_available()


def check_dense_eigenproblem(n_free: int, n_elements: int | None = None) -> None:
    """Refuse a dense eigenproblem of ``n_free`` DOFs that exceeds :data:`MAX_DENSE_ELEMENTS`
    elements or the memory available (``geometry.n_elements`` named in the message)."""
    n_elements = max(n_free // 6 - 1, 1) if n_elements is None else n_elements
    need = DENSE_COPIES * 8.0 * n_free**2
    seconds = DENSE_SECONDS_AT_400 * (n_free / 2406) ** 3
    if n_elements > MAX_DENSE_ELEMENTS or need > MEMORY_SHARE * _available():
        raise ModelError(
            "geometry.n_elements",
            n_elements,
            f"is too many for the frequency domain: its dense eigenproblem of {n_free} DOFs would need "
            f"{_gb(need)} and time growing as DOFs^3 (about {seconds:.3g} s per body on one core "
            f"of a 2-core machine); at most {MAX_DENSE_ELEMENTS} elements (docs/model_file.md, Limits)",
        )


def check_time_domain(model, duration: float, dt: float) -> None:
    """Refuse a time-domain run of ``duration`` s at step ``dt`` s whose matrices and record would
    not fit in the memory available (the message names the figures and the keys to change)."""
    steps = math.ceil(duration / dt - 1e-9)
    n = model.geometry["n_elements"]
    ndof = 6 * (n + 1)
    matrices = len(model.bodies) * TIME_DOMAIN_COPIES * 8.0 * ndof**2
    record = float(steps) * BYTES_PER_STEP
    have = MEMORY_SHARE * _available()
    if matrices + record > have:
        raise ModelError(
            "scenario.duration",
            duration,
            f"with dt = {dt:g} s ({steps:.4g} steps) and {n} elements the run would need {_gb(record)} for its "
            f"record and {_gb(matrices)} for its matrices, more than the {_gb(have)} of memory it may use; "
            "shorten the duration, lengthen the step or use fewer elements (docs/model_file.md, Limits)",
        )


#: Seconds without any finished sample after which a dask run gives up (docs/studies.md): far above
#: one sample of the default study (about 30 s for a 1 s record on one core).
PROGRESS_TIMEOUT = 900.0
