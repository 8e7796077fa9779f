"""The report of a model (``cablecasing report [MODEL.toml] [--out DIR]``; ``make demo`` adds the FMU
check): every figure and table from one set of runs (:mod:`.runs`), which the report names (model,
scenario, seeds, duration, dt, version, date, the parameters with their units), as PNG and CSV files
and one ``report.html`` (:mod:`.page`), all under ``out`` and nowhere else.

Files: ``report.html``; ``runs.json`` (the runs: model fingerprint, overrides, seeds, duration, dt,
files); ``parameters.csv``; ``modes.csv`` (Hz); ``trfam.uff`` and ``trfam_<x|y|z>.csv`` with
``trfam_xyz.png`` (Fig. 17); ``records/<variant>.npz`` (the reference records); ``rms.csv`` (the
support forces' mean, RMS total and RMS dynamic, N); ``simulation.png`` (time histories);
``scalograms.png`` (Figs. 20-21); ``routing_contact.png`` and ``contact_histogram.png`` (Fig. 22);
``bands_<variant>.csv`` and ``band_levels.png`` (ensemble means with confidence intervals, N and dB
re 1 N; a band more than :data:`~cablecasing_core.studies.octave.NO_RESPONSE_DB` below its variant's strongest holds no
response and is left out of the figure and dashed in the table); ``bands_net_B.csv`` (a model with a
cable: the band levels of the reference records' casing.B.Fz, cable.B.Fz and their sum net.B.Fz, the
force the transmission at B receives); ``psd.png`` (casing.B.Fz and net.B.Fz, from 2 df, where
Welch's lines measure); ``apparent_mass.png`` (H1 of a reference record against the TRFAM averaged
over the estimator's window, what H1 estimates, and the TRFAM as computed); ``study/study.csv``,
``study/correlations.png`` (Fig. 23) and ``study/sobol.png``. The page states what the band levels'
intervals cover (the seeds' scatter) and quotes the model's numerical error they do not cover
(docs/time_domain.md).
"""

from __future__ import annotations

import csv
import datetime
import json
import sys
from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..files import atomic_path, write_text
from .runs import OUTPUT, drive_harmonics, run_variant, variants


def _say(text, progress):
    if progress:
        print(f"report: {text}", file=sys.stderr, flush=True)


def check_report_settings(model=None, duration=0.5, seeds=6, study_samples=32, skip=None):
    """The settings of :func:`write_report` checked before anything is run or written: returns
    ``(model, seeds, study_samples, skip)``: the model loaded (a Model, a TOML path, or None for the
    built-in specimen), skip (s) resolved (None: the model's
    :func:`~cablecasing_core.timedomain.scenario.whole_period_skip`); a :class:`ModelError` naming
    the setting otherwise."""
    from ..model import Model, load_model
    from ..model.limits import MAX_STUDY_SAMPLES
    from ..model.validators import integer, seconds
    from ..timedomain.scenario import whole_period_skip

    model = model if isinstance(model, Model) else load_model(model)
    if "casing" not in model.bodies:  # (its output, band levels, scalograms and spectra are the casing's)
        raise ModelError(
            "model",
            model.source,
            f"must have a casing: the report shows the support force {OUTPUT}; this model has only the "
            + " and the ".join(model.bodies),
        )
    seconds("duration", duration)
    seconds("skip", skip, zero_ok=True, none_ok=True)
    given_skip = skip
    if skip is None:
        skip = whole_period_skip(model, duration)
    n_seeds = integer("seeds", seeds, 2)
    study_samples = integer("study_samples", study_samples, 0, MAX_STUDY_SAMPLES)
    if study_samples == 1:
        raise ModelError("study_samples", 1, f"must be 0 (no study) or 2 to {MAX_STUDY_SAMPLES} (a study's runs)")
    if study_samples:
        from ..studies.executor import STUDY_EXTRA, missing_packages

        if missing_packages("serial"):  # (a serial study: SALib's design and Sobol' indices, no dask)
            raise ModelError(
                "study_samples",
                study_samples,
                "must be 0 (no study): a study needs the optional package SALib, which is not installed: "
                + STUDY_EXTRA,
            )
    bin_ = 1.0 / (22.0 - 11.0)  # one FFT bin in the narrowest band of Table 3 (octave_rms's rule)
    if duration < skip + bin_:
        if given_skip is not None:
            raise ModelError(
                "duration",
                duration,
                f"must be at least {skip + bin_:.4g} s: skip = {skip:g} s and one bin of the 11-22 Hz band",
            )
        least = shortest_report_duration(model)
        raise ModelError(
            "duration",
            duration,
            f"must be at least {least:.4g} s: one bin of the 11-22 Hz band ({bin_:.4g} s) after the skip, "
            f"{whole_period_skip(model, least):g} s at that duration (the start left out so that the rest holds "
            "whole periods of the drive, which changes with the duration)",
        )
    return model, n_seeds, study_samples, skip


def shortest_report_duration(model) -> float:
    """The shortest duration (s, to 4 significant digits, rounded up) that :func:`check_report_settings`
    takes with the default skip: the rest after :func:`~cablecasing_core.timedomain.scenario.whole_period_skip`,
    which grows with the duration, must hold one bin of the 11-22 Hz band. The rest never shrinks as
    the duration grows (whole periods of the drive), so the bound is found by bisection."""
    import math

    from ..timedomain.scenario import whole_period_skip

    bin_ = 1.0 / (22.0 - 11.0)

    def passes(t):
        return not t < whole_period_skip(model, t) + bin_

    lo, hi = 0.0, bin_
    while not passes(hi):  # (a passing duration: the rest grows by at least one common period per doubling)
        lo, hi = hi, 2.0 * hi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if passes(mid) else (mid, hi)
    unit = 10.0 ** (math.floor(math.log10(hi)) - 3)
    for t in (round(hi / unit) * unit, math.ceil(hi / unit) * unit, (math.ceil(hi / unit) + 1) * unit):
        t = float(f"{t:.4g}")
        if passes(t):
            return t
    return hi  # pragma: no cover - (a 4-digit duration at or above hi passes)


def write_report(
    out: str | Path,
    model=None,
    duration: float = 0.5,
    seeds: int = 6,
    study_samples: int = 32,
    skip: float | None = None,
    progress: bool = True,
    fmu: dict | None = None,
) -> Path:
    """Run ``model`` (a Model, a TOML path, or None for the built-in specimen) and write its report
    into the folder ``out``; returns the path of report.html.

    duration (s): simulated time of every run; seeds: excitation seeds 1..seeds of the band-level
    ensembles (>= 2; the first seed gives the reference records); study_samples: runs of the small
    Monte-Carlo study of Fig. 23 (0: none); skip (s): start of each record left out of levels and
    spectra (default 0.05 s lengthened to whole periods of the harmonic excitations,
    :func:`~cablecasing_core.timedomain.scenario.whole_period_skip`); progress: bars and notes on
    stderr; fmu: the FMU check of ``examples/demo.py`` (a dict of labels to values,
    :func:`.runs.fmu_check`'s, shown as it is).
    """
    import cablecasing_core as cc

    from ..frequency.modal import frequencies_up_to, mode_count
    from . import figures, page

    model, n_seeds, study_samples, skip = check_report_settings(model, duration, seeds, study_samples, skip)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    seed_list = list(range(1, n_seeds + 1))
    info = {
        "model": model.source,
        "fingerprint": model.fingerprint(),
        "version": cc.__version__,
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "duration": duration,
        "dt": model.scenario["dt"],
        "skip": skip,
        "seeds": seed_list,
        "output": OUTPUT,
    }
    body = "casing"  # (check_report_settings: the model has one)
    _say("natural frequencies and TRFAM (frequency domain)", progress)
    # the first 10 modes of each body, or all it has (a coarse mesh has fewer: one per free DOF)
    modes = {b: cc.natural_frequencies(model, b, min(10, mode_count(model, b))) for b in model.bodies}
    lines = ["mode," + ",".join(f"{b} [Hz]" for b in modes)]
    lines += [
        f"{i + 1}," + ",".join(repr(float(f[i])) if i < len(f) else "" for f in modes.values())
        for i in range(max(len(f) for f in modes.values()))
    ]
    write_text(out / "modes.csv", "\n".join(lines) + "\n")
    with atomic_path(out / "parameters.csv") as tmp, open(tmp, "w", newline="", encoding="utf-8") as fh:
        csv.writer(fh).writerows([("key", "value", "unit", "description"), *page.parameter_rows(model, duration)])
    freq = figures.trfam_figure(model, body, out)
    vs = variants(model, out, seed_list[0])
    for v in vs:
        _say(f"runs {v.title}: the reference record (seed {seed_list[0]}) and {n_seeds} seeds", progress)
        run_variant(v, duration, seed_list, skip, progress)
        if v.ensemble is not None:
            v.ensemble.save(out / f"bands_{v.key}.csv")
    _say("figures", progress)
    f_min, f_max = figures.SCALOGRAM_HZ[0], figures.SCALOGRAM_HZ[-1]  # (the scalograms' range, Hz)
    harmonics = drive_harmonics(model, f_max)  # all of them up to f_max; the scalogram draws the first few
    natural = [f for f in frequencies_up_to(model, body, f_max) if f >= f_min]
    figures.time_figure(vs, out / "simulation.png")
    figures.scalogram_figure(vs, out / "scalograms.png", natural, harmonics, skip)
    figures.contact_figures(model, vs[-1], out)
    figures.band_figure(vs, out / "band_levels.png")
    figures.psd_figure(vs, out / "psd.png", skip)
    figures.net_table(vs, out / "bands_net_B.csv")
    am = figures.apparent_mass_figure(model, vs[0], out / "apparent_mass.png", skip)
    rms = figures.rms_table(vs, out / "rms.csv", skip)
    study = None
    figures.clear_study(out / "study")  # (a report's study starts afresh; none leaves none)
    if study_samples:
        say = lambda runs: _say(f"a small study of {runs} runs (Fig. 23)", progress)  # noqa: E731
        study = figures.study_figures(model, out / "study", study_samples, duration, skip, progress, say)
    runs = {
        **info,
        "variants": [
            {
                "key": v.key,
                "title": v.title,
                "model_fingerprint": v.model.fingerprint(),
                "seed_overrides": v.seed_overrides,
                "record": str(v.record.relative_to(out)),
                "ensemble": f"bands_{v.key}.csv" if v.ensemble is not None else None,
                "ensemble_first_member_vs_record": v.member_check,
            }
            for v in vs
        ],
        "study": study and {k: study[k] for k in ("csv", "runs", "ok", "bounds")},
        "fmu": fmu,
    }
    write_text(out / "runs.json", json.dumps(runs, indent=1, default=_json))
    html = page.render(model, info, modes, freq, vs, rms, am, study, fmu, harmonics, out)
    return write_text(out / "report.html", html)


def _json(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


__all__ = ["write_report"]
