"""Command line ``cablecasing``: a thin shell over the core API.

Sub-commands: ``modes``, ``trfam``, ``keys`` (the model file's keys, from the schema), ``geometry``
(``geometry.py``), ``simulate`` (``simulate.py``), ``static`` (``static.py``), ``spectrum`` and
``bands`` (``nvh.py``), ``identify ...`` (``identify.py``), ``study``, ``ensemble``, ``pool`` (``study.py``), ``report``
(``report.py``), each module registering its own with ``add_parser``. A model argument is a TOML
file or the name of a built-in specimen (``default``, ``installed``). Every ``--help`` shows the
defaults. Every error in the input prints one line naming the key, the value and what is
allowed, and exits with status 2; an interrupt (Ctrl-C) prints one line and exits with status
130, leaving earlier output files intact (they are written atomically, at the end); SIGTERM (a
``kill``) and SIGHUP (a terminal closed) take the same way out (:class:`Terminated`) with status
128 + the signal's number, 143 and 129; a warning prints one line ``cablecasing: warning: ...`` (a warning
that ``-W error`` or ``PYTHONWARNINGS=error`` makes an exception stops the command: one line
``cablecasing: error: (a warning made an error by -W error / PYTHONWARNINGS): ...``, status 2). An
output the system fails to write (a full disk: :class:`~cablecasing_core.files.WriteError`) prints
one line naming the option, the file and the cause, and exits with status 1. A failure of the
computing infrastructure (a study's dask scheduler lost, no worker left or making progress) prints
one line and exits with status 3 (the same command resumes). Anything else is a bug: one line
``cablecasing: internal error: ...`` and status 1 (``CABLECASING_TRACEBACK=1`` shows the traceback).

Exit statuses: 0 done, 1 every run of a study failed, an output could not be written or an internal
error, 2 bad input (or a run that cannot work: too large for the machine, a blow-up; or a warning made
an error by -W error / PYTHONWARNINGS), 3 infrastructure, 130 interrupted (Ctrl-C), 143 and 129
stopped by SIGTERM and SIGHUP (docs/cli.md, "Exit status", tabulates the same).
"""

from __future__ import annotations

import argparse
import contextlib
import errno
import json
import os
import signal
import sys
import threading
import warnings

import numpy as np

from ..errors import CableCasingError, InfrastructureError, ModelError, internal_error_text, renamed
from . import geometry, identify, nvh, report, simulate, static, study
from .assignments import add_model_argument, model_argument
from .helptext import FromApi, choice_argument, expand_api_texts, name_by_choices
from .paths import PLOT_SUFFIXES, check_distinct, check_output_path, check_plotting, emit_table, kept


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Help that shows every option's default (argparse's own formatter, without the noise of
    ``(default: None)``, ``False`` flags, empty lists and helps that state their default already)."""

    def _get_help_string(self, action):
        text = action.help or ""
        d = action.default
        if "default" in text or d is None or d is False or d is argparse.SUPPRESS or (isinstance(d, list) and not d):
            return text
        if not action.option_strings and action.nargs not in ("?", "*"):
            return text
        return text + " (default: %(default)s)"

    def _expand_help(self, action):
        return expand_api_texts(super()._expand_help(action))


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose sub-commands (at every level) use :class:`HelpFormatter`."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)


def cmd_modes(args):
    from ..frequency.modal import mode_count, natural_frequencies
    from ..model.validators import integer

    model = model_argument(args.model, args.set)
    count = integer("--count", args.count, 1)
    # (a body has as many modes as free degrees of freedom: all of them printed, and the warning below
    # names --count; asked for no more than there are, the API does not warn a second time)
    res = {b: natural_frequencies(model, b, min(count, mode_count(model, b))).tolist() for b in model.bodies}
    for b, f in res.items():
        if len(f) < count:
            warnings.warn(
                f"--count = {count}: the {b} of {model.source} has only {len(f)} modes (one per free degree of "
                f"freedom of its {model.geometry['n_elements']} elements); all {len(f)} are printed",
                stacklevel=1,
            )
    _warn_free_motions(model)
    if args.json:
        print(json.dumps(res))
    else:
        _print_scope(model)
        for b, f in res.items():
            print(f"{b}: natural frequencies (Hz)")
            for i, v in enumerate(f, 1):
                print(f"  {i:3d}  {v:12.4f}")
    return 0


def _warn_free_motions(model):
    """Warn, per body, of the rigid motions its supports and mounts leave free (its first modes are
    0 Hz, to rounding): the motions that the loads check (structure/support_check.py) would refuse
    under gravity or a tension, named as it names them."""
    from ..structure.support_check import free_motions

    for b in model.bodies:
        motions = free_motions(model, b)
        if not motions:
            continue
        k = len(motions)
        which = (
            "all six rigid motions (no support or mount holds it)"
            if k == 6
            else f"{k} rigid motion{'s' * (k > 1)}: " + "; ".join(motions)
        )
        warnings.warn(
            f"the {b} of {model.source}: its supports leave it free in {which}, so "
            f"{f'its first {k} modes are' if k > 1 else 'its first mode is'} rigid at 0 Hz (to rounding); under a "
            "load (gravity, a tension) the model "
            "would be refused: clamp a support or give the isolators or clips a stiffness in that direction",
            stacklevel=1,
        )


def _print_scope(model):
    """The line ``# each body alone ...`` of ``modes`` and ``trfam`` for a model with both bodies and
    contact enabled, or installed (frequency.modal.frequency_domain_scope): what the frequency domain
    leaves out."""
    from ..frequency.modal import frequency_domain_scope

    scope = frequency_domain_scope(model)
    if scope:
        print(f"# {scope}")


def cmd_trfam(args):
    from ..frequency.trfam import parse_port, trfam
    from ..model.validators import number
    from .nvh import check_frequency_range

    model = model_argument(args.model, args.set)
    check_frequency_range(args.fmin, args.fmax)
    number("--df", args.df, gt=0, unit="Hz")
    if args.df > args.fmax - args.fmin:
        raise ModelError(
            "--df", args.df, f"must be at most fmax - fmin = {args.fmax - args.fmin:g} Hz (two frequencies or more)"
        )
    from ..model.limits import MAX_FREQUENCIES

    count = (args.fmax - args.fmin) / args.df + 1
    if not count <= MAX_FREQUENCIES:
        raise ModelError(
            "--fmin/--fmax/--df",
            (args.fmin, args.fmax, args.df),
            f"give {count:.3g} frequencies; at most {MAX_FREQUENCIES}",
        )
    # fmin, fmin + df, ... up to fmax, never beyond it (arange's end overshot by up to df / 2)
    f = args.fmin + args.df * np.arange(int(np.floor((args.fmax - args.fmin) / args.df * (1 + 1e-12))) + 1)
    check_output_path("--out", args.out, (".csv",) if args.bands else (".csv", ".uff"))  # (bands: a CSV table)
    check_output_path("--plot", args.plot, PLOT_SUFFIXES)
    check_distinct(("--out", args.out), ("--plot", args.plot))
    args.interrupted = kept("stopped", args.out, args.plot)
    with renamed({"input": "--input", "output": "--output"}):
        body = parse_port("input", args.input, model)[0]
        H = trfam(model, args.input, args.output, f, damping=args.damping)
    _warn_coarse_grid(model, body, args)
    _print_scope(model)
    table = np.column_stack([f, H.real, H.imag, np.abs(H), np.degrees(np.angle(H))])
    header = ["frequency_hz", "re_kg", "im_kg", "magnitude_kg", "phase_deg"]
    if args.bands:
        from .nvh import trfam_bands

        trfam_bands(args, f, H)
    elif args.out and args.out.lower().endswith(".uff"):
        from ..records import uff_dof
        from ..uff import Record, frf_fields, write_uff

        node, d, *_ = uff_dof(args.output)
        ref_node, ref_d, *_ = uff_dof(args.input)
        name = f"TRFAM {args.output}/{args.input} ({args.damping})"
        # apparent mass: reaction force (N) over acceleration (m/s2), in kg
        rec = Record("frf", f, H, name, node, d, ref_node, ref_d, **frf_fields("apparent_mass"))
        write_uff(args.out, [rec])
        print(f"wrote {args.out} (UFF 58, {name}, kg)")
    else:
        emit_table(args.out, header, table, 10, note="")
    if args.plot:
        from ..plotting import plot_trfam

        title = f"TRFAM {args.output} / {args.input} (kg)"
        plot_trfam(f, {f"{args.damping}": H}, args.plot, title=title, log_frequency=args.log_frequency)
        print(f"wrote {args.plot}")
    return 0


def _warn_coarse_grid(model, body, args):
    """Warn when the grid step ``--df`` may miss the peak of a resonance between --fmin and --fmax.

    A grid of step df lands at worst df/2 from a peak of half-power bandwidth b, where |TRFAM| is
    1/sqrt(1 + (df/b)^2) of the peak's height (a single mode's resonance): the criterion is df <= b/2,
    which keeps each peak within 11 % (1/sqrt(1.25) = 0.894). Undamped (b = 0), no grid resolves a
    peak, which is infinite."""
    from ..frequency.trfam import PEAK_GRID_SHARE, grid_peak_height, half_power_bandwidths

    fn, bw = half_power_bandwidths(model, body, args.damping, args.fmin, args.fmax)
    if not len(fn):
        return
    where = f"between --fmin {args.fmin:g} and --fmax {args.fmax:g} Hz"
    if not np.all(bw > 0):
        zero = fn[bw <= 0]
        why = "--damping none" if args.damping == "none" else f"the {body} has no {args.damping} damping"
        at = (
            f"the natural frequency {zero[0]:.6g} Hz"
            if len(zero) == 1
            else (f"each of the {len(zero)} natural frequencies (the first at {zero[0]:.6g} Hz)")
        )
        warnings.warn(
            f"--df = {args.df:g} Hz: {why}, so the TRFAM is infinite at {at} of the {body} {where}: no grid "
            "resolves such a peak, and the values near it are the grid's, not the peak's height",
            stacklevel=1,
        )
        return
    coarse = args.df > PEAK_GRID_SHARE * bw
    if not np.any(coarse):
        return
    k = int(np.argmin(bw))
    low = grid_peak_height(args.df, bw[k])
    most = PEAK_GRID_SHARE * bw[k]
    unit = 10.0 ** (np.floor(np.log10(most)) - 2)  # (three digits, rounded down: a step that resolves)
    fine = float(f"{np.floor(most / unit) * unit:.3g}")
    kept = 100 * (1 - grid_peak_height(PEAK_GRID_SHARE, 1.0))
    warnings.warn(
        f"--df = {args.df:g} Hz is wider than half the half-power bandwidth of {int(coarse.sum())} of the "
        f"{len(fn)} mode(s) of the {body} {where} ({args.damping} damping): the narrowest, at {fn[k]:.6g} Hz, is "
        f"{bw[k]:.4g} Hz wide, and a grid of step df may miss its peak by df/2, where |TRFAM| is down to "
        f"1/sqrt(1 + (df/bandwidth)^2) = {100 * low:.0f} % of it; --df {fine:g} or less keeps every peak "
        f"within {kept:.0f} %",
        stacklevel=1,
    )


def cmd_keys(args):
    """Print the model file's keys from the schema: key, type, default, unit, allowed, description."""
    from ..model.schema import SCHEMA

    rows = [s for k, s in SCHEMA.items() if k.startswith(args.prefix or "")]
    if not rows:
        raise ModelError(
            "PREFIX", args.prefix, "matches no key of the model file; " + _closest_keys(args.prefix, SCHEMA)
        )
    for s in rows:  # (the columns of docs/model_file.md's key table, schema.markdown_table)
        print(f"{s.key}\t{s.type}\t{s.default_text}\t{s.unit or '-'}\t{s.allowed_text}\t{s.description}")
    return 0


def _closest_keys(prefix, keys):
    """``did you mean ...?`` with the sections, tables and keys of the model file closest to
    ``prefix`` (errors.closest), or the sections when none is close."""
    from ..errors import closest

    names = sorted({".".join(k.split(".")[:n]) for k in keys for n in range(1, k.count(".") + 2)})
    close = closest(prefix, names, n=3)
    if close:
        return "did you mean " + " or ".join(repr(c) for c in close) + "?"
    return "its sections are " + ", ".join(sorted({k.split(".")[0] for k in keys}))


def _installed_package(dist):
    """The folder of the package ``cablecasing_core`` that the installed distribution ``dist`` holds: an
    editable install's source folder (its ``direct_url.json``), else where its files lie; None when it
    cannot be told."""
    from pathlib import Path
    from urllib.parse import unquote, urlparse

    try:
        direct = json.loads(dist.read_text("direct_url.json") or "null")
    except ValueError:
        direct = None
    if isinstance(direct, dict) and direct.get("dir_info", {}).get("editable"):
        url = urlparse(str(direct.get("url", "")))
        return Path(unquote(url.path)).resolve() / "cablecasing_core" if url.scheme == "file" else None
    init = Path(dist.locate_file("cablecasing_core/__init__.py"))
    return init.resolve().parent if init.exists() else None


def version_text() -> str:
    """What ``cablecasing --version`` prints: the installed distribution's version (its metadata), the
    folder the package runs from and the Python, ``cablecasing 0.3.0 (cablecasing_core from /.../cablecasing_core;
    Python 3.11.7)``. A copy that is not the installed one (a checkout on ``PYTHONPATH``) or not
    installed at all says so, with the version its checkout's pyproject.toml states."""
    import importlib.metadata
    import platform
    from pathlib import Path

    here = Path(__file__).resolve().parents[1]  # (the folder cablecasing_core)
    python = f"Python {platform.python_version()}"
    try:
        dist = importlib.metadata.distribution("cablecasing")
    except importlib.metadata.PackageNotFoundError:
        dist = None
    installed = None if dist is None else _installed_package(dist)
    if dist is not None and installed in (None, here):
        return f"cablecasing {dist.version} (cablecasing_core from {here}; {python})"
    stated = ""
    try:
        try:
            import tomllib
        except ModuleNotFoundError:  # (Python 3.10: tomli, a dependency there)
            import tomli as tomllib
        project = tomllib.loads((here.parent / "pyproject.toml").read_text(encoding="utf-8"))["project"]
        if project.get("name") == "cablecasing":
            stated = f"; its checkout's pyproject.toml states version {project['version']}"
    except (OSError, ValueError, KeyError):  # (no checkout beside it, or not this project's)
        pass
    if dist is not None:  # (another copy is installed; this one runs from a folder on sys.path)
        return (
            f"cablecasing: this cablecasing_core, from {here}, is not the installed one (cablecasing {dist.version}, "
            f"from {installed}){stated}; {python}"
        )
    return (
        f"cablecasing: not installed (no package metadata): cablecasing_core runs from {here}{stated}; {python}; "
        "pip install . in the checkout installs it"
    )


class _Version(argparse.Action):
    """``--version``: prints :func:`version_text` on one line (argparse's own version action re-wraps
    it to the terminal's width) and exits with status 0."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings=option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        print(version_text())
        parser.exit(0)


def build_parser():
    p = Parser(prog="cablecasing", description="Cable-in-casing vibration model (SI units).")
    p.add_argument("--version", action=_Version, help="the version, where the package runs from and the Python")
    sub = p.add_subparsers(dest="command", required=True)

    alone = (
        "Each body alone on its supports and mounts: the frequency domain has no contact between the cable and "
        "the casing (the time domain has). An installed model's bodies carry the axial prestress of "
        "loads.cable_tension (the cable stiffened by its tension, the casing softened by its compression) about "
        "their route, not the static state: gravity's sag, a straight cable's bending into the route and the "
        "contact forces that `cablecasing static` shows are not in it. For such a model (both bodies with "
        "contact.enabled, or installed) the output's first line, '# each body alone ...', says so."
    )
    m = sub.add_parser(
        "modes", help="natural frequencies of each body (Hz)", description="Natural frequencies (Hz). " + alone
    )
    add_model_argument(m, settable=True)
    m.add_argument("--count", type=int, default=10, help="number of modes per body")
    m.add_argument("--json", action="store_true", help="print JSON {body: [Hz, ...]}")
    m.set_defaults(func=cmd_modes)

    t = sub.add_parser(
        "trfam",
        help="apparent-mass transfer function (kg), Eq. (12)",
        description="The apparent-mass transfer function TRFAM (kg, Eq. 12) between two supports of a body. " + alone,
    )
    add_model_argument(t, settable=True)
    t.add_argument("--input", default="casing.A.x", help="driven support DOF, e.g. casing.A.x")
    t.add_argument("--output", default="casing.B.x", help="support DOF whose force is the output")
    t.add_argument("--fmin", type=float, default=10.0, help="lowest frequency, Hz")
    t.add_argument("--fmax", type=float, default=1000.0, help="highest frequency, Hz")
    t.add_argument(
        "--df", type=float, default=0.25, help="frequency step, Hz (0.25: the casing's narrowest peak within 11 %%)"
    )
    choice_argument(
        t,
        "--damping",
        choices=FromApi("frequency.trfam", "DAMPING_MODELS"),
        default="viscous",
        help="viscous: Rayleigh alpha, beta (as the time domain); structural: the loss factor (Eq. 11)",
    )
    choice_argument(
        t,
        "--bands",
        choices=FromApi("nvh.bands", "BAND_KINDS"),
        default=None,
        help="write the band values instead of the lines: the RMS of |TRFAM| over each band within --fmin..--fmax "
        "(table3: the paper's octaves [TABLE3_RANGE], the report's bands; octave, third: IEC 61260-1), kg",
    )
    t.add_argument(
        "--out",
        help="file to write: .csv (frequency, re, im, magnitude, phase; with --bands the band table) or .uff "
        "(UFF 58 FRF)",
    )
    t.add_argument("--plot", help="figure to write (.png), magnitude and phase")
    t.add_argument("--log-frequency", action="store_true", help="logarithmic frequency axis in --plot")
    t.set_defaults(func=cmd_trfam)

    k = sub.add_parser("keys", help="the keys of the model file: type, default, unit, allowed values, meaning")
    k.add_argument(
        "prefix", nargs="?", default=None, metavar="PREFIX", help="only keys that start with this, e.g. contact"
    )
    k.set_defaults(func=cmd_keys)

    for module in (geometry, simulate, static, nvh, identify, study, report):
        module.add_parser(sub)
    name_by_choices(sub)  # (a missing command is named as the usage line names it, not 'command')
    return p


def _warning_line(message, category, filename, lineno, file=None, line=None):
    """Warnings as one line on stderr, without the file and line of the code that warned; on a line
    of its own above a progress bar that is being drawn (tqdm's write), not after it."""
    text = f"cablecasing: warning: {message}"
    bars = sys.modules.get("tqdm.auto")
    if file is None and bars is not None:
        bars.tqdm.write(text, file=sys.stderr)
    else:
        print(text, file=sys.stderr if file is None else file)


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP (a ``kill``, a terminal closed), raised in the main thread as Ctrl-C's
    KeyboardInterrupt is, so that it takes the same way out: every cleanup of an interrupt runs (a
    file being written is removed, its target kept as it was; a study's cluster is closed)."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


#: The signals that stop the command line as Ctrl-C does (those the platform has).
_STOP_SIGNALS = tuple(getattr(signal, n) for n in ("SIGTERM", "SIGHUP") if hasattr(signal, n))


@contextlib.contextmanager
def _stopped_by_signals():
    """SIGTERM and SIGHUP raise :class:`Terminated` while the block runs (in the main thread only:
    signal handlers live there); a signal that is ignored (``nohup``) stays ignored. The first one
    raises; those that follow while the interrupt is handled are ignored, so that its cleanup runs
    to the end (Ctrl-C and SIGKILL still stop it). The handlers before are restored at the end.
    (Processes started meanwhile, a study's dask workers, run a new interpreter: a Python handler is
    not inherited; they are started with SIGINT and SIGHUP blocked, studies/executor.py, and keep
    SIGTERM's default action.)"""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    raised = []

    def stop(signum, frame):
        if not raised:
            raised.append(signum)
            raise Terminated(signum)

    before = {}
    for sig in _STOP_SIGNALS:
        old = signal.getsignal(sig)
        if old is signal.SIG_IGN:
            continue
        before[sig] = signal.SIG_DFL if old is None else old
        signal.signal(sig, stop)
    try:
        yield
    finally:
        for sig, old in before.items():
            signal.signal(sig, old)


#: Causes of an OSError that are the machine's, never the program's (a full disk, a quota, a device).
_SYSTEM_ERRNOS = {getattr(errno, n) for n in ("ENOSPC", "EDQUOT", "EFBIG", "EIO", "EROFS") if hasattr(errno, n)}


def _output_option(args, filename):
    """The option of ``args`` that named the output ``filename`` (``--out``, its ``_against`` twin
    included, ``--plot``, ``--toml``; a file in an output folder by that folder's option), or None."""
    from pathlib import Path

    from .study import _against_path

    target = Path(str(filename)).resolve()
    for attr in ("out", "plot", "toml"):
        given = getattr(args, attr, None)
        if attr == "plot" and given is True:
            given = "simulation.png"
        if not isinstance(given, str):
            continue
        named = [Path(p).resolve() for p in (given, _against_path(given))]
        if target in named or named[0] in target.parents:
            return f"--{attr}"
    return None


def _write_failed(args, exc):
    """The one line of an output that the system failed to write (:class:`~cablecasing_core.files.WriteError`:
    the option and the file, the cause, what was kept) or of another OSError of the machine (a full
    disk while a study appends its rows)."""
    from ..files import WriteError

    if exc.filename is None:
        return f"{exc.strerror or type(exc).__name__} (an error of the machine, not of the program)"
    key = _output_option(args, exc.filename)
    cause = exc.strerror or type(exc).__name__
    if isinstance(exc, WriteError):
        kept_ = "the previous file is kept as it was" if exc.kept else "no file was made"
        return str(ModelError(key or "output", str(exc.filename), f"could not be written ({cause}); {kept_}"))
    return str(ModelError(key or "file", str(exc.filename), f"failed ({cause})"))


class _ReaderGone:
    """Standard output or standard error for a command whose reader may leave early (``| head``,
    ``2>&1 | head``): once the pipe is broken, what the command prints there is dropped and the
    command goes on, so that it still writes the files it was asked for (a run printed its summary,
    a warning or a progress bar before saving and stopped there, with status 0). The pipe's file
    descriptor is then pointed at /dev/null (Python flushes the stream again at exit; the Python
    docs' "Note on SIGPIPE"). Everything else is the wrapped stream's. A stream that is not there
    (``sys.stderr`` is None when the command starts with it closed, ``2>&-``) is /dev/null: the text
    is dropped, the command runs and its status says how it ended. Text the stream's encoding cannot
    spell (a path in ``PYTHONIOENCODING=ascii``) is written escaped (``\\xfc``), not raised."""

    def __init__(self, stream):
        if stream is None:
            stream = open(os.devnull, "w", encoding="utf-8")  # noqa: SIM115 (open while the command runs)
        self._stream = stream
        self.gone = False

    def write(self, text):
        if not self.gone:
            try:
                try:
                    return self._stream.write(text)
                except UnicodeEncodeError:  # (a path its encoding cannot spell, PYTHONIOENCODING=ascii:
                    # escaped, \xfc, rather than a done run turned into an internal error)
                    encoding = getattr(self._stream, "encoding", None) or "ascii"
                    self._stream.write(text.encode(encoding, "backslashreplace").decode(encoding))
            except BrokenPipeError:
                self._left()
        return len(text)

    def flush(self):
        if not self.gone:
            try:
                self._stream.flush()
            except BrokenPipeError:
                self._left()

    def _left(self):
        self.gone = True
        with contextlib.suppress(OSError, ValueError):  # (a stream without a descriptor: its text is dropped)
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, self._stream.fileno())
            os.close(devnull)

    def __getattr__(self, name):
        return getattr(self._stream, name)


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)  # (the command line, which a report states)
    shown = warnings.showwarning
    warnings.showwarning = _warning_line
    stdout, stderr = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = _ReaderGone(stdout), _ReaderGone(stderr)
    try:
        with _stopped_by_signals():
            return args.func(args)
    except InfrastructureError as exc:
        print(f"cablecasing: error: {exc}", file=sys.stderr)
        return 3
    except CableCasingError as exc:
        print(f"cablecasing: error: {exc}", file=sys.stderr)
        return 2
    except MemoryError as exc:  # (the sizes a run needs are checked before it starts; this is the last resort)
        print(f"cablecasing: error: {internal_error_text(exc)}", file=sys.stderr)
        return 2
    except BrokenPipeError as exc:  # (a pipe of the command's own, not stdout or stderr, which _ReaderGone
        # keeps going): it stopped the work, which is not done, so never status 0
        print(
            f"cablecasing: error: a pipe the command wrote to was closed ({exc.strerror or 'broken pipe'}): it "
            "stopped before the end, and the files it was to write may be missing",
            file=sys.stderr,
        )
        return 1
    except KeyboardInterrupt as exc:
        # (said now: what the command has written so far, paths.kept)
        hint = str(getattr(args, "interrupted", "nothing was written; files written before are as they were"))
        if isinstance(exc, Terminated):  # (SIGTERM, SIGHUP: 128 + its number, as a shell reports it)
            with contextlib.suppress(OSError):  # (the terminal of a hang-up may be gone: the status stays)
                print(f"cablecasing: terminated ({signal.Signals(exc.signum).name}): {hint}", file=sys.stderr)
            return 128 + exc.signum
        print(f"\ncablecasing: interrupted: {hint}", file=sys.stderr)
        return 130
    except OSError as exc:  # an output the system failed to write (a full disk): not a bug
        from ..files import WriteError

        if not isinstance(exc, WriteError) and exc.errno not in _SYSTEM_ERRNOS:
            return _internal_error(exc)
        print(f"cablecasing: error: {_write_failed(args, exc)}", file=sys.stderr)
        return 1
    except Warning as exc:  # (-W error, PYTHONWARNINGS=error: a warning raised as an exception, not a bug)
        text = " ".join(str(exc).split())
        print(
            f"cablecasing: error: (a warning made an error by -W error / PYTHONWARNINGS): {type(exc).__name__}: {text}",
            file=sys.stderr,
        )
        return 2
    except Exception as exc:
        if isinstance(exc, ValueError) and os.environ.get("MPLBACKEND"):  # (an import of matplotlib that the
            try:  # environment failed, in a command drawing no figure: not a bug)
                check_plotting()
            except ModelError as bad:
                print(f"cablecasing: error: {bad}", file=sys.stderr)
                return 2
        return _internal_error(exc)
    finally:
        warnings.showwarning = shown
        sys.stdout, sys.stderr = stdout, stderr


def _internal_error(exc):
    """A bug: one line (:func:`~cablecasing_core.errors.internal_error_text`; CABLECASING_TRACEBACK=1 adds
    the traceback); status 1."""
    print(f"cablecasing: internal error: {internal_error_text(exc, report=' with the command')}", file=sys.stderr)
    return 1
