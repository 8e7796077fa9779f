"""The report of a model (``cablecasing report [MODEL.toml] [--out DIR]``; ``make demo`` adds the FMU
check): every figure and table from one set of runs (:mod:`.runs`), which the report names (model,
scenario, seeds, duration, dt, the skip and why, the record's FFT resolution, the code that made it,
date, the parameters with their units), as PNG and CSV files and one ``report.html`` (:mod:`.page`),
all under ``out`` and nowhere else. The run is written into a folder of its own inside ``out`` and
moved in at the end (:func:`staged_report`), so an interrupted report leaves an earlier one whole.

Files: ``report.html``; ``runs.json`` (the runs: model fingerprint, overrides, seeds, duration, dt,
skip, df, the code (git commit and dirty flag, or the installed version), the libraries' versions,
the command line, the reference records' energy ledgers, every file of the report relative to
``out``); ``parameters.csv``; ``modes.csv`` (Hz); ``trfam.uff`` and ``trfam_<x|y|z>.csv`` with
``trfam_xyz.png`` (Fig. 17); ``records/<variant>.npz`` (the reference records); ``rms.csv`` (the
support forces' mean, RMS total and RMS dynamic, N); ``simulation.png`` (time histories);
``scalograms.png`` (Figs. 20-21); ``routing_contact.png`` and ``contact_histogram.png`` (Fig. 22);
``bands_<variant>.csv`` and ``band_levels.png`` (ensemble means with confidence intervals, N and dB
re 1 N; a band more than :data:`~cablecasing_core.nvh.bands.NO_RESPONSE_DB` below its variant's strongest holds no
response and is left out of the figure and dashed in the table); ``bands_net_B.csv`` (a model with a
cable: the band levels of the reference records' casing.B.Fz, cable.B.Fz and their sum net.B.Fz, the
force the transmission at B receives); ``bands_net_B_<variant>.csv`` (net.B.Fz's ensemble, of the same
runs as ``bands_<variant>.csv``); ``psd.png`` (casing.B.Fz and net.B.Fz, from 2 df, where
Welch's lines measure); ``apparent_mass.png`` (H1 of a reference record against the TRFAM averaged
over the estimator's window, what H1 estimates, and the TRFAM as computed); ``study/study.csv``,
``study/correlations.png`` (Fig. 23) and ``study/sobol.png``. The page states what the band levels'
intervals cover (the seeds' scatter) and quotes the model's numerical error they do not cover
(docs/time_domain.md).
"""

from __future__ import annotations

import contextlib
import csv
import datetime
import errno
import json
import math
import os
import shlex
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

from ..errors import NOT_SHOWN, ModelError
from ..files import atomic_path, write_text
from .runs import OUTPUT, drive_harmonics, run_variant, variants


def _say(text, progress):
    if progress:
        print(f"report: {text}", file=sys.stderr, flush=True)


def start_transients(model) -> list[dict]:
    """The start transient of each harmonic excitation of ``model``'s scenario (docs/nvh.md, "The start
    transient of a harmonic drive"): the drive's start sets off a free vibration that lies in the
    levels until it has decayed; near the drive's frequency f (Hz) the casing's Rayleigh damping
    (``casing.alpha``, 1/s, and ``casing.beta``, s: ``identification.rayleigh_zeta``) gives it the
    damping ratio zeta = alpha / (2 omega) + beta omega / 2 at omega = 2 pi f, so it decays to a tenth of
    its amplitude in t = ln 10 / (zeta omega) s: 0.30 s at the built-in specimen's 50 Hz (zeta = 0.024),
    whose measured windows show it gone by then (0-0.25 s off, 0.25-0.5 s within 2 SE).

    The casing's, whatever body the drive acts on: the report's levels are of the casing's support
    force at B. A cable drive's own free vibration (the cable's Rayleigh damping alone: 0.66 s on the
    built-in specimen) is given as ``cable_t`` but not counted: it reaches the casing only through the
    contact, which damps it, and the specimen's casing.B.Fz shows no such tail (docs/nvh.md's table).

    One dict per excitation of :func:`~cablecasing_core.timedomain.scenario.harmonic_excitations`, in the model
    file's order: ``excitation`` (its name), ``frequency`` (Hz), ``alpha`` (1/s) and ``beta`` (s) of
    the casing, ``zeta`` (-), ``t`` (s; None for a casing without Rayleigh damping, whose transient
    does not decay) and, for a drive on the cable, ``cable_zeta`` and ``cable_t``."""
    from ..identification.rayleigh import rayleigh_zeta

    def decay(body, f):
        b = model.data[body]
        zeta = float(rayleigh_zeta([f], b["alpha"], b["beta"])[0])
        return zeta, (math.log(10.0) / (zeta * 2.0 * math.pi * f) if zeta > 0 else None)

    from ..timedomain.scenario import harmonic_excitations

    out = []
    for name, e in harmonic_excitations(model).items():
        f = float(e["frequency"])
        zeta, t = decay("casing", f)
        casing = model.data["casing"]
        item = {"excitation": name, "frequency": f, "alpha": casing["alpha"], "beta": casing["beta"]}
        item.update(zeta=zeta, t=t)
        if e["target"].startswith("cable.") and "cable" in model.data:
            item["cable_zeta"], item["cable_t"] = decay("cable", f)
        out.append(item)
    return out


def start_transient(model) -> float:
    """The start the report leaves out for its harmonic excitations' start transients (s): the longest
    finite ``t`` of :func:`start_transients` (0 without a harmonic excitation, or when no transient
    decays: the page says so)."""
    return max((d["t"] for d in start_transients(model) if d["t"] is not None), default=0.0)


def report_skip(model, duration: float) -> float:
    """The report's default skip (s) of records ``duration`` s long of ``model``: 0.05 s (or the
    scenario's fade-in), at least :func:`start_transient` (ln 10 / (zeta omega) of the casing at each
    harmonic excitation's frequency), lengthened so that the rest holds whole periods of the harmonic
    excitations (:func:`~cablecasing_core.timedomain.scenario.whole_period_skip`): 0.32 s of the
    built-in specimen's 1 s with its 50 Hz drive (0.30 s, then 34 periods after it)."""
    from ..timedomain.scenario import whole_period_skip

    return whole_period_skip(model, duration, least=start_transient(model))


def describe_start_transients(model) -> str:
    """What :func:`report_skip` leaves out for the start transients, in words (plain text): per harmonic
    line ``ln 10/(ζω) = 0.30 s at 50 Hz, ζ = 0.024``, or that the model has no harmonic excitation."""
    items = start_transients(model)
    if not items:
        return "no harmonic excitation: no drive's start transient"
    said = [
        f"ln 10/(ζω) = {d['t']:.2f} s at {d['frequency']:g} Hz, ζ = {d['zeta']:.2g}"
        if d["t"] is not None
        else f"no decay at {d['frequency']:g} Hz (the casing has no Rayleigh damping, ζ = 0)"
        for d in items
    ]
    return "the casing's start transient of the harmonic drive, " + "; ".join(said)


def check_report_settings(model=None, duration=None, seeds=6, study_samples=32, skip=None):
    """The settings of :func:`write_report` checked before anything is run or written: returns
    ``(model, seeds, study_samples, skip, duration)``: the model loaded (a Model, a TOML path, or
    None for the built-in specimen), skip (s) resolved (None: :func:`report_skip`), duration (s)
    resolved (None: the model's ``scenario.duration``); a :class:`ModelError` naming the setting
    otherwise."""
    from ..model import Model, load_model
    from ..model.limits import MAX_STUDY_SAMPLES
    from ..model.validators import integer, seconds

    model = model if isinstance(model, Model) else load_model(model)
    if "casing" not in model.bodies:  # (its output, band levels, scalograms and spectra are the casing's)
        raise ModelError(
            "model",
            model.source,
            f"must have a casing: the report shows the support force {OUTPUT}; this model has only the "
            + " and the ".join(model.bodies),
        )
    if duration is None:
        duration = float(model.scenario["duration"])
    seconds("duration", duration)
    seconds("skip", skip, zero_ok=True, none_ok=True)
    given_skip = skip
    if skip is None:
        skip = report_skip(model, duration)
    n_seeds = integer("seeds", seeds, 2)
    study_samples = integer("study_samples", study_samples, 0, MAX_STUDY_SAMPLES)
    if study_samples == 1:
        raise ModelError("study_samples", 1, f"must be 0 (no study) or 2 to {MAX_STUDY_SAMPLES} (a study's runs)")
    _check_report_packages(study_samples)
    bin_ = 1.0 / (22.0 - 11.0)  # one FFT bin in the narrowest band of Table 3 (octave_rms's rule)
    if duration < skip + bin_:
        if given_skip is not None:
            raise ModelError(
                "duration",
                duration,
                f"must be at least {skip + bin_:.4g} s: skip = {skip:g} s and one bin of the 11-22 Hz band",
            )
        least = shortest_report_duration(model)
        if start_transient(model) > 0:
            why = f"{describe_start_transients(model)}, then whole periods of the drive, which change with the duration"
        elif start_transients(model):  # (a drive whose transient does not decay: nothing to leave out for it)
            why = f"the supports' fade-in and the first response; {describe_start_transients(model)}"
        else:
            why = "the supports' fade-in and the first response"
        raise ModelError(
            "duration",
            duration,
            f"must be at least {least:.4g} s: one bin of the 11-22 Hz band ({bin_:.4g} s) after the skip, "
            f"{report_skip(model, least):g} s at that duration (the start left out: {why})",
        )
    return model, n_seeds, study_samples, skip, float(duration)


def _check_report_packages(study_samples):
    """Refuse, in one line before anything runs or is made, a report whose optional packages are not
    installed: pyuff, which writes its trfam.uff (the extra ``identify``), and with ``study_samples`` > 0
    SALib, its study's design and Sobol' indices (the extra ``study``; its runs need no dask)."""
    from ..extras import install_hint
    from ..studies.executor import missing_packages

    try:
        import pyuff  # noqa: F401
    except ImportError:
        pyuff_missing = True
    else:
        pyuff_missing = False
    salib_missing = bool(study_samples) and bool(missing_packages("serial"))
    if pyuff_missing and salib_missing:  # (both in one line: one install, not two tries)
        raise ModelError(
            "report",
            NOT_SHOWN,
            "needs the optional packages pyuff (for its trfam.uff) and SALib (for its study), which are not "
            "installed: " + install_hint({"identify": ["pyuff"], "study": ["SALib"]}),
        )
    if pyuff_missing:
        raise ModelError(
            "report",
            NOT_SHOWN,
            "needs the optional package pyuff (for its trfam.uff), which is not installed: "
            + install_hint("identify", ["pyuff"]),
        )
    if salib_missing:
        raise ModelError(
            "study_samples",
            study_samples,
            "must be 0 (no study): a study needs the optional package SALib, which is not installed: "
            + install_hint("study", ["SALib"]),
        )


def shortest_report_duration(model) -> float:
    """The shortest duration (s, to 4 significant digits, rounded up) that :func:`check_report_settings`
    takes with the default skip: the rest after :func:`report_skip`, which grows with the duration,
    must hold one bin of the 11-22 Hz band. The rest never shrinks as
    the duration grows (whole periods of the drive), so the bound is found by bisection."""
    import math

    bin_ = 1.0 / (22.0 - 11.0)

    def passes(t):
        return not t < report_skip(model, t) + bin_

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


#: The files a report writes last, after every other, and removes first when its files are moved
#: into the folder (:func:`staged_report`): while they are missing no page shows a mix of two runs.
PAGE_FILES = ("runs.json", "report.html")
#: The prefix of the folder in ``out`` that a report's run writes into before its files are moved in.
STAGE_PREFIX = ".report-run-"
#: The names (glob patterns, relative to ``out``) of the files a report writes, some only for some
#: models (tests/cli/test_report_review_s.py checks a report's runs.json ``files`` against them):
#: :func:`check_report_folder` checks these targets before the runs.
REPORT_FILES = (
    *PAGE_FILES,
    "parameters.csv",
    "modes.csv",
    "trfam.uff",
    "trfam_x.csv",
    "trfam_y.csv",
    "trfam_z.csv",
    "trfam_xyz.png",
    "records/*.npz",
    "bands_*.csv",
    "simulation.png",
    "scalograms.png",
    "routing_contact.png",
    "contact_histogram.png",
    "band_levels.png",
    "psd.png",
    "apparent_mass.png",
    "rms.csv",
    "study/study.csv",
    "study/study.csv.meta.json",
    "study/model.toml",
    "study/correlations.png",
    "study/sobol.png",
)


def check_report_folder(flag: str, out: str | Path) -> None:
    """Refuse, before the runs, a folder ``out`` into which a report's files (:data:`REPORT_FILES`)
    could not be moved (a :class:`ModelError` naming ``flag``): a folder where the report writes a file
    (``psd.png/``), a file where it writes into a folder (``records``), a subfolder on another file
    system than ``out`` (``records`` a link to another disk: a file is moved, not copied, in) or one
    that cannot be written in. A folder ``out`` that does not exist yet passes (it is created empty).
    What a name with a wildcard (``bands_*.csv``) will be is known after the runs: the existing files
    of that pattern are checked here, :func:`_move_in` checks every target again before the move."""
    out = Path(out)
    if not out.is_dir():
        return
    dev = os.stat(out).st_dev
    for pattern in REPORT_FILES:
        folder = pattern.rsplit("/", 1)[0] if "/" in pattern else ""
        names = [p.relative_to(out).as_posix() for p in out.glob(pattern)] if "*" in pattern else [pattern]
        for problem in [_folder_problem(out, folder, dev)] + [_target_problem(out, n, dev) for n in names]:
            if problem:
                raise ModelError(
                    flag, str(out), f"must be a folder into which the report's files can be moved: {problem[1]}"
                )


def _folder_problem(out: Path, folder: str, dev: int) -> tuple[int, str] | None:
    """Why no file on the device ``dev`` can be moved into the folder ``folder`` (relative to ``out``,
    '' for ``out`` itself): ``(errno, reason)``, or None. Each part of it that exists must be a folder;
    the deepest that exists (the move creates the rest in it) must lie on ``dev`` and be writable."""
    here = out
    for part in Path(folder).parts:
        if not os.path.lexists(here / part):
            break
        here = here / part
        if not here.is_dir():
            return errno.ENOTDIR, f"{here} is a file where the report writes into a folder of that name"
    if os.stat(here).st_dev != dev:
        return errno.EXDEV, (
            f"{here} lies on another file system ({os.path.realpath(here)}) than the report's run, and the "
            "report's files are moved in (renamed), which cannot cross file systems"
        )
    if not os.access(here, os.W_OK | os.X_OK):
        return errno.EACCES, f"no file can be created in {here} (permission denied)"
    return None


def _target_problem(out: Path, name: str, dev: int) -> tuple[int, str] | None:
    """Why the file ``name`` (relative to ``out``) of a finished run on the device ``dev`` cannot be
    moved to ``out / name`` (``os.replace``): ``(errno, reason)``, or None when it can, as far as can
    be known before the move (:func:`_folder_problem` of its folder; the target not a folder)."""
    folder = name.rsplit("/", 1)[0] if "/" in name else ""
    problem = _folder_problem(out, folder, dev)
    if problem:
        return problem
    target = out / name
    if os.path.lexists(target) and target.is_dir():
        return errno.EISDIR, f"{target} is a folder where the report writes a file of that name"
    return None


@contextlib.contextmanager
def staged_report(out: str | Path):
    """A report is a set of files: yield a new empty folder inside ``out`` (created if need be; a
    hidden one, ``.report-run-*``, on the same file system) to write the run into, and, when the block
    ends without an exception, move its files into ``out`` (:func:`_move_in`): each target is checked
    first (:func:`_target_problem`: not a folder, on the stage's file system, in a folder that can be
    written), then runs.json and report.html of ``out`` are removed, every other file of the run
    replaces its namesake (each file whole, ``os.replace``), the files an earlier report listed in its
    runs.json (``files``; a runs.json of a report, ``"report": true``) that this run does not write
    are removed, with the folders they leave empty, and runs.json and report.html come last. An
    interrupt (Ctrl-C) or an error during the run leaves ``out`` as it was, an earlier report whole,
    and removes the staging folder; one while the files are moved in (a fraction of a second) leaves
    no report.html or runs.json, never an earlier page beside this run's files. A target that cannot
    take its file raises :class:`~cablecasing_core.files.WriteError` naming it and keeps the staging
    folder, the whole finished run, which the error names: found by the check, before anything is
    removed or moved (``out`` as it was); failing in the move, after the files moved so far were
    moved back into it (``out`` then holds no report.html or runs.json)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    stage = Path(tempfile.mkdtemp(prefix=STAGE_PREFIX, dir=out))
    keep = False
    try:
        yield stage
        try:
            _move_in(stage, out)
        except OSError:
            keep = True
            raise
    finally:
        if not keep:
            shutil.rmtree(stage, ignore_errors=True)


def _files_under(folder: Path) -> list[str]:
    """Every file under ``folder`` as a relative POSIX path, sorted."""
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())


def is_report_runs(runs) -> bool:
    """Whether ``runs`` (a runs.json's content) is a report's: marked ``"report": true``, or written by a
    report before the mark (its ``files``, ``variants``, ``fingerprint`` and ``seeds``)."""
    if not isinstance(runs, dict):
        return False
    return runs.get("report") is True or {"files", "variants", "fingerprint", "seeds"} <= set(runs)


def _earlier_files(out: Path) -> list[str]:
    """The files an earlier report in ``out`` wrote: its runs.json's ``files`` (relative paths inside
    ``out``; anything else is ignored) when that runs.json is a report's (:func:`is_report_runs`);
    nothing else, so what a user keeps in ``out`` (a study's ``study/study.csv``) stays."""
    try:
        runs = json.loads((out / "runs.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):  # (none, or not JSON: not a report's)
        return []
    listed = runs.get("files") if is_report_runs(runs) else None
    if not isinstance(listed, list):
        return []
    root = out.resolve()
    keep = []
    for name in listed:
        if not isinstance(name, str):
            continue
        path = Path(name)
        if path.is_absolute() or ".." in path.parts or not (out / path).resolve().is_relative_to(root):
            continue
        keep.append(path.as_posix())
    return keep


def _move_in(stage: Path, out: Path) -> None:
    """The files of a finished run in ``stage`` moved into ``out`` (see :func:`staged_report`)."""
    from ..files import WriteError

    new = _files_under(stage)
    old = _earlier_files(out)
    kept = (
        f"this run's report is kept whole in {stage} (its report.html opens there): move its files into "
        f"{out} once the cause is fixed, or remove it"
    )
    dev = os.stat(stage).st_dev
    for name in new:  # (every target before anything is removed or moved)
        problem = _target_problem(out, name, dev)
        if problem:
            raise WriteError(
                problem[0],
                f"{problem[1]}; nothing was moved or removed: {out} is as it was, and {kept}",
                str(out / name),
                os.path.lexists(out / name),
            )
    moved = []

    def move(name):
        try:
            (out / name).parent.mkdir(parents=True, exist_ok=True)
            os.replace(stage / name, out / name)
        except OSError as exc:
            for done in reversed(moved):  # (back into the stage, which then holds the whole run again)
                with contextlib.suppress(OSError):
                    os.replace(out / done, stage / done)
            raise WriteError(
                exc.errno,
                f"{exc.strerror or exc} while the report's files were moved in; {out} holds no report.html or "
                f"runs.json now (removed first), and {kept}",
                str(out / name),
                os.path.lexists(out / name),
            ) from exc
        moved.append(name)

    for name in PAGE_FILES:
        (out / name).unlink(missing_ok=True)
    for name in new:
        if name not in PAGE_FILES:
            move(name)
    gone = set(old) - set(new)
    for name in gone:  # (once the run's files are in, before its page is)
        with contextlib.suppress(IsADirectoryError, PermissionError):
            (out / name).unlink(missing_ok=True)
    for folder in sorted({(out / n).parent for n in gone}, key=lambda p: -len(p.parts)):
        if folder != out and folder.is_dir() and not any(folder.iterdir()):  # (a folder the report left empty)
            with contextlib.suppress(OSError):
                folder.rmdir()
    for name in PAGE_FILES:
        if name in new:
            move(name)


def write_report(
    out: str | Path,
    model=None,
    duration: float | None = None,
    seeds: int = 6,
    study_samples: int = 32,
    skip: float | None = None,
    progress: bool = True,
    fmu: dict | None = None,
    command: str | None = None,
    staged: bool = True,
    scheduler: str = "threads",
) -> Path:
    """Run ``model`` (a Model, a TOML path, or None for the built-in specimen) and write its report
    into the folder ``out``; returns the path of report.html.

    duration (s): simulated time of every run (default the model's ``scenario.duration``: 1 s for
    the built-in specimens); seeds: excitation seeds 1..seeds of the band-level ensembles (>= 2; the
    first seed gives the reference records); study_samples: runs of the small Monte-Carlo study of
    Fig. 23 (0: none); skip (s): start of each record left out of levels and spectra (default
    :func:`report_skip`: 0.05 s, at least the casing's start transient ln 10 / (zeta omega) at each
    harmonic excitation's frequency, lengthened to whole periods of them); progress: bars and notes on
    stderr; fmu: the FMU check of
    ``examples/demo.py`` (a dict of labels to values, :func:`.runs.fmu_check`'s, shown as it is);
    command: the command line that made the report, stated in it (default: this process's);
    staged: write the run into a folder inside ``out`` and move it in at the end
    (:func:`staged_report`); False writes into ``out`` itself, which must then be a new folder the
    caller stages (as ``examples/demo.py`` does with its FMU's outputs): every file in it counts as
    the report's (runs.json's ``files``, which a later report in the same place removes when it does
    not write them). A folder ``out`` whose files the report's could not replace is refused before
    the runs (:func:`check_report_folder`). scheduler: where the ensembles' and the study's runs go,
    ``"threads"`` (default: at once, one per core, in this process) or ``"serial"`` (one after the
    other); the page is the same to the bit (docs/studies.md, "Where the samples run").
    """
    from ..model.validators import Choice

    Choice("serial", "threads")("scheduler", scheduler)
    model, n_seeds, study_samples, skip, duration = check_report_settings(model, duration, seeds, study_samples, skip)
    with _each_warning_once():  # (the same note from each ensemble's check, from each variant's figures)
        if staged:
            check_report_folder("out", out)
            with staged_report(out) as stage:
                _write(stage, model, duration, n_seeds, study_samples, skip, progress, fmu, command, scheduler)
            return Path(out) / "report.html"
        return _write(Path(out), model, duration, n_seeds, study_samples, skip, progress, fmu, command, scheduler)


@contextlib.contextmanager
def _each_warning_once():
    """Within the block, a warning whose category and text were shown already is not shown again: the
    report's ensembles each check their records (``studies.evaluators``: "fewer than 4 FFT lines"), and
    a ``catch_warnings`` between them (each run's) clears Python's own record of what was said."""
    said = set()
    show = warnings.showwarning

    def once(message, category, *args, **kwargs):
        if (category, str(message)) not in said:
            said.add((category, str(message)))
            show(message, category, *args, **kwargs)

    warnings.showwarning = once
    try:
        yield
    finally:
        warnings.showwarning = show


def _write(out, model, duration, n_seeds, study_samples, skip, progress, fmu, command, scheduler) -> Path:
    import cablecasing_core as cc

    from ..frequency.modal import frequencies_up_to, mode_count
    from . import figures, page
    from .provenance import code_state, library_versions

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    seed_list = list(range(1, n_seeds + 1))
    dt = float(model.scenario["dt"])
    kept = round((duration - skip) / dt)  # (the samples after the skip: records.after_skip keeps these)
    info = {
        "model": model.source,
        "fingerprint": model.fingerprint(),
        "version": cc.__version__,
        # (the report's own folder left out of the checkout's status: its earlier output is not a change
        # of the code; a run written into a stage, .report-run-*, is moved into the stage's folder)
        "code": code_state(exclude=out.parent if out.name.startswith(STAGE_PREFIX) else out),
        "libraries": library_versions(),
        "command": command if command is not None else shlex.join(sys.argv),
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "duration": duration,
        "dt": dt,
        "skip": skip,
        "skip_least": start_transient(model) or None,
        "start_transients": start_transients(model),
        "window": "hann",
        "record_after_skip": kept * dt,
        "df": 1.0 / (kept * dt),
        "lines_oct1": (22.0 - 11.0) * kept * dt,
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
        run_variant(v, duration, seed_list, skip, progress, scheduler)
        if v.ensemble is not None:
            v.ensemble.save(out / f"bands_{v.key}.csv")
        if v.net_ensemble is not None:
            v.net_ensemble.save(out / f"bands_net_B_{v.key}.csv")
    _say("figures", progress)
    f_min, f_max = figures.SCALOGRAM_HZ[0], figures.SCALOGRAM_HZ[-1]  # (the scalograms' range, Hz)
    harmonics = drive_harmonics(model, f_max)  # all of them up to f_max; the scalogram draws the first few
    natural = [f for f in frequencies_up_to(model, body, f_max) if f >= f_min]
    figures.time_figure(vs, out / "simulation.png", info)
    figures.scalogram_figure(vs, out / "scalograms.png", natural, harmonics, skip, info)
    contact = figures.contact_figures(model, vs[-1], out, info)
    figures.band_figure(vs, out / "band_levels.png", info=info, bias=page.mesh_bias(model, info))
    figures.psd_figure(vs, out / "psd.png", skip, info)
    figures.net_table(vs, out / "bands_net_B.csv")
    am = figures.apparent_mass_figure(model, vs[0], out / "apparent_mass.png", skip)
    rms = figures.rms_table(vs, out / "rms.csv", skip)
    study = None
    figures.clear_study(out / "study")  # (a report's study starts afresh; none leaves none)
    if study_samples:
        say = lambda runs: _say(f"a small study of {runs} runs (Fig. 23)", progress)  # noqa: E731
        study = figures.study_figures(model, out / "study", study_samples, duration, skip, progress, say, scheduler)
    runs = {
        "report": True,  # (a report's runs.json: a later report removes the files it lists, and only those)
        **info,
        "variants": [
            {
                "key": v.key,
                "title": v.title,
                "model_fingerprint": v.model.fingerprint(),
                "seed_overrides": v.seed_overrides,
                "record": v.record.relative_to(out).as_posix(),
                "ensemble": f"bands_{v.key}.csv" if v.ensemble is not None else None,
                "net_ensemble": f"bands_net_B_{v.key}.csv" if v.net_ensemble is not None else None,
                "ensemble_first_member_vs_record": v.member_check,
                "energies": getattr(v.result, "energies", None),
            }
            for v in vs
        ],
        "study": study and {k: study[k] for k in ("csv", "runs", "ok", "bounds", "seeds")},
        "fmu": fmu,
        # (every file of the report, relative to its folder: a later report removes those it does not write)
        "files": sorted({*_files_under(out), *PAGE_FILES}),
    }
    write_text(out / "runs.json", json.dumps(runs, indent=1, default=_json))
    html = page.render(model, info, modes, freq, vs, rms, am, study, fmu, harmonics, out, contact)
    return write_text(out / "report.html", html)


def _json(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


__all__ = [
    "check_report_folder",
    "check_report_settings",
    "report_skip",
    "staged_report",
    "start_transient",
    "start_transients",
    "write_report",
]
