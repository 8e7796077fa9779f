"""Per-sample functions of the studies (Section 4.4): ``evaluate(overrides: dict[str, float],
**kwargs) -> dict[str, float]`` (output name -> value).

:func:`default_evaluate` is the time-domain evaluation (engine run, octave-band RMS of a support
output). The stand-ins for the tests and the study benchmark (no physics) are in
:mod:`._stand_ins`; they are importable here too, by the paths study files may name
(``cablecasing_core.studies.evaluators:analytic_evaluate``).
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import ModelError, ModelWarning, excerpt
from ..model.schema import SETTING_KEYS, STUDY_OUTPUT
from ..nvh.bands import octave_bands, octave_rms, window_options

#: Output names of the default study: the Table 3 band labels "oct1" .. "oct9".
DEFAULT_OUTPUTS = octave_bands("table3").labels
#: The dotted path of :func:`default_evaluate` (what dask workers import).
DEFAULT_EVALUATE = "cablecasing_core.studies.evaluators:default_evaluate"
#: The record settings of :func:`default_evaluate` a study stores with its arguments: skip None (the
#: whole periods of ``whole_period_skip``) and Hann's window ...
RECORD_SETTINGS = {"skip": None, "window": "hann"}
#: ... and what a study whose stored arguments lack them took (study files written before the
#: settings were stored; CHANGELOG.md): a resume compares them, so that its samples are not mixed
#: with samples of the present defaults.
EARLIER_RECORD_SETTINGS = {"skip": 0.05, "window": "boxcar"}
_SETTING_WHAT = {"duration": "the simulated time", "dt": "the time step", "contact": "the contact switch"}


def check_not_overridden(changes, settings, runs="every run", instead=""):
    """Refuse, before any run, a model change of a key that a run setting given beside it takes the
    place of (:data:`SETTING_KEYS`: ``duration`` wins over ``scenario.duration``, ``dt`` over
    ``scenario.dt``, ``contact`` over ``contact.enabled``): the change would be recorded and do
    nothing (an ensemble's paired change of +0.0000 +- 0.0000, a study's nan correlations).

    changes : {model key: (name, value)}
        The model changes, each with the name its error gives it (``"--set scenario.dt"``,
        ``"bounds.scenario.duration"``) and its value.
    settings : {setting: (name, value)}
        Run settings (keys of :data:`SETTING_KEYS`), each with the name it was given by (``"--dt"``,
        ``"duration"``) and its value; None is not given (the model's key is in force). A setting
        whose value is True or False is named alone (``--no-contact``).
    runs : str
        Whose setting it is, in the message (``"every run of both ensembles"``).
    instead : str
        What to do instead, appended to the message; ``{key}`` and ``{name}`` stand for the key and
        the setting's name.
    """
    for setting, (name, value) in settings.items():
        key = SETTING_KEYS[setting]
        if value is None or key not in changes:
            continue
        label, given = changes[key]
        typed = name if isinstance(value, bool) else f"{name} {excerpt(value)}"
        raise ModelError(
            label,
            given,
            f"cannot be given with {typed} ({name} is {_SETTING_WHAT[setting]} of {runs} and takes the place of "
            f"{key}, which would be ignored){instead.format(key=key, name=name)}",
        )


def default_evaluate(
    overrides,
    duration=None,
    skip=None,
    dt=None,
    model_file=None,
    *,
    model=None,
    output=STUDY_OUTPUT,
    bands="table3",
    contact_time=False,
    window="hann",
    excitation_seeds=None,
    **kwargs,
):
    """The per-sample function of Section 4.4: run the time-domain model (the scenario of the model,
    with ``overrides`` applied) and return the octave-band RMS (N, Table 3) of the force at casing end
    B in z, ``{"oct1": N, ..., "oct9": N}``.

    duration (s): simulated time (default ``scenario.duration``); skip (s): start of the record left
    out of the RMS (the support fade-in and the first transient; default None: 0.05 s lengthened so
    that the rest holds whole periods of the harmonic excitations of the sample's model,
    :func:`~cablecasing_core.timedomain.scenario.whole_period_skip`); dt (s): time step (default
    ``scenario.dt``); model_file: a model TOML (default the built-in specimen); model: a
    :class:`~cablecasing_core.model.Model` to use instead of ``model_file``; output: the support
    output whose band levels are returned (N or N.m: a support or isolator output of ``SUPPORT_OUTPUTS``
    or a clip's, ``casing.clip0.Fz``; or a tuple of them, whose levels of the one record return
    as ``"<output>:<band>"``, as :func:`~.ensemble_runs.seed_ensembles` takes them); bands: the band
    set of :func:`~cablecasing_core.nvh.bands.octave_rms`; contact_time: also return the contact
    time per cable node (s, Fig. 22) as ``"contact_time_<i>"``; window: the window of the band
    levels (``octave_rms``'s: ``"hann"``, or ``"boxcar"``, the rectangular window).
    excitation_seeds: None runs the model's own random excitation once (its seeds as the model
    gives them); an integer k >= 2 runs it with the seeds of ensemble members 1..k
    (:func:`~.ensemble_runs.seed_overrides`) and returns each value's mean over the k runs (a
    sample's expected band levels, whose scatter over the seeds no longer enters a study's
    statistics in full; k times the run time).
    """
    from ..model import load_model
    from ..timedomain.scenario import whole_period_skip

    model = (load_model(model_file) if model is None else model).with_overrides(overrides)
    if skip is None:
        skip = whole_period_skip(model, duration, dt)
    if excitation_seeds is None:
        return _band_levels(model, duration, dt, skip, output, bands, contact_time, window)
    from .ensemble_runs import seed_overrides

    runs = [
        _band_levels(
            model.with_overrides(seed_overrides(model, s)), duration, dt, skip, output, bands, contact_time, window
        )
        for s in range(1, int(excitation_seeds) + 1)
    ]
    return {k: float(np.mean([r[k] for r in runs])) for k in runs[0]}


def _band_levels(model, duration, dt, skip, output, bands, contact_time, window):
    """The band RMS of ``output`` of one run of ``model`` after ``skip`` s (and the contact time per
    cable node): :func:`default_evaluate`'s result."""
    from ..records import after_skip
    from ..timedomain.simulation import simulate

    res = simulate(model, duration=duration, dt=dt)
    keep = after_skip(res.time, skip)
    if keep.sum() < 2:
        raise ModelError("skip", skip, f"must leave part of the {res.time[-1]:.6g} s record for the RMS")
    fs = 1.0 / (res.time[1] - res.time[0])
    # (check_record_settings warned before the runs of bands with few lines: not once per run)
    # (several outputs of the one record, as seed_ensembles takes them: keys "<output>:<band>")
    names = (output,) if isinstance(output, str) else tuple(output)
    out = {}
    for name in names:
        x = res.support_force(name)[keep]
        levels = octave_rms(x, fs, bands, warn_few_lines=False, **window_options(window)).as_dict()
        out.update(levels if isinstance(output, str) else {f"{name}:{k}": v for k, v in levels.items()})
    if contact_time:
        out.update({f"contact_time_{i}": float(v) for i, v in enumerate(res.contact_time)})
    return out


def check_record_settings(model, duration=None, dt=None, skip=None, bands="table3"):
    """Refuse before any run the record settings of :func:`default_evaluate` that make every run
    fail: ``duration - skip`` (s) shorter than one bin of the narrowest band (1 / its width), a
    time step ``dt`` (s) whose Nyquist frequency lies below the highest band edge, a duration that
    does not fit the machine (:func:`~cablecasing_core.model.limits.check_time_domain`).
    ``duration``, ``dt``: None takes the model's scenario; ``skip`` None, the model's
    :func:`~cablecasing_core.timedomain.scenario.whole_period_skip`; ``bands``: a band set or its name.
    Records that put fewer than ``LINES_PER_BAND`` FFT lines in a band warn here, once
    (:func:`~cablecasing_core.nvh.bands.few_lines`), and not from each run."""
    from ..model.limits import check_time_domain
    from ..model.validators import seconds
    from ..nvh.bands import Bands, few_lines
    from ..timedomain.scenario import whole_period_skip

    seconds("duration", duration, none_ok=True)
    seconds("dt", dt, none_ok=True)
    seconds("skip", skip, zero_ok=True, none_ok=True)
    given_skip = skip is not None
    if skip is None:
        skip = whole_period_skip(model, duration, dt)
    band_set = bands if isinstance(bands, Bands) else octave_bands(bands)
    # the time step first: a step too coarse for the bands is what is wrong, not the duration that its
    # whole steps of skip leave too short (--dt 1: a skip of one whole 1 s step)
    step = model.scenario["dt"] if dt is None else dt
    if not 0.5 / step >= band_set.upper.max():  # (octave_rms's rule, checked before the runs)
        key, value = ("dt", dt) if dt is not None else ("scenario.dt", step)
        raise ModelError(
            key,
            value,
            f"must be at most {0.5 / band_set.upper.max():.4g} s so that every band lies "
            f"below the Nyquist frequency (highest edge {band_set.upper.max():g} Hz)",
        )
    total = model.scenario["duration"] if duration is None else duration
    narrow = int(np.argmin(band_set.upper - band_set.lower))
    need = 1.0 / (band_set.upper[narrow] - band_set.lower[narrow])
    if not total - skip >= need:  # the band would hold less than one FFT bin (octave_rms refuses it)
        band = f"band {band_set.labels[narrow]!r} ({band_set.lower[narrow]:g}-{band_set.upper[narrow]:g} Hz)"
        if given_skip and total >= need:  # (the record would do: the skip the user gave is what is wrong)
            raise ModelError("skip", skip, f"must leave at least {need:.4g} s of the {total:g} s record for {band}")
        key, value = ("duration", duration) if duration is not None else ("scenario.duration", total)
        raise ModelError(key, value, f"must leave at least {need:.4g} s after skip = {skip:g} s for {band}")
    if note := few_lines(band_set, total - skip, fmin_advice=False):  # (once here, not from every run)
        # (stacklevel 1: one place, so that a command checking twice, as the study's does, says it once)
        warnings.warn(f"the records after skip = {skip:g} s: {note}", ModelWarning, stacklevel=1)
    check_time_domain(model, model.scenario["duration"] if duration is None else duration, step)


def check_model_runs(model, dt=None):
    """Refuse, before any run, a model that no run of it can start, whatever its excitation seed:
    what the time-domain engine refuses when it is set up for ``model`` with the time step ``dt``
    (s; None: ``scenario.dt``), its bodies assembled (a compression at or above the casing's
    buckling load, structure/buckling.py), the static state of an installed model solved and the
    friction law checked. It sets the engine up once (:class:`~cablecasing_core.timedomain.engine.Engine`,
    the rules' one place; about 0.1 s on the installed specimen) and raises what it raises
    (ModelError naming the key, or SimulationError); the warnings of the set-up are not said here
    (each run says them)."""
    from ..timedomain.engine import Engine

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (warn_once_per_process does not count a message ignored)
        Engine(model, dt=dt, ledger=False)


def _study_model(kwargs, model=None):
    """The model a study of :func:`default_evaluate` runs: ``model``, the study's loaded Model
    (run_study's is that of ``kwargs["model_file"]`` when given); else the model of
    ``kwargs["model_file"]``, of a path ``model`` or the built-in specimen, loaded here."""
    from ..model import Model, load_model

    if isinstance(model, Model):
        return model
    path = kwargs.get("model_file")
    return load_model(path if path is not None else (model if isinstance(model, str) else None))


def _check_default_samples(kwargs, samples, bounds, model=None):
    """Refuse (ModelError) a study of :func:`default_evaluate` none of whose samples can run, before
    the first: ``samples``, the (index, overrides) of its design in order (those its constraints
    reject left out), are each applied to the study's model (:func:`_study_model`; the keys' rules,
    ``casing.d_inner`` below ``casing.d_outer``) and set up as a run sets it up
    (:func:`check_model_runs` with ``kwargs["dt"]``), in order until one passes: one set-up when the
    first passes (about 0.1 s), every sample's when none does. The error names what every sample
    fails: a key of the model that no sample varies (``loads.cable_tension``, above the casing's
    buckling load) by its value, a varied one by its bounds (``bounds.casing.d_inner``), with the
    first sample that failed."""
    from ..errors import SimulationError

    base = _study_model(kwargs, model)
    first, n = None, 0
    for i, p in samples:
        n += 1
        try:
            check_model_runs(base.with_overrides(p), kwargs.get("dt"))
            return
        except (ModelError, SimulationError) as exc:
            if first is None:
                first = (i, p, exc)
    if first is None:  # (no sample left to run)
        return
    i, p, exc = first
    said = ", ".join(f"{k} = {excerpt(v)}" for k, v in p.items())
    every = (
        f"every one of the {n} samples of the study over {', '.join(bounds)} fails so before its run (the first, "
        f"sample {i}: {said}); refused before any run"
    )
    key = getattr(exc, "key", None)
    if key in bounds:
        raise ModelError(f"bounds.{key}", list(bounds[key]), f"{exc.allowed}: {every}; change the bounds")
    if isinstance(exc, ModelError):
        raise ModelError(key, exc.value, f"{exc.allowed}: {every}")
    raise ModelError("bounds", list(bounds), f"{every}: {type(exc).__name__}: {exc}")


def _check_default_evaluate(kwargs, model=None):
    """The settings ``kwargs`` of a study of :func:`default_evaluate` checked before anything runs
    (:func:`check_record_settings` on the study's model, :func:`_study_model`)."""
    model = _study_model(kwargs, model)
    known = {"duration", "skip", "dt", "bands"}
    check_record_settings(model, **{k: v for k, v in kwargs.items() if k in known})
    window_options(kwargs.get("window", "hann"))  # (a bad window refused before any sample)
    if kwargs.get("excitation_seeds") is not None:  # (each sample the mean over seeds 1..k of the ensemble)
        from ..model.limits import MAX_SEEDS
        from ..model.validators import integer
        from .ensemble_runs import seed_keys

        integer("excitation_seeds", kwargs["excitation_seeds"], 2, MAX_SEEDS, " (None: the model's own seeds, once)")
        seed_keys(model)  # (a model without a random excitation refused: no seed to vary)


default_evaluate.check_settings = _check_default_evaluate
#: (run_study: the samples that cannot run, all of them, refused before the first)
default_evaluate.check_samples = _check_default_samples
#: The settings of default_evaluate that take the place of a model key (run_study refuses bounds on that key).
default_evaluate.run_settings = ("duration", "dt")


# (the stand-ins, by their paths here too: dask workers import a study's evaluate by its dotted path)
from ._stand_ins import analytic_evaluate, cpu_burn_evaluate, faulty_evaluate, ishigami_evaluate  # noqa: E402, F401
