"""``cablecasing identify ...``: parameter identification from measured files (the paper's Section 3).

Sub-commands (each reads CSV or UFF dataset 58, prints a table and the identified parameters as
model-file TOML, optionally writes a figure and a TOML file):

* ``damping FILE``     wavelet ridges of an impulse response -> zeta per mode; Rayleigh alpha, beta
                       (Section 3.2.1, Eqs. 41-44, Fig. 11)
* ``loss-factor FILE`` Nyquist circles of an FRF -> loss factor per mode (Section 3.2.2, Eq. 45, Fig. 13)
* ``modulus FILE``     measured natural frequencies -> E per mode and an E(f) table (Section 3.1, Figs. 8-9)

The main CLI registers them with :func:`add_parser`; every handler returns an exit code
(0 success, 2 invalid input, with the offending field named on stderr).
"""

from __future__ import annotations

import contextlib
import sys
import warnings

import numpy as np

from ..errors import CableCasingError, ModelError, renamed
from ..model.schema import BODY_NAMES
from .helptext import FromApi, choice_argument, name_by_choices, taking_api_defaults
from .paths import PLOT_SUFFIXES


def _fail(exc):
    """One line and status 2, in the form of every command's errors (``cablecasing: error: ...``)."""
    print(f"cablecasing: error: {exc}", file=sys.stderr)
    return 2


def _check_outputs(args):
    """--toml and --plot writable before the identification starts (cli/paths.py)."""
    from .paths import check_distinct, check_output_path

    check_output_path("--toml", args.toml, (".toml",))
    check_output_path("--plot", args.plot, PLOT_SUFFIXES)
    check_distinct(("file", args.file), ("--model", getattr(args, "model", None)), ("--toml", args.toml))


#: ``identify modulus --resolution`` (Hz) for a table ``mode,f_hz`` (the paper's 0.5 Hz); an FRF's frequencies
#: are iterated to a tenth of their circle fits' uncertainty (to half the line spacing for its peaks).
TABLE_RESOLUTION_HZ = 0.5

#: find_resonances' advice when an FRF has fewer peaks than asked for, in the words of its arguments.
_PEAKS_HINT = "give the resonances themselves (f_res_hz, --freqs) or a smaller count"


@contextlib.contextmanager
def _hint(replacements):
    """A :class:`ModelError` raised in the block again with the texts ``replacements`` ({text: new})
    replaced in what it says is allowed (advice in the words of a function's arguments put in the
    command line's)."""
    try:
        yield
    except ModelError as exc:
        allowed = exc.allowed
        for text, new in replacements.items():
            allowed = allowed.replace(text, new)
        if allowed == exc.allowed:
            raise
        raise ModelError(exc.key, exc.value, allowed) from None


def _write_toml(path, text):
    from ..files import write_text

    write_text(path, text)
    print(f"wrote {path}")


def _emit(args, toml, plot_name, res, **plot_kw):
    """Print the TOML snippet (if any) and write it to --toml; draw --plot with
    ``identification.plots.<plot_name>(res, path, **plot_kw)``."""
    if toml:
        print(toml, end="")
        if args.toml:
            _write_toml(args.toml, toml)
    if args.plot:
        from ..identification import plots

        getattr(plots, plot_name)(res, args.plot, **plot_kw)
        print(f"wrote {args.plot}")


def _max_iter(args):
    """``--max-iter`` (default the circle fit's own, ``circlefit.MAX_ITER``), checked (>= 0)."""
    from ..model.validators import integer

    args.max_iter = integer("--max-iter", args.max_iter, 0)
    return args.max_iter


def _unsettled(args, fits):
    """What the TOML's comment and the refusal of ``--toml`` say when the circle fits' neighbour correction
    stopped at ``--max-iter`` sweeps before the loss factors settled (``extra["settled"]``); None when settled."""
    change = max(r.extra["correction_change"] for r in fits)
    if change == 0.0:
        return None
    return (
        f"the neighbouring-mode correction did not settle in --max-iter {args.max_iter} sweeps (the loss factors "
        f"still changed by {change:.2g}, relative, in the last: an error of about that size)"
    )


def _fitted_toml(args, fits, comment, **values):
    """The TOML (``parameters_toml`` of ``--body``) of ``values`` identified through the circle fits ``fits``
    (none: nothing to settle), its ``comment`` marked NOT SETTLED when their neighbour correction did not settle
    (:func:`_unsettled`); then :func:`_toml_of_unsettled`."""
    from ..identification import parameters_toml

    note = _unsettled(args, fits) if fits else None
    toml = parameters_toml(args.body, comment=comment + (f"\nNOT SETTLED: {note}" if note else ""), **values)
    _toml_of_unsettled(args, toml, note)
    return toml


def _toml_of_unsettled(args, toml, note):
    """A ModelError naming --toml (after printing the TOML) when the fits did not settle and --toml is given
    without --allow-unsettled: unsettled values are not written silently."""
    if note and args.toml and not args.allow_unsettled:
        print(toml, end="")
        raise ModelError(
            "--toml",
            args.toml,
            f"not written: {note}; give a larger --max-iter (close modes: 0.75 half-power bandwidths apart settle "
            "in about 450 sweeps, 0.4 apart in about 4600), or --allow-unsettled to write these values, marked as "
            "not settled",
        )


#: The peaks ``identify damping`` takes without ``--freqs`` or ``--count``: up to this many, the most prominent.
DAMPING_PEAKS = 3


def _spectrum_peaks(x, fs, count, path):
    """``identification.spectrum_peaks`` of the record read from ``path`` (its ``count``, ``--count``, most
    prominent peaks; None: up to :data:`DAMPING_PEAKS` of them, as many as it has), its errors in the
    command line's words: a record without a peak names the file, a ``--count`` given beyond the peaks
    says how many there are; both ask for the frequencies (``--freqs``)."""
    from ..identification import spectrum_peaks

    try:
        if count is None:
            count = min(DAMPING_PEAKS, spectrum_peaks(x, fs).size)
        return spectrum_peaks(x, fs, count)
    except ModelError as exc:
        if exc.key == "x":
            raise ModelError("file", str(path), f"{exc.allowed}: give the natural frequencies (--freqs)") from None
        if exc.key != "count":
            raise
        allowed = exc.allowed.replace("of the record", f"of {path}")
        raise ModelError(
            "--count", count, f"{allowed}; give a smaller --count, or the natural frequencies themselves (--freqs)"
        ) from None


#: The wavelet's advice in the words of its arguments, in the command line's.
_DAMPING_HINTS = {
    "Skipping the check (max_departure None, --max-departure off)": "Skipping the check (--max-departure off)",
    "a larger gamma (the CLI's --gamma)": "a larger --gamma",
    "a larger gamma, the CLI's --gamma,": "a larger --gamma",
    "(allowed: max_departure = ": "(allowed: --max-departure = ",
    "cut the record (t_max)": "cut the record (--t-max)",
    "give t_max (the CLI's --t-max)": "give --t-max",
    "(give t0)": "(give --t0, the first sample's time with the impulse at t = 0)",
    "pick the response channel (the CLI's --channel)": "pick the response channel with --channel",
    "give its time axis, t0 = the first sample's time": "give --t0, the first sample's time",
    "a smaller gamma or a noise_floor": "a smaller --gamma or a --noise-floor",
    "(search, the CLI's --search,": "(--search,",
    "(search, the CLI's --search)": "(--search)",
}


@contextlib.contextmanager
def _record_named(args, channel, keys=("x",)):
    """A :class:`ModelError` about the data read from the file (the function's arguments ``keys``:
    the wavelet's record ``x``, the circle fit's ``freqs_hz`` and ``H``) raised again naming the file
    and the channel (None: the file's only one) it was read from."""
    try:
        yield
    except ModelError as exc:
        if exc.key not in keys:
            raise
        where = "" if channel is None else f"channel {channel}, "
        raise ModelError("file", str(args.file), f"{where}{exc.value}: {exc.allowed}") from None


#: The wavelet's arguments by the options that give them (their errors name the option).
_DAMPING_OPTIONS = {"gamma": "--gamma", "window_tau": "--window-tau", "max_departure": "--max-departure",
                    "edge_factor": "--edge-factor", "search": "--search", "noise_floor": "--noise-floor",
                    "t_max": "--t-max", "channel": "--channel", "t0": "--t0"}  # fmt: skip


def _max_departure(text):
    """``--max-departure``: None (the check off) for 'off', else a number of nepers > 0 (default the
    wavelet's MAX_DEPARTURE)."""
    from ..model.validators import number

    if str(text).strip().lower() == "off":
        return None
    try:
        value = float(text)
    except ValueError:
        raise ModelError("max_departure", text, "must be a number of nepers > 0, or off") from None
    return number("max_departure", value, gt=0)


def _check_rayleigh_toml(args):
    """``--toml`` writes the Rayleigh factors, whose fit needs two modes or more: one mode (``--freqs``
    of one frequency, ``--count 1``) with ``--toml`` is a :class:`ModelError` naming --toml before the
    record is read (there would be nothing to write)."""
    modes = len(args.freqs) if args.freqs else (DAMPING_PEAKS if args.count is None else args.count)
    if args.toml and modes < 2:
        given = f"--freqs gives one frequency ({args.freqs[0]:g} Hz)" if args.freqs else "--count is 1"
        raise ModelError(
            "--toml",
            args.toml,
            f"writes the Rayleigh factors alpha, beta, whose fit needs the damping of two modes or more: {given}; "
            "give two natural frequencies or more (--freqs, --count), or leave --toml out (the table of zeta "
            "is printed)",
        )


@taking_api_defaults
def cmd_damping(args):
    try:
        _check_outputs(args)
        from ..identification import parameters_toml, rayleigh_fit, read_time_record_from, wavelet_damping
        from ..identification.wavelet import refuse_pulse
        from ..model.validators import frequencies, integer, number

        with renamed(_DAMPING_OPTIONS):  # (the options' ranges before any work on the record)
            number("gamma", args.gamma, gt=0, le=1e3)
            departure = _max_departure(args.max_departure)
            if args.noise_floor is not None:
                number("noise_floor", args.noise_floor, gt=0)
            if not args.freqs and args.count is not None:
                integer("--count", args.count, 1)
            _check_rayleigh_toml(args)
            x, fs, name, t_start = read_time_record_from(args.file, args.channel)
            if args.t0 is not None:  # (the first sample's time, the impulse at 0: the file's axis shifted)
                t_start = number("t0", args.t0, unit="s")
        if args.freqs:  # (each in (0, fs/2): named as the option before any work)
            frequencies("--freqs", args.freqs, fs)
        with _hint(_DAMPING_HINTS), _record_named(args, name):  # (a force channel: said before its spectrum's peaks)
            refuse_pulse(x, fs, t_start)
        if not args.freqs:  # (the peaks of the record before a padding of zeros: the fit ends before it too)
            from ..identification.wavelet import trailing_padding

            pad = trailing_padding(x)
        freqs = args.freqs if args.freqs else _spectrum_peaks(x[:pad] if pad else x, fs, args.count, args.file)
        if args.toml and len(freqs) < 2:  # (the default count found one peak only)
            raise ModelError(
                "--toml",
                args.toml,
                f"writes the Rayleigh factors alpha, beta, whose fit needs the damping of two modes or more: the "
                f"amplitude spectrum of {args.file} has one peak above its noise ({freqs[0]:.6g} Hz); give two "
                "natural frequencies or more (--freqs), or leave --toml out (the table of zeta is printed)",
            )
        if args.t_max is not None:  # (on the file's time axis, as the fit's times)
            number("--t-max", args.t_max, gt=t_start, unit="s")
        try:
            with renamed({**_DAMPING_OPTIONS, "freqs_hz": "--freqs"}), _hint(_DAMPING_HINTS), _record_named(args, name):
                res = wavelet_damping(
                    x,
                    fs,
                    freqs,
                    max_departure=departure,
                    gamma=args.gamma,
                    edge_factor=args.edge_factor,
                    search=args.search,
                    noise_floor=args.noise_floor,
                    t_max=args.t_max,
                    t0=t_start,
                    window_tau=args.window_tau,
                )
        except ModelError as exc:
            if args.freqs or exc.key != "--freqs":
                raise
            found = ", ".join(f"{v:.6g}" for v in freqs)
            raise ModelError(
                "--freqs",
                exc.value,
                f"{exc.allowed} (the frequencies were the amplitude spectrum's {len(freqs)} most prominent peaks, "
                f"{found} Hz, not given: on a noisy record these may be noise; give --freqs)",
            ) from None
        pre = " (a pre-trigger: the impulse at t = 0)" if t_start < 0 else ""
        pre += " (--t0)" if args.t0 is not None else ""
        win = "" if args.window_tau is None else f"; exponential window tau = {args.window_tau:g} s taken off"
        if not args.freqs:
            win += f"; f_req_Hz: the {len(freqs)} most prominent peaks of its amplitude spectrum"
        print(
            f"# {args.file} ({name}): {x.size} samples at {fs:g} Hz from t = {t_start:g} s{pre}; Morlet gamma = "
            f"{args.gamma:g}; the fit's times on the file's time axis{win}"
        )
        print(
            f"{'mode':>4} {'f_req_Hz':>10} {'f_ridge_Hz':>11} {'f_n_Hz':>10} {'zeta':>9} {'zeta_unc_%':>10} "
            f"{'fit_from_s':>10} {'fit_to_s':>9}"
        )
        for i, r in enumerate(res, 1):
            t0, t1 = r.t_fit
            print(
                f"{i:>4} {r.f_requested_hz:>10.3f} {r.f_ridge_hz:>11.3f} {r.f_natural_hz:>10.3f} "
                f"{r.zeta:>9.5f} {100 * r.zeta_sd / r.zeta:>10.2g} {t0:>10.4f} {t1:>9.4f}"
            )
        print(
            "# zeta_unc_%: one standard deviation for the record's noise, from the fitted line (it does not cover "
            "a close mode, a second hit, or a bias where the noise floor ends the window: docs/identification.md)"
        )
        toml = None
        if len(res) >= 2:
            fn = [r.f_natural_hz for r in res]
            zs = [r.zeta for r in res]
            sd = [r.zeta_sd for r in res]
            with warnings.catch_warnings(record=True) as said:  # (said of the fit used: this, or the nonnegative)
                warnings.simplefilter("always")
                fit = rayleigh_fit(fn, zs, nonnegative=args.nonnegative, zeta_sd=sd)
            if not args.nonnegative and (fit.alpha < 0 or fit.beta < 0):
                print(
                    f"# least squares gives alpha = {fit.alpha:.6g} 1/s, beta = {fit.beta:.6g} s; the model "
                    "file needs both >= 0, so the nonnegative fit follows"
                )
                fit = rayleigh_fit(fn, zs, nonnegative=True, zeta_sd=sd)
            else:
                for w in said:
                    warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)

            def pm(v):
                return " (at its bound)" if np.isnan(v) else f" +- {v:.2g}"

            misfit = (
                "" if np.isnan(fit.reduced_chi2) else f", reduced chi-square {fit.reduced_chi2:.3g} against zeta_unc"
            )
            print(
                f"Rayleigh (Eq. 44): alpha = {fit.alpha:.6g}{pm(fit.alpha_sd)} 1/s, beta = {fit.beta:.6g}"
                f"{pm(fit.beta_sd)} s (one standard deviation from zeta_unc), rms residual of zeta = "
                f"{fit.rms_residual:.3g}{misfit}"
            )
            for f_, z_, zf in zip(fn, zs, fit.zeta_fit):
                print(f"    {f_:10.3f} Hz: zeta = {z_:.5f}, Rayleigh {zf:.5f}")
            toml = parameters_toml(
                args.body, alpha=fit.alpha, beta=fit.beta, comment=f"Rayleigh damping identified from {args.file}"
            )
        _emit(args, toml, "plot_ridges", res, x=x, fs=fs)
        return 0
    except CableCasingError as exc:
        return _fail(exc)


def _same_resonance(exc, off, fewer):
    """What a circle fit's refusal ``exc`` of two requests that found the same resonance (``f_res_hz``,
    a list, Hz) says when the command took them from the peaks of |H| for want of --freqs: the peaks as
    found (6 digits), and either that the neighbour correction, which separates close modes, was off
    (``off``: the options that turned it off, ``exc.allowed`` then names the resonances the uncorrected
    fits found) or to give fewer peaks (``fewer``: the option of their number) or the resonances."""
    peaks = " and ".join(f"{v:.6g}" for v in exc.value)
    said = exc.allowed.split(": request each mode once")[0]  # (found the same resonance (..., ... Hz, ...))
    fix = (
        f"the neighbouring-mode correction, which separates close modes, was off ({off}): leave it on"
        if off
        else f"give fewer peaks ({fewer}) or the resonances themselves (--freqs)"
    )
    return f"the peaks of |H| at {peaks} Hz, taken for want of --freqs, {said}: {fix}"


@contextlib.contextmanager
def _peaks_found(args):
    """Without --freqs, a :class:`ModelError` about one of the resonances (``f_res_hz``) names
    ``--count``, their number, and says that the command took it from the peaks of |H|; without
    --count too (every peak above the noise fitted) it names the file and asks for --count or --freqs."""
    try:
        yield
    except ModelError as exc:
        if not args.freqs and exc.key == "f_res_hz" and isinstance(exc.value, list):  # (two found one resonance)
            if args.no_correction or args.max_iter == 0:
                key, value = ("--no-correction", True) if args.no_correction else ("--max-iter", 0)
            else:
                key, value = ("file", str(args.file)) if args.count is None else ("--count", args.count)
            raise ModelError(key, value, _same_resonance(exc, "--no-correction or --max-iter 0", "--count")) from None
        if args.freqs or exc.key != "f_res_hz" or not isinstance(exc.value, float):
            raise
        if args.count is None:  # (every peak above the noise: no option to name, the file's peaks are at fault)
            raise ModelError(
                "file",
                str(args.file),
                f"the resonance near {exc.value:g} Hz, one of the peaks of |H| above its noise, all of which are "
                f"fitted when neither --freqs nor --count is given: {exc.allowed}; a broad maximum of |H| (the rise "
                "after an anti-resonance) is such a peak too: give the number of resonances to fit, the most "
                "prominent peaks (--count N), or the resonances themselves (--freqs)",
            ) from None
        raise ModelError(
            "--count",
            args.count,
            f"the resonance near {exc.value:g} Hz, one of the peaks of |H| taken for want of --freqs: {exc.allowed}; "
            "give the resonances themselves (--freqs)",
        ) from None


@taking_api_defaults
def cmd_loss_factor(args):
    try:
        _check_outputs(args)
        from ..identification import loss_factor_circle, read_frf_function
        from ..model.validators import frequencies, integer

        if args.freqs:
            frequencies("--freqs", args.freqs)
        count = None if args.count is None else integer("--count", args.count, 1)
        with renamed({"channel": "--channel"}):
            measured = read_frf_function(args.file, args.channel, strict=args.kind is None)
        f, H, declared = measured.freqs_hz, measured.H, measured.kind

        overridden = ""
        if args.kind is not None and declared is not None and args.kind != declared and measured.kind_by_labels:
            # (unit labels are free text: the user's stated kind is taken, the labels' said in the '#' line)
            overridden = f", against {declared!r} from {measured.kind_from}"
        elif args.kind is not None and declared is not None and args.kind != declared:
            raise ModelError(
                "--kind",
                args.kind,
                f"the FRF's kind by {measured.kind_from.replace('the file', str(args.file))} is {declared!r}: give "
                f"--kind {declared} or leave --kind out (the file's kind is taken)",
            )
        kind = args.kind or declared or "apparent_mass"
        source = "given" if args.kind else (f"from {measured.kind_from}" if declared else "default")
        source += overridden
        names = {"window_tau": "--window-tau", "bandwidths": "--bandwidths", "search": "--search"}
        names.update({"f_res_hz": "--freqs", "count": "--count", "max_iter": "--max-iter"})
        hints = {
            _PEAKS_HINT: "give the resonances themselves (--freqs) or a smaller --count",
            "give a smaller search": "give a smaller --search",
            "give a larger bandwidths": "give a larger --bandwidths",
        }
        if not args.freqs:
            hints["(give the frequency of a peak)"] = "(give the frequencies of the peaks, --freqs)"
        with renamed(names), _hint(hints), _peaks_found(args), _record_named(args, args.channel, ("freqs_hz", "H")):
            res = loss_factor_circle(
                f,
                H,
                args.freqs,
                kind=kind,
                count=count,
                bandwidths=args.bandwidths,
                search=args.search,
                correct_neighbours=not args.no_correction,
                max_iter=_max_iter(args),
                window_tau=args.window_tau,
            )
        win = "" if args.window_tau is None else f"; exponential window tau = {args.window_tau:g} s taken off"
        used = f" ({measured.described})" if measured.described else ""
        print(f"# {args.file}{used}: {f.size} points, {f[0]:g}..{f[-1]:g} Hz, kind {kind} ({source}){win}")
        if f[0] == 0.0:
            print("# the 0 Hz line is left out (no resonance uses it)")
        if res[0].extra["unrequested_hz"]:
            found = ", ".join(f"{v:.6g}" for v in res[0].extra["unrequested_hz"])
            print(f"# also fitted and subtracted, not requested (a peak within --search of a request): {found} Hz")
        print(
            f"{'mode':>4} {'f_r_Hz':>10} {'eta':>9} {'eta_unc_%':>9} {'f_unc_Hz':>9} {'eta/2':>9} {'diag_spread':>11} "
            f"{'circle_rms/R':>12} {'points':>6}"
        )
        for i, r in enumerate(res, 1):
            print(
                f"{i:>4} {r.f_r_hz:>10.4f} {r.eta:>9.5f} {100 * r.extra['eta_rel_uncertainty']:>9.2g} "
                f"{r.extra['f_r_uncertainty_hz']:>9.2g} {r.eta / 2:>9.5f} {np.ptp(r.diagonal):>11.3g} "
                f"{r.rms / r.radius:>12.3g} {r.freqs_hz.size:>6}"
            )
        print(
            "# eta_unc_%, f_unc_Hz: one standard deviation for the FRF's noise, not a bias (few lines per bandwidth, "
            "a close mode hidden in a circle, leakage); diag_spread: the largest minus the smallest loss factor on "
            "the plane's diagonal, of which eta is the median (near 0: one clean circle)"
        )
        lf = res[0].eta if len(res) == 1 else res
        toml = _fitted_toml(args, res, f"loss factor identified from {args.file}", loss_factor=lf)
        _emit(args, toml, "plot_circles", res)
        return 0
    except CableCasingError as exc:
        return _fail(exc)


def _read_measured(path, modes_arg, channel, max_iter=None):
    """(frequencies Hz, mode numbers, where the mode numbers came from: "file" or "--modes", and for an FRF
    a dict with ``sd_hz`` (each frequency's uncertainty, Hz), ``df`` (line spacing, Hz), ``how`` ("circle"
    or "peaks"), ``why`` (for peaks: the reason) and ``fits`` (the circle fits, with at most ``max_iter``
    correction sweeps; None: the circle fit's default), None for a table) from a CSV table ``mode,f_hz`` (the
    frequency's unit from its header, as an FRF's: ``f [rad/s]``, ``frequency_khz``) or from an FRF file:
    the resonances of the circle fits (``loss_factor_circle``, its ``f_r_uncertainty_hz``) started at the
    ``len(--modes)`` most prominent peaks of |H|; an FRF without a circle there (a magnitude, too coarse a
    resolution) gives the peaks themselves, known to half the line spacing at best."""
    from ..identification.circlefit import find_resonances, loss_factor_circle
    from ..identification.uff_io import frequency_column, is_frequency_header, is_uff, read_frf_function
    from ..model.validators import integer

    if not is_uff(path):
        from ..files import read_csv_table, unreadable

        names, data = read_csv_table(path, "file", min_rows=1, zero_row_free=True)  # (an FRF's 0 Hz line)
        header = [h.strip().lower() for h in names]
        if "mode" in header:
            if unreadable(data).any():  # (a table has no 0 Hz line)
                read_csv_table(path, "file", min_rows=1)  # (its refusal, naming the line and column)
            fcol = next((i for i, h in enumerate(names) if header[i] != "mode" and is_frequency_header(h)), None)
            if fcol is None:
                raise ModelError(
                    "file",
                    str(path),
                    "a measured-frequency table needs columns mode,f_hz (f [rad/s], f [kHz], ... are converted to Hz)",
                )
            to_hz = frequency_column(path, [names[fcol]])
            modes = data[:, header.index("mode")]
            if np.any(modes != np.round(modes)) or np.any(modes < 1) or np.any(modes > 1000):
                raise ModelError("file", str(path), "the column mode must hold whole numbers 1 to 1000")
            if modes_arg and [int(m) for m in modes] != [int(m) for m in modes_arg]:
                raise ModelError(
                    "--modes",
                    list(modes_arg),
                    f"contradicts the column mode of {path} ({', '.join(str(int(m)) for m in modes)}): a table "
                    "mode,f_hz gives its own mode numbers; leave --modes out (it is for an FRF file)",
                )
            if channel is not None:  # (a table has one column of frequencies: no channel to choose)
                raise ModelError(
                    "--channel",
                    channel,
                    f"{path} is a table mode,f_hz of measured frequencies, with no channels to choose from; leave "
                    "--channel out (it picks the FRF of an FRF file)",
                )
            return data[:, fcol] * to_hz, modes.astype(int), "file", None
    if not modes_arg:
        raise ModelError("--modes", None, "an FRF file needs the mode number of each resonance (--modes 1 2 ...)")
    for m in modes_arg:  # (the range of a table's column mode)
        integer("--modes", m, 1, 1000, " (mode numbers: 1 = the lowest)")
    with renamed({"channel": "--channel"}):
        measured = read_frf_function(path, channel, strict=False)
    f, H, declared = measured.freqs_hz, measured.H, measured.kind
    used = f"{path} ({measured.described})" if measured.described else str(path)
    kind = declared or "displacement"  # (the peaks of |H| in displacement form; a CSV's |H| as it is)
    try:  # (as many peaks as --modes gives mode numbers)
        peaks = find_resonances(f, H, count=len(modes_arg), kind=kind)
    except ModelError as exc:
        if exc.key != "count":
            raise
        allowed = exc.allowed.replace(_PEAKS_HINT, "give fewer --modes, or a table mode,f_hz of the frequencies")
        raise ModelError("--modes", list(modes_arg), allowed) from None
    modes = np.asarray(modes_arg, dtype=int)
    df = float(np.median(np.diff(f)))
    try:
        fits = loss_factor_circle(f, H, peaks, kind=kind, **({} if max_iter is None else {"max_iter": max_iter}))
    except ModelError as exc:  # (a magnitude |H|, too few lines per bandwidth: the peaks are all there is)
        why = exc
        if exc.key == "f_res_hz" and isinstance(exc.value, list):  # (two peaks, one resonance: said as found)
            why = _same_resonance(exc, "--max-iter 0" if max_iter == 0 else None, "--modes")
        info = {"sd_hz": np.full(peaks.size, df / 2), "df": df, "how": "peaks", "why": why, "fits": [], "used": used}
        return peaks, modes, "--modes", info
    f_r = np.array([r.f_r_hz for r in fits])
    sd = np.array([r.extra["f_r_uncertainty_hz"] for r in fits])
    return f_r, modes, "--modes", {"sd_hz": sd, "df": df, "how": "circle", "why": None, "fits": fits, "used": used}


@taking_api_defaults
def cmd_modulus(args):
    try:
        _check_outputs(args)
        from ..identification import identify_modulus_model
        from ..model import load_model
        from ..model.validators import integer, number

        with renamed({"model_file": "--model"}):
            model = load_model(args.model)
        if args.resolution is not None:
            number("--resolution", args.resolution, gt=0, unit="Hz")
        if not (args.degree == -1 or args.degree >= 0):
            raise ModelError("--degree", args.degree, "must be -1 (no smoothing) or an integer >= 0")
        n_table = integer("--n-table", args.n_table, 2)
        f_meas, modes, given_by, frf = _read_measured(args.file, args.modes, args.channel, _max_iter(args))
        if frf is None:
            resolution = TABLE_RESOLUTION_HZ if args.resolution is None else args.resolution
            said = "--resolution" if args.resolution is not None else "the paper's, the default for a table"
            source = f"a table; f_unc_Hz is half the resolution, {resolution / 2:.4g} Hz, a bound"
            sd = np.full(f_meas.size, resolution / 2)
            until = f"{resolution / 2:.4g} Hz (half the resolution {resolution:.4g} Hz, {said})"
        else:
            sd = frf["sd_hz"]
            if frf["how"] == "circle":
                source = (
                    f"the resonances of circle fits (loss-factor's) at the {f_meas.size} most prominent peaks of "
                    f"|H| of {frf['used']}; f_unc_Hz is their standard deviation for the FRF's noise (not a bias: "
                    "a viscous mode's f_r lies zeta^2 below f_n)"
                )
                # (a tenth of the smallest uncertainty: the adaptive process adds nothing to it)
                tenth, least = 0.2 * float(sd.min()), 2e-9 * float(f_meas.max())
                resolution = max(tenth, least)
                until = f"{resolution / 2:.4g} Hz (" + (
                    "a tenth of the smallest f_unc_Hz)"
                    if tenth >= least
                    else f"1e-9 of the highest frequency: a tenth of the smallest f_unc_Hz, {tenth / 2:.2g} Hz, is "
                    "below what the process resolves)"
                )
            else:
                source = (
                    f"the peaks of |H| of {frf['used']}, no circle fit ({frf['why']}); f_unc_Hz is half the line "
                    f"spacing {frf['df']:.4g} Hz, a lower bound: noise and a neighbour's tail move a peak further"
                )
                resolution = frf["df"]
                until = f"{resolution / 2:.4g} Hz (half the FRF's line spacing)"
            if args.resolution is not None:
                resolution = args.resolution
                until = f"{resolution / 2:.4g} Hz (half --resolution)"
        names = {"freq_resolution_hz": "--resolution", "degree": "--degree", "body": "--body"}
        names["modes"] = given_by if given_by == "--modes" else f"{args.file}, column mode"
        with renamed(names):
            res = identify_modulus_model(
                model,
                args.body,
                f_meas,
                modes,
                freq_resolution_hz=resolution,
                degree=None if args.degree == -1 else args.degree,
                n_table=n_table,
            )
        print(
            f"# {args.body} of {model.source}: E_start = {model.bodies[args.body].E_ref:.6g} Pa; frequencies from "
            f"{source}; each mode updated at least once, then until within {until}; E_unc_% is f_unc_Hz "
            "carried to E through the model (about 2 f_unc / f)"
        )
        E_unc = res.E_uncertainty(sd)
        print(
            f"{'mode':>4} {'f_meas_Hz':>10} {'f_unc_Hz':>9} {'f_comp_Hz':>10} {'E_Pa':>12} {'E_unc_%':>8} {'steps':>5}"
        )
        for m, fm, u, fc, E, dE, h in zip(
            res.modes, res.f_measured_hz, sd, res.f_computed_hz, res.E_mode, E_unc, res.history
        ):
            print(f"{m:>4} {fm:>10.4f} {u:>9.2g} {fc:>10.4f} {E:>12.5g} {100 * dE / E:>8.2g} {len(h) - 1:>5}")
        fits = frf["fits"] if frf else []
        toml = _fitted_toml(args, fits, f"dynamic modulus E(f) identified from {args.file}", E=res.table)
        _emit(args, toml, "plot_modulus", res)
        return 0
    except CableCasingError as exc:
        return _fail(exc)


def _unsettled_options(p, where=""):
    """``--max-iter`` and ``--allow-unsettled`` of the circle fits' neighbour correction (the default is
    ``circlefit.MAX_ITER``: :class:`~.helptext.FromApi`)."""
    p.add_argument(
        "--max-iter",
        type=int,
        default=FromApi("identification.circlefit", "MAX_ITER"),
        help=f"most neighbouring-mode correction sweeps of the circle fits{where} (default %(default)s, the circle "
        "fit's; modes under a half-power bandwidth apart may need thousands; 0: no correction, the uncorrected fits, "
        "which do not tell close modes apart)",
    )
    p.add_argument(
        "--allow-unsettled",
        action="store_true",
        help="write --toml even when the correction did not settle in --max-iter sweeps (marked NOT SETTLED); "
        "without it such a run writes nothing and exits 2",
    )


def add_parser(subparsers):
    """Register ``identify`` with sub-commands ``damping``, ``loss-factor``, ``modulus`` on an
    ``argparse`` sub-parsers object; returns the ``identify`` parser."""
    p = subparsers.add_parser("identify", help="identify damping and modulus from measurements (Section 3)")
    sub = p.add_subparsers(dest="identify_command", required=True)

    d = sub.add_parser("damping", help="damping ratios from wavelet ridges of an impulse response; Rayleigh fit")
    d.add_argument("file", help="impulse response: CSV (time_s,<signal>...), NPZ or UFF 58 time record")
    d.add_argument("--channel", default=None, help="CSV column name/index or n-th UFF time record (default first)")
    d.add_argument(
        "--freqs", type=float, nargs="+", help="natural frequencies to analyse (Hz); default: spectrum peaks"
    )
    d.add_argument(
        "--count",
        type=int,
        default=None,
        help=f"number of spectrum peaks when --freqs is not given (default: the {DAMPING_PEAKS} most prominent, or "
        "as many as the record has above its noise)",
    )
    wavelet = "identification.wavelet"
    d.add_argument(
        "--gamma",
        type=float,
        default=FromApi(wavelet, "DEFAULT_GAMMA"),
        help="Morlet parameter (sigma_t = gamma / (2 pi f))",
    )
    d.add_argument(
        "--edge-factor", type=float, default=FromApi(wavelet, "EDGE_FACTOR"), help="edge length in sigma_t at each end"
    )
    d.add_argument(
        "--search", type=float, default=FromApi(wavelet, "SEARCH"), help="relative half-width of the ridge search"
    )
    d.add_argument(
        "--noise-floor", type=float, default=None, help="|W| noise level (signal unit); default from the tail"
    )
    d.add_argument("--t-max", type=float, default=None, help="latest time used in the fit (s)")
    d.add_argument(
        "--t0",
        type=float,
        default=None,
        help="time (s) of the record's first sample, the impulse at t = 0 (default: the file's time axis; -0.02 for "
        "a record whose impulse lies 20 ms after its first sample); --t-max and the printed times are on that axis",
    )
    d.add_argument(
        "--max-departure",
        default=FromApi(wavelet, "MAX_DEPARTURE"),
        help="largest departure (nepers) of ln|W| from the fitted line before the record is refused as not one "
        "free decay (default %(default)s; 'off' skips the check: only for a clean record whose slower neighbour "
        "leaks into the window's end; modes that beat need a larger --gamma)",
    )
    d.add_argument(
        "--window-tau",
        type=float,
        default=None,
        help="time constant (s) of an exponential window applied to the record; its decay 1/tau is taken off",
    )
    d.add_argument("--nonnegative", action="store_true", help="constrain alpha, beta >= 0")
    d.add_argument("--body", choices=BODY_NAMES, default="casing", help="TOML section")
    d.add_argument("--plot", help="PNG: record, scalogram and ridges (Figs. 10-11)")
    d.add_argument("--toml", help="write the alpha, beta lines to this file")
    d.set_defaults(func=cmd_damping)

    lf = sub.add_parser("loss-factor", help="loss factors from Nyquist circles of an FRF (Eq. 45)")
    lf.add_argument("file", help="FRF: CSV (frequency_hz,re_*,im_*) or UFF 58 FRF")
    lf.add_argument(
        "--channel",
        default=None,
        help="the FRF of a file holding several: a UFF FRF's name or place, a CSV's re_/im_ pair's name (H21, re_H21) "
        "or place (default the first)",
    )
    lf.add_argument("--freqs", type=float, nargs="+", help="approximate resonance frequencies (Hz); default: peaks")
    lf.add_argument("--count", type=int, default=None, help="number of peaks when --freqs is not given")
    choice_argument(
        lf,
        "--kind",
        default=None,
        choices=FromApi("identification.circlefit", "FRF_KINDS"),
        help="FRF type (the paper's TRFAM is apparent_mass, kg); default: the kind the file declares (a UFF "
        "header's data types, a CSV's line '# kind = ...'), else apparent_mass; a kind that contradicts the file's "
        "is refused",
    )
    lf.add_argument(
        "--window-tau",
        type=float,
        default=None,
        help="time constant (s) of an exponential window applied to the response; its damping is taken off",
    )
    lf.add_argument(
        "--bandwidths",
        type=float,
        default=FromApi("identification.circlefit", "BANDWIDTHS"),
        help="full width (> 0) of each circle's window in half-power bandwidths B = eta f_r: omega^2 within "
        "omega_r^2 (1 +- bandwidths eta), f_r +- (bandwidths/2) B (2: +-B; 1: the half-power points)",
    )
    lf.add_argument(
        "--search",
        type=float,
        default=FromApi("identification.circlefit", "SEARCH"),
        help="relative half-width (0 < search < 1) around each resonance searched for its peak, no further than "
        "halfway to the next; other peaks within it are fitted and subtracted too",
    )
    lf.add_argument("--no-correction", action="store_true", help="skip the neighbouring-mode correction")
    _unsettled_options(lf)
    lf.add_argument("--body", choices=BODY_NAMES, default="casing", help="TOML section")
    lf.add_argument("--plot", help="PNG: Nyquist circles, loss-factor planes, diagonal ridges (Fig. 13)")
    lf.add_argument("--toml", help="write the loss_factor line to this file")
    lf.set_defaults(func=cmd_loss_factor)

    m = sub.add_parser("modulus", help="dynamic modulus E(f) from measured natural frequencies (Section 3.1)")
    m.add_argument("file", help="CSV table with columns mode,f_hz; or an FRF (CSV/UFF) whose peaks are taken")
    m.add_argument("--model", default=None, help="model TOML file (default: built-in specimen)")
    m.add_argument(
        "--body",
        choices=BODY_NAMES,
        default="casing",
        help="the body of --model whose modes were measured; TOML section",
    )
    m.add_argument("--modes", type=int, nargs="+", help="mode number of each measured frequency (1 = lowest)")
    m.add_argument(
        "--channel", default=None, help="the FRF of a file holding several, as for loss-factor (default the first)"
    )
    m.add_argument(
        "--resolution",
        type=float,
        default=None,
        help="frequency resolution of the measurement (Hz): each mode's modulus is updated at least once, then "
        f"until its frequency is within half of it (default: {TABLE_RESOLUTION_HZ:g} Hz, the paper's, for a table "
        "mode,f_hz; for an FRF a fifth of its circle fits' smallest frequency uncertainty, or its line spacing "
        "for its peaks)",
    )
    m.add_argument(
        "--degree",
        type=int,
        default=FromApi("identification.modulus", "DEGREE"),
        help="degree of the smooth fit in ln f (-1: no smoothing)",
    )
    _unsettled_options(m, " (an FRF file)")
    m.add_argument(
        "--n-table", type=int, default=FromApi("identification.modulus", "N_TABLE"), help="rows of the E(f) table"
    )
    m.add_argument("--plot", help="PNG: adaptive process and E against f (Figs. 8-9)")
    m.add_argument("--toml", help="write the E table line to this file")
    m.set_defaults(func=cmd_modulus)
    name_by_choices(sub)  # (a missing sub-command is named as the usage line names it)
    return p
