"""Monte-Carlo correlation study of Section 4.4 (Fig. 23): Latin hypercube sampling, resumable
CSV results, serial or dask.distributed execution, Pearson/Spearman correlations and the figure.

The paper varies six parameters of the cable-casing system (over 300 simulations) and correlates
each with the RMS of the support force in z in the octave bands of Table 3. Here:

* **Sampling** (:func:`latin_hypercube`): ``scipy.stats.qmc.LatinHypercube(d, rng=seed)`` with
  ``scramble=True`` (a random point inside each stratum), scaled to the bounds. The design is a
  pure function of ``(bounds, n_samples, seed)``; sample ``i`` is row ``i`` of it, so it is the same
  in serial and in parallel runs and after a restart.
* **Per-sample function**: ``evaluate(overrides: dict[str, float], **evaluate_kwargs) ->
  dict[str, float]`` (output name -> value, e.g. band label -> RMS in N). Pass it as a dotted import
  path ``"package.module:function"`` (what dask workers import) or as a callable.
  :func:`default_evaluate` is the time-domain evaluation (engine run, octave RMS of
  ``casing.B.Fz``). A function with the attribute ``placeholder = True`` is refused before starting.
* **Results** (:func:`run_study`): an append-only CSV, one row per sample, flushed and fsynced per
  row: ``index, status, <parameters>, <outputs>, elapsed_s, error``. Status is ``ok``, ``failed``
  (the exception is in ``error``; the study goes on) or ``infeasible`` (a constraint rejected the
  sample before evaluation; the reason is in ``error``). A sidecar ``<csv>.meta.json`` holds the
  seed, bounds, sample count, outputs and evaluate; a restart with the same settings reads the CSV
  and skips every index already present (a failed sample is *not* retried), so no sample is
  repeated. A torn last line (process killed mid-write) is cut off and that sample is run again.
* **Correlation** (:func:`correlations`, :func:`plot_correlations`): Pearson and Spearman
  coefficients of each parameter, and of the derived ``gap = casing.d_inner - cable.d`` (m, as in
  Fig. 23(c)), with each output over the ``ok`` samples.

Infeasible samples: the cable must fit in the casing (``cable.d < casing.d_inner``). With the
paper's bounds this always holds (max cable.d 3.3 mm < min casing.d_inner 3.4 mm). For other bounds
the study *rejects* such samples (status ``infeasible``, reason recorded) rather than sampling the
gap, so that the six named parameters keep their Latin-hypercube stratification.
"""
from __future__ import annotations

import csv
import importlib
import io
import json
import math
import os
import time
import warnings
import zlib
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .octave import octave_bands, octave_rms

#: Model key of the amplitude (m) of the cable's longitudinal (axial) excitation, \bar X_jv of Section 4.4.
AXIAL_AMPLITUDE_KEY = "scenario.excitation.cable_axial.amplitude"

#: The six parameters of Section 4.4 with their bounds (SI). The paper gives no bounds for the
#: axial amplitude; 0.5x-2x the built-in 5e-4 m (displacement amplitude along the cable tangent,
#: the unit of the scenario's harmonic excitation) is used.
PAPER_BOUNDS = {
    "cable.E": (3.0e10, 8.5e10),          # Pa, E_jv
    "casing.E": (0.2e10, 1.0e10),         # Pa, E_op
    "cable.d": (0.003, 0.0033),           # m, D_z0
    "casing.d_inner": (0.0034, 0.0046),   # m, d_5
    AXIAL_AMPLITUDE_KEY: (2.5e-4, 1.0e-3),  # m, \bar X_jv
    "contact.friction": (0.05, 0.2),      # -, eta
}

#: Output names of the default study: the Table 3 band labels "oct1" .. "oct9".
DEFAULT_OUTPUTS = octave_bands("table3").labels
DEFAULT_EVALUATE = "cablecasing_core.studies.montecarlo:default_evaluate"
META_COLUMNS = ("index", "status")
TAIL_COLUMNS = ("elapsed_s", "error")
STATUSES = ("ok", "failed", "infeasible")
FORMAT_VERSION = 1


# ------------------------------------------------------------------------------------------------
# per-sample functions

def default_evaluate(overrides, duration=None, skip=0.05, dt=None, model_file=None, *, model=None,
                     output="casing.B.Fz", bands="table3", contact_time=False, **kwargs):
    """The per-sample function of Section 4.4: run the time-domain model (the scenario of the model,
    with ``overrides`` applied) and return the octave-band RMS (N, Table 3) of the force at casing end
    B in z, ``{"oct1": N, ..., "oct9": N}``.

    duration (s): simulated time (default ``scenario.duration``); skip (s): start of the record left
    out of the RMS (the support fade-in and the first transient); dt (s): time step (default
    ``scenario.dt``); model_file: a model TOML (default the built-in specimen); model: a
    :class:`~cablecasing_core.config.Model` to use instead of ``model_file``; output: the support
    output whose band levels are returned (N or N.m, a name of ``SUPPORT_OUTPUTS``); bands: the band
    set of :func:`~cablecasing_core.studies.octave.octave_rms`; contact_time: also return the contact
    time per cable node (s, Fig. 22) as ``"contact_time_<i>"``.
    """
    from ..config import load_model
    from ..simulation import simulate

    model = (load_model(model_file) if model is None else model).with_overrides(overrides)
    res = simulate(model, duration=duration, dt=dt)
    keep = res.time > skip
    if keep.sum() < 2:
        raise ModelError("skip", skip, f"must leave part of the {res.time[-1]:.6g} s record for the RMS")
    fs = 1.0 / (res.time[1] - res.time[0])
    out = octave_rms(res.support_force(output)[keep], fs, bands).as_dict()
    if contact_time:
        out.update({f"contact_time_{i}": float(v) for i, v in enumerate(res.contact_time)})
    return out


def _analytic_evaluate(overrides, fail_above=None, **_):
    """Cheap deterministic closed-form 'band levels' (N) for tests: no physics, Section 4.4 shape only.

    level_j = 1e3 * amplitude * (casing.E / 5e9)^(j/9) * (cable.E / 5.5e10)^0.1 / (1 + 5 friction)
              * (1 + 100 (gap - 1e-3) (5 - j)),  j = 1..9, gap = casing.d_inner - cable.d (m).
    Raises ValueError when ``fail_above`` is given and contact.friction exceeds it (deterministic
    failures for the tests).
    """
    p = {k: float(v) for k, v in overrides.items()}
    fr = p.get("contact.friction", 0.15)
    if fail_above is not None and fr > fail_above:
        raise ValueError(f"contact.friction = {fr!r} above the test threshold {fail_above}")
    amp = p.get(AXIAL_AMPLITUDE_KEY, 5e-4)
    gap = p.get("casing.d_inner", 0.004) - p.get("cable.d", 0.003)
    out = {}
    for j, lab in enumerate(DEFAULT_OUTPUTS, start=1):
        out[lab] = (1e3 * amp * (p.get("casing.E", 5e9) / 5e9) ** (j / 9) * (p.get("cable.E", 5.5e10) / 5.5e10) ** 0.1
                    / (1 + 5 * fr) * (1 + 100 * (gap - 1e-3) * (5 - j)))
    return out


def _cpu_burn_evaluate(overrides, repeats=200, n=2 ** 12, **_):
    """Benchmark stand-in for the engine: a fixed amount of CPU work per sample (not a fixed time).

    Builds a synthetic 'force' record of ``n`` samples at 16384 Hz from the parameters and computes
    its Table 3 octave RMS ``repeats`` times (numpy FFTs, single-threaded). The default 4096-sample
    record keeps the working set in cache, like the engine's small banded matrices, so the work is
    compute-bound. Returns band RMS (N).
    """
    from .octave import octave_rms
    fs = 16384.0
    t = np.arange(n) / fs
    p = {k: float(v) for k, v in overrides.items()}
    rng = np.random.default_rng(zlib.crc32(repr(sorted(p.items())).encode()))
    x = p.get(AXIAL_AMPLITUDE_KEY, 5e-4) * 1e3 * np.sin(2 * np.pi * 50 * t) + rng.standard_normal(n)
    res = None
    for _ in range(int(repeats)):
        res = octave_rms(x, fs)
    return res.as_dict()


def resolve_evaluate(spec):
    """The per-sample function of the study (Section 4.4) named by ``spec``: a callable (returned as
    is) or ``"package.module:function"`` (also ``"package.module.function"``). Raises ModelError if
    it cannot be imported."""
    if callable(spec):
        return spec
    if not isinstance(spec, str) or not spec:
        raise ModelError("evaluate", spec, "must be a callable or a dotted import path 'package.module:function'")
    mod_name, sep, attr = spec.partition(":")
    if not sep:
        mod_name, _, attr = spec.rpartition(".")
    try:
        fn = getattr(importlib.import_module(mod_name), attr)
    except (ImportError, AttributeError, ValueError) as exc:
        raise ModelError("evaluate", spec, f"must name an importable function 'package.module:function' ({exc})") from None
    if not callable(fn):
        raise ModelError("evaluate", spec, "must name a callable")
    return fn


def _spec_name(spec):
    if isinstance(spec, str):
        return spec
    return f"{getattr(spec, '__module__', '?')}:{getattr(spec, '__qualname__', repr(spec))}"


def _evaluate_sample(spec, kwargs, index, overrides, outputs):
    """Run one sample (in the main process or on a dask worker); never raises for an Exception."""
    t0 = time.perf_counter()
    row = {"index": index, "status": "ok", "error": ""}
    try:
        res = resolve_evaluate(spec)(dict(overrides), **kwargs)
        if not isinstance(res, dict):
            raise TypeError(f"evaluate returned {type(res).__name__}, expected dict of output name -> float")
        missing = [o for o in outputs if o not in res]
        if missing:
            raise KeyError(f"evaluate returned no value for {missing}; it gave {sorted(res)}")
        for o in outputs:
            row[o] = float(res[o])
    except Exception as exc:  # a failed sample is recorded, the study goes on
        row = {"index": index, "status": "failed", "error": f"{type(exc).__name__}: {exc}".replace("\n", " | ")}
    row["elapsed_s"] = time.perf_counter() - t0
    return row


# ------------------------------------------------------------------------------------------------
# sampling

def check_bounds(bounds=None, model=None):
    """Validated ``{dotted.key: (low, high)}`` (SI units of the key). Section 4.4.

    ``None`` gives :data:`PAPER_BOUNDS`. Every key must be a numeric parameter of ``model`` (a Model,
    a TOML path, or None for the built-in specimen; ``False`` skips the key check). Raises
    ModelError for an unknown key, non-finite bounds or ``low >= high``.
    """
    bounds = dict(PAPER_BOUNDS if bounds is None else bounds)
    if not bounds:
        raise ModelError("bounds", bounds, "must name at least one parameter")
    known = None
    if model is not False:
        from ..config import Model, load_model
        m = model if isinstance(model, Model) else load_model(model)
        known = m.parameters()
    out = {}
    for key, b in bounds.items():
        if not isinstance(key, str):
            raise ModelError("bounds", key, "parameter names must be dotted model keys such as 'casing.E'")
        if known is not None and key not in known:
            raise ModelError(f"bounds.{key}", b, "is not a numeric parameter of the model; known: " + ", ".join(sorted(known)))
        try:
            lo, hi = (float(v) for v in b)
        except (TypeError, ValueError):
            raise ModelError(f"bounds.{key}", b, "must be a pair (low, high) of numbers") from None
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise ModelError(f"bounds.{key}", b, "must be finite numbers")
        if lo >= hi:
            raise ModelError(f"bounds.{key}", b, "lower bound must be below the upper bound")
        out[key] = (lo, hi)
    return out


def _check_int(key, v, minimum):
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < minimum:
        raise ModelError(key, v, f"must be an integer >= {minimum}")
    return int(v)


def latin_hypercube(bounds=None, n_samples=300, seed=0):
    """Latin-hypercube design (n_samples, d) in the bounds' SI units (Section 4.4, "Monte Carlo").

    Columns follow the order of ``bounds`` (default :data:`PAPER_BOUNDS`). Each column has exactly
    one point in each of the ``n_samples`` equal strata of its interval
    (``scipy.stats.qmc.LatinHypercube(d, scramble=True, rng=seed)``). Deterministic in
    (bounds, n_samples, seed). Keys are not checked against a model here (see :func:`check_bounds`).
    """
    bounds = check_bounds(bounds, model=False)
    n = _check_int("n_samples", n_samples, 2)
    seed = _check_int("seed", seed, 0)
    from scipy.stats import qmc
    try:
        sampler = qmc.LatinHypercube(len(bounds), scramble=True, rng=seed)
    except TypeError:                       # scipy < 1.15 names it seed (same default_rng stream)
        sampler = qmc.LatinHypercube(len(bounds), scramble=True, seed=seed)
    unit = sampler.random(n)
    lo = np.array([b[0] for b in bounds.values()])
    hi = np.array([b[1] for b in bounds.values()])
    return qmc.scale(unit, lo, hi)


def gap_constraint(params):
    """Feasibility of a sample (Section 4.4; the radial gap of Eqs. 30-31 must be positive):
    ``None`` if ``cable.d < casing.d_inner`` (both in m), else the reason. Only checked when both
    diameters are sampled; the model's own validation catches the rest at evaluation."""
    if "cable.d" in params and "casing.d_inner" in params and params["cable.d"] >= params["casing.d_inner"]:
        return (f"infeasible: cable.d = {params['cable.d']!r} m is not below casing.d_inner = "
                f"{params['casing.d_inner']!r} m")
    return None


DEFAULT_CONSTRAINTS = (gap_constraint,)


# ------------------------------------------------------------------------------------------------
# results file

@dataclass
class StudyResults:
    """Rows of a Monte-Carlo study (Section 4.4), sorted by sample index.

    index (n,) int; parameters (names); X (n, d) parameter values (SI); outputs (names);
    Y (n, m) output values (NaN where not ok); status (n,) str; error (n,) str; elapsed_s (n,) s.
    """

    index: np.ndarray
    parameters: tuple
    X: np.ndarray
    outputs: tuple
    Y: np.ndarray
    status: np.ndarray
    error: np.ndarray
    elapsed_s: np.ndarray

    @property
    def ok(self):
        """Boolean mask of the successful samples."""
        return self.status == "ok"

    def __len__(self):
        return self.index.size


def _meta_path(path):
    return str(path) + ".meta.json"


def _header(params, outputs):
    return list(META_COLUMNS) + list(params) + list(outputs) + list(TAIL_COLUMNS)


def _fmt(v):
    if isinstance(v, float):
        return repr(v)            # shortest repr round-trips the float exactly
    return str(v)


def _repair_tail(path):
    """Cut a torn last line (no trailing newline) left by a process killed mid-write."""
    with open(path, "rb+") as fh:
        data = fh.read()
        if data and not data.endswith(b"\n"):
            cut = data.rfind(b"\n") + 1
            fh.truncate(cut)
            return True
    return False


def load_results(path):
    """Read a study CSV written by :func:`run_study` into :class:`StudyResults` (sorted by index;
    parameters and outputs in the units they were written in, SI). Section 4.4.

    The parameter and output columns are told from the sidecar ``<path>.meta.json``. If an index
    appears twice (not written by run_study), the first row wins.
    """
    path = str(path)
    try:
        with open(_meta_path(path)) as fh:
            meta = json.load(fh)
        params, outputs = tuple(meta["bounds"]), tuple(meta["outputs"])
    except (OSError, ValueError, KeyError) as exc:
        raise ModelError("path", path, f"must be a study CSV with its {_meta_path(path)} sidecar ({exc})") from None
    header = _header(params, outputs)
    try:
        with open(path, newline="") as fh:
            text = fh.read()
    except OSError as exc:
        raise ModelError("path", path, f"must be a readable study CSV ({exc.strerror})") from None
    if text and not text.endswith("\n"):
        text = text[:text.rfind("\n") + 1]      # a torn last line is ignored (run_study cuts it off)
    reader = csv.reader(io.StringIO(text, newline=""))
    head = next(reader, None)
    if head != header:
        raise ModelError("path", path, f"must have the header {','.join(header)} (found {head})")
    rows = {}
    for lineno, r in enumerate(reader, start=2):
        if len(r) != len(header):
            raise ModelError("path", path, f"line {lineno} has {len(r)} fields, expected {len(header)}")
        rows.setdefault(int(r[0]), r)
    order = sorted(rows)
    d, m = len(params), len(outputs)
    num = lambda s: float(s) if s != "" else np.nan  # noqa: E731
    X = np.array([[num(rows[i][2 + k]) for k in range(d)] for i in order], float).reshape(len(order), d)
    Y = np.array([[num(rows[i][2 + d + k]) for k in range(m)] for i in order], float).reshape(len(order), m)
    return StudyResults(index=np.array(order, int), parameters=params, X=X, outputs=outputs, Y=Y,
                        status=np.array([rows[i][1] for i in order], dtype=object).astype(str),
                        error=np.array([rows[i][-1] for i in order], dtype=object).astype(str),
                        elapsed_s=np.array([num(rows[i][-2]) for i in order], float))


class _Writer:
    """Append-only CSV writer, one flushed and fsynced row per sample."""

    def __init__(self, path, params, outputs, design):
        self.path, self.params, self.outputs, self.design = path, params, outputs, design
        self.fh = open(path, "a", newline="")
        self.w = csv.writer(self.fh)

    def write(self, row):
        i = row["index"]
        vals = [i, row["status"]] + [_fmt(float(v)) for v in self.design[i]]
        vals += [_fmt(row[o]) if o in row else "" for o in self.outputs]
        vals += [f"{row.get('elapsed_s', 0.0):.6g}", row.get("error", "")]
        self.w.writerow(vals)
        self.fh.flush()
        os.fsync(self.fh.fileno())

    def close(self):
        self.fh.close()


def _prepare_file(path, meta, design, params):
    """Create the CSV and sidecar, or check them for a resume. Returns the set of indices present."""
    header = _header(params, meta["outputs"])
    mp = _meta_path(path)
    exists = os.path.exists(path) and os.path.getsize(path) > 0
    if not exists:
        d = os.path.dirname(os.path.abspath(path))
        os.makedirs(d, exist_ok=True)
        with open(mp, "w") as fh:
            json.dump(meta, fh, indent=1)
        with open(path, "w", newline="") as fh:
            csv.writer(fh).writerow(header)
            fh.flush()
            os.fsync(fh.fileno())
        return set()
    try:
        with open(mp) as fh:
            old = json.load(fh)
    except (OSError, ValueError) as exc:
        raise ModelError("path", path, f"exists but its sidecar {mp} cannot be read ({exc}); "
                         "choose a new file to start a study") from None
    for key in ("format", "seed", "n_samples", "bounds", "outputs", "evaluate", "evaluate_kwargs", "constraints"):
        if old.get(key) != meta.get(key):
            raise ModelError(key, meta.get(key), f"must equal {old.get(key)!r} to resume the study in {path} "
                             "(or choose a new file)")
    _repair_tail(path)
    res = load_results(path)
    for j, i in enumerate(res.index):
        if not (0 <= i < len(design)) or not np.array_equal(res.X[j], design[i]):
            raise ModelError("path", path, f"row of sample {i} does not match the design of this seed and bounds")
    return set(int(i) for i in res.index)


# ------------------------------------------------------------------------------------------------
# running

def run_study(path, evaluate=DEFAULT_EVALUATE, bounds=None, n_samples=300, seed=0, *, outputs=None,
              evaluate_kwargs=None, scheduler=None, n_workers=None, max_samples=None,
              constraints=DEFAULT_CONSTRAINTS, model=None, progress=True, max_in_flight=None):
    """Run (or resume) the Monte-Carlo study of Section 4.4 and write every sample to ``path`` (CSV).

    Parameters
    ----------
    path : str
        Results CSV (created with a ``.meta.json`` sidecar; resumed if it exists with equal settings).
    evaluate : str or callable
        ``evaluate(overrides, **evaluate_kwargs) -> {output: value}``; a dotted path
        ``"package.module:function"`` is imported on each worker. Default :func:`default_evaluate`.
    bounds : dict, optional
        ``{dotted.key: (low, high)}`` in SI units; default :data:`PAPER_BOUNDS` (Section 4.4).
    n_samples, seed : int
        Size of the Latin hypercube (>= 2) and its seed (>= 0).
    outputs : sequence of str, optional
        Output names to record, default the Table 3 labels ``oct1`` .. ``oct9``.
    evaluate_kwargs : dict, optional
        Extra keyword arguments of evaluate (JSON-serialisable; stored in the sidecar).
    scheduler : None, "serial", "local", str address or distributed.Client
        ``None``/``"local"``: a LocalCluster with ``n_workers`` (default: one per core) worker
        processes of one thread each; ``"serial"``: in this process, no dask; ``"tcp://host:8786"``:
        an existing cluster; a Client: use it (left open).
    max_samples : int, optional
        Evaluate at most this many new samples in this call (the rest on a later resume).
    constraints : sequence of callables
        ``constraint(params) -> None or reason``; a rejected sample is written as ``infeasible``
        without evaluation. Default: the cable must fit in the casing (:func:`gap_constraint`).
    model : Model, str, None or False
        The model whose keys ``bounds`` must name (None: built-in specimen; False: no check).
    progress : bool
        Show a tqdm bar (samples done, rate, time left).
    max_in_flight : int, optional
        Tasks submitted ahead to dask (default 4 per worker).

    Returns
    -------
    StudyResults
        Everything in the file after this call.
    """
    bounds = check_bounds(bounds, model=model)
    n = _check_int("n_samples", n_samples, 2)
    seed = _check_int("seed", seed, 0)
    outputs = tuple(DEFAULT_OUTPUTS if outputs is None else outputs)
    if not outputs or len(set(outputs)) != len(outputs) or not all(isinstance(o, str) and o for o in outputs):
        raise ModelError("outputs", outputs, "must be a non-empty sequence of unique output names")
    clash = set(outputs) & (set(bounds) | set(META_COLUMNS) | set(TAIL_COLUMNS))
    if clash:
        raise ModelError("outputs", sorted(clash), "must not reuse a parameter name or index/status/elapsed_s/error")
    if max_samples is not None:
        max_samples = _check_int("max_samples", max_samples, 0)
    evaluate_kwargs = dict(evaluate_kwargs or {})
    try:
        json.dumps(evaluate_kwargs)
    except TypeError as exc:
        raise ModelError("evaluate_kwargs", evaluate_kwargs, f"must be JSON-serialisable ({exc})") from None
    if not (isinstance(evaluate, str) or callable(evaluate)):
        raise ModelError("evaluate", evaluate, "must be a callable or a dotted import path 'package.module:function'")
    fn = resolve_evaluate(evaluate)
    if getattr(fn, "placeholder", False):   # fail early on a bad path or a placeholder
        fn({})
    if not (scheduler is None or isinstance(scheduler, str) or type(scheduler).__name__ == "Client"):
        raise ModelError("scheduler", scheduler, "must be None, 'serial', 'local', an address 'tcp://host:8786' or a distributed.Client")
    constraints = tuple(constraints or ())
    path = str(path)
    params = tuple(bounds)
    design = latin_hypercube(bounds, n, seed)
    meta = {"format": FORMAT_VERSION, "seed": seed, "n_samples": n, "bounds": {k: list(v) for k, v in bounds.items()},
            "outputs": list(outputs), "evaluate": _spec_name(evaluate), "evaluate_kwargs": evaluate_kwargs,
            "constraints": [_spec_name(c) for c in constraints],
            "sampler": "scipy.stats.qmc.LatinHypercube(scramble=True)"}
    done = _prepare_file(path, meta, design, params)

    writer = _Writer(path, params, outputs, design)
    try:
        todo = []
        for i in range(n):
            if i in done:
                continue
            p = {k: float(v) for k, v in zip(params, design[i])}
            reason = next((r for r in (c(p) for c in constraints) if r), None)
            if reason:
                writer.write({"index": i, "status": "infeasible", "error": reason, "elapsed_s": 0.0})
                done.add(i)
                continue
            todo.append((i, p))
        if max_samples is not None:
            todo = todo[:max_samples]
        from tqdm.auto import tqdm
        bar = tqdm(total=n, initial=len(done), unit="sample", desc="study", disable=not progress,
                   dynamic_ncols=True, smoothing=0.1)
        try:
            execute(todo, evaluate, evaluate_kwargs, outputs, writer, bar, scheduler, n_workers, max_in_flight)
        finally:
            bar.close()
    finally:
        writer.close()
    return load_results(path)


def execute(todo, evaluate, kwargs, outputs, writer, bar, scheduler, n_workers=None, max_in_flight=None):
    """Evaluate the samples ``todo`` = [(index, overrides), ...] with ``evaluate(overrides, **kwargs)``
    in this process (``scheduler="serial"``) or on dask, passing each row to ``writer.write`` as it
    completes and counting it on ``bar``. A failed sample is a row with status "failed"."""
    if scheduler == "serial":
        for i, p in todo:
            writer.write(_evaluate_sample(evaluate, kwargs, i, p, outputs))
            bar.update(1)
    else:
        _run_dask(todo, evaluate, kwargs, outputs, writer, bar, scheduler, n_workers, max_in_flight)


def _run_dask(todo, evaluate, kwargs, outputs, writer, bar, scheduler, n_workers, max_in_flight):
    """Submit the samples to dask.distributed and write each result as it completes."""
    from distributed import Client, LocalCluster, as_completed
    own_client = cluster = None
    if scheduler is None or scheduler == "local":
        nw = os.cpu_count() if n_workers is None else _check_int("n_workers", n_workers, 1)
        cluster = LocalCluster(n_workers=nw, threads_per_worker=1, processes=True, dashboard_address=None)
        client = own_client = Client(cluster)
    elif isinstance(scheduler, str):
        try:
            client = own_client = Client(scheduler, timeout="30s")
        except (OSError, ValueError) as exc:
            raise ModelError("scheduler", scheduler, f"must be 'serial', 'local' or a reachable scheduler address such as "
                             f"tcp://host:8786 ({exc})") from None
    elif isinstance(scheduler, Client):
        client = scheduler
    else:
        raise ModelError("scheduler", scheduler, "must be None, 'serial', 'local', an address 'tcp://host:8786' or a distributed.Client")
    try:
        if not todo:
            return
        nthreads = max(1, sum(client.nthreads().values()))
        window = max_in_flight or 4 * nthreads
        pending = iter(todo)
        ac = as_completed()
        keyed = {}

        def submit_next():
            item = next(pending, None)
            if item is None:
                return
            i, p = item
            fut = client.submit(_evaluate_sample, evaluate, kwargs, i, p, outputs, pure=False)
            keyed[fut.key] = i
            ac.add(fut)

        for _ in range(window):
            submit_next()
        for fut in ac:
            i = keyed.pop(fut.key)
            try:
                row = fut.result()
            except Exception as exc:   # e.g. a worker died: record and go on
                row = {"index": i, "status": "failed", "error": f"{type(exc).__name__}: {exc}".replace("\n", " | "),
                       "elapsed_s": float("nan")}
            fut.release()
            writer.write(row)
            bar.update(1)
            submit_next()
    finally:
        if own_client is not None:
            own_client.close()
        if cluster is not None:
            cluster.close()


# ------------------------------------------------------------------------------------------------
# correlation (Fig. 23)

GAP = "gap"


@dataclass
class Correlation:
    """Correlation coefficients (dimensionless, -1..1) of parameters (rows) with outputs (columns).

    ``method`` is "pearson" or "spearman"; ``r`` and ``pvalue`` are (len(parameters), len(outputs));
    ``n`` is the number of ok samples used. Section 4.4, Fig. 23.
    """

    method: str
    parameters: tuple
    outputs: tuple
    r: np.ndarray
    pvalue: np.ndarray
    n: int

    def as_dict(self):
        """``{parameter: {output: r}}``."""
        return {p: {o: float(self.r[i, j]) for j, o in enumerate(self.outputs)} for i, p in enumerate(self.parameters)}


def _columns(results, include_gap):
    names = list(results.parameters)
    X = results.X
    if include_gap and "cable.d" in names and "casing.d_inner" in names:
        gap = X[:, names.index("casing.d_inner")] - X[:, names.index("cable.d")]
        names.append(GAP)
        X = np.column_stack([X, gap])
    return tuple(names), X


def correlations(results, method="pearson", include_gap=True):
    """Pearson or Spearman correlation of every parameter with every output over the ok samples.

    ``results`` is a :class:`StudyResults` or a CSV path. With ``include_gap`` and both diameters
    sampled, the derived ``gap = casing.d_inner - cable.d`` (m; Fig. 23(c)) is added as a parameter.
    Uses ``scipy.stats.pearsonr`` / ``spearmanr``; a constant column gives NaN. Section 4.4, Fig. 23.
    """
    from scipy import stats
    if not isinstance(results, StudyResults):
        results = load_results(results)
    if method not in ("pearson", "spearman"):
        raise ModelError("method", method, "must be 'pearson' or 'spearman'")
    names, X = _columns(results, include_gap)
    ok = results.ok & np.all(np.isfinite(results.Y), axis=1)
    n_ok = int(ok.sum())
    if n_ok < 3:
        raise ModelError("results", f"{n_ok} ok samples", "need at least 3 successful samples for a correlation")
    fn = stats.pearsonr if method == "pearson" else stats.spearmanr
    r = np.full((len(names), len(results.outputs)), np.nan)
    pv = np.full_like(r, np.nan)
    for a in range(len(names)):
        for b in range(len(results.outputs)):
            x, y = X[ok, a], results.Y[ok, b]
            if np.ptp(x) == 0 or np.ptp(y) == 0:
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = fn(x, y)
            r[a, b], pv[a, b] = float(res.statistic), float(res.pvalue)
    return Correlation(method=method, parameters=names, outputs=tuple(results.outputs), r=r, pvalue=pv, n=n_ok)


#: Panels of Fig. 23: (a) E_jv, (b) E_op, (c) gap, (d) axial amplitude, (e) friction.
FIG23_PARAMETERS = ("cable.E", "casing.E", GAP, AXIAL_AMPLITUDE_KEY, "contact.friction")
_LABELS = {"cable.E": "$E_{jv}$ (cable.E)", "casing.E": "$E_{op}$ (casing.E)", GAP: "gap = $d_5 - D_{z0}$",
           AXIAL_AMPLITUDE_KEY: r"$\bar X_{jv}$ (axial amplitude)", "contact.friction": r"$\eta$ (contact.friction)",
           "cable.d": "$D_{z0}$ (cable.d)", "casing.d_inner": "$d_5$ (casing.d_inner)"}


def plot_correlations(results, path, parameters=None, methods=("pearson", "spearman"), title=None):
    """Write a figure like Fig. 23 (Section 4.4): one panel per parameter, bars of the correlation
    coefficient (-1..1) per output band, one bar colour per method. Returns ``path``.

    ``parameters`` defaults to Fig. 23's five panels (E_jv, E_op, gap, axial amplitude, friction)
    when they were sampled, else every sampled parameter. Matplotlib, Agg backend.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    if not isinstance(results, StudyResults):
        results = load_results(results)
    cors = [correlations(results, m) for m in methods]
    names = cors[0].parameters
    if parameters is None:
        parameters = [p for p in FIG23_PARAMETERS if p in names]
        if len(parameters) < len(FIG23_PARAMETERS):
            parameters = list(names)
    bad = [p for p in parameters if p not in names]
    if bad:
        raise ModelError("parameters", bad, "must be sampled parameters (or 'gap'): " + ", ".join(names))
    nb = len(results.outputs)
    fig, axes = plt.subplots(len(parameters), 1, figsize=(7, 1.9 * len(parameters) + 0.6), sharex=True, squeeze=False)
    width = 0.8 / len(cors)
    x = np.arange(nb)
    ticks = [o[3:] if o.startswith("oct") else o for o in results.outputs]
    for k, (ax, p) in enumerate(zip(axes[:, 0], parameters)):
        row = names.index(p)
        for m, c in enumerate(cors):
            ax.bar(x + (m - (len(cors) - 1) / 2) * width, c.r[row], width, label=c.method)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_ylim(-1, 1)
        ax.set_ylabel("r (-)")
        ax.set_title(f"({chr(97 + k)}) {_LABELS.get(p, p)}", fontsize=9, loc="left")
        ax.grid(True, axis="y", alpha=0.3)
    axes[-1, 0].set_xticks(x, ticks, rotation=0 if nb <= 12 else 90)
    axes[-1, 0].set_xlabel("octave band (Table 3)" if ticks[0].isdigit() else "band")
    axes[0, 0].legend(fontsize=8, loc="upper right")
    fig.suptitle(title or f"Correlation with band RMS, {cors[0].n} samples (Fig. 23)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
