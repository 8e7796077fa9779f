"""The Monte-Carlo study of Section 4.4 (Fig. 23): :func:`run_study`.

The paper varies six parameters of the cable-casing system (over 300 simulations) and correlates
each with the RMS of the support force in z in the octave bands of Table 3. Here any numeric keys of
any model can be varied within bounds (default: the paper's six, :data:`~.sampling.PAPER_BOUNDS`),
checked against the model and the schema before any run; the runs follow Saltelli's design on a
scrambled Sobol' sequence (:mod:`.sampling`), so that besides the correlations (:mod:`.correlation`)
the first-order and total Sobol indices follow (:mod:`.sensitivity`). Each run is evaluated by a
per-sample function (:mod:`.evaluators`) in this process or on dask.distributed (:mod:`.executor`),
and every row goes to a resumable CSV (:mod:`.results_store`).

* **Per-sample function**: ``evaluate(overrides: dict[str, float], **evaluate_kwargs) ->
  dict[str, float]`` (output name -> value, e.g. band label -> RMS in N). Pass it as a dotted import
  path ``"package.module:function"`` (what dask workers import) or as a callable.
  :func:`~.evaluators.default_evaluate` is the time-domain evaluation (engine run, octave RMS of
  ``casing.B.Fz``). A function with the attribute ``placeholder = True`` is refused before starting.
* **Results**: an append-only CSV, one row per run, flushed and fsynced per row: ``index, status,
  <parameters>, <outputs>, warnings, elapsed_s, error``. Status is ``ok``, ``failed`` (the exception,
  or the output that was not a finite number, is in ``error``; the study goes on) or ``infeasible``
  (a constraint rejected the sample before evaluation; the reason is in ``error``); ``warnings``
  holds what the run warned. A sidecar ``<csv>.meta.json`` holds the seed, bounds, size, outputs,
  evaluate and the fingerprint of the model evaluate runs; a restart with the same
  settings reads the CSV and skips every index already present (a failed sample is *not* retried),
  so no sample is repeated; a restart with more samples continues the sequence and runs only the new
  ones. A torn last line (process killed mid-write) is cut off and that sample is run again.
"""

from __future__ import annotations

import inspect
import json
import os
import warnings

from ..errors import ModelError, ModelWarning
from ..files import output_folder
from ..model.limits import MAX_STUDY_SAMPLES
from ..model.validators import integer
from .evaluators import DEFAULT_EVALUATE, DEFAULT_OUTPUTS, RECORD_SETTINGS
from .executor import (
    PROGRESS_TIMEOUT,
    Workers,
    check_packages,
    check_scheduler,
    execute,
    kernel_environments,
    resolve_evaluate,
    spec_name,
)
from .results_store import (
    FORMAT_VERSION,
    META_COLUMNS,
    TAIL_COLUMNS,
    WARNINGS_COLUMN,
    LostLog,
    ResultsWriter,
    StudyResults,
    load_results,
    prepare_file,
    read_meta,
    recover_header,
    study_lock,
)
from .sampling import DEFAULT_CONSTRAINTS, base_points, check_bounds, group_size, sobol_design

#: How the design is made (stored in the sidecar; a resume must use the same).
SAMPLER = "SALib.sample.sobol.sample(calc_second_order=False, scramble=True): Saltelli on scipy.stats.qmc.Sobol"


def run_study(
    path,
    evaluate=DEFAULT_EVALUATE,
    bounds=None,
    n_samples=300,
    seed=0,
    *,
    outputs=None,
    quantity=None,
    evaluate_kwargs=None,
    scheduler=None,
    n_workers=None,
    max_samples=None,
    constraints=DEFAULT_CONSTRAINTS,
    model=None,
    progress=True,
    max_in_flight=None,
    progress_timeout=PROGRESS_TIMEOUT,
) -> StudyResults:
    """Run (or resume) the Monte-Carlo study of Section 4.4 and write every sample to ``path`` (CSV).

    Parameters
    ----------
    path : str
        Results CSV (created with a ``.meta.json`` sidecar; resumed if it exists with equal settings).
    evaluate : str or callable
        ``evaluate(overrides, **evaluate_kwargs) -> {output: value}``; a dotted path
        ``"package.module:function"`` is imported on each worker. Default :func:`default_evaluate`.
    bounds : dict, optional
        ``{dotted.key: (low, high)}`` in SI units; default :data:`PAPER_BOUNDS` (Section 4.4). A key
        that a setting of evaluate given in ``evaluate_kwargs`` takes the place of (its attribute
        ``run_settings``: ``duration`` of :func:`default_evaluate` over ``scenario.duration``, ``dt``
        over ``scenario.dt``) is refused: the samples would not vary it.
    n_samples, seed : int
        Runs asked for (>= 2), rounded up to whole groups of d + 2 runs of Saltelli's design (at least
        two base points), and the seed of the scrambled Sobol' sequence (>= 0). A file holding a larger
        study keeps its size; a smaller one is enlarged (the sequence continues; nothing is recomputed).
    outputs : sequence of str, optional
        Output names to record, default the Table 3 labels ``oct1`` .. ``oct9``.
    quantity : dict, optional
        What each output is a value of, ``{"name": "casing.B.Fz", "unit": "N", "what": "band RMS"}``:
        kept in the sidecar and named in the CSV's header (``casing.B.Fz oct1 [N]``), the tables and
        figures.
    evaluate_kwargs : dict, optional
        Extra keyword arguments of evaluate (JSON-serialisable; stored in the sidecar).
    scheduler : None, "serial", "threads", "local", str address or distributed.Client
        ``None``/``"local"``: a LocalCluster with ``n_workers`` (default: one per core) worker
        processes of one thread each; ``"serial"``: in this process, no dask; ``"threads"``: in this
        process on ``n_workers`` threads (default: one per core), no dask (docs/studies.md, "Where
        the samples run"); ``"tcp://host:8786"``: an existing cluster; a Client: use it (left open).
    max_samples : int, optional
        Evaluate at most this many new samples in this call (the rest on a later resume).
    constraints : sequence of callables
        ``constraint(params) -> None or reason``, ``params`` the sample's values over the model's
        other numeric parameters (``Model.parameters()``; the sample's alone with ``model=False``); a
        rejected sample is written as ``infeasible`` without evaluation (a warning when most of
        those to run are). Default: the cable must fit in the casing (:func:`gap_constraint`).
    model : Model, str, None or False
        The model of the study: ``bounds`` must name its keys, the constraints see its values, and
        evaluate runs it: a TOML path or a specimen's name is given to evaluate as ``model_file``
        (stored in the sidecar), a Model as ``model`` (an evaluate without that parameter is
        refused), and its fingerprint is recorded (a resume must run the same model). None: the
        model of ``evaluate_kwargs["model_file"]``, else the built-in specimen (evaluate gets no
        model); False: no model checks.
    progress : bool
        Show a tqdm bar (samples done, rate, time left).
    max_in_flight : int, optional
        Tasks submitted ahead to dask (default 4 per worker).
    progress_timeout : float
        Seconds without a finished sample after which a dask run stops with an
        :class:`~cablecasing_core.errors.InfrastructureError` naming the cause (default
        :data:`~.executor.PROGRESS_TIMEOUT`).

    Returns
    -------
    StudyResults
        Everything in the file after this call.
    """
    if not (isinstance(evaluate, str) or callable(evaluate)):
        raise ModelError("evaluate", evaluate, "must be a callable or a dotted import path 'package.module:function'")
    fn = resolve_evaluate(evaluate)
    evaluate_kwargs = dict(evaluate_kwargs or {})
    if spec_name(evaluate) == DEFAULT_EVALUATE:  # (stored, so that a resume compares them: results_store)
        evaluate_kwargs = RECORD_SETTINGS | evaluate_kwargs
    the_model, stored, passed, fingerprint = _study_model(evaluate, fn, model, evaluate_kwargs)
    evaluate_kwargs.update(stored)
    # (a setting of evaluate that takes the place of a model key, default_evaluate's duration and dt: that key
    # is not varied beside it)
    settings = {k: (k, evaluate_kwargs.get(k)) for k in getattr(fn, "run_settings", ())}
    bounds = check_bounds(bounds, model=False if the_model is None else the_model, settings=settings)
    n = integer("n_samples", n_samples, 2, MAX_STUDY_SAMPLES, " (model/limits.py: its design and CSV would not fit)")
    seed = integer("seed", seed, 0)
    outputs = tuple(DEFAULT_OUTPUTS if outputs is None else outputs)
    if not outputs or len(set(outputs)) != len(outputs) or not all(isinstance(o, str) and o for o in outputs):
        raise ModelError("outputs", outputs, "must be a non-empty sequence of unique output names")
    clash = set(outputs) & (set(bounds) | set(META_COLUMNS) | {WARNINGS_COLUMN} | set(TAIL_COLUMNS))
    if clash:
        raise ModelError(
            "outputs", sorted(clash), "must not reuse a parameter name or index/status/warnings/elapsed_s/error"
        )
    if quantity is not None and not (
        isinstance(quantity, dict) and all(isinstance(quantity.get(k), str) for k in ("name", "unit"))
    ):
        raise ModelError("quantity", quantity, "must be a dict with the strings 'name' and 'unit' (and 'what')")
    if max_samples is not None:
        max_samples = integer("max_samples", max_samples, 0)
    try:
        json.dumps(evaluate_kwargs)
    except TypeError as exc:
        raise ModelError("evaluate_kwargs", evaluate_kwargs, f"must be JSON-serialisable ({exc})") from None
    if getattr(fn, "placeholder", False):  # fail early on a bad path or a placeholder
        fn({})
    check_scheduler(scheduler)
    constraints = tuple(constraints or ())
    check = getattr(fn, "check_settings", None)  # settings that make every sample fail, refused first
    if check is not None:
        check(evaluate_kwargs, model=the_model)
    check_packages(scheduler)  # (SALib's design, and dask unless serial: refused before any file)
    path = str(path)
    params = tuple(bounds)
    check_samples = getattr(fn, "check_samples", None)  # a study none of whose samples can run, refused first
    if check_samples is not None and the_model is not None:
        _check_samples(check_samples, path, bounds, n, seed, constraints, {**evaluate_kwargs, **passed}, the_model)
    folder, name = os.path.split(os.path.abspath(path))
    output_folder("path", folder, name, create=False)  # (checked before a local cluster starts)
    with Workers(scheduler, n_workers) as workers:  # (an unreachable scheduler is refused before any file)
        output_folder("path", folder, name)
        with study_lock(path):
            recover_header(path, params, outputs, quantity)
            # (the design, the file prepared or resumed, the samples not yet done run)
            old = read_meta(path)
            n_base = _base_points_of(bounds, n, old)
            n = n_base * group_size(bounds)
            design = sobol_design(bounds, n_base, seed)
            meta = {
                "format": FORMAT_VERSION,
                "seed": seed,
                "n_base": n_base,
                "n_samples": n,
                "bounds": {k: list(v) for k, v in bounds.items()},
                "outputs": list(outputs),
                "quantity": quantity,
                "evaluate": spec_name(evaluate),
                "evaluate_kwargs": evaluate_kwargs,
                "constraints": [spec_name(c) for c in constraints],
                "sampler": SAMPLER,
                "warnings": True,  # (the CSV has the warnings column; prepare_file drops it for an older study)
                "units": True,  # (its parameter columns name their units; the same)
            }
            if fingerprint is not None:  # (the model evaluate runs: a resume must run the same)
                meta["model_fingerprint"] = fingerprint
            meta["kernels"], other_kernels = _kernels(path, old, kernel_environments(workers))
            done = prepare_file(path, meta, design, params)
            if other_kernels:  # (said once the study is resumed, not before a refusal)
                warnings.warn(other_kernels, ModelWarning, stacklevel=2)

            writer = ResultsWriter(path, params, outputs, design, warnings=meta.get("warnings") is True)
            fixed = {} if the_model is None else the_model.parameters()  # (what the constraints see besides)
            try:
                todo, rejected = [], []
                for i, p, reason in _samples(
                    design, params, fixed, constraints, [i for i in range(n) if i not in done]
                ):
                    if reason:
                        writer.write({"index": i, "status": "infeasible", "error": reason, "elapsed_s": 0.0})
                        done.add(i)
                        rejected.append((i, reason))
                        continue
                    todo.append((i, p))
                if 2 * len(rejected) > len(rejected) + len(todo):
                    warnings.warn(
                        f"{len(rejected)} of the {len(rejected) + len(todo)} samples to run are infeasible (sample "
                        f"{rejected[0][0]}: {rejected[0][1]}): the bounds put most of the box outside the constraints; "
                        "narrow them",
                        ModelWarning,
                        stacklevel=2,
                    )
                if max_samples is not None:
                    todo = todo[:max_samples]
                from tqdm.auto import tqdm

                bar = tqdm(
                    total=n,
                    initial=len(done),
                    unit="sample",
                    desc="study",
                    disable=not progress,
                    dynamic_ncols=True,
                    smoothing=0.1,
                )
                try:
                    execute(
                        todo,
                        evaluate,
                        {**evaluate_kwargs, **passed},
                        outputs,
                        writer,
                        bar,
                        workers,
                        max_in_flight=max_in_flight,
                        progress_timeout=progress_timeout,
                        lost=LostLog(path),
                    )
                finally:
                    bar.close()
            finally:
                writer.close()
    return load_results(path)


def _kernels(path, old, now):
    """The sidecar's ``kernels``: the :func:`~.executor.kernel_environment` of every process that has
    run samples of the study (``old``'s list, then those of ``now`` it lacks), and what is warned
    when this run's processes have kernels the study's earlier rows were not computed with, or
    differ among themselves (dask workers of mixed machines; None when neither): its rows are not
    bitwise those the other processes give (docs/studies.md, "Where the samples run")."""
    before = old.get("kernels") if old is not None and isinstance(old.get("kernels"), list) else []
    new = [env for env in now if env not in before]
    kernels = before + new
    if not new or len(kernels) < 2:
        return kernels, None
    then, other = (before[-1], new[0]) if before else (new[0], new[1])
    differ = sorted({k for k in set(other) | set(then) if other.get(k) != then.get(k)})
    first, second = ("then", "now") if before else ("on one", "on another")
    said = "; ".join(f"{k} {then.get(k, 'not set')!r} {first}, {other.get(k, 'not set')!r} {second}" for k in differ)
    what = (
        f"the study in {path} goes on with other floating-point kernels than its rows so far were computed with"
        if before
        else f"the workers of this run of the study in {path} have different floating-point kernels"
    )
    note = (
        f"{what} ({said}): its rows are not bitwise what the other processes give (with contact, another draw of the "
        'chaotic response); docs/studies.md, "Where the samples run"'
    )
    return kernels, note


def _check_samples(check_samples, path, bounds, n, seed, constraints, kwargs, model):
    """``check_samples(kwargs, samples, bounds, model=)`` of evaluate (``default_evaluate``'s: a
    study none of whose samples can start, refused) on the samples of the design in order, those
    the constraints reject left out: the design of the study's size (that of a study in ``path``
    when larger, as the run takes it). What the check warns is not said: the runs say it, each
    message with its sample, and a sample the check refuses or a study already complete does not run."""
    try:
        old = read_meta(path)
    except ModelError:  # (an unreadable sidecar: refused by the run, which names it)
        old = None
    design = sobol_design(bounds, _base_points_of(bounds, n, old), seed)
    every = _samples(design, tuple(bounds), model.parameters(), constraints, range(len(design)))
    with warnings.catch_warnings(record=True):  # (dropped: docs/studies.md, "Warnings")
        warnings.simplefilter("always")  # (recorded, not raised under an "error" filter)
        check_samples(kwargs, ((i, p) for i, p, reason in every if not reason), bounds, model=model)


def _base_points_of(bounds, n, old):
    """The base points of a study of ``n`` samples over ``bounds`` whose file's sidecar is ``old``
    (None: a new study): :func:`base_points`, or the file's when larger (a study is never shrunk)."""
    n_base = base_points(bounds, n)
    if old is not None and isinstance(old.get("n_base"), int):
        n_base = max(n_base, old["n_base"])
    return n_base


def _samples(design, params, fixed, constraints, indices):
    """``(i, p, reason)`` for each sample ``i`` of ``indices``: its parameters ``p`` ({key: value}
    from row i of ``design``) and the first reason a constraint gives to reject it, seeing ``fixed``
    (the model's values) besides ``p`` (None: feasible)."""
    for i in indices:
        p = {k: float(v) for k, v in zip(params, design[i])}
        yield i, p, next((r for r in (c({**fixed, **p}) for c in constraints) if r), None)


def _study_model(evaluate, fn, model, evaluate_kwargs):
    """The model of a study: ``(model, stored, passed, fingerprint)``: the Model the bounds are
    checked against and whose values the constraints see besides the sample's (None with
    ``model=False``), the keyword arguments of evaluate that give it (``stored`` in the sidecar's
    evaluate_kwargs, or only ``passed``) and its fingerprint when evaluate runs it (None otherwise).

    A ``model_file`` of ``evaluate_kwargs`` is the study's model (``model``, if given too, must be the
    same). Else a given ``model`` is given to evaluate, a path or a specimen's name as ``model_file``
    (a path made absolute: workers run in any folder), a Model as ``model``; an evaluate without that
    parameter is refused (it would run a model other than the one checked). With ``model=None``
    evaluate gets nothing and the bounds are checked against the built-in specimen."""
    from pathlib import Path

    from ..model import Model, load_model
    from ..model.load import specimen_names

    if not (model is None or model is False or isinstance(model, (Model, str, os.PathLike))):
        raise ModelError("model", model, "must be a Model, a model TOML path, a specimen's name, None or False")
    if "model_file" in evaluate_kwargs:
        runs = load_model(evaluate_kwargs["model_file"])
        given = model if isinstance(model, Model) or model in (None, False) else load_model(model)
        if isinstance(given, Model) and given.fingerprint() != runs.fingerprint():
            raise ModelError(
                "model",
                given.source,
                f"must be the model of evaluate_kwargs['model_file'] = {evaluate_kwargs['model_file']!r} (which "
                "evaluate runs), or None",
            )
        return (None if model is False else runs), {}, {}, runs.fingerprint()
    if model is None or model is False:
        return (None if model is False else load_model(None)), {}, {}, None
    name = "model" if isinstance(model, Model) else "model_file"
    try:
        takes = inspect.signature(fn).parameters.get(name)
    except (TypeError, ValueError):  # (no signature to read)
        takes = None
    if takes is None or takes.kind not in (takes.POSITIONAL_OR_KEYWORD, takes.KEYWORD_ONLY):
        raise ModelError(
            "model",
            model.source if isinstance(model, Model) else str(model),
            f"is given, but evaluate {spec_name(evaluate)} has no parameter {name!r} to run it (a "
            f"{type(model).__name__} is given as {name}=); give an evaluate that takes it, or model=None (the bounds "
            "checked against the built-in specimen) or False (against no model)",
        )
    if isinstance(model, Model):
        return model, {}, {"model": model}, model.fingerprint()
    m = load_model(model)
    file = model if isinstance(model, str) and model in specimen_names() else str(Path(model).resolve())
    return m, {"model_file": file}, {}, m.fingerprint()
