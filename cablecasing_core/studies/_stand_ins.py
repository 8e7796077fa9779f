"""Stand-ins for the studies' per-sample function (Section 4.4's ``evaluate(overrides, **kwargs) ->
dict``) used by the tests and the study benchmark; none of them is physics. They live in the
package, not in tests/, because a study's dask workers import its evaluate by a dotted path
(``cablecasing_core.studies._stand_ins:analytic_evaluate``; :func:`~.executor.resolve_evaluate`).

* :func:`analytic_evaluate`: closed-form 'band levels' of the varied parameters, deterministic.
* :func:`faulty_evaluate`: kills its worker or the scheduler, or stalls, while a trigger file exists.
* :func:`cpu_burn_evaluate`: a fixed amount of CPU work per sample (the study benchmark).
* :func:`ishigami_evaluate`: the Ishigami function, whose Sobol indices are known in closed form.
"""

from __future__ import annotations

import zlib
from functools import cache

import numpy as np

from .sampling import AXIAL_AMPLITUDE_KEY


@cache
def _specimen():
    """The built-in specimen's parameters (:func:`~cablecasing_core.model.default_model`), read once
    per process: the values :func:`analytic_evaluate` takes for the keys a sample does not vary."""
    from ..model import default_model

    return default_model().parameters()


def analytic_evaluate(overrides, fail_above=None, **_):
    """Cheap deterministic closed-form 'band levels' (N) for tests, one per output of the default
    study (``evaluators.DEFAULT_OUTPUTS``): no physics, Section 4.4 shape only.

    level_j = 1e3 * amplitude * (casing.E / E_s)^(j/9) * (cable.E / E_c)^0.1 / (1 + 5 friction)
              * (1 + 100 (gap - 1e-3) (5 - j)),  j = 1..9, gap = casing.d_inner - cable.d (m),
    amplitude the cable's axial excitation amplitude (m), E_s and E_c (Pa) the built-in specimen's
    moduli (5e9 and 5.5e10); a key the overrides do not give takes the specimen's value (friction
    0.15, the schema's default, gap 1 mm, amplitude 5e-4 m).
    Raises ValueError when ``fail_above`` is given and contact.friction exceeds it (deterministic
    failures for the tests).
    """
    from .evaluators import DEFAULT_OUTPUTS  # (evaluators imports this module: not at the top)

    p = {k: float(v) for k, v in overrides.items()}
    spec = _specimen()
    given = lambda key: p.get(key, spec[key])  # noqa: E731
    fr = given("contact.friction")
    if fail_above is not None and fr > fail_above:
        raise ValueError(f"contact.friction = {fr!r} above the test threshold {fail_above}")
    amp = given(AXIAL_AMPLITUDE_KEY)
    gap = given("casing.d_inner") - given("cable.d")
    out = {}
    for j, lab in enumerate(DEFAULT_OUTPUTS, start=1):
        out[lab] = (
            1e3
            * amp
            * (given("casing.E") / spec["casing.E"]) ** (j / 9)
            * (given("cable.E") / spec["cable.E"]) ** 0.1
            / (1 + 5 * fr)
            * (1 + 100 * (gap - 1e-3) * (5 - j))
        )
    return out


def faulty_evaluate(overrides, trigger=None, action="kill_worker", pid_file=None, **kwargs):
    """A stand-in for the tests of the study's infrastructure failures (no physics): while the file
    ``trigger`` exists, ``action`` happens instead of the evaluation: ``"kill_worker"`` kills the
    process that runs the sample (SIGKILL), ``"kill_scheduler"`` kills the process whose id is in
    ``pid_file``, ``"stall"`` sleeps for an hour. Otherwise :func:`analytic_evaluate` of
    ``overrides`` (with ``kwargs``)."""
    import os
    import signal
    import time

    if trigger is not None and os.path.exists(trigger):
        if action == "kill_worker":
            os.kill(os.getpid(), signal.SIGKILL)
        elif action == "kill_scheduler":
            with open(pid_file) as fh:
                os.kill(int(fh.read().strip()), signal.SIGKILL)
        time.sleep(3600.0)
    return analytic_evaluate(overrides, **kwargs)


def cpu_burn_evaluate(overrides, repeats=200, n=2**12, **_):
    """Benchmark stand-in for the engine: a fixed amount of CPU work per sample (not a fixed time).

    Builds a synthetic 'force' record of ``n`` samples at 16384 Hz from the parameters and computes
    its Table 3 octave RMS ``repeats`` times (numpy FFTs, single-threaded). The default 4096-sample
    record keeps the working set in cache, like the engine's small banded matrices, so the work is
    compute-bound. Returns band RMS (N).
    """
    from ..nvh.bands import octave_rms

    fs = 16384.0
    t = np.arange(n) / fs
    p = {k: float(v) for k, v in overrides.items()}
    rng = np.random.default_rng(zlib.crc32(repr(sorted(p.items())).encode()))
    x = p.get(AXIAL_AMPLITUDE_KEY, 5e-4) * 1e3 * np.sin(2 * np.pi * 50 * t) + rng.standard_normal(n)
    res = None
    for _ in range(int(repeats)):
        res = octave_rms(x, fs)
    return res.as_dict()


def ishigami_evaluate(overrides, a=7.0, b=0.1, **_):
    """The Ishigami function, a stand-in with closed-form Sobol indices (benchmarks.md, "Sensitivity
    analysis"): ``f = sin x1 + a sin^2 x2 + b x3^4 sin x1`` of the overrides ``x1``, ``x2``, ``x3``
    (uniform on [-pi, pi] in the test), returned as the output ``"f"``. No physics."""
    x1, x2, x3 = (float(overrides[k]) for k in ("x1", "x2", "x3"))
    return {"f": np.sin(x1) + a * np.sin(x2) ** 2 + b * x3**4 * np.sin(x1)}
