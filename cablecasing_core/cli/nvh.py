"""``cablecasing spectrum`` and ``bands``: NVH outputs of a time record (.csv, .npz or .uff, as
``simulate --out`` writes them, an FMU's outputs, or a measurement)."""

from __future__ import annotations

import math
import os

import numpy as np

from .helptext import FromApi, add_window_argument, choice_argument

#: --skip of spectrum and bands.
SKIP_HELP = (
    "start of the record left out, s (default: [LEAST_SKIP], or the fade-in a run's record states if longer, # ramp_s, "
    "lengthened so that the rest holds whole periods of the lines it states, # lines_hz: 0.06 s of 1 s with a "
    "50 Hz drive)"
)
RECORD_HELP = "time record: .csv, .npz or .uff (as 'cablecasing simulate --out' writes, or with a time column first)"


def _record(path):
    """The time record in ``path``; an ensemble CSV (``ensemble --out``: band levels per seed, whose
    seed column would be read as a time axis) is refused as what it is."""
    import contextlib

    from ..errors import ModelError
    from ..records import read_records
    from ..studies.ensemble import _META

    ensemble = False
    with contextlib.suppress(OSError):  # (what is not a readable file is read_records's to name)
        if os.path.isfile(path):
            with open(path, encoding="utf-8", errors="replace") as f:
                f.readline(1 << 16)  # (the header; the second line marks an ensemble)
                ensemble = f.readline(1 << 16).startswith(_META)
    if ensemble:
        raise ModelError(
            "RECORD",
            path,
            "is an ensemble CSV (band levels per seed, written by 'cablecasing ensemble --out'), not a time "
            f"record: 'cablecasing pool {path}' prints its statistics",
        )
    return read_records(path)


def _names_the_record(cmd):
    """``cmd`` (spectrum, bands) whose errors about its record (``records.read_records``, ``Records.fs``:
    named ``file``) name it ``RECORD``, as its --help does."""
    import functools

    @functools.wraps(cmd)
    def named(args):
        from ..errors import renamed

        with renamed({"file": "RECORD"}):
            return cmd(args)

    return named


#: What the total of the band levels weights, by window (``bands``' RMS line): Hann's weights the
#: middle of the record (w^2 falls to 0 at both ends), so on a record whose level drifts along it
#: (a chaotic contact run) the total differs from the evenly weighted PSD's by that drift.
_WEIGHTS = {
    "hann": "Hann's window weights the middle of the record, 'spectrum --fmin/--fmax' and --window boxcar weight "
    "it evenly: they agree within the estimates' scatter where the level does not drift along the record, and "
    "differ by the drift where it does",
    "boxcar": "the rectangular window weights the record evenly: 'spectrum --fmin/--fmax' over the same range gives "
    "it within its estimate's scatter",
}


def _window(rec, args, columns):
    """The samples after ``args.skip`` (s; None takes the record's
    :meth:`~cablecasing_core.records.Records.default_skip`, stored back in ``args.skip`` for what the
    command prints). A record too short for any skip (fewer than 16 samples even with ``--skip 0``)
    is refused naming the file, the ``columns`` asked for, its length and the minimum."""
    from ..errors import ModelError
    from ..model.validators import seconds
    from ..records import after_skip
    from ..timedomain.start_skip import LEAST_SKIP

    seconds("--skip", args.skip, zero_ok=True, none_ok=True)
    dt = 1.0 / rec.fs  # (refuses an unevenly sampled record first)
    default = args.skip is None
    args.skip_words = "the default skip" if default else "--skip"  # (what the messages call it)
    if default:
        args.skip = rec.default_skip()
    skip = args.skip
    keep = after_skip(rec.time, skip, rec.time[0])
    ramp = f", or the fade-in the record states (# ramp_s = {rec.ramp_s:g} s) if longer" if rec.ramp_s > 0 else ""
    lines = ", lengthened to whole periods of the lines it states" if rec.lines_hz else ""
    whole = rec.time.size  # (what --skip 0 keeps: after_skip keeps every sample)
    if keep.sum() < 16 and whole < 16:  # (no skip helps: the record itself is too short)
        raise ModelError(
            "file",
            f"{rec.source} ({', '.join(columns)})",
            f"holds {whole} samples ({rec.time[-1] - rec.time[0]:.6g} s at dt = {dt:.4g} s): at least 16 samples are "
            "needed after the skip, more than the whole record (--skip 0) holds; record a longer one",
        )
    if keep.sum() < 16:
        raise ModelError(
            "--skip",
            skip,
            f"must leave at least 16 samples of the {rec.time[-1] - rec.time[0]:.6g} s record {rec.source} "
            f"({rec.time.size} samples at dt = {dt:.4g} s)"
            + (f"; it is the default ({LEAST_SKIP:g} s{ramp}{lines}): give a shorter one" if default else ""),
        )
    return keep


def _columns(given, default):
    """The ``--column`` options (all of them, in order): a column given twice is refused."""
    from ..errors import ModelError

    cols = list(given or default)
    for c in cols:
        if cols.count(c) > 1:
            raise ModelError("--column", c, "is given twice: give each column once")
    return cols


def _signal(rec, path, name, keep, role="--column"):
    """The samples of column ``name`` after --skip; a constant column (no spectrum, every line
    and band 0 and a level of -inf dB) is refused naming the file and the column."""
    from ..errors import ModelError

    x = rec.column(name, role)[keep]
    if np.ptp(x) == 0:
        raise ModelError(
            role,
            rec.resolve(name),
            f"is constant ({x[0]:g} {rec.unit(name)}) in {path} after the skip: it has no spectrum (every line and "
            "band would be 0, a level of -inf dB)",
        )
    return x


def _no_line(path, col, fs, n, fmin, fmax, df=None):
    """The error of a record that holds no spectral line in --fmin..--fmax (Hz)."""
    from ..errors import ModelError

    first = f"from {df:.4g} Hz " if df else ""
    return ModelError(
        "--fmin/--fmax",
        (fmin, fmax),
        f"hold no spectral line of {path}, column {col}: its {n} samples after the skip at dt = {1 / fs:.4g} s "
        f"({n / fs:.4g} s) give lines {first}up to the Nyquist frequency {fs / 2:.4g} Hz; lines down to {fmin:g} Hz "
        f"need about {4 / fmin:.4g} s of record, lines up to {fmax:g} Hz need dt <= {1 / (2 * fmax):.4g} s",
    )


def _no_covered_range(rec, args, p, top, n):
    """The error of a PSD ``p`` whose lines measure (from 2 df, ``PSD.covered``) only above ``top``
    (Hz: --fmax, or the record's passband or Nyquist frequency below it), so that --fmin..--fmax
    leaves its RMS no range: named by the option as typed (--resolution when given, else --fmax, else
    RECORD), with what would work: a higher --fmax, a finer --resolution (a power of two of
    samples per segment, at most the ``n`` samples after the skip) or a longer record."""
    from ..errors import ModelError
    from ..nvh.spectra import COVERED_FROM_DF

    fs, low = rec.fs, COVERED_FROM_DF * p.df
    seg = 2 ** (math.floor(math.log2(COVERED_FROM_DF * fs / top)) + 1)  # (the fewest samples with 2 df < top)
    if top < args.fmax:
        limit = f"the record's passband, {top:.4g} Hz ({_passband_note(rec, args.record)})"
        if top >= fs / 2:
            limit = f"the record's Nyquist frequency, {top:.4g} Hz"
    else:
        limit = f"--fmax {args.fmax:g} Hz"
    how = "--resolution" if args.resolution is not None else "the default resolution for this record"
    fixes = [f"--fmax above {low:.4g} Hz"] if top == args.fmax and low < min(rec.passband_hz, fs / 2) else []
    if seg <= n:
        fixes.append(f"--resolution {fs / seg:.4g} Hz or finer (fewer averages)")
    else:
        fixes.append(
            f"a record that leaves at least {seg / fs:.4g} s after the skip (this one leaves {n / fs:.4g} s) with "
            f"--resolution {fs / seg:.4g} Hz or finer"
        )
    key, value = ("--resolution", args.resolution) if args.resolution is not None else ("--fmax", args.fmax)
    if args.resolution is None and top < args.fmax:
        key, value = "RECORD", args.record
    return ModelError(
        key,
        value,
        f"leaves the PSD's RMS no range: its lines measure from 2 df = {low:.4g} Hz (df = {p.df:.4g} Hz, {how}), "
        f"above {limit}; give " + ", or ".join(fixes),
    )


@_names_the_record
def cmd_spectrum(args):
    import warnings

    from ..errors import ModelError, renamed
    from ..model.schema import STUDY_OUTPUT
    from ..nvh import apparent_mass, level_unit, psd, transmissibility
    from ..nvh.spectra import level_reference, squared
    from .paths import PLOT_SUFFIXES, check_distinct, check_output_path, emit_table, kept

    check_output_path("--out", args.out, (".csv",))
    check_output_path("--plot", args.plot, PLOT_SUFFIXES)
    check_distinct(("RECORD", args.record), ("--out", args.out), ("--plot", args.plot))
    args.interrupted = kept("stopped", args.out, args.plot)
    rec = _record(args.record)
    columns = _columns(args.column, [STUDY_OUTPUT])
    check_frequency_range(args.fmin, args.fmax)
    f_range = (args.fmin, args.fmax)
    keep = _window(rec, args, columns)
    fs, n = rec.fs, int(keep.sum())
    if fs / 2 <= args.fmin:
        raise _no_line(args.record, rec.resolve(columns[0], "--column"), fs, n, args.fmin, args.fmax)
    if rec.passband_hz <= args.fmin:
        raise ModelError(
            "--fmin", args.fmin, f"must lie below the record's passband: {_passband_note(rec, args.record)}"
        )
    if args.kind == "psd":
        with warnings.catch_warnings(record=True) as said:  # (said after the range is checked)
            warnings.simplefilter("always")
            res = [
                psd(
                    _signal(rec, args.record, c, keep),
                    fs,
                    nperseg=_nperseg(rec, args, n),
                    unit=rec.unit(c),
                    name=rec.resolve(c),
                    f_min=args.fmin,
                    f_max=args.fmax,
                )
                for c in columns
            ]
        top = min(args.fmax, rec.passband_hz)
        sel = (res[0].f_hz >= args.fmin) & (res[0].f_hz <= top) & (res[0].f_hz > 0)
        if not sel.any():
            raise _no_line(args.record, res[0].name, fs, n, args.fmin, args.fmax, res[0].df)
        lo, hi = res[0].covered(args.fmin, top)
        if not lo < hi:  # (before anything is printed: the RMS below would have no range)
            raise _no_covered_range(rec, args, res[0], top, n)
        for w in said:
            warnings.warn(w.message, w.category, stacklevel=1)
        with renamed({"ref": "--ref"}):
            refs = [level_reference(r.unit, args.ref) for r in res]  # (each its unit's)
        names = [f"{r.name} PSD [{squared(r.unit)}/Hz]" for r in res]
        names += [f"{r.name} level [{level_unit(ref, r.unit, power=True)}]" for r, ref in zip(res, refs)]
        table = np.column_stack([res[0].f_hz] + [r.density for r in res] + [r.level_db(f) for r, f in zip(res, refs)])
        first, last = res[0].f_hz[sel][[0, -1]]
        print(
            f"# {args.record}: PSD (Welch, Hann, segments overlapping by {res[0].noverlap / res[0].nperseg:.1%}, at "
            "least 50 %, so that they span the record after the skip to within "
            f"{n - ((res[0].n_averages - 1) * (res[0].nperseg - res[0].noverlap) + res[0].nperseg)} samples of its "
            "end), df = "
            f"{res[0].df:.4g} Hz (lines {first:.4g}-{last:.4g} Hz written), {res[0].n_averages} averages, after "
            f"{args.skip:g} s"
        )
        if top < args.fmax and rec.passband_hz < fs / 2:
            print(f"# {_passband_note(rec, args.record)}: lines and RMS end there")
        if note := _alias_note(rec, args.record, "lines"):
            print(note)
        for r in res:
            rms = np.sqrt(r.mean_square(lo, hi))
            print(
                f"# {r.name}: RMS {rms:.6g} {r.unit} in {lo:.4g}-{hi:.4g} Hz (the PSD integrated over its lines, each "
                "df wide, split at the edges, from 2 df: lines below hold a tone's power only in part, or more; its "
                "segments span the record and weight it evenly but for its first and last half segment, which weigh "
                "less (the first window rises from 0 over it, the last falls to 0), as 'bands "
                "--window boxcar' over the same range weights it evenly, whose levels add up to it within the "
                "estimates' scatter; 'bands' through Hann's window weights the "
                "middle)"
            )
        table = table[sel]
    else:
        fn = apparent_mass if args.kind == "apparent-mass" else transmissibility
        inp = args.input or ("casing.A.az" if args.kind == "apparent-mass" else "casing.A.Fz")
        _signal(rec, args.record, inp, keep, "--input")
        for c in columns:
            _signal(rec, args.record, c, keep)
        seg = _nperseg(rec, args, n, transfer=True)
        with renamed({"input": "--input", "output": "--column", "input/output": "--input/--column"}):
            res = [fn(rec, inp, c, args.estimator, args.skip, nperseg=seg) for c in columns]
        sel = (res[0].f_hz >= args.fmin) & (res[0].f_hz <= args.fmax) & (res[0].f_hz > 0)
        if not sel.any():
            raise _no_line(args.record, res[0].output, fs, n, args.fmin, args.fmax, res[0].f_hz[1])
        bad = [r for r in res if not np.all(np.isfinite(r.H[sel]))]
        if bad:
            raise ModelError(
                "--input",
                bad[0].input,
                f"has lines of zero power in {args.record} between --fmin and --fmax: the transfer function to "
                f"{bad[0].output} is undefined there (0/0); choose a range the input excites",
            )
        names = []
        cols = [res[0].f_hz]
        for r in res:
            tag = r.ratio
            names += [f"re {tag} [{r.unit}]", f"im {tag} [{r.unit}]", f"coherence {tag} [1]", f"random error {tag} [1]"]
            cols += [r.H.real, r.H.imag, r.coherence, r.error]
        table = np.column_stack(cols)[sel]
        print(
            f"# {args.record}: {res[0].kind} ({args.estimator}), df = {res[0].f_hz[1]:.4g} Hz, "
            f"{res[0].n_averages} averages, after {args.skip:g} s"
        )
        if args.kind == "apparent-mass":
            print(
                f"# {res[0].ratio}: the TRFAM's sign convention, the force the support applies to the body, "
                "the recorded force negated (docs/nvh.md)"
            )
        if note := _alias_note(rec, args.record, "lines"):
            print(note)
    emit_table(args.out, ["frequency [Hz]", *names], table, 9)
    if args.plot:
        from ..nvh.plots import plot_psd, plot_transfer

        if args.kind == "psd":
            plot_psd(res, args.plot, args.ref, log_frequency=not args.linear_frequency, f_range=f_range)
        else:
            plot_transfer(res[0], args.plot, log_frequency=not args.linear_frequency, f_range=f_range)
        print(f"# wrote {args.plot}")
    return 0


def _model_output(name):
    """Whether the column ``name`` is a model output, or the sum of model outputs that a derived
    column's name says it is (``net.B.Fz`` read back from a file written after it was derived:
    ``records.derived_terms``)."""
    from ..errors import ModelError
    from ..model.schema import is_output
    from ..records import derived_terms

    if is_output(name):
        return True
    try:
        terms = derived_terms(name, ())
    except ModelError:
        return False
    return terms is not None and all(is_output(t) for t in terms)


def _beyond_table3_note(terms, top_hz, step):
    """The note on a model output's bands that reach above the paper's Table 3 (its top octave ends
    at 5680 Hz), over which the model's accuracy is shown (docs/time_domain.md); None for other
    columns (a measurement's) or bands within it. ``terms``: the columns the column sums
    (``Records.terms``: ``net.B.Fz`` is a model output's if its terms are); ``step``: what the record says
    of its run's time step (``Records.run_step``). Above it Newmark's period error grows as (ω Δt)² / 12
    (``structure.route_summary.newmark_period_error``: 1.1 % at 5.68 kHz, 13 % at 20 kHz at Δt = 1e-5 s),
    quoted at the run's step where the record tells it, at most at its bound for a decimated record, and
    at the default step, as such, where it cannot be known; and the 35 elements' mesh resolves fewer
    bending waves (about one element per wavelength of the casing at 20 kHz)."""
    from ..model.schema import lookup
    from ..nvh.bands import TABLE3_UPPER
    from ..timedomain.accuracy import newmark_period_error

    if top_hz <= TABLE3_UPPER[-1] or not all(_model_output(t) for t in terms):
        return None
    f3, default = TABLE3_UPPER[-1], lookup("scenario.dt").default

    def errors(dt):
        at = (newmark_period_error(top_hz, dt), newmark_period_error(f3, dt))
        return f"{100 * at[0]:.2g} % at {top_hz:.0f} Hz ({100 * at[1]:.2g} % at {f3:g} Hz)"

    if step is None:
        said = (
            "the run's step is unknown (the record states no passband: picked samples, or another program's), so "
            f"Newmark's period error (2 pi f dt)^2 / 12 is too; at the default step, {default:g} s, it would be "
            f"{errors(default)}"
        )
    elif step[1] == "every step":
        said = f"at the run's step, {step[0]:.6g} s (the record holds every step), Newmark's period error is "
        said += errors(step[0])
    else:
        said = (
            "the record is decimated and does not state the run's step, at most half its sample interval, "
            f"{step[0]:.6g} s, where Newmark's period error is at most {errors(step[0])}"
        )
    return (
        f"# the bands above {f3:g} Hz lie beyond the paper's Table 3, over which the model's accuracy is shown "
        f"(docs/time_domain.md): {said}, and the mesh resolves fewer waves"
    )


def _alias_note(rec, path, what):
    """The note on a record that states no passband (``passband_hz``: a CSV of an FMU's outputs
    written by a host such as fmpy or fmusim, a measurement, a run's record picked, another tool's
    UFF file): its samples hold what lay above their Nyquist frequency folded below it, unless the
    signal was low-pass filtered before it was sampled; None for a record that states its passband
    (a run's record every step or filtered by ``simulate --output-interval``, in ``.csv``, ``.npz``
    or ``.uff``)."""
    if "passband_hz" in rec.extra:
        return None
    return (
        f"# {path} states no passband: content above its "
        f"Nyquist frequency {rec.fs / 2:.6g} Hz (dt = {1 / rec.fs:.4g} s) may have aliased into the {what} unless it "
        "was filtered before sampling (a run's record every step or filtered holds none; an FMU's outputs are samples "
        'at its communication points; docs/nvh.md, "Sampled records")'
    )


def _passband_note(rec, path):
    """What a decimated record's passband (``Records.passband_hz``) is, for a note or an error."""
    return (
        f"{path} was decimated to dt = {1 / rec.fs:.4g} s: its anti-alias filter is flat (0.01 dB) up to "
        f"{rec.passband_hz:.4g} Hz, {rec.passband_hz / (rec.fs / 2):.2g} of its Nyquist frequency {rec.fs / 2:.4g} Hz, "
        "and attenuates above"
    )


def check_frequency_range(fmin, fmax):
    """``--fmin``/``--fmax`` (Hz): 1e-6 <= fmin < fmax <= 1e6 (``frequency.trfam.MIN_FREQUENCY_HZ`` and
    ``MAX_FREQUENCY_HZ``: the model and its records lie far inside; a spectrum has no line at 0 Hz to
    resolve, and the TRFAM none to compute)."""
    from ..errors import ModelError
    from ..frequency.trfam import MAX_FREQUENCY_HZ, MIN_FREQUENCY_HZ
    from ..model.validators import number

    number("--fmin", fmin, ge=MIN_FREQUENCY_HZ, le=MAX_FREQUENCY_HZ, unit="Hz")
    number("--fmax", fmax, ge=MIN_FREQUENCY_HZ, le=MAX_FREQUENCY_HZ, unit="Hz")
    if not fmin < fmax:
        raise ModelError("--fmin/--fmax", (fmin, fmax), "need fmin < fmax (Hz)")


def _nperseg(rec, args, n, transfer=False):
    """Samples per Welch segment for ``--resolution`` Hz (a power of two), or None (the default);
    n: the record's samples after --skip (:func:`_window`); transfer: for a transfer function,
    whose segment must leave ``nvh.transfer.MIN_AVERAGES`` Welch averages (50 % overlap; its
    coherence needs them) and hold ``nvh.transfer.MIN_SEGMENT`` samples, else a PSD's (one
    segment, ``nvh.spectra.MIN_PSD_SEGMENT`` samples)."""
    if args.resolution is None:
        return None
    from ..model.validators import number
    from ..nvh.spectra import MIN_PSD_SEGMENT, segment_for_resolution
    from ..nvh.transfer import MIN_AVERAGES, MIN_SEGMENT

    number("--resolution", args.resolution, gt=0, unit="Hz")
    averages, least = (MIN_AVERAGES, MIN_SEGMENT) if transfer else (1, MIN_PSD_SEGMENT)
    return segment_for_resolution("--resolution", args.resolution, rec.fs, n, averages, least)


def _fmin_option(text):
    """``text`` of ``octave_rms`` (an error or a warning) with its advice to leave out the lowest bands
    by ``octave_bands``' f_min (``nvh.bands.FMIN_ADVICE``) said as this command's ``--fmin``."""
    import re

    from ..nvh.bands import FMIN_ADVICE

    pattern = re.escape(FMIN_ADVICE).replace(re.escape("{f_min:g}"), r"([^)\s]+)")
    return re.sub(pattern, r"--fmin \1", text)


@_names_the_record
def cmd_bands(args):
    import warnings

    from ..errors import ModelError, renamed
    from ..files import atomic_path
    from ..model.schema import STUDY_OUTPUT
    from ..nvh.bands import WINDOW_NAMES, octave_bands, octave_rms, window_options
    from ..nvh.spectra import level_reference
    from .paths import PLOT_SUFFIXES, check_distinct, check_output_path, kept

    check_output_path("--out", args.out, (".csv",))
    check_output_path("--plot", args.plot, PLOT_SUFFIXES)
    check_distinct(("RECORD", args.record), ("--out", args.out), ("--plot", args.plot))
    args.interrupted = kept("stopped", args.out, args.plot)
    columns = _columns(args.column, [STUDY_OUTPUT])
    if len(columns) > 1:
        raise ModelError("--column", ", ".join(columns), "bands takes one column: run it once per column")
    with renamed({"f_min": "--fmin", "f_max": "--fmax", "f_min/f_max": "--fmin/--fmax"}, in_text=True):
        band_set = octave_bands(args.kind, args.fmin, args.fmax)
    rec = _record(args.record)
    keep = _window(rec, args, columns)
    col = rec.resolve(columns[0], "--column")
    unit = rec.unit(col)
    with renamed({"ref": "--ref"}):  # (BandRMS.level_db's rule: the unit's reference, 1 where none is known)
        ref = level_reference(unit, args.ref)
    x = _signal(rec, args.record, col, keep)
    if band_set.upper[0] > rec.fs / 2:
        raise ModelError(
            "--column",
            col,
            f"of {args.record} is sampled at dt = {1 / rec.fs:.4g} s: its Nyquist frequency {rec.fs / 2:.4g} Hz lies "
            f"below every {args.kind} band (the lowest ends at {band_set.upper[0]:.4g} Hz); the bands need dt <= "
            f"{0.5 / band_set.upper[0]:.4g} s",
        )
    passband = rec.passband_hz
    if passband < rec.fs / 2:  # a decimated record: bands beyond its passband as bands beyond Nyquist
        within = band_set.upper <= passband
        if not within.any():
            share = passband / (rec.fs / 2)  # (of the Nyquist frequency: the filter's, whatever the interval)
            raise ModelError(
                "--column",
                col,
                f"has no {args.kind} band within its passband: {_passband_note(rec, args.record)}; the lowest "
                f"band ends at {band_set.upper[0]:.4g} Hz (write the record with an output interval <= "
                f"{share / (2 * band_set.upper[0]):.4g} s)",
            )
        if not within.all():  # (octave_rms leaves them out: passband, beyond_nyquist="drop")
            print(f"# {_passband_note(rec, args.record)}: the bands above it are left out")
    name = f"{col} in {args.record} (the record after {args.skip_words}, {args.skip:g} s)"
    with warnings.catch_warnings(record=True) as said:  # (its advice said as this command's option, below)
        warnings.simplefilter("always")
        try:
            bands = octave_rms(
                x,
                rec.fs,
                band_set,
                beyond_nyquist="drop",
                name=name,
                passband=passband,
                unit=unit,
                **window_options(args.window),
            )
        except ModelError as exc:
            raise ModelError(exc.key, exc.value, _fmin_option(exc.allowed)) from None
    for w in said:
        warnings.warn(_fmin_option(str(w.message)), w.category, stacklevel=1)
    level = bands.level_db(ref)
    total = float(np.sqrt(np.sum(bands.mean_square)))
    print(
        f"# {args.record}: {col} after {args.skip:g} s, {args.kind} bands, {WINDOW_NAMES[args.window]} window; "
        f"level in dB re {ref:g} {unit}"
    )
    if note := _alias_note(rec, args.record, "bands"):
        print(note)
    if note := _beyond_table3_note(rec.terms(col), bands.upper[-1], rec.run_step()):
        print(note)
    print(
        f"# RMS over the bands, {bands.lower[0]:.4g}-{bands.upper[-1]:.4g} Hz: {total:.6g} {unit} (their mean "
        f"squares summed; {_WEIGHTS[args.window]})"
    )
    header, rows = band_table(bands, unit, ref, level)
    print(header)
    print("\n".join(rows))
    if args.out:
        with atomic_path(args.out) as tmp, open(tmp, "w", encoding="utf-8") as fh:
            fh.write(header + "\n" + "\n".join(rows) + "\n")
        print(f"# wrote {args.out}")
    if args.plot:
        from ..nvh.plots import plot_band_levels

        plot_band_levels([bands], args.plot, unit, ref, title=f"{col}: {args.kind} band levels ({args.record})")
        print(f"# wrote {args.plot}")
    return 0


def band_table(bands, unit, ref=None, level=None):
    """(header, rows) of a band table as ``bands`` and ``trfam --bands`` print and write it:
    ``band,f_centre [Hz],f_low [Hz],f_high [Hz],rms [unit]`` and, with ``level`` (dB re ``ref``,
    one per band), ``level [dB re ref unit]``; the values to 6 significant digits, a level to 0.01 dB."""
    header = f"band,f_centre [Hz],f_low [Hz],f_high [Hz],rms [{unit}]"
    rows = [
        f"{lab},{c:.6g},{lo:.6g},{hi:.6g},{r:.6g}"
        for lab, c, lo, hi, r in zip(bands.labels, bands.centre, bands.lower, bands.upper, bands.rms)
    ]
    if level is not None:
        header += f",level [dB re {ref:g} {unit}]"
        rows = [f"{row},{L:.2f}" for row, L in zip(rows, level)]
    return header, rows


def trfam_bands(args, f, H):
    """``cablecasing trfam --bands KIND``: the band values of the TRFAM ``H`` (kg) computed at ``f``
    (Hz), :func:`~cablecasing_core.frequency.trfam.trfam_band_rms` (the RMS of |TRFAM| over each
    band), printed, or written to ``--out`` (.csv), after a note of what they are and of the bands
    the grid --fmin..--fmax leaves out."""
    from ..errors import renamed
    from ..files import atomic_path
    from ..frequency.trfam import trfam_band_rms
    from ..nvh.bands import octave_bands

    every = octave_bands(args.bands)
    with renamed({"freqs_hz": "--fmin/--fmax"}):
        bands = trfam_band_rms(f, H, every)
    print(
        f"# TRFAM {args.output} / {args.input} ({args.damping} damping), kg: the RMS of |TRFAM| over each "
        f"{args.bands} band, sqrt(integral of |TRFAM|^2 df / (f_high - f_low)), over the grid {f[0]:g}-{f[-1]:g} Hz "
        f"(--df {args.df:g}): the force's band RMS per acceleration band RMS of an input flat in the band"
    )
    gone = [lab for lab in every.labels if lab not in bands.labels]
    if gone:
        import math

        def rounded(x, up):  # (to 4 significant digits, outwards: the grid then covers the band)
            u = 10.0 ** (math.floor(math.log10(x)) - 3)
            return float(f"{(math.ceil(x / u) if up else math.floor(x / u)) * u:.4g}")

        need = []
        if every.lower[0] < f[0]:
            need.append(f"down to {rounded(every.lower[0], False):g} Hz (--fmin)")
        if every.upper[-1] > f[-1]:
            need.append(f"up to {rounded(every.upper[-1], True):g} Hz (--fmax)")
        print(
            f"# the grid leaves out band(s) {', '.join(gone)}, which reach beyond it: they need frequencies "
            + " and ".join(need)
        )
    header, rows = band_table(bands, "kg")
    if args.out:
        with atomic_path(args.out) as tmp, open(tmp, "w", encoding="utf-8") as fh:
            fh.write(header + "\n" + "\n".join(rows) + "\n")
        print(f"# wrote {args.out}")
    else:
        print(header)
        print("\n".join(rows))


def add_parser(sub):
    s = sub.add_parser("spectrum", help="PSD (Welch), apparent mass or force transmissibility of a time record")
    s.add_argument("record", metavar="RECORD", help=RECORD_HELP)
    s.add_argument(
        "--kind",
        choices=["psd", "apparent-mass", "transmissibility"],
        default="psd",
        help="psd: PSD of each --column; apparent-mass: F/a from --input (m/s2) to --column (N), kg, in the TRFAM's "
        "sign convention; transmissibility: --column / --input (two forces)",
    )
    s.add_argument(
        "--column",
        action="append",
        default=None,
        help="record column, e.g. casing.B.Fz, or a sum of columns: net.B.Fz (casing.B.Fz + cable.B.Fz, the force "
        "into the part both ends attach to), paths.Fz (every end and clip), a+b; repeat --column for more columns, "
        "--column casing.B.Fz --column net.B.Fz (default: casing.B.Fz)",
    )
    s.add_argument(
        "--input",
        default=None,
        help="input column of a transfer function (default: casing.A.az for the apparent mass, casing.A.Fz for "
        "the transmissibility)",
    )
    s.add_argument("--estimator", choices=["H1", "H2"], default="H1", help="H1 (noise on the output) or H2")
    s.add_argument(
        "--resolution",
        type=float,
        default=None,
        help="frequency resolution, Hz (a power of two of samples per segment; default for the PSD: twice the "
        "resolution, where its lines measure from, at or below --fmin, with at least 7 averages, else the first "
        "line at or below --fmin, else a warning names where they start; for the transfer kinds 1 Hz, at most an "
        "eighth of the record)",
    )
    s.add_argument(
        "--skip",
        type=float,
        default=None,
        help=SKIP_HELP,
    )
    s.add_argument("--fmin", type=float, default=1.0, help="lowest frequency written and drawn, Hz")
    s.add_argument("--fmax", type=float, default=2000.0, help="highest frequency written and drawn, Hz")
    s.add_argument(
        "--ref",
        type=float,
        default=None,
        help="reference of the dB levels in the column's unit (default: by unit, [REFERENCES]; docs/nvh.md)",
    )
    s.add_argument("--out", default=None, help="CSV to write (default: print the table)")
    s.add_argument("--plot", default=None, metavar="PNG", help="figure to write")
    s.add_argument("--linear-frequency", action="store_true", help="linear frequency axis in --plot (default: log)")
    s.set_defaults(func=cmd_spectrum)

    b = sub.add_parser("bands", help="octave or third-octave band RMS and levels (dB) of a record column")
    b.add_argument("record", metavar="RECORD", help=RECORD_HELP)
    b.add_argument(
        "--column",
        action="append",
        default=None,
        help="record column, e.g. casing.B.Fz, or a sum of columns: net.B.Fz (casing.B.Fz + cable.B.Fz, the force "
        "into the part both ends attach to), paths.Fz (every end and clip), a+b (default: casing.B.Fz)",
    )
    choice_argument(
        b,
        "--kind",
        choices=FromApi("nvh.bands", "BAND_KINDS"),
        default="table3",
        help="table3: the paper's nine octaves [TABLE3_RANGE] (oct1..oct9); octave, third: IEC 61260-1 base-10 bands, "
        "named by their nominal mid-band frequencies (16Hz, 31.5Hz, ...)",
    )
    b.add_argument(
        "--fmin",
        type=float,
        default=None,
        help="lowest mid-band frequency kept, Hz (default: all of table3; [IEC_F_MIN] for octave and third): "
        "leaves out bands the record is too short to resolve",
    )
    b.add_argument(
        "--fmax", type=float, default=None, help="highest mid-band frequency kept, Hz (default: all; [IEC_F_MAX])"
    )
    add_window_argument(b)
    b.add_argument(
        "--skip",
        type=float,
        default=None,
        help=SKIP_HELP,
    )
    b.add_argument(
        "--ref", type=float, default=None, help="reference of the dB levels (default: by unit, as 'spectrum')"
    )
    b.add_argument("--out", default=None, help="CSV of the table")
    b.add_argument("--plot", default=None, metavar="PNG", help="figure to write")
    b.set_defaults(func=cmd_bands)
