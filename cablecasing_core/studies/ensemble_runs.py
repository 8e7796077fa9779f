"""The runs of an ensemble over excitation seeds (docs/studies.md): :func:`seed_ensemble` runs the
model once per seed (member ``s`` is exactly the single run with the varied random excitations'
seeds set by :func:`seed_overrides`) and returns the band RMS of one support output per member as an
:class:`~cablecasing_core.studies.ensemble.Ensemble`.

The runs go through the Monte-Carlo study's per-sample function and executor
(:func:`~cablecasing_core.studies.evaluators.default_evaluate`; serial, or dask.distributed), so an
ensemble member is computed exactly like a study sample.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..model.limits import MAX_ENSEMBLE_SEED, MAX_SEEDS
from ..model.schema import STUDY_OUTPUT, SUPPORT_OUTPUTS, clip_outputs
from ..model.validators import Choice, integer, seconds
from ..nvh.bands import WINDOWS, Bands, octave_bands
from ..records import check_column_name
from .ensemble import Ensemble
from .evaluators import DEFAULT_EVALUATE, check_model_runs, check_not_overridden, check_record_settings
from .executor import execute

if TYPE_CHECKING:
    from ..model import Model


def random_excitations(model: Model) -> tuple[str, ...]:
    """Names of the model's random excitations (``[scenario.excitation.NAME]`` with kind random), in
    the order of the model file."""
    return tuple(name for name, e in model.scenario["excitation"].items() if e["kind"] == "random")


def seed_overrides(model: Model, seed: int, excitations: Sequence[str] | None = None) -> dict[str, int]:
    """The model overrides of ensemble member ``seed``: ``{"scenario.excitation.NAME.seed": int}``.

    With one varied excitation, member ``s`` gives it seed ``s``, so a member is the single run of the
    model with that seed. With k excitations, the j-th (0-based, in ``excitations`` order) gets
    ``s * k + j``: distinct records across excitations and members (two excitations with the same
    seed and band would get the same record, fully correlated).
    """
    names = _check_excitations(model, excitations)
    s = integer("seeds", seed, 0)
    k = len(names)
    return {f"scenario.excitation.{n}.seed": s * k + j for j, n in enumerate(names)}


def seeds_varied(clash) -> str:
    """Why an ensemble refuses the changes ``clash`` of keys its members set (:func:`seed_keys`)."""
    why = (
        "; scenario.seed would do nothing: it gives only the seeds of random excitations that give none, and the "
        "ensemble varies all of them"
        if "scenario.seed" in clash
        else ""
    )
    return f"must not set the seeds that the ensemble varies (each member sets them{why})"


def seed_keys(model: Model, excitations: Sequence[str] | None = None) -> set[str]:
    """The model keys whose values the members of an ensemble over ``excitations`` (default: every
    random excitation of ``model``) take the place of: each varied excitation's seed
    (:func:`seed_overrides`), and ``scenario.seed`` when every random excitation is varied (it gives
    only the seeds of random excitations that give none: a change of it would do nothing)."""
    names = _check_excitations(model, excitations)
    keys = set(seed_overrides(model, 0, names))
    if set(names) == set(random_excitations(model)):
        keys.add("scenario.seed")
    return keys


def seed_ensemble(
    model: Model | str | os.PathLike | None = None,
    seeds: int | Sequence[int] = 8,
    *,
    output: str = STUDY_OUTPUT,
    bands: str | Bands = "table3",
    duration: float | None = None,
    dt: float | None = None,
    skip: float | None = None,
    window: str = "hann",
    overrides: Mapping[str, object] | None = None,
    excitations: Sequence[str] | None = None,
    scheduler="serial",
    n_workers: int | None = None,
    progress: bool = False,
) -> Ensemble:
    """Band levels of a support output over an ensemble of excitation seeds.

    Parameters
    ----------
    model : Model, str or None
        The model (a :class:`~cablecasing_core.model.Model`, a TOML path, or None for the built-in
        specimen); its ``[scenario]`` drives every member.
    seeds : int or sequence of int
        ``n`` gives seeds 1..n (n >= 2); or the seeds themselves (unique, >= 0).
    output : str
        Support output, e.g. ``"casing.B.Fz"`` (N) or ``"casing.B.Mx"`` (N.m), a clip's ``"casing.clip0.Fz"``,
        or a sum of them: ``"net.B.Fz"`` (the force into the part end B attaches to), ``"paths.Fz"``, ``"a+b"``.
    bands : str or Bands
        Band set (``"table3"``, ``"octave"``, ``"third"``; Hz).
    duration, dt : float, optional
        s; default the scenario's.
    skip : float, optional
        s; start of each record left out of the band levels (fade-in and first transient); default
        0.05 s lengthened so that the rest holds whole periods of the harmonic excitations
        (:func:`~cablecasing_core.timedomain.scenario.whole_period_skip` of the model with
        ``overrides``; the ensemble's ``settings["skip"]`` holds the value taken).
    window : {"hann", "boxcar"}
        The window of the band levels (:func:`~cablecasing_core.nvh.bands.octave_rms`; Hann's by
        default, the rectangular one to compare with ensembles made with it); kept in ``settings``.
    overrides : dict, optional
        ``{dotted.key: value}`` applied to every member (e.g. ``{"contact.friction": 0.2}``); not a
        key the members set (:func:`seed_keys`: a varied seed, ``scenario.seed``), nor
        ``scenario.duration`` with ``duration`` given or ``scenario.dt`` with ``dt`` (the setting
        would win: the change would do nothing).
    excitations : sequence of str, optional
        Random excitations whose seed is varied (default all; :func:`seed_overrides`).
    scheduler : "serial", "threads", None, "local", address or distributed.Client
        As :func:`~cablecasing_core.studies.study.run_study`; default ``"serial"``: members one
        after the other in this process (no dask needed); ``"threads"``: at once on threads of this
        process.
    progress : bool
        Show a tqdm bar of the members done.

    Returns
    -------
    Ensemble

    Raises
    ------
    ModelError
        For bad input (before any run), and when a member fails (naming its seed and the error).
    """
    return seed_ensembles(
        model,
        seeds,
        outputs=(output,),
        bands=bands,
        duration=duration,
        dt=dt,
        skip=skip,
        window=window,
        overrides=overrides,
        excitations=excitations,
        scheduler=scheduler,
        n_workers=n_workers,
        progress=progress,
    )[output]


def seed_ensembles(
    model: Model | str | os.PathLike | None = None,
    seeds: int | Sequence[int] = 8,
    *,
    outputs: Sequence[str] = (STUDY_OUTPUT,),
    bands: str | Bands = "table3",
    duration: float | None = None,
    dt: float | None = None,
    skip: float | None = None,
    window: str = "hann",
    overrides: Mapping[str, object] | None = None,
    excitations: Sequence[str] | None = None,
    scheduler="serial",
    n_workers: int | None = None,
    progress: bool = False,
) -> dict[str, Ensemble]:
    """The band levels of several support outputs over one ensemble of excitation seeds, from the
    same runs: ``{output: Ensemble}``, each as :func:`seed_ensemble` gives it for that output (the
    same seeds, settings, contact times and warnings), for the cost of one ensemble. The outputs of
    one member are of one record, so they can be compared member by member (e.g. ``casing.B.Fz``
    and ``net.B.Fz``, the force into the part end B attaches to). ``outputs``: one or more support
    outputs (N or N.m), each named once; the other parameters are :func:`seed_ensemble`'s."""
    from ..model import Model, load_model
    from ..timedomain.scenario import whole_period_skip

    if model is None or isinstance(model, (str, os.PathLike)):
        model = load_model(model)
    if not isinstance(model, Model):
        raise ModelError("model", model, "must be a Model, a model TOML path or None (the built-in specimen)")
    seeds = _check_seeds(seeds)
    seconds("duration", duration, none_ok=True)
    seconds("dt", dt, none_ok=True)
    seconds("skip", skip, zero_ok=True, none_ok=True)
    Choice(*WINDOWS)("window", window)
    # (a clip's force too, and a sum of them: net.B.Fz, paths.Fz, a+b, docs/nvh.md "Net forces and paths")
    if isinstance(outputs, str) or not len(outputs) or len(set(outputs)) != len(outputs):
        raise ModelError("outputs", outputs, "must be a sequence of one or more support outputs, each once")
    for output in outputs:
        check_column_name(output, SUPPORT_OUTPUTS + clip_outputs(model), "output")
    band_set = bands if isinstance(bands, Bands) else octave_bands(bands)
    names = _check_excitations(model, excitations)
    overrides = dict(overrides or {})
    clash = sorted(set(overrides) & seed_keys(model, names))
    if clash:
        raise ModelError(f"overrides[{clash[0]!r}]", overrides[clash[0]], seeds_varied(clash))
    check_not_overridden(
        {k: (f"overrides[{k!r}]", v) for k, v in overrides.items()},
        {"duration": ("duration", duration), "dt": ("dt", dt)},
        "every member",
        "; give one of them",
    )
    base = model.with_overrides(overrides)  # validates the overrides before any run
    check_record_settings(base, duration, dt, skip, band_set)  # (the skip as given: None, the default)
    check_model_runs(base, dt)  # (what no seed can run, a tension above the buckling load: refused before the first)
    if skip is None:
        skip = whole_period_skip(base, duration, dt)
    step = base.scenario["dt"] if dt is None else dt
    kwargs = {
        "duration": duration,
        "dt": dt,
        "skip": skip,
        "model": base,
        "output": tuple(outputs),
        "bands": band_set,
        "contact_time": True,
        "window": window,
    }
    # (contact, and so a contact time per cable node, needs the cable and the casing)
    nodes = base.geometry["n_elements"] + 1 if {"cable", "casing"} <= set(base.bodies) else 0
    levels = tuple(f"{o}:{b}" for o in outputs for b in band_set.labels)
    columns = levels + tuple(f"contact_time_{k}" for k in range(nodes))
    todo = [(i, seed_overrides(base, s, names)) for i, s in enumerate(seeds)]

    rows = _Rows()
    bar = _progress_bar(len(todo), progress)
    try:
        label = lambda i: f"seed {seeds[i]}"  # noqa: E731
        execute(todo, DEFAULT_EVALUATE, kwargs, columns, rows, bar, scheduler, n_workers, label=label)
    finally:
        bar.close()
    failed = [(seeds[i], r["error"]) for i, r in sorted(rows.rows.items()) if r["status"] != "ok"]
    if failed:
        s, err = failed[0]
        raise ModelError("seeds", s, f"run failed ({err}); {len(failed)} of {len(seeds)} members failed")
    table = np.array([[rows.rows[i][c] for c in columns] for i in range(len(seeds))])
    nb = len(band_set.labels)
    settings = {
        "duration": float(base.scenario["duration"] if duration is None else duration),
        "dt": float(step),
        "skip": float(skip),
        "window": window,
        "model": base.fingerprint(),
        "base_model": model.fingerprint(),  # (before the overrides: two ensembles compared must share it)
    }
    warned = {int(seeds[i]): r["warnings"] for i, r in sorted(rows.rows.items()) if r.get("warnings")}
    return {
        output: Ensemble(
            np.array(seeds),
            output,
            tuple(band_set.labels),
            np.asarray(band_set.lower, float),
            np.asarray(band_set.upper, float),
            table[:, k * nb : (k + 1) * nb],
            dict(overrides),
            table[:, len(levels) :].copy(),
            dict(settings),
            dict(warned),
        )
        for k, output in enumerate(outputs)
    }


class _NoBar:
    def update(self, n):
        pass

    def close(self):
        pass


def _progress_bar(total, progress):
    """A tqdm bar of the members done (none if tqdm cannot be imported)."""
    if progress:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return _NoBar()
        return tqdm(total=total, unit="run", desc="ensemble", dynamic_ncols=True)
    return _NoBar()


class _Rows:
    """Collects the executor's rows by index (the ``writer`` of ``executor.execute``)."""

    def __init__(self):
        self.rows = {}

    def write(self, row):
        self.rows[row["index"]] = row


def _check_seeds(seeds):
    if isinstance(seeds, (int, np.integer)) and not isinstance(seeds, bool):
        if not 2 <= seeds <= MAX_SEEDS:
            raise ModelError("seeds", seeds, f"must be 2 to {MAX_SEEDS} (seeds 1..n), or a sequence of seeds")
        return list(range(1, int(seeds) + 1))
    try:
        why = " (an ensemble's CSV holds its seeds exactly up to 2**53)"
        out = [integer("seeds", s, 0, MAX_ENSEMBLE_SEED, why) for s in seeds]
    except TypeError:
        raise ModelError("seeds", seeds, "must be a count n >= 2 or a sequence of non-negative integer seeds") from None
    seen = set()
    for s in out:  # (one pass: a million seeds are refused at once)
        if s in seen:
            raise ModelError("seeds", f"{len(out)} seeds", f"must hold each seed once: {s} is given twice")
        seen.add(s)
    if len(out) < 2 or len(out) > MAX_SEEDS:
        raise ModelError("seeds", f"{len(out)} seeds", f"must hold 2 to {MAX_SEEDS} seeds, each once")
    return out


def _check_excitations(model, excitations):
    available = random_excitations(model)
    if excitations is None:
        if not available:
            raise ModelError(
                "scenario.excitation",
                sorted(model.scenario["excitation"]),
                "an ensemble over seeds needs at least one excitation of kind 'random'",
            )
        return available
    names = tuple(excitations)
    bad = [n for n in names if n not in available]
    if bad or not names or len(set(names)) != len(names):
        raise ModelError(
            "excitations",
            list(names),
            "must name random excitations of the model, each once: " + (", ".join(available) or "(the model has none)"),
        )
    return names
